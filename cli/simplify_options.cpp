#include "simplify_options.h"

#include <cmath>
#include <cstdlib>
#include <limits>

#include "common.h"

namespace topotet::cli {
namespace {

// "NAME=W" with a non-empty NAME and W a finite number >= 0 (split at the last '=': a field name
// may contain one). Returns the CLI11 validator's message, empty when the value is fine.
std::string field_weight_syntax(const std::string& value, std::string* name = nullptr, double* weight = nullptr) {
  const std::size_t eq = value.rfind('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == value.size()) return "expected NAME=W, got '" + value + "'";
  char* end = nullptr;
  const double w = std::strtod(value.c_str() + eq + 1, &end);
  if (*end != '\0' || !std::isfinite(w) || w < 0.0) return "the weight in '" + value + "' must be a number >= 0";
  if (name) *name = value.substr(0, eq);
  if (weight) *weight = w;
  return {};
}

}  // namespace

CLI::Option* SimplifyOptionSet::find(const std::string& long_name) const {
  for (CLI::Option* option : all)
    if (option->check_lname(long_name.substr(2))) return option;
  return nullptr;
}

SimplifyOptionSet add_simplify_options(CLI::App* cmd, SimplifyArgs& args) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  SimplifyOptionSet set;
  const auto keep = [&set](CLI::Option* option) {
    set.all.push_back(option);
    return option;
  };
  set.input = cmd->add_option("IN", args.input, "Input mesh (.mesh, .meshb, .msh, optionally .gz; - = stdin, with --format)")
                  ->required();
  set.output = keep(cmd->add_option("-o,--output", args.output,
                                    "Output mesh (.mesh, .meshb, .msh or .vtu; - = stdout, with --format)")
                        ->required());
  keep(cmd->add_option("--format", args.format,
                       "Format of - (stdin/stdout) and of paths without a mesh extension (/dev/null, a FIFO): mesh, "
                       "msh, vtu"));
  auto* ratio = keep(cmd->add_option("--ratio", args.ratio, "Keep this fraction of the vertices, in (0, 1]")
                         ->check(number_in(0.0, 1.0, true))
                         ->capture_default_str());
  auto* target = keep(cmd->add_option("--target-vertices", args.target_vertices, "Stop at this many vertices"));
  keep(cmd->add_option("--max-cost,--max-error", args.max_cost,
                       "Stop when the cheapest collapse costs more (quadric error / bbox diagonal^2; 0 = no limit)")
           ->check(number_in(0.0, kInfinity, false))
           ->capture_default_str());
  const auto quality_given = [&args](const std::string&) { args.quality_given = true; };
  const auto tolerance_given = [&args](const std::string&) { args.tolerance_given = true; };
  keep(cmd->add_option("--min-quality", args.min_quality,
                       "Reject collapses creating tets below this mean ratio (given: a hard limit; by default it "
                       "halves, with --min-dihedral, where it would stop the run before its target)")
           ->check(number_in(0.0, 1.0, false))
           ->each(quality_given)
           ->capture_default_str());
  keep(cmd->add_option("--min-dihedral", args.min_dihedral,
                       "Reject collapses and optimisation steps creating tets with a dihedral angle below this "
                       "(degrees; or above 180 minus it), unless the tets they replace were already worse; 0 = no floor")
           ->check(number_in(0.0, 60.0, false))
           ->each(quality_given)
           ->capture_default_str());
  keep(cmd->add_option("--size-weight", args.size_weight,
                       "Weight W of the edge size in the ranking of collapses: short edges go first where the error "
                       "is small, so sizes even out (flat surfaces coarsen too); about a relative field error of "
                       "sqrt(W); 0 = rank by the error alone; auto = " + format_number(kAutoSizeWeight) +
                           " when no field steers the cost, else 0")
           ->type_name("auto|W")
           ->check([](const std::string& value) {
             std::string text = value;
             return value == "auto" ? std::string() : number_in(0.0, kInfinity, false)(text);
           })
           ->capture_default_str());
  auto* tolerance = keep(cmd->add_option("--tolerance", args.tolerance,
                                         "Keep boundary, interfaces, surfaces and polylines within this distance of "
                                         "the original ones (mesh units; 0 = unchecked; default: --tolerance-rel)")
                             ->check(number_in(0.0, kInfinity, false))
                             ->each(tolerance_given));
  keep(cmd->add_option("--tolerance-rel", args.tolerance_rel,
                       "The same, relative to the bounding box diagonal (0 = unchecked). Given (either): a hard "
                       "limit; by default H doubles where it would stop the run before its target, and the report "
                       "gives the H that holds")
           ->check(number_in(0.0, kInfinity, false))
           ->excludes(tolerance)
           ->each(tolerance_given)
           ->capture_default_str());
  keep(cmd->add_flag("--hard-limits", args.hard_limits,
                     "Keep the default tolerance, quality floors and feature curves as they are even when they stop "
                     "the run before its target (the report then says what held the vertices left)"));
  auto* max_field_error =
      keep(cmd->add_option("--max-field-error", args.max_field_error,
                           "Refuse collapses that would let the field error at an original vertex exceed E (field "
                           "units, every component; a per-tet bound kept exact through the run); 0 = no limit")
               ->type_name("E")
               ->check(number_in(0.0, kInfinity, false)));
  auto* max_field_error_rel =
      keep(cmd->add_option("--max-field-error-rel", args.max_field_error_rel,
                           "The same, relative to each field component's range (both given: the smaller)")
               ->type_name("E")
               ->check(number_in(0.0, kInfinity, false)));
  keep(cmd->add_option("--field-bound-mode", args.field_bound_mode,
                       "What the field error bound covers: the original vertices (exact there), or every point of "
                       "the input the output covers (paper 003's rule; needs a limit, and keeps a curved boundary "
                       "from moving)")
           ->check(CLI::IsMember({"vertices", "everywhere"}))
           ->capture_default_str());
  auto* field_bounds = keep(cmd->add_flag("--field-bounds", args.field_bounds,
                                          "Keep the per-tet field error bounds and report them, without a limit"));
  keep(cmd->add_option("--feature-angle", args.feature_angle,
                       "Keep as feature curves (like polylines) the surface edges whose faces turn by more than this "
                       "angle in degrees, and pin their corners; 180 = off. Given: kept; by default they are dropped "
                       "where their corners would stop the run before its target")
           ->check(CLI::Range(0.0, 180.0))
           ->each([&args](const std::string&) { args.features_given = true; })
           ->capture_default_str());
  keep(cmd->add_option("--feature-ref", args.feature_ref,
                       "Also write the detected feature curves as edges (MEDIT ridges) with this ref, their corners "
                       "as corners (to inspect them)"));
  keep(cmd->add_option("--optimize", args.optimize,
                       "After the collapses, move the interior vertices of badly shaped tets (and those inside flat sheets, in their plane) to better places: "
                       "none, light (tets below mean ratio 0.4: 4 smoothing passes, then face and edge flips) or full "
                       "(6 rounds of 2 smoothing passes and the flips; more field error)")
           ->check(CLI::IsMember({"none", "light", "full"}))
           ->capture_default_str());
  keep(cmd->add_flag("--sequential", args.sequential, "Use the sequential reference engine (lazy priority queue)"));
  keep(cmd->add_option("--threads", args.threads, "Threads (0 = all cores; the output is the same for every value)")
           ->check(whole_number_at_least(0))
           ->capture_default_str());
  keep(cmd->add_option("--round-fraction", args.round_fraction,
                       "Parallel engine: about this fraction of the proposals, the cheapest legal ones, compete in one round (the share grows where the cheapest fail their check)")
           ->check(number_in(0.0, 1.0, true))
           ->capture_default_str());
  keep(cmd->add_option("--field-weight", args.field_weights,
                       "Weight W of field NAME in the cost (repeatable; fields not given weigh 1; 0 = carried but not "
                       "preserved); errors are relative to each field's range")
           ->type_name("NAME=W")
           ->expected(1)
           ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
           ->check([](const std::string& value) { return field_weight_syntax(value); }));
  keep(cmd->add_option("--extensive", args.extensive,
                       "Cell array NAME holds amounts per tet (mass, heat): the output's tets share them out so that "
                       "the sum is conserved (repeatable; other real arrays are averaged by volume)")
           ->type_name("NAME")
           ->expected(1)
           ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll));
  keep(cmd->add_option("--categorical", args.categorical,
                       "Cell array NAME holds labels although the file stores reals (.sol, .msh, Exodus): each output "
                       "tet takes the value of the largest part of its volume (repeatable; integer arrays already are)")
           ->type_name("NAME")
           ->expected(1)
           ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll));
  keep(cmd->add_option("--isosurface", args.isosurfaces,
                       "Keep the topology of the level set FIELD=VALUE (repeatable; several values by commas; "
                       "name:C for component C): the tets it crosses are split so that it becomes a listed surface "
                       "(ref above the input's, named iso:FIELD=VALUE), and its vertices keep the value exactly")
           ->type_name("FIELD=VALUE[,VALUE...]")
           ->expected(1)
           ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
           ->check([](const std::string& value) {
             std::vector<IsoLevel> levels;
             return parse_isosurface_spec(value, levels);
           }));
  keep(cmd->add_option("--json,--report", args.report, "Write the report as JSON to this file (- = stdout)"));
  keep(cmd->add_flag("--no-verify", args.no_verify,
                     "Skip the topology checker (quality, field error and distance are still measured)"));
  keep(cmd->add_flag("--no-metrics", args.no_metrics,
                     "Skip every measurement (quality, field error, Hausdorff distance, topology): report only "
                     "counts, times and memory"));
  auto* levels = keep(cmd->add_option("--levels", args.levels,
                                      "Simplify successively to each vertex ratio, writing OUT with the ratio before "
                                      "the extension (out_0.3.mesh), one table row per level")
                          ->delimiter(','));
  levels->excludes(ratio)->excludes(target);
  // Each level simplifies the previous one's output: its bounds would be against that, not the input.
  for (CLI::Option* bounds_option : {max_field_error, max_field_error_rel, field_bounds}) levels->excludes(bounds_option);
  auto* hierarchy = keep(cmd->add_option("--hierarchy", args.hierarchy,
                                         "Also record every collapse into this hierarchy file (.tth): `topotet "
                                         "extract` then gives any level, uniform or fine in a volume of interest; "
                                         "with fields, each collapse's field error bound too (levels by a guaranteed "
                                         "error); out of core too, recorded on disk")
                             ->excludes(levels));
  keep(cmd->add_option("--vertex-map", args.vertex_map,
                       "Also write, for every input vertex in input order, the 0-based index of the output vertex it "
                       "became or merged into (-1: used by no tet), to transfer vertex data: FILE.npy (NumPy int64) "
                       "or FILE.txt (one per line); in core and out of core")
           ->excludes(levels)
           ->excludes(hierarchy));
  keep(cmd->add_flag("--no-field-bounds", args.no_field_bounds,
                     "With --hierarchy: record no field error bounds (recording then costs a few percent instead of "
                     "~20%; levels by error use the collapse cost)")
           ->needs(hierarchy)
           ->excludes(field_bounds));
  keep(cmd->add_option("--levels-error", args.levels_error,
                       "With --hierarchy: also extract one uniform level per error threshold from it, written as OUT "
                       "with the threshold before the extension, with a table (the columns of --levels, the field "
                       "error and its bound)")
           ->delimiter(',')
           ->check(number_in(0.0, kInfinity, false))
           ->excludes(levels));
  ratio->excludes(target);
  add_verbosity_flags(cmd);
  keep(cmd->get_option("--verbose"));
  keep(cmd->get_option("--quiet"));
  keep(cmd->add_option("--progress", args.progress,
                       "auto (a bar when stderr is a terminal), bar, lines (one line every --progress-interval "
                       "seconds, for batch logs) or none")
           ->check(CLI::IsMember({"auto", "bar", "lines", "none"}))
           ->capture_default_str());
  keep(cmd->add_option("--progress-interval", args.progress_interval, "Seconds between --progress lines")
           ->check(CLI::PositiveNumber)
           ->capture_default_str());
  keep(cmd->add_flag("--binary", args.binary, "Binary Gmsh 4.1 / raw appended VTU data"));
  keep(cmd->add_flag("--msh22", args.msh22, "Write .msh as Gmsh 2.2 ASCII (for tools that read only the old format)")
           ->excludes("--binary"));
  keep(cmd->add_flag("--tets-only", args.tets_only,
                     "Leave hexahedra, prisms and pyramids out of a mixed mesh (with a warning and their count) "
                     "instead of refusing it"));
  keep(cmd->add_option("--material-array", args.material_array, kMaterialArrayHelp));
  // Out of core (topotet/out_of_core.h): what it cannot do is excluded here, before any reading.
  auto* memory_limit = keep(cmd->add_option("--memory-limit", args.memory_limit,
                                            "Simplify out of core, keeping the peak memory under SIZE (2G, 256M, ...): "
                                            "the input (MEDIT .mesh / .meshb with its .sol / .solb, or Gmsh MSH "
                                            "4.1 .msh with its fields; also .gz) is streamed and cut into pieces kept in "
                                            "a scratch folder, simplified with frozen borders and merged pairwise (the "
                                            "report says what was left apart)"));
  auto* scratch = keep(cmd->add_option("--scratch", args.scratch,
                                       "Out of core: the folder in which the scratch folder is made (default: OUT's "
                                       "folder); it is removed at the end, on failure and on SIGINT/SIGTERM"));
  auto* pieces = keep(cmd->add_option("--pieces", args.pieces,
                                      "Out of core in exactly N pieces (a power of two), whatever the limit (tests, "
                                      "benchmarks); without --memory-limit nothing limits the merges")
                          ->check(CLI::Range(1u, 4096u)));
  auto* piece_tets = keep(cmd->add_option("--piece-tets", args.piece_tets,
                                          "Out of core with pieces of at most N tets, at the cut and in every merge, "
                                          "whatever the limit allows (tests, benchmarks: what a small limit does on a "
                                          "small mesh)")
                              ->check(CLI::Range(std::uint64_t{1}, std::numeric_limits<std::uint64_t>::max())));
  for (CLI::Option* out_of_core : {memory_limit, pieces, piece_tets})
    for (const char* not_out_of_core : {"--levels", "--levels-error", "--isosurface", "--feature-ref"})
      out_of_core->excludes(not_out_of_core);
  scratch->check(CLI::ExistingDirectory);
  return set;
}

SimplifyOptions engine_options(const SimplifyArgs& args) {
  SimplifyOptions o;
  o.target_vertex_ratio = args.ratio;
  o.target_vertices = args.target_vertices;
  o.max_cost = args.max_cost;
  o.min_quality = args.min_quality;
  o.min_dihedral = args.min_dihedral;
  o.size_weight = args.size_weight == "auto" ? kSizeWeightAuto : std::stod(args.size_weight);  // checked when parsing
  if (args.tolerance >= 0.0) {
    o.tolerance = args.tolerance;
    o.tolerance_rel = 0.0;  // --tolerance 0 turns the check off
  } else {
    o.tolerance_rel = args.tolerance_rel;
  }
  o.relax_tolerance = !args.hard_limits && !args.tolerance_given;
  o.relax_quality = !args.hard_limits && !args.quality_given;
  // --feature-ref writes the feature curves to the output: they stay to the end then.
  o.relax_features = !args.hard_limits && !args.features_given && !args.feature_ref;
  o.max_field_error = args.max_field_error;
  o.max_field_error_rel = args.max_field_error_rel;
  o.field_bound_mode = args.field_bound_mode == "everywhere" ? FieldBoundMode::kEverywhere : FieldBoundMode::kVertices;
  o.track_field_bounds = args.field_bounds;
  o.feature_angle = args.feature_angle;
  o.engine = args.sequential ? Engine::kSequential : Engine::kParallel;
  o.optimize = args.optimize == "none" ? Optimize::kNone : (args.optimize == "full" ? Optimize::kFull : Optimize::kLight);
  o.num_threads = args.threads;
  o.round_fraction = args.round_fraction;
  for (const std::string& entry : args.field_weights) {
    std::string name;
    double weight = 1.0;
    field_weight_syntax(entry, &name, &weight);  // checked when parsing
    o.field_weights[name] = weight;              // the last one given wins
  }
  for (const std::string& spec : args.isosurfaces) parse_isosurface_spec(spec, o.isosurfaces);  // checked when parsing
  return o;
}

std::string options_text(const SimplifyOptions& o, const std::vector<double>& levels) {
  std::string s;
  if (!levels.empty()) {
    s = "levels";
    for (double l : levels) s += " " + format_ratio(l);
  } else if (o.target_vertices) {
    s = "target " + format_count(o.target_vertices) + " vertices";
  } else {
    s = "ratio " + format_number(o.target_vertex_ratio);
  }
  if (o.max_cost > 0) s += ", max cost " + format_number(o.max_cost);
  s += ", min quality " + format_number(o.min_quality);
  if (o.min_dihedral > 0) s += ", min dihedral " + format_number(o.min_dihedral);
  s += o.size_weight < 0 ? std::string(", size weight auto")
       : o.size_weight > 0 ? ", size weight " + format_number(o.size_weight) : std::string(", error only");
  s += o.tolerance > 0 ? ", tolerance " + format_number(o.tolerance)
       : o.tolerance_rel > 0 ? ", tolerance " + format_number(100.0 * o.tolerance_rel) + "% of the diagonal"
                             : std::string(", no tolerance");
  const bool tolerance_relaxes = o.relax_tolerance && (o.tolerance > 0 || o.tolerance_rel > 0);
  std::string relaxing;
  for (const auto& [on, name] : {std::pair{tolerance_relaxes, "tolerance"}, std::pair{o.relax_quality, "quality floors"},
                                 std::pair{o.relax_features && o.feature_angle < 180.0, "features"}})
    if (on) relaxing += std::string(relaxing.empty() ? "" : ", ") + name;
  s += relaxing.empty() ? std::string(", hard limits") : ", relaxed to reach the target: " + relaxing;
  s += o.feature_angle < 180.0 ? ", feature angle " + format_number(o.feature_angle) : std::string(", no features");
  if (o.engine == Engine::kParallel) s += ", round fraction " + format_number(o.round_fraction);
  s += std::string(", optimize ") + to_string(o.optimize);
  s += ", boundary weight " + format_number(o.boundary_weight) + ", polyline weight " + format_number(o.polyline_weight);
  for (const auto& [name, weight] : o.field_weights) s += ", weight of " + name + " " + format_number(weight);
  for (const IsoLevel& l : o.isosurfaces) s += ", isosurface " + l.field + (l.component ? ":" + std::to_string(l.component) : "") + "=" + format_number(l.value);
  return s;
}

}  // namespace topotet::cli
