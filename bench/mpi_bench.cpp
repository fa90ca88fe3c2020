// One distributed run, measured:
//   mpirun -np N mpi_bench FAMILY TETS RATIO [THREADS] [--compare] [--former-borders]
// (--former-borders: Options::later_passes_on_former_borders = true).
// Rank 0 generates the mesh, METIS spreads it, topotet::mpi::simplify runs; rank 0 gathers and
// prints one JSON line: time per pass, migrated tets, bytes sent, peak memory per rank, and the
// quality of the result (dihedral spread of all tets and, separately, of the tets with a vertex
// that was frozen on a partition border in some pass: where seams would show), field RMS error.
// --compare also runs the shared-memory engine on rank 0 at the same target and measures it the
// same way (the "shm_" keys). bench/mpi_scaling.sh runs the scaling tables with it.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "topotet/generate.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/mpi.h"

namespace {

using Json = nlohmann::ordered_json;

Json measure(const topotet::MeshData& input, const topotet::MeshData& out, const std::vector<std::uint8_t>* touched) {
  const auto q = topotet::compute_quality(out);
  const auto f = topotet::compare_fields(input, out);
  Json j = {{"tets", out.tet_count()},
            {"vertices", out.vertex_count()},
            {"dihedral_std_deg", q.dihedral_deg.std_dev},
            {"min_mean_ratio", q.mean_ratio.min},
            {"field_rms_rel", f.worst_rms_rel}};
  if (touched != nullptr) {
    topotet::MeshData border;
    border.positions = out.positions;
    for (const auto& t : out.tets)
      if ((*touched)[t[0]] || (*touched)[t[1]] || (*touched)[t[2]] || (*touched)[t[3]]) border.tets.push_back(t);
    border.tet_material.assign(border.tets.size(), 0);
    const auto qb = topotet::compute_quality(border);
    j["border_tets"] = border.tet_count();
    j["border_dihedral_std_deg"] = qb.dihedral_deg.std_dev;
    j["border_min_mean_ratio"] = qb.mean_ratio.min;
  }
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  if (argc < 4) {
    if (rank == 0) std::fprintf(stderr, "usage: mpi_bench FAMILY TETS RATIO [THREADS] [--compare] [--former-borders]\n");
    MPI_Finalize();
    return 2;
  }
  topotet::GenerateOptions g;
  g.family = argv[1];
  g.target_tets = std::stoull(argv[2]);
  const double ratio = std::stod(argv[3]);
  const int threads = argc > 4 && argv[4][0] != '-' ? std::stoi(argv[4]) : 0;
  bool compare = false, restrict_later = false;
  for (int i = 4; i < argc; ++i) {
    compare = compare || std::strcmp(argv[i], "--compare") == 0;
    if (std::strcmp(argv[i], "--former-borders") == 0) restrict_later = true;
  }

  topotet::MeshData input;
  if (rank == 0) input = topotet::generate_mesh(g);
  topotet::mpi::DistributedMesh part = rank == 0 ? topotet::mpi::from_whole(input) : topotet::mpi::DistributedMesh{};
  const auto t0 = std::chrono::steady_clock::now();
  topotet::mpi::distribute(MPI_COMM_WORLD, part);
  const double distribute_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  topotet::mpi::Options options;
  options.simplify.target_vertex_ratio = ratio;
  options.simplify.num_threads = threads;
  options.later_passes_on_former_borders = restrict_later;
  const topotet::mpi::Result r = topotet::mpi::simplify(MPI_COMM_WORLD, part, options);
  std::vector<topotet::mpi::GlobalId> ids;
  const topotet::MeshData out = topotet::mpi::gather(MPI_COMM_WORLD, part, 0, &ids);
  // The border marks, by global id, to rank 0.
  std::vector<topotet::mpi::GlobalId> touched_ids;
  for (std::size_t v = 0; v < part.global_ids.size(); ++v)
    if (r.touched_border[v]) touched_ids.push_back(part.global_ids[v]);
  int count = static_cast<int>(touched_ids.size());
  std::vector<int> counts(ranks), displs(ranks);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  int total = 0;
  for (int k = 0; k < ranks; ++k) {
    displs[k] = total;
    total += counts[k];
  }
  std::vector<topotet::mpi::GlobalId> all(rank == 0 ? total : 0);
  MPI_Gatherv(touched_ids.data(), count, MPI_UINT64_T, all.data(), counts.data(), displs.data(), MPI_UINT64_T, 0,
              MPI_COMM_WORLD);
  if (rank == 0) {
    std::unordered_map<topotet::mpi::GlobalId, topotet::VertId> index;
    for (topotet::VertId o = 0; o < ids.size(); ++o) index[ids[o]] = o;
    std::vector<std::uint8_t> touched(out.vertex_count(), 0);
    for (auto g2 : all) touched[index.at(g2)] = 1;
    Json j = {{"family", g.family},        {"tets_in", input.tet_count()}, {"ratio", ratio},
              {"ranks", ranks},            {"threads", threads},
              {"status", topotet::to_string(r.report.status)},
              {"distribute_seconds", distribute_seconds}, {"simplify_seconds", r.report.seconds}};
    Json passes = Json::array();
    for (const auto& p : r.passes)
      passes.push_back({{"seconds", p.seconds},
                        {"simplify_seconds", p.simplify_seconds},
                        {"partition_seconds", p.partition_seconds},
                        {"collapses", p.collapses},
                        {"frozen_vertices", p.frozen_vertices},
                        {"migrated_tets", p.migrated_tets},
                        {"bytes_sent", p.bytes_sent}});
    j["passes"] = passes;
    j["peak_rss_bytes_per_rank"] = r.peak_rss_per_rank;
    j["mpi"] = measure(input, out, &touched);
    if (compare) {
      topotet::TetMesh mesh = topotet::build_tet_mesh(input);
      topotet::SimplifyOptions o;
      o.target_vertices = r.report.vertices_after;  // the same target as the distributed run reached
      o.num_threads = threads;
      const auto s0 = std::chrono::steady_clock::now();
      (void)topotet::simplify(mesh, o);
      j["shm_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
      j["shm"] = measure(input, mesh.to_mesh_data(), nullptr);
    }
    std::printf("%s\n", j.dump().c_str());
  }
  MPI_Finalize();
  return 0;
}
