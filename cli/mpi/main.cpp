// topotet-mpi: the distributed simplifier on a mesh file.
//   mpirun -np 4 topotet-mpi simplify in.mesh -o out.mesh --ratio 0.1
// Rank 0 reads IN, checks it (the mesh builder, as `topotet simplify` does), and METIS spreads it
// over the ranks, or each rank reads its part of a partitioned Gmsh mesh (read_input.h);
// topotet::mpi::simplify runs the passes; rank 0 gathers the result and writes OUT, or with
// --partitioned every rank writes its piece (topotet::mpi::write_partitioned). The options are
// those of `topotet simplify`, from the same definitions (mpi_options.h says which ones MPI
// refuses); the measurements of `topotet simplify` run on one node: use `topotet check IN OUT`.
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common.h"
#include "mpi_options.h"
#include "read_input.h"
#include "topotet/cell_fields.h"
#include "topotet/error.h"
#include "topotet/io.h"
#include "topotet/mpi.h"

namespace {

using topotet::cli::mpi::MpiSimplifyArgs;

bool ends_with_pvtu(const std::string& path) {
  return path.size() >= 5 && (path.compare(path.size() - 5, 5, ".pvtu") == 0 || path.compare(path.size() - 5, 5, ".PVTU") == 0);
}

topotet::mpi::Options mpi_options(const MpiSimplifyArgs& args) {
  topotet::mpi::Options options;
  options.simplify = topotet::cli::engine_options(args.simplify);
  options.max_passes = args.max_passes;
  options.shares_by_cost = !args.count_shares;
  return options;
}

int run(MPI_Comm comm, const MpiSimplifyArgs& args) {
  using topotet::cli::report_stream;
  const topotet::cli::SimplifyArgs& a = args.simplify;
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  // Every rank has the same arguments: each finds this alone, before any work.
  if (args.partitioned && !ends_with_pvtu(a.output)) {
    if (rank == 0)
      std::fprintf(stderr, "topotet-mpi: error: %s: --partitioned writes a .pvtu (and one .vtu per rank beside it)\n",
                   a.output.c_str());
    return 2;
  }
  if (args.partitioned && (!a.extensive.empty() || !a.categorical.empty())) {
    if (rank == 0)
      std::fprintf(stderr, "topotet-mpi: error: --extensive / --categorical: the cell arrays are carried onto a gathered "
                   "output only, not with --partitioned (the remap needs every input tet an output tet overlaps)\n");
    return 2;
  }
  // The JSON report on stdout: the text report moves to stderr.
  if (a.report == "-") topotet::cli::send_report_to_stderr();
  // Read and distributed together (a partitioned Gmsh input is read where its parts go).
  topotet::ReadOptions read_options;
  read_options.tets_only = a.tets_only;
  read_options.format = topotet::cli::format_for(a.input, a.format);
  read_options.material_array = a.material_array;
  topotet::CellRemapOptions cell_remap;
  cell_remap.extensive = a.extensive;
  cell_remap.categorical = a.categorical;
  topotet::cli::mpi::Input input =
      topotet::cli::mpi::read_input(comm, a.input, 1, read_options, args.partitioned ? nullptr : &cell_remap);
  topotet::mpi::DistributedMesh& mesh = input.part;
  const std::uint64_t input_tets = input.tets;
  const double read_seconds = seconds();

  const topotet::mpi::Options options = mpi_options(args);
  const topotet::mpi::Result result = topotet::mpi::simplify(comm, mesh, options);
  const double gather_start = seconds();
  // --partitioned: each rank writes its piece; else rank 0 gathers the whole mesh and writes it.
  topotet::MeshData out;
  if (args.partitioned) topotet::mpi::write_partitioned(comm, mesh, a.output);
  else out = topotet::mpi::gather(comm, mesh, 0);
  const std::uint64_t local_tets = mesh.local.tet_count();
  std::uint64_t output_tets = 0;
  MPI_Reduce(&local_tets, &output_tets, 1, MPI_UINT64_T, MPI_SUM, 0, comm);
  if (rank != 0) return 0;
  // The input's cell arrays onto the gathered tets (topotet/cell_fields.h), as topotet simplify does.
  std::optional<topotet::CellRemapReport> remapped;
  if (!input.cell_source.cell_fields.empty()) {
    remapped = topotet::remap_cell_fields(input.cell_source, out, cell_remap);
    input.cell_source = topotet::MeshData{};
  }
  if (!args.partitioned) {
    topotet::WriteOptions write_options;
    write_options.binary = a.binary;
    write_options.msh22 = a.msh22;
    write_options.format = topotet::cli::format_for(a.output, a.format);
    topotet::cli::write_mesh_file(a.output, out, write_options);
  }
  const double write_seconds = seconds() - gather_start;
  const topotet::Report& r = result.report;
  nlohmann::ordered_json json = {
      {"ranks", ranks},
      {"input", a.input},
      {"tets_before", input_tets},
      {"tets_after", output_tets},
      {"partitioned", args.partitioned},
      {"vertices_before", r.vertices_before},
      {"vertices_after", r.vertices_after},
      {"status", topotet::to_string(r.status)},
      {"message", r.message},
      {"read_distribute_seconds", read_seconds},
      {"input_form", input.kind == topotet::cli::mpi::InputKind::kWhole ? "whole (METIS)"
                : input.kind == topotet::cli::mpi::InputKind::kGmshSplit ? "gmsh split parts" : "gmsh partitioned"},
      {"simplify_seconds", r.seconds},
      {"gather_write_seconds", write_seconds},
      {"total_seconds", seconds()},
      {"collapses", r.collapses},
      {"peak_rss_bytes_max_rank", result.peak_rss_bytes},
  };
  // The limits that held the output (relaxed where the run would have stopped before its target,
  // for every rank alike: topotet/mpi.h).
  json["tolerance"] = r.tolerance;
  json["tolerance_asked"] = r.tolerance_asked;
  json["min_quality_used"] = r.min_quality_used;
  json["min_dihedral_used"] = r.min_dihedral_used;
  json["relaxations"] = topotet::cli::relaxations_json(r);
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
  nlohmann::ordered_json cells = nlohmann::ordered_json::array();
  for (const topotet::CellField& f : out.cell_fields)
    cells.push_back({{"name", f.name}, {"components", f.components}, {"kind", topotet::cell_kind_name(f.kind)}});
  json["cell_arrays"] = cells;
  if (remapped)
    json["cell_remap"] = {{"seconds", remapped->seconds},
                          {"overlap_pairs", remapped->overlap_pairs},
                          {"nearest_new_tets", remapped->nearest_new_tets},
                          {"nearest_original_tets", remapped->nearest_original_tets},
                          {"covered_volume_fraction", remapped->covered_volume_fraction}};
  else
    json["cell_remap"] = nullptr;
  if (!a.report.empty()) topotet::write_text_file(a.report, json.dump(2) + "\n");
  // report_stream() is a sink with -q and stderr when the JSON report takes stdout.
  std::FILE* text = report_stream();
  std::fprintf(text, "ranks     %d\n", ranks);
  if (topotet::cli::verbosity() >= topotet::cli::Verbosity::kVerbose)
    std::fprintf(text, "options   %s, max passes %d, shares by %s\n",
                 topotet::cli::options_text(options.simplify, {}).c_str(), options.max_passes,
                 options.shares_by_cost ? "cost" : "count");
  std::fprintf(text, "vertices  %llu -> %llu (%s)\n", static_cast<unsigned long long>(r.vertices_before),
               static_cast<unsigned long long>(r.vertices_after), topotet::to_string(r.status));
  std::fprintf(text, "tets      %llu -> %llu\n", static_cast<unsigned long long>(input_tets),
               static_cast<unsigned long long>(output_tets));
  for (std::size_t i = 0; i < result.passes.size(); ++i) {
    const auto& p = result.passes[i];
    std::fprintf(text, "pass %zu    %.2f s (simplify %.2f s of which trial %.2f s, repartition %.2f s), %llu vertices, "
                 "%llu collapses, %llu frozen, %llu tets migrated, %llu bytes sent\n",
                 i + 1, p.seconds, p.simplify_seconds, p.trial_seconds, p.partition_seconds,
                 static_cast<unsigned long long>(p.vertices_after), static_cast<unsigned long long>(p.collapses),
                 static_cast<unsigned long long>(p.frozen_vertices), static_cast<unsigned long long>(p.migrated_tets),
                 static_cast<unsigned long long>(p.bytes_sent));
  }
  if (remapped) {
    std::string names;
    for (const topotet::CellField& f : out.cell_fields)
      names += (names.empty() ? "" : ", ") + f.name + ": " + topotet::cell_kind_name(f.kind);
    std::fprintf(text, "cell data %zu array%s (%s), remapped on rank 0 in %.2f s, %llu new tets by the nearest original\n",
                 out.cell_fields.size(), out.cell_fields.size() == 1 ? "" : "s", names.c_str(), remapped->seconds,
                 static_cast<unsigned long long>(remapped->nearest_new_tets));
  }
  if (!r.relaxations.empty())
    std::fprintf(text, "relaxed   %s to reach the target, for every rank alike; the output holds its guarantees with these values\n",
                 topotet::cli::relaxations_text(r).c_str());
  std::fprintf(text, "time      read+distribute %.2f s, simplify %.2f s, gather+write %.2f s\n", read_seconds, r.seconds,
               write_seconds);
  std::fprintf(text, "memory    peak RSS %.1f MB (largest rank)\n", static_cast<double>(result.peak_rss_bytes) / 1e6);
  if (!r.message.empty()) std::fprintf(text, "note      %s\n", r.message.c_str());
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
  MpiSimplifyArgs args;
  topotet::cli::mpi::add_mpi_simplify_command(app, args);
  int code = 0;
  try {
    app.parse(argc, argv);
    topotet::cli::mpi::check_mpi_simplify_args(app, args);
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
