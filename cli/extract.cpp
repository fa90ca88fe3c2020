// topotet extract H.tth -o OUT [--vertices N | --max-error E | --voi SHAPE --inside-error E1
//                               --outside-error E2 | --levels-error e0,e1,...]
//
//   read the hierarchy -> select the collapses (a prefix, or a VOI selection closed under the
//   dependencies) -> extract the mesh -> write -> check it against the original (topology,
//   inverted tets) and print the time and the extraction speed (output tets per second).
// --levels-error writes one mesh per error threshold (OUT with the threshold before the
// extension, as `simplify --levels` does) and prints one table row per level.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "common.h"
#include "json_report.h"
#include "topotet/error.h"
#include "topotet/hierarchy.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/topology.h"
#include "topotet/threads.h"

namespace topotet::cli {
namespace {

constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;

struct ExtractArgs {
  std::string input, output, format;
  std::optional<std::uint64_t> vertices;
  std::optional<double> max_error;
  std::string voi;
  double inside_error = 0.0;
  double outside_error = std::numeric_limits<double>::infinity();
  std::vector<double> levels_error;
  std::string report;  // --json (with --levels-error): the levels' rows as a JSON report
  std::string voi_closure = "fine";
  bool binary = false;
  bool no_verify = false;
  int threads = 0;
};

void row(const char* key, const std::string& value) { std::fprintf(report_stream(), "%-10s%s\n", key, value.c_str()); }

double per(double a, double b) { return b > 0 ? a / b : 0.0; }

// The largest recorded error bound of the applied collapses (Hierarchy::error_bound), or NaN
// while the bounds are unknown.
double max_error_bound(const Hierarchy& h, const std::vector<std::uint8_t>& applied) {
  double bound = 0.0;
  for (std::size_t i = 0; i < applied.size(); ++i) {
    if (!applied[i]) continue;
    if (std::isnan(h.error_bound[i])) return std::numeric_limits<double>::quiet_NaN();
    bound = std::max(bound, static_cast<double>(h.error_bound[i]));
  }
  return bound;
}

struct Checked {
  bool ok = true;
  std::string differences;
  std::size_t inverted = 0;
  QualityStats quality;
};

Checked check_level(const metrics::TopologyReport& original, const MeshData& level) {
  Checked c;
  c.quality = compute_quality(level);
  c.inverted = c.quality.inverted + c.quality.zero_volume;
  c.ok = metrics::same_topology(original, metrics::compute_topology(level), &c.differences) && c.inverted == 0;
  if (c.inverted != 0) c.differences += "inverted or flat tets: " + std::to_string(c.inverted) + "\n";
  return c;
}

}  // namespace

int print_error_levels(const Hierarchy& h, const std::string& output, std::vector<double> levels,
                       const WriteOptions& write_options, Json* rows) {
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  const MeshData& original = h.original;
  const metrics::TopologyReport original_topology = metrics::compute_topology(original);
  const QualityStats q0 = compute_quality(original);
  auto angles = [](const QualityStats& q) {
    return format_number(q.dihedral_deg.std_dev * kRadiansPerDegree) + " " + format_number(q.solid_sr.std_dev) + " " +
           format_number(q.face_deg.std_dev * kRadiansPerDegree);
  };
  bool all_ok = true;
  std::FILE* out = report_stream();
  std::fprintf(out, "%10s %6s %10s %10s %9s %9s %9s %10s %18s %9s  %s\n", "error", "%vert", "#vert", "#tets", "rms", "max",
               "max@orig", "bound", "dihed/solid/face", "extract", "topology");
  std::fprintf(out, "%10s %6s %10s %10s %9s %9s %9s %10s %18s %9s\n", "0", "100",
               format_count(original.vertex_count()).c_str(), format_count(original.tet_count()).c_str(), "0", "0", "0",
               "0", angles(q0).c_str(), "-");
  for (double e : levels) {
    const std::vector<std::uint8_t> applied = select_error(h, e);
    const Stopwatch clock;
    const MeshData level = extract(h, applied);
    const double seconds = clock.seconds();
    write_mesh_file(level_path(output, e), level, write_options);
    const Checked c = check_level(original_topology, level);
    all_ok = all_ok && c.ok;
    const FieldError f = compare_fields(original, level);
    const double bound = max_error_bound(h, applied);
    const double at_original = f.worst_max_rel_at_original();  // what the bound covers
    char pct[32];
    std::snprintf(pct, sizeof pct, "%.1f", 100.0 * per(static_cast<double>(level.vertex_count()), original.vertex_count()));
    std::fprintf(out, "%10s %6s %10s %10s %9s %9s %9s %10s %18s %9s  %s\n", format_number(e).c_str(), pct,
                 format_count(level.vertex_count()).c_str(), format_count(level.tet_count()).c_str(),
                 format_number(f.worst_rms_rel).c_str(), format_number(f.worst_max_rel).c_str(),
                 format_number(at_original).c_str(),
                 std::isnan(bound) ? "-" : format_number(bound).c_str(), angles(c.quality).c_str(),
                 format_seconds(seconds).c_str(), c.ok ? "PASS" : "FAIL");
    if (!c.ok) std::fprintf(stderr, "level %s: %s", format_number(e).c_str(), c.differences.c_str());
    if (rows != nullptr)
      rows->push_back({{"error", e},
                       {"path", level_path(output, e)},
                       {"vertices", level.vertex_count()},
                       {"vertex_share", per(static_cast<double>(level.vertex_count()), original.vertex_count())},
                       {"tets", level.tet_count()},
                       {"field_rms_rel", f.worst_rms_rel},
                       {"field_max_rel", f.worst_max_rel},
                       {"field_max_rel_at_original", at_original},
                       {"bound", std::isnan(bound) ? Json(nullptr) : Json(bound)},
                       {"extract_seconds", seconds},
                       {"topology", c.ok ? "pass" : "fail"}});
  }
  std::fprintf(out, "(error = the hierarchy's monotone error: the field error bound when it has bounds, else the collapse cost; rms/max field error relative to the range, both directions; "
                    "max@orig = the largest error at the original vertices, which the bound covers; bound = max field "
                    "error bound of the applied collapses, - without bounds; std dev of dihedral and face angles in rad, "
                    "solid angles in sr)\n");
  return all_ok ? kExitOk : kExitCheckFailed;
}

namespace {

int run_extract(const ExtractArgs& args) {
  const int given = (args.vertices ? 1 : 0) + (args.max_error ? 1 : 0) + (args.voi.empty() ? 0 : 1) +
                    (args.levels_error.empty() ? 0 : 1);
  if (given != 1) throw InputError("give exactly one of --vertices, --max-error, --voi, --levels-error");
  if (!args.report.empty() && args.levels_error.empty()) throw InputError("--json is for --levels-error (its table)");
  if (!args.report.empty() && args.report == "-" && args.output == "-")
    throw InputError("-o - and --json -: only one of them can go to stdout");
  std::optional<Voi> voi;
  if (!args.voi.empty()) voi = parse_voi(args.voi);  // bad syntax fails before reading
  parse_format(args.format);
  WriteOptions write_options;
  write_options.binary = args.binary;
  write_options.format = format_for(args.output, args.format);
  if (args.output == "-" || args.report == "-") send_report_to_stderr();
  check_output_folder(args.output);
  int exit_code = kExitOk;
  run_with_thread_limit(args.threads, [&] {
    const Stopwatch read_clock;
    const Hierarchy h = read_hierarchy(args.input);
    const double read_seconds = read_clock.seconds();
    if (!args.levels_error.empty()) {
      Json rows = Json::array();
      exit_code = print_error_levels(h, args.output, args.levels_error, write_options, &rows);
      if (!args.report.empty()) {
        Json j = json_header("extract");
        j["hierarchy"] = {{"file", args.input},
                          {"original_vertices", h.original.vertex_count()},
                          {"original_tets", h.original.tet_count()},
                          {"read_seconds", read_seconds}};
        j["error_levels"] = rows;
        j["checks"] = exit_code == kExitOk ? "pass" : "fail";
        write_json_atomically(args.report, j);
      }
      return;
    }
    const Stopwatch select_clock;
    std::vector<std::uint8_t> applied;
    std::string how;
    if (args.vertices) {
      applied = select_prefix(h, prefix_for_vertices(h, *args.vertices));
      how = "uniform, " + format_count(*args.vertices) + " vertices";
    } else if (args.max_error) {
      applied = select_error(h, *args.max_error);
      how = "uniform, error <= " + format_number(*args.max_error);
    } else {
      const VoiClosure closure = args.voi_closure == "coarse" ? VoiClosure::kReachCoarse : VoiClosure::kKeepFine;
      applied = select_voi(h, *voi, args.inside_error, args.outside_error, closure);
      how = "VOI " + args.voi + ", error <= " + format_number(args.inside_error) + " inside, <= " +
            format_number(args.outside_error) + " outside, closure " + args.voi_closure;
      std::size_t in_voi = 0, above = 0;
      for (std::size_t i = 0; i < applied.size(); ++i)
        if (applied[i] && (voi->contains(h.u_before[i]) || voi->contains(h.v_position[i]) || voi->contains(h.u_after[i]))) {
          ++in_voi;
          above += collapse_error(h, i) > args.inside_error;
        }
      how += " (" + format_count(in_voi) + " applied in the VOI, " + format_count(above) + " of them above the inside error)";
    }
    const double select_seconds = select_clock.seconds();
    const Stopwatch extract_clock;
    const MeshData level = extract(h, applied);
    const double extract_seconds = extract_clock.seconds();
    const Stopwatch write_clock;
    write_mesh_file(args.output, level, write_options);
    const double write_seconds = write_clock.seconds();
    std::size_t applied_count = 0;
    for (std::uint8_t a : applied) applied_count += a;
    Checked checked;
    double check_seconds = 0.0;
    if (!args.no_verify) {
      const Stopwatch check_clock;
      checked = check_level(metrics::compute_topology(h.original), level);
      check_seconds = check_clock.seconds();
      if (!checked.ok) exit_code = kExitCheckFailed;
    }
    if (verbosity() != Verbosity::kQuiet) {
      row("hierarchy", args.input + ": " + format_count(h.original.vertex_count()) + " vertices, " +
                           format_count(h.original.tet_count()) + " tets, " + format_count(h.collapse_count()) +
                           " collapses of error up to " + format_number(h.error.empty() ? 0.0 : h.error.back()) +
                           " (read " + format_seconds(read_seconds) + ")");
      row("level", how + ": " + format_count(applied_count) + " collapses applied (select " +
                       format_seconds(select_seconds) + ")");
      row("output", args.output + ": " + format_count(level.vertex_count()) + " vertices, " +
                        format_count(level.tet_count()) + " tets (write " + format_seconds(write_seconds) + ")");
      row("extract", format_seconds(extract_seconds) + ", " +
                         format_count(static_cast<std::uint64_t>(per(static_cast<double>(level.tet_count()), extract_seconds))) +
                         " output tets/s");
      const double bound = max_error_bound(h, applied);
      if (!std::isnan(bound)) row("bound", "max field error bound " + format_number(bound));
      if (args.no_verify)
        row("topology", "not checked (--no-verify)");
      else
        row("topology", std::string(checked.ok ? "PASS" : "FAIL") + " against the original, inverted tets " +
                            std::to_string(checked.inverted) + " (" + format_seconds(check_seconds) + ")");
    }
    if (!checked.ok) std::fprintf(stderr, "%s", checked.differences.c_str());
  });
  return exit_code;
}

}  // namespace

void add_extract_command(CLI::App& app, CommandRunner& run) {
  auto args = std::make_shared<ExtractArgs>();
  CLI::App* cmd = app.add_subcommand(
      "extract", "Extract a level of detail from a hierarchy file (simplify --hierarchy): uniform by vertex count or "
                 "error, or fine inside a volume of interest and coarse elsewhere");
  cmd->add_option("H", args->input, "Hierarchy file (.tth)")->required();
  cmd->add_option("-o,--output", args->output, "Output mesh (.mesh, .meshb, .msh or .vtu; - = stdout, with --format)")->required();
  cmd->add_option("--format", args->format, "Format of - (stdout) and of paths without a mesh extension: mesh, msh, vtu");
  cmd->add_option("--vertices", args->vertices, "Uniform level: keep this many vertices (or the coarsest level)");
  cmd->add_option("--max-error", args->max_error, "Uniform level: apply every collapse of error <= E (the field error bound relative to the range when the hierarchy has bounds, else the collapse cost)")
      ->check(number_in(0.0, std::numeric_limits<double>::infinity(), false));
  auto* voi = cmd->add_option("--voi", args->voi,
                              "Volume of interest: box:x0,y0,z0,x1,y1,z1 or sphere:x,y,z,r (with --inside-error "
                              "and --outside-error)");
  cmd->add_option("--inside-error", args->inside_error, "Error of the collapses applied in the VOI (default 0: finest)")
      ->needs(voi)
      ->check(number_in(0.0, std::numeric_limits<double>::infinity(), false));
  cmd->add_option("--outside-error", args->outside_error, "Error of the collapses applied outside (default: all)")
      ->needs(voi)
      ->check(number_in(0.0, std::numeric_limits<double>::infinity(), false));
  cmd->add_option("--voi-closure", args->voi_closure,
                  "When a coarse collapse outside needs a fine one inside: fine = leave it out (the VOI stays at "
                  "--inside-error), coarse = apply both (the outside reaches --outside-error)")
      ->needs(voi)
      ->check(CLI::IsMember({"fine", "coarse"}))
      ->capture_default_str();
  cmd->add_option("--levels-error", args->levels_error,
                  "One uniform level per error threshold, written as OUT with the threshold before the extension, "
                  "and a table of their size, field error, quality and topology")
      ->delimiter(',')
      ->check(number_in(0.0, std::numeric_limits<double>::infinity(), false));
  cmd->add_option("--json,--report", args->report,
                  "With --levels-error: write its table as JSON to this file (- = stdout; docs/cli.md, JSON reports)");
  cmd->add_flag("--binary", args->binary, "Binary Gmsh 4.1 / raw appended VTU data");
  cmd->add_flag("--no-verify", args->no_verify, "Skip the topology and inversion check against the original");
  cmd->add_option("--threads", args->threads, "Threads for reading and checking (0 = all cores)")
      ->check(whole_number_at_least(0));
  add_verbosity_flags(cmd);
  cmd->callback([args, &run] { run = [args] { return run_extract(*args); }; });
}

}  // namespace topotet::cli
