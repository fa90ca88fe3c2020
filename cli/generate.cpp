// topotet generate NAME --tets N [--seed S] [--cells C] -o OUT: a procedural test mesh
// (topotet/generate.h).
#include <cstdio>
#include <memory>


#include "common.h"
#include "io/atomic_file.h"
#include "io/formats.h"
#include "topotet/error.h"
#include "topotet/generate.h"
#include "topotet/io.h"
#include "topotet/medit_stream.h"

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

// Writes what generate_streamed sends as MEDIT ASCII through io's streaming writer
// (topotet/medit_stream.h): <stem>.mesh, <stem>.sol (the field "f") and <stem>.sol.fields.txt (its
// name), byte for byte what write_mesh_file writes for the in-memory mesh, all committed together.
class MeditSink final : public GenerateSink {
 public:
  explicit MeditSink(const std::string& path) : out_(path, {VertexField{"f", 1, {}}}) {}
  void begin_vertices(std::uint64_t count) override {
    vertex_count_ = count;
    out_.begin_vertices(count);
  }
  void vertex(const std::array<double, 3>& p, double value) override { out_.vertex(p, 0, &value); }
  void begin_tets(std::uint64_t count) override {
    counts_[0] = count;
    out_.begin_tets(count);
  }
  void tet(const std::array<VertId, 4>& v, std::int32_t material) override { out_.tet(v, material, nullptr); }
  void begin_triangles(std::uint64_t count) override {
    counts_[1] = count;
    out_.begin_triangles(count);
  }
  void triangle(const Triangle& t) override { out_.triangle(t); }
  void begin_segments(std::uint64_t count) override {
    counts_[2] = count;
    out_.begin_segments(count);
  }
  void segment(const Segment& s) override { out_.segment(s); }
  void begin_corners(std::uint64_t count) override {
    counts_[3] = count;
    out_.begin_corners(count);
  }
  void corner(VertId v) override { out_.corner(v); }
  std::uint64_t vertex_count() const { return vertex_count_; }
  std::uint64_t count(int section) const { return counts_[section]; }
  void commit() { out_.commit(); }

 private:
  MeditStreamWriter out_;
  std::uint64_t vertex_count_ = 0;
  std::uint64_t counts_[4] = {};  // tets, triangles, edges, corners
};

// Streams when the output is a plain .mesh file (not a stream or device, which has no folder for
// the .sol): memory then stays bounded whatever the size.
bool streams(const GenerateArgs& args, const GenerateOptions& options) {
  return can_stream(options) && !args.binary && io::iends_with(args.output, ".mesh") && !io::is_direct_output(args.output);
}

int run_generate_streamed(const GenerateArgs& args, const GenerateOptions& options) {
  const Stopwatch clock;
  MeditSink sink(args.output);
  try {
    generate_streamed(options, sink);
  } catch (const InputError& e) {
    throw_input_error(args.family, e.what());
  }
  sink.commit();
  std::fprintf(report_stream(), "%s: %s vertices, %s tets, %s triangles, %s edges, %s corners, 1 field\n", args.family.c_str(),
               format_count(sink.vertex_count()).c_str(), format_count(sink.count(0)).c_str(),
               format_count(sink.count(1)).c_str(), format_count(sink.count(2)).c_str(),
               format_count(sink.count(3)).c_str());
  // Generating and writing are interleaved: the write time is included in the generate time.
  std::fprintf(report_stream(), "generated in %s, wrote %s in %s\n", format_seconds(clock.seconds()).c_str(),
               args.output.c_str(), format_seconds(0.0).c_str());
  return kExitOk;
}

int run_generate(const GenerateArgs& args) {
  check_output_format(args.output);  // an unknown extension fails before the work
  check_output_folder(args.output);
  GenerateOptions options;
  options.family = args.family;
  options.target_tets = args.tets;
  options.seed = args.seed;
  options.cells = args.cells;
  if (streams(args, options)) return run_generate_streamed(args, options);
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
  cmd->add_option("-o,--output", args->output, "Output file (.mesh, .meshb, .msh or .vtu)")->required();
  cmd->add_flag("--binary", args->binary, "Binary Gmsh 4.1 / raw appended VTU data");
  add_verbosity_flags(cmd);
  cmd->callback([args, &run] { run = [args] { return run_generate(*args); }; });
}

}  // namespace topotet::cli
