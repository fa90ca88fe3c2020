// topotet convert IN OUT [--binary] [--validate]: change the file format (chosen by extension).
// Converting does not need the working model; --validate builds it first and refuses bad input.
#include <cstdio>
#include <memory>
#include <optional>

#include "common.h"
#include "topotet/error.h"
#include "topotet/features.h"
#include "topotet/io.h"
#include "topotet/simplify.h"

namespace topotet::cli {
namespace {

struct ConvertArgs {
  std::string input;
  std::string output;
  bool binary = false;
  bool validate = false;
  bool tets_only = false;
  std::string material_array;
  bool msh22 = false;
  std::string format;
  std::optional<std::int32_t> feature_ref;
  double feature_angle = SimplifyOptions{}.feature_angle;
};

int run_convert(const ConvertArgs& args) {
  parse_format(args.format);  // a bad --format fails before reading
  const std::optional<MeshFormat> output_format = format_for(args.output, args.format);
  if (args.output == "-") {
    send_report_to_stderr();
    if (!output_format) throw InputError("-: the output format must be given (--format mesh, msh or vtu)");
  } else if (!output_format) {
    check_output_format(args.output);  // an unknown output extension fails before reading
  }
  check_output_folder(args.output);
  double read_seconds = 0.0, build_seconds = 0.0;
  ReadOptions read_options;
  read_options.tets_only = args.tets_only;
  read_options.material_array = args.material_array;
  read_options.format = format_for(args.input, args.format);
  MeshData mesh = read_input(args.input, &read_seconds, read_options);
  std::string features_text;
  if (args.feature_ref) {
    // The model renumbers nothing but drops unreferenced vertices: the features come with its
    // own export of the whole mesh.
    TetMesh model = build_input(args.input, mesh, &build_seconds);
    const FeatureStats found = detect_features(model, args.feature_angle, feature_scale(model, SimplifyOptions{}));
    MeshExportOptions export_options;
    export_options.feature_edges = true;
    export_options.feature_ref = *args.feature_ref;
    std::vector<CellField> cells = std::move(mesh.cell_fields);
    const std::size_t tets = mesh.tet_count();
    mesh = model.to_mesh_data(export_options);
    if (mesh.tet_count() == tets) mesh.cell_fields = std::move(cells);  // the model keeps the tets and their order
    features_text = ", features: " + format_count(found.edges) + " sharp edges (ref " +
                    std::to_string(*args.feature_ref) + "), " + format_count(found.corners) + " corners";
  } else if (args.validate) {
    build_input(args.input, mesh, &build_seconds);
  }
  const Stopwatch write_clock;
  WriteOptions options;
  options.binary = args.binary;
  options.msh22 = args.msh22;
  options.format = output_format;
  write_mesh_file(args.output, mesh, options);
  const double write_seconds = write_clock.seconds();
  std::fprintf(report_stream(), "%s -> %s: %s vertices, %s tets, %s triangles, %s edges, %zu field%s, %zu cell array%s\n",
              args.input.c_str(), args.output.c_str(), format_count(mesh.vertex_count()).c_str(),
              format_count(mesh.tet_count()).c_str(), format_count(mesh.triangles.size()).c_str(),
              format_count(mesh.segments.size()).c_str(), mesh.fields.size(), mesh.fields.size() == 1 ? "" : "s",
              mesh.cell_fields.size(), mesh.cell_fields.size() == 1 ? "" : "s");
  std::fprintf(report_stream(), "read %s, %swrite %s%s\n", format_seconds(read_seconds).c_str(),
               args.validate || args.feature_ref ? ("validated " + format_seconds(build_seconds) + ", ").c_str() : "",
               format_seconds(write_seconds).c_str(), features_text.c_str());
  return kExitOk;
}

}  // namespace

void add_convert_command(CLI::App& app, CommandRunner& run) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* cmd = app.add_subcommand(
      "convert", "Convert between formats by extension: read .mesh/.msh (+ .gz), write .mesh/.msh/.vtu.");
  cmd->add_option("IN", args->input, "Input mesh")->required();
  cmd->add_option("OUT", args->output, "Output mesh")->required();
  cmd->add_flag("--binary", args->binary, "Binary Gmsh 4.1 / raw appended VTU data");
  add_verbosity_flags(cmd);
  cmd->add_flag("--validate", args->validate, "Build the model first: refuse invalid meshes (exit 2)");
  cmd->add_option("--format", args->format, "Format of the - paths (stdin, stdout): mesh, msh or vtu");
  cmd->add_flag("--msh22", args->msh22, "Write .msh as Gmsh 2.2 ASCII (for tools that read only the old format)")
      ->excludes("--binary");
  cmd->add_flag("--tets-only", args->tets_only, "Leave hexahedra, prisms and pyramids out of a mixed mesh (with a warning and their count) instead of refusing it");
  cmd->add_option("--material-array", args->material_array, kMaterialArrayHelp);
  cmd->add_option("--features", args->feature_ref,
                  "Validate, detect the sharp edges and corners simplify keeps, and write them as edges (MEDIT "
                  "ridges) with this ref and as corners");
  cmd->add_option("--feature-angle", args->feature_angle, "With --features: the angle in degrees (180 = off)")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  cmd->callback([args, &run] { run = [args] { return run_convert(*args); }; });
}

}  // namespace topotet::cli
