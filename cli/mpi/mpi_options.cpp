#include "mpi_options.h"

#include "common.h"
#include "topotet/error.h"
#include "topotet/io.h"

namespace topotet::cli::mpi {
namespace {

// Options of `simplify` that topotet::mpi cannot honour, and why (topotet/mpi.h, mpi/simplify.cpp).
struct Unavailable {
  const char* name;
  const char* why;
};
// The per-tet bounds live in one engine mesh, built anew on every rank at every pass: they would
// bound only the last pass, against its own input, not the original vertices.
constexpr const char* kNoBounds =
    "the field error bounds are kept in one engine mesh, and the ranks rebuild theirs at every pass "
    "(a bound would cover the last pass only); use topotet simplify";
constexpr Unavailable kUnavailable[] = {
    {"--max-field-error", kNoBounds},
    {"--max-field-error-rel", kNoBounds},
    {"--field-bounds", kNoBounds},
    {"--feature-ref", "the feature curves are found anew by each rank in each pass and are not gathered"},
    {"--isosurface", "the level sets are embedded by topotet simplify only so far (embed_isosurfaces)"},
    {"--levels", "one target per run: run topotet-mpi once per ratio"},
    {"--hierarchy", "a hierarchy records the collapses of one engine mesh; the ranks' parts are rebuilt every pass"},
    {"--vertex-map", "each rank's map covers its part only (topotet/mpi.h gives it per rank to a library caller); "
                     "one file for the whole mesh is written by topotet simplify, in core or with --memory-limit"},
    {"--no-field-bounds", "it belongs to --hierarchy"},
    {"--levels-error", "it belongs to --hierarchy"},
    {"--progress", "the ranks draw no progress; the report lists every pass at the end"},
    {"--memory-limit", "out of core is topotet simplify --memory-limit (one process); each rank holds its part"},
    {"--scratch", "it belongs to --memory-limit"},
    {"--pieces", "it belongs to --memory-limit"},
    {"--progress-interval", "the ranks draw no progress; the report lists every pass at the end"},
};

// Options that mean a little more, or nothing, here.
struct Note {
  const char* name;
  const char* note;
};
constexpr Note kNotes[] = {
    {"--output", "with --partitioned a .pvtu"},
    {"--format", "not for -: stdin and stdout are not read or written under MPI"},
    {"--ratio", "of the whole mesh's vertices"},
    {"--target-vertices", "over the whole mesh"},
    {"--threads", "per rank"},
    {"--no-verify", "always: topotet-mpi measures nothing; run topotet check IN OUT on the result"},
    {"--no-metrics", "always: topotet-mpi measures nothing; run topotet check IN OUT on the result"},
    {"--json", "passes, times, traffic and memory"},
    {"--verbose", "-v adds the effective options to the report; there is no stage log"},
    {"--binary", "not with --partitioned (its pieces are ASCII .vtu)"},
    {"--extensive", "the cell arrays of a whole input file are remapped on rank 0 onto the gathered output; not with "
                    "--partitioned or a split input"},
    {"--categorical", "the cell arrays of a whole input file are remapped on rank 0 onto the gathered output; not with "
                      "--partitioned or a split input"},
};

void append_to_help(CLI::Option* option, const std::string& text) {
  option->description(option->get_description() + " [topotet-mpi: " + text + "]");
}

}  // namespace

void add_mpi_simplify_command(CLI::App& app, MpiSimplifyArgs& args) {
  CLI::App* cmd = app.add_subcommand("simplify", "Simplify a mesh over the MPI ranks; rank 0 reads IN and writes OUT");
  const SimplifyOptionSet shared = add_simplify_options(cmd, args.simplify);
  shared.input->description(
      "Input mesh (.mesh, .msh, optionally .gz), or a partitioned Gmsh 4.1 mesh with one part per rank (IN with "
      "$PartitionedEntities, or IN_1.msh .. IN_N.msh from gmsh -part N -part_split)");
  for (const Note& n : kNotes) append_to_help(shared.find(n.name), n.note);
  for (const Unavailable& u : kUnavailable) append_to_help(shared.find(u.name), std::string("not available: ") + u.why);
  cmd->add_flag("--partitioned", args.partitioned,
                "Each rank writes its piece: OUT.pvtu and OUT_<rank>.vtu beside it (ParaView), with a global_id "
                "point array");
  cmd->add_option("--max-passes", args.max_passes, "Passes (simplify, then repartition) at most")
      ->check(whole_number_at_least(1))
      ->capture_default_str();
  cmd->add_flag("--count-shares", args.count_shares,
                "Split each pass's target over the ranks by vertex count, without the trial runs that split it by "
                "cost (faster, larger field error)");
}

void check_mpi_simplify_args(const CLI::App& app, const MpiSimplifyArgs& args) {
  const CLI::App* cmd = app.get_subcommand("simplify");
  for (const Unavailable& u : kUnavailable)
    if (cmd->get_option(u.name)->count() > 0) throw InputError(std::string(u.name) + ": not available under MPI: " + u.why);
  const SimplifyArgs& a = args.simplify;
  if (a.input == "-" || a.output == "-")
    throw InputError("-: stdin and stdout are not read or written under MPI (only rank 0 has them); give a file");
  if (args.partitioned && a.binary)
    throw InputError("--binary: --partitioned writes its pieces as ASCII .vtu");
  parse_format(a.format);  // a bad --format fails before reading
  // As topotet simplify does: a typo in -o or --json fails before the run, not after it.
  if (!args.partitioned && !format_for(a.output, a.format)) check_output_format(a.output);
  check_output_folder(a.output);
  check_output_folder(a.report);
}

}  // namespace topotet::cli::mpi
