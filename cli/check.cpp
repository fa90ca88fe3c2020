// topotet check IN OUT [--json FILE] [--fast]: the independent topology checker on two meshes.
// Prints the topology of both, the verdict (exit 1 on any difference), the quality of OUT (whose
// inverted tets must be 0), the Hausdorff distances between their surfaces, per label, and the
// error of the fields both carry.
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>

#include "common.h"
#include "distance_report.h"
#include "json_report.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/topology.h"

namespace topotet::cli {
namespace {

struct CheckArgs {
  std::string before;
  std::string after;
  std::string json_path;
  bool fast = false;
  double sample_spacing_rel = SurfaceDistanceOptions{}.sample_spacing_rel;
  bool has_sample_spacing = false;  // --sample-spacing-rel given: exactly that spacing
  std::string material_array;       // --material-array: for the inputs in a VTK format
};

void print_indented(std::FILE* out, const std::string& text) {
  for (const std::string& line : split_lines(text)) std::fprintf(out, "  %s\n", line.c_str());
}

int run_check(const CheckArgs& args) {
  check_output_folder(args.json_path);
  double read_before = 0.0, read_after = 0.0;
  const auto options_for = [&](const std::string& path) {
    ReadOptions o;
    if (is_vtk_input(path)) o.material_array = args.material_array;
    return o;
  };
  const MeshData before = read_input(args.before, &read_before, options_for(args.before));
  const MeshData after = read_input(args.after, &read_after, options_for(args.after));

  topotet::TopologyOptions options;
  options.fast = args.fast;
  const Stopwatch topology_clock;
  const topotet::TopologyReport before_topology = topotet::compute_topology(before, options);
  const topotet::TopologyReport after_topology = topotet::compute_topology(after, options);
  const double topology_seconds = topology_clock.seconds();
  std::string differences;
  bool ok = topotet::same_topology(before_topology, after_topology, &differences);

  const Stopwatch quality_clock;
  const QualityStats quality = compute_quality(after);
  const double quality_seconds = quality_clock.seconds();
  if (quality.inverted != 0) {
    ok = false;
    differences += "inverted tets (quality check): " + std::to_string(quality.inverted) + "\n";
  }

  std::fprintf(report_stream(), "IN  %s: %s vertices, %s tets (read %s)\n", args.before.c_str(), format_count(before.vertex_count()).c_str(),
              format_count(before.tet_count()).c_str(), format_seconds(read_before).c_str());
  print_indented(report_stream(), topotet::format_topology_table(before_topology));
  std::fprintf(report_stream(), "\nOUT %s: %s vertices, %s tets (read %s)\n", args.after.c_str(), format_count(after.vertex_count()).c_str(),
              format_count(after.tet_count()).c_str(), format_seconds(read_after).c_str());
  print_indented(report_stream(), topotet::format_topology_table(after_topology));
  constexpr double kRad = std::numbers::pi / 180.0;
  std::fprintf(report_stream(), "\nquality   OUT: std dev dihedral %s rad, solid %s sr, face %s rad; min mean ratio %s; inverted %zu, "
              "zero volume %zu (%s)\n",
              format_number(quality.dihedral_deg.std_dev * kRad).c_str(), format_number(quality.solid_sr.std_dev).c_str(),
              format_number(quality.face_deg.std_dev * kRad).c_str(), format_number(quality.mean_ratio.min).c_str(),
              quality.inverted, quality.zero_volume, format_seconds(quality_seconds).c_str());
  std::fprintf(report_stream(), "topology  %s (%s%s)\n", ok ? "PASS" : "FAIL", args.fast ? "fast mode, " : "",
              format_seconds(topology_seconds).c_str());
  if (!ok) {
    // A failed check prints even with -q (on stderr then): it is why the exit code is 1.
    std::FILE* out = verbosity() == Verbosity::kQuiet ? stderr : report_stream();
    if (verbosity() == Verbosity::kQuiet) std::fprintf(out, "topology: FAIL\n");
    print_indented(out, differences);
  }

  const Stopwatch distance_clock;
  // Every label accurate (the table lists them); the spacing is the coarser of 1e-3 x the diagonal
  // and IN's resolution, unless --sample-spacing-rel asks for one.
  SurfaceDistanceOptions distance_options = report_surface_distance_options();
  distance_options.per_label_accuracy = true;
  distance_options.sample_spacing_rel = args.sample_spacing_rel;
  if (args.has_sample_spacing) distance_options.pieces_per_triangle = 0.0;
  const SurfaceDistance distance = surface_distance(before, after, distance_options);
  const double distance_seconds = distance_clock.seconds();
  print_surface_distance(distance, distance_seconds, /*per_label=*/true);
  // Fields both meshes carry (same name and size): the error an out-of-core run, or any run whose
  // report did not measure it, is compared with (topotet simplify reports it in core).
  std::optional<FieldError> fields;
  double field_seconds = 0.0;
  if (!before.fields.empty() && !after.fields.empty()) {
    const Stopwatch field_clock;
    fields = compare_fields(before, after);
    field_seconds = field_clock.seconds();
    // "at IN's vertices": what a field error bound covers (simplify --max-field-error, in core and out).
    std::fprintf(report_stream(), "fields    rms %s, max %s, max at IN's vertices %s (relative to the range, worst of %zu components; %s)\n",
                 format_number(fields->worst_rms_rel).c_str(), format_number(fields->worst_max_rel).c_str(),
                 format_number(fields->worst_max_rel_at_original()).c_str(), fields->components.size(),
                 format_seconds(field_seconds).c_str());
  }

  if (!args.json_path.empty()) {
    Json j = json_header("check");
    Json in = mesh_json(args.before, before, read_before);
    in["topology_report"] = topology_report_json(before_topology);
    Json out = mesh_json(args.after, after, read_after);
    out["topology_report"] = topology_report_json(after_topology);
    out["quality"] = quality_json(quality);
    out["quality_seconds"] = quality_seconds;
    j["before"] = in;
    j["after"] = out;
    j["fast"] = args.fast;
    j["topology"] = ok ? "pass" : "fail";
    j["topology_differences"] = split_lines(differences);
    j["topology_seconds"] = topology_seconds;  // both meshes' topology and the comparison
    j["surface_distance"] = surface_distance_json(distance);
    j["surface_distance_seconds"] = distance_seconds;
    if (fields) {
      j["field_error"] = {{"rms_rel", fields->worst_rms_rel},
                          {"max_rel", fields->worst_max_rel},
                          {"max_rel_at_input_vertices", fields->worst_max_rel_at_original()}};
      j["field_error_seconds"] = field_seconds;
    }
    write_json_atomically(args.json_path, j);
  }
  return ok ? kExitOk : kExitCheckFailed;
}

}  // namespace

void add_check_command(CLI::App& app, CommandRunner& run) {
  auto args = std::make_shared<CheckArgs>();
  CLI::App* cmd = app.add_subcommand(
      "check", "Compare the topology of two meshes (Betti numbers of the mesh and of every substructure) and check "
               "OUT's tets (exit 1 on any difference or inverted tet).");
  cmd->add_option("IN", args->before, "Original mesh")->required();
  cmd->add_option("OUT", args->after, "Simplified mesh")->required();
  cmd->add_option("--json", args->json_path, "Also write both reports and the verdict as JSON");
  add_verbosity_flags(cmd);
  cmd->add_flag("--fast", args->fast, "Euler characteristics and components only (for huge meshes)");
  cmd->add_option("--material-array", args->material_array,
                  std::string(kMaterialArrayHelp) + " (for IN and OUT when they are in a VTK format)");
  cmd->add_option("--sample-spacing-rel", args->sample_spacing_rel,
                  "Surface distance: finest sampling, relative to the bounding box diagonal (error <= it / sqrt(3)); "
                  "by default the coarser of this and IN's surface resolution")
      ->check(CLI::PositiveNumber)
      ->capture_default_str()
      ->each([args](const std::string&) { args->has_sample_spacing = true; });
  cmd->callback([args, &run] { run = [args] { return run_check(*args); }; });
}

}  // namespace topotet::cli
