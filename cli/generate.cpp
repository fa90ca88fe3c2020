// topotet generate NAME --tets N [--seed S] [--cells C] -o OUT: a procedural test mesh
// (topotet/generate.h).
#include <cstdio>
#include <memory>

#include <filesystem>

#include "common.h"
#include "io/atomic_file.h"
#include "io/formats.h"
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

// Writes what generate_streamed sends as MEDIT ASCII: <stem>.mesh, <stem>.sol (the field "f") and
// <stem>.sol.fields.txt (its name), byte for byte what write_mesh_file writes for the in-memory
// mesh (io/medit.cpp), all three committed together at the end (io/atomic_file.h).
class MeditSink final : public GenerateSink {
 public:
  MeditSink(const std::string& path, const std::string& stem)
      : stem_(stem), mesh_(path), sol_(stem + ".sol"), names_(stem + ".sol.fields.txt") {}
  void begin_vertices(std::uint64_t count) override {
    vertex_count_ = count;
    mesh_.put("MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n");
    mesh_.put_int(count);
    mesh_.put('\n');
    sol_.put("MeshVersionFormatted 2\n\nDimension 3\n\nSolAtVertices\n");
    sol_.put_int(count);
    sol_.put("\n1 1\n\n");
  }
  void vertex(const std::array<double, 3>& p, double value) override {
    mesh_.put_double(p[0]);
    mesh_.put(' ');
    mesh_.put_double(p[1]);
    mesh_.put(' ');
    mesh_.put_double(p[2]);
    mesh_.put(" 0\n");
    sol_.put_double(value);
    sol_.put('\n');
  }
  void begin_tets(std::uint64_t count) override { begin("Tetrahedra", count); }
  void tet(const std::array<VertId, 4>& v, std::int32_t material) override { entry(v.data(), 4, material); }
  void begin_triangles(std::uint64_t count) override { begin("Triangles", count); }
  void triangle(const Triangle& t) override { entry(t.v.data(), 3, t.ref); }
  void begin_segments(std::uint64_t count) override { begin("Edges", count); }
  void segment(const Segment& s) override { entry(s.v.data(), 2, s.ref); }
  void begin_corners(std::uint64_t count) override { begin("Corners", count); }
  void corner(VertId v) override {
    mesh_.put_int(std::uint64_t{v} + 1);
    mesh_.put('\n');
  }
  std::uint64_t vertex_count() const { return vertex_count_; }
  std::uint64_t count(int section) const { return counts_[section]; }
  void commit() {
    mesh_.put("\nEnd\n");
    sol_.put("\nEnd\n");
    names_.put("columns of SolAtVertices in order: f\n");
    io::commit_all({&sol_, &names_, &mesh_});
    std::error_code ec;
    std::filesystem::remove(stem_ + ".sol.gz", ec);  // a stale companion would be read with the new mesh
  }

 private:
  // Sections with no entries are left out, as write_medit does.
  void begin(const char* name, std::uint64_t count) {
    counts_[section_++] = count;
    if (count == 0) return;
    mesh_.put("\n");
    mesh_.put(name);
    mesh_.put('\n');
    mesh_.put_int(count);
    mesh_.put('\n');
  }
  void entry(const VertId* v, int n, std::int32_t ref) {
    for (int k = 0; k < n; ++k) {
      mesh_.put_int(std::uint64_t{v[k]} + 1);
      mesh_.put(' ');
    }
    mesh_.put_int(ref);
    mesh_.put('\n');
  }

  std::string stem_;
  io::AtomicFile mesh_, sol_, names_;
  std::uint64_t vertex_count_ = 0;
  std::uint64_t counts_[4] = {};  // tets, triangles, edges, corners
  int section_ = 0;
};

// Streams when the output is a plain .mesh file (not a stream or device, which has no folder for
// the .sol): memory then stays bounded whatever the size.
bool streams(const GenerateArgs& args, const GenerateOptions& options) {
  return can_stream(options) && !args.binary && io::iends_with(args.output, ".mesh") && !io::is_direct_output(args.output);
}

int run_generate_streamed(const GenerateArgs& args, const GenerateOptions& options) {
  const Stopwatch clock;
  const std::string stem = args.output.substr(0, args.output.size() - 5);
  MeditSink sink(args.output, stem);
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
  cmd->add_option("-o,--output", args->output, "Output file (.mesh, .msh or .vtu)")->required();
  cmd->add_flag("--binary", args->binary, "Binary Gmsh 4.1 / raw appended VTU data");
  add_verbosity_flags(cmd);
  cmd->callback([args, &run] { run = [args] { return run_generate(*args); }; });
}

}  // namespace topotet::cli
