// topotet demo [--tets N] [--threads T] [-o OUT] [--json F]: no input needed. Generates the cube-sphere
// mesh, simplifies it to 10% of its vertices with the parallel engine, verifies the topology and
// prints the report. Writes nothing unless -o is given.
#include <cstdio>
#include <memory>

#include "common.h"
#include "topotet/error.h"
#include "topotet/generate.h"

namespace topotet::cli {
namespace {

struct DemoArgs {
  std::uint64_t tets = 200000;
  int threads = 0;
  std::string output;
  std::string json;
};

int run_demo(const DemoArgs& args) {
  GenerateOptions generate;
  generate.family = "cube-sphere";
  generate.target_tets = args.tets;
  SimplifyJob job;
  job.input_label = "cube-sphere (generated, seed 1)";
  const Stopwatch clock;
  try {
    job.input = generate_mesh(generate);
  } catch (const InputError& e) {
    throw_input_error("demo", e.what());
  }
  job.read_seconds = clock.seconds();
  job.read_verb = "generate";
  job.reload = [generate] { return generate_mesh(generate); };  // deterministic: the same mesh
  std::fprintf(report_stream(), "topotet demo: a cube (material 1) holding a ball (material 2), an open surface patch, a polyline\n"
              "through the ball's surface and 8 pinned corners; simplify to 10%% of the vertices, in parallel.\n\n");
  job.options.target_vertex_ratio = 0.1;
  job.options.engine = Engine::kParallel;
  job.options.num_threads = args.threads;
  job.output_path = args.output;
  job.report_path = args.json;
  job.quiet = verbosity() == Verbosity::kQuiet;
  return run_simplify_job(job);
}

}  // namespace

void add_demo_command(CLI::App& app, CommandRunner& run) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "demo", "Generate a cube-sphere mesh, simplify it to 10% of its vertices in parallel, verify its topology.");
  cmd->add_option("--tets", args->tets, "Tets of the generated mesh")->capture_default_str();
  cmd->add_option("--threads", args->threads, "Threads (0 = all cores)")->check(whole_number_at_least(0))->capture_default_str();
  cmd->add_option("-o,--output", args->output, "Also write the simplified mesh (.mesh, .meshb, .msh or .vtu)");
  cmd->add_option("--json", args->json, "Also write the report as JSON to this file (- = stdout)");
  add_verbosity_flags(cmd);
  cmd->callback([args, &run] { run = [args] { return run_demo(*args); }; });
}

}  // namespace topotet::cli
