// topotet generate NAME --tets N [--seed S] [--cells C] -o OUT: a procedural test mesh
// (topotet/generate.h).
#include <cstdio>
#include <memory>

#include "common.h"
#include "topotet/error.h"
#include "topotet/generate.h"
#include "topotet/io.h"

namespace topotet::cli {
namespace {

struct GenerateArgs {
  std::string family;
  std::uint64_t tets = 100000;
  std::uint64_t seed = 1;
  std::uint32_t cells = 0;
  std::string output;
  bool binary = false;
};

int run_generate(const GenerateArgs& args) {
  check_output_format(args.output);  // an unknown extension fails before the work
  check_output_folder(args.output);
  GenerateOptions options;
  options.family = args.family;
  options.target_tets = args.tets;
  options.seed = args.seed;
  options.cells = args.cells;
  const Stopwatch generate_clock;
  MeshData mesh;
  try {
    mesh = generate_mesh(options);
  } catch (const InputError& e) {
    throw_input_error(args.family, e.what());
  }
  const double generate_seconds = generate_clock.seconds();
  const Stopwatch write_clock;
  WriteOptions write_options;
  write_options.binary = args.binary;
  write_mesh_file(args.output, mesh, write_options);
  std::fprintf(report_stream(), "%s: %s vertices, %s tets, %s triangles, %s edges, %s corners, %zu field%s\n", args.family.c_str(),
              format_count(mesh.vertex_count()).c_str(), format_count(mesh.tet_count()).c_str(),
              format_count(mesh.triangles.size()).c_str(), format_count(mesh.segments.size()).c_str(),
              format_count(mesh.corners.size()).c_str(), mesh.fields.size(), mesh.fields.size() == 1 ? "" : "s");
  std::fprintf(report_stream(), "generated in %s, wrote %s in %s\n", format_seconds(generate_seconds).c_str(), args.output.c_str(),
              format_seconds(write_clock.seconds()).c_str());
  return kExitOk;
}

}  // namespace

void add_generate_command(CLI::App& app, CommandRunner& run) {
  auto args = std::make_shared<GenerateArgs>();
  CLI::App* cmd = app.add_subcommand("generate", "Write a procedural test mesh (deterministic for a given seed).");
  cmd->add_option("NAME", args->family, "Mesh family")->required()->check(CLI::IsMember(generator_families()));
  cmd->add_option("--tets", args->tets, "Approximate number of tets")->capture_default_str();
  cmd->add_option("--seed", args->seed, "Seed of the vertex jitter")->capture_default_str();
  cmd->add_option("--cells", args->cells, "polycrystal: number of cells (materials); 0 = one per ~4000 tets")
      ->capture_default_str();
  cmd->add_option("-o,--output", args->output, "Output file (.mesh, .msh or .vtu)")->required();
  cmd->add_flag("--binary", args->binary, "Binary Gmsh 4.1 / raw appended VTU data");
  add_verbosity_flags(cmd);
  cmd->callback([args, &run] { run = [args] { return run_generate(*args); }; });
}

}  // namespace topotet::cli
