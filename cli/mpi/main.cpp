// topotet-mpi: the distributed simplifier on a mesh file.
//   mpirun -np 4 topotet-mpi simplify in.mesh -o out.mesh --ratio 0.1
// Rank 0 reads IN, checks it (the mesh builder, as `topotet simplify` does), and METIS spreads it
// over the ranks, or each rank reads its part of a partitioned Gmsh mesh (read_input.h);
// topotet::mpi::simplify runs the passes; rank 0 gathers the result and writes OUT, or with
// --partitioned every rank writes its piece (topotet::mpi::write_partitioned). The options are
// those of `topotet simplify` that steer the engine (the measurements and reports of `topotet
// simplify` run on one node: use `topotet check IN OUT` on the result).
#include <chrono>
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "topotet/error.h"
#include "topotet/io.h"
#include "topotet/mpi.h"
#include "read_input.h"

namespace {

struct Args {
  std::string input, output, report;
  double ratio = 0.25;
  std::uint64_t target_vertices = 0;
  double max_cost = 0.0, min_quality = 0.05, tolerance = 0.0, tolerance_rel = topotet::kDefaultToleranceRel;
  double feature_angle = 45.0, round_fraction = 0.015;
  int threads = 0, max_passes = 8;
  bool sequential = false, quiet = false, partitioned = false, count_shares = false;
};

bool ends_with_pvtu(const std::string& path) {
  return path.size() >= 5 && (path.compare(path.size() - 5, 5, ".pvtu") == 0 || path.compare(path.size() - 5, 5, ".PVTU") == 0);
}

int run(MPI_Comm comm, const Args& args) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  // Every rank has the same arguments: each finds this alone, before any work.
  if (args.partitioned && !ends_with_pvtu(args.output)) {
    if (rank == 0)
      std::fprintf(stderr, "topotet-mpi: error: %s: --partitioned writes a .pvtu (and one .vtu per rank beside it)\n",
                   args.output.c_str());
    return 2;
  }
  // Read and distributed together (a partitioned Gmsh input is read where its parts go).
  topotet::mpi::cli::Input input = topotet::mpi::cli::read_input(comm, args.input, 1);
  topotet::mpi::DistributedMesh& mesh = input.part;
  const std::uint64_t input_tets = input.tets;
  const double read_seconds = seconds();

  topotet::mpi::Options options;
  topotet::SimplifyOptions& o = options.simplify;
  o.target_vertex_ratio = args.ratio;
  o.target_vertices = args.target_vertices;
  o.max_cost = args.max_cost;
  o.min_quality = args.min_quality;
  o.tolerance = args.tolerance;
  o.tolerance_rel = args.tolerance_rel;
  o.feature_angle = args.feature_angle;
  o.round_fraction = args.round_fraction;
  o.num_threads = args.threads;
  o.engine = args.sequential ? topotet::Engine::kSequential : topotet::Engine::kParallel;
  options.max_passes = args.max_passes;
  options.shares_by_cost = !args.count_shares;
  const topotet::mpi::Result result = topotet::mpi::simplify(comm, mesh, options);
  const double gather_start = seconds();
  // --partitioned: each rank writes its piece; else rank 0 gathers the whole mesh and writes it.
  topotet::MeshData out;
  if (args.partitioned) topotet::mpi::write_partitioned(comm, mesh, args.output);
  else out = topotet::mpi::gather(comm, mesh, 0);
  const std::uint64_t local_tets = mesh.local.tet_count();
  std::uint64_t output_tets = 0;
  MPI_Reduce(&local_tets, &output_tets, 1, MPI_UINT64_T, MPI_SUM, 0, comm);
  if (rank != 0) return 0;
  if (!args.partitioned) topotet::write_mesh(args.output, out);
  const double write_seconds = seconds() - gather_start;
  const topotet::Report& r = result.report;
  nlohmann::ordered_json json = {
      {"ranks", ranks},
      {"input", args.input},
      {"tets_before", input_tets},
      {"tets_after", output_tets},
      {"partitioned", args.partitioned},
      {"vertices_before", r.vertices_before},
      {"vertices_after", r.vertices_after},
      {"status", topotet::to_string(r.status)},
      {"message", r.message},
      {"read_distribute_seconds", read_seconds},
      {"input_form", input.kind == topotet::mpi::cli::InputKind::kWhole ? "whole (METIS)"
                : input.kind == topotet::mpi::cli::InputKind::kGmshSplit ? "gmsh split parts" : "gmsh partitioned"},
      {"simplify_seconds", r.seconds},
      {"gather_write_seconds", write_seconds},
      {"total_seconds", seconds()},
      {"collapses", r.collapses},
      {"peak_rss_bytes_max_rank", result.peak_rss_bytes},
  };
  nlohmann::ordered_json passes = nlohmann::ordered_json::array();
  for (const auto& p : result.passes)
    passes.push_back({{"seconds", p.seconds},
                      {"simplify_seconds", p.simplify_seconds},
                      {"trial_seconds", p.trial_seconds},
                      {"partition_seconds", p.partition_seconds},
                      {"vertices_after", p.vertices_after},
                      {"collapses", p.collapses},
                      {"frozen_vertices", p.frozen_vertices},
                      {"migrated_tets", p.migrated_tets},
                      {"bytes_sent", p.bytes_sent}});
  json["passes"] = passes;
  if (!args.report.empty()) topotet::write_text_file(args.report, json.dump(2) + "\n");
  if (!args.quiet) {
    std::printf("ranks     %d\n", ranks);
    std::printf("vertices  %llu -> %llu (%s)\n", static_cast<unsigned long long>(r.vertices_before),
                static_cast<unsigned long long>(r.vertices_after), topotet::to_string(r.status));
    std::printf("tets      %llu -> %llu\n", static_cast<unsigned long long>(input_tets),
                static_cast<unsigned long long>(output_tets));
    for (std::size_t i = 0; i < result.passes.size(); ++i) {
      const auto& p = result.passes[i];
      std::printf("pass %zu    %.2f s (simplify %.2f s of which trial %.2f s, repartition %.2f s), %llu vertices, "
                  "%llu collapses, %llu frozen, %llu tets migrated, %llu bytes sent\n",
                  i + 1, p.seconds, p.simplify_seconds, p.trial_seconds, p.partition_seconds,
                  static_cast<unsigned long long>(p.vertices_after), static_cast<unsigned long long>(p.collapses),
                  static_cast<unsigned long long>(p.frozen_vertices), static_cast<unsigned long long>(p.migrated_tets),
                  static_cast<unsigned long long>(p.bytes_sent));
    }
    std::printf("time      read+distribute %.2f s, simplify %.2f s, gather+write %.2f s\n", read_seconds, r.seconds,
                write_seconds);
    std::printf("memory    peak RSS %.1f MB (largest rank)\n", static_cast<double>(result.peak_rss_bytes) / 1e6);
    if (!r.message.empty()) std::printf("note      %s\n", r.message.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  CLI::App app{"topotet-mpi: distributed topology-preserving simplification of tetrahedral meshes (MPI + METIS)"};
  app.name("topotet-mpi");
  app.require_subcommand(1);
  Args args;
  CLI::App* cmd = app.add_subcommand("simplify", "Simplify a mesh over the MPI ranks; rank 0 reads IN and writes OUT");
  cmd->add_option("IN", args.input,
                  "Input mesh (.mesh, .msh, optionally .gz), or a partitioned Gmsh 4.1 mesh with one part per rank "
                  "(IN with $PartitionedEntities, or IN_1.msh .. IN_N.msh from gmsh -part N -part_split)")
      ->required();
  cmd->add_option("-o,--output", args.output, "Output mesh (.mesh, .msh or .vtu; with --partitioned a .pvtu)")->required();
  cmd->add_flag("--partitioned", args.partitioned,
                "Each rank writes its piece: OUT.pvtu and OUT_<rank>.vtu beside it (ParaView), with a global_id point array");
  cmd->add_option("--ratio", args.ratio, "Keep this fraction of the vertices, in (0, 1]")->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--target-vertices", args.target_vertices, "Stop at this many vertices (wins over --ratio)");
  cmd->add_option("--max-cost,--max-error", args.max_cost, "Stop when the cheapest collapse costs more (0 = no limit)");
  cmd->add_option("--min-quality", args.min_quality, "Reject collapses creating tets below this mean ratio");
  cmd->add_option("--tolerance", args.tolerance, "Geometric tolerance in mesh units (wins over --tolerance-rel)");
  cmd->add_option("--tolerance-rel", args.tolerance_rel, "Geometric tolerance relative to the bounding box diagonal");
  cmd->add_option("--feature-angle", args.feature_angle, "Sharp-feature angle in degrees (180 = off)");
  cmd->add_option("--round-fraction", args.round_fraction, "Fraction of the cheapest proposals per parallel round");
  cmd->add_option("--threads", args.threads, "Threads per rank (0 = all; the output is the same for every value)");
  cmd->add_flag("--sequential", args.sequential, "Use the sequential reference engine on each rank");
  cmd->add_option("--max-passes", args.max_passes, "Passes (simplify, then repartition) at most");
  cmd->add_flag("--count-shares", args.count_shares,
                "Split each pass's target over the ranks by vertex count, without the trial runs that split it by cost "
                "(faster, larger field error)");
  cmd->add_option("--report", args.report, "Write the report (passes, times, traffic, memory) as JSON");
  cmd->add_flag("--quiet", args.quiet, "No report on stdout");
  int code = 0;
  try {
    app.parse(argc, argv);
    code = run(MPI_COMM_WORLD, args);
  } catch (const CLI::ParseError& e) {
    code = rank == 0 ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 2);
    if (code != 0) code = 2;
  } catch (const std::exception& e) {
    if (rank == 0) std::fprintf(stderr, "topotet-mpi: error: %s\n", e.what());
    code = 2;
  }
  MPI_Finalize();
  return code;
}
