// One distributed run, measured:
//   mpirun -np N mpi_bench FAMILY TETS RATIO [THREADS] [--compare] [--former-borders] [--count-shares]
// (--former-borders: Options::later_passes_on_former_borders = true; --count-shares:
// Options::shares_by_cost = false).
// With --compare, "breakdown" splits the field error at the original vertices (original ->
// simplified RMS, relative to the range) of both runs by where each input vertex was in the
// distributed run: by the rank that owned it in pass 1, and by whether it merged into a vertex
// frozen on a border in some pass. It tells whether the distributed run loses accuracy at the
// borders or in the parts' interiors, and in which parts.
// Rank 0 generates the mesh, METIS spreads it, topotet::mpi::simplify runs; rank 0 gathers and
// prints one JSON line: time per pass, migrated tets, bytes sent, peak memory per rank, and the
// quality of the result (dihedral spread of all tets and, separately, of the tets with a vertex
// that was frozen on a partition border in some pass: where seams would show), field RMS error.
// --compare also runs the shared-memory engine on rank 0 at the same target and measures it the
// same way (the "shm_" keys). bench/mpi_scaling.sh runs the scaling tables with it.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
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

std::uint64_t peak_rss_bytes() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key)
    if (key == "VmHWM:") {
      std::uint64_t kb = 0;
      status >> kb;
      return kb * 1024;
    }
  return 0;
}

// RMS (relative to the range, worst component) of the original -> simplified error at the input
// vertices whose class is `cls`: the input restricted to the tets with all four vertices in it.
double class_rms(const topotet::MeshData& input, const topotet::MeshData& out, const std::vector<int>& cls, int c) {
  topotet::MeshData sub;
  sub.positions = input.positions;
  sub.fields = input.fields;
  for (const auto& t : input.tets)
    if (cls[t[0]] == c && cls[t[1]] == c && cls[t[2]] == c && cls[t[3]] == c) sub.tets.push_back(t);
  sub.tet_material.assign(sub.tets.size(), 0);
  if (sub.tets.empty()) return 0.0;
  double worst = 0.0;
  for (const auto& comp : topotet::compare_fields(sub, out).components)
    worst = std::max(worst, comp.original_to_simplified.rms_rel);
  return worst;
}

// Gathers every rank's 64-bit values on rank 0 (the (key, value) pairs of the breakdown, the
// global ids of the border marks); other ranks get an empty vector.
std::vector<std::uint64_t> gather_u64(const std::vector<std::uint64_t>& mine, int ranks) {
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(ranks), displs(ranks);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  int total = 0;
  for (int k = 0; k < ranks; ++k) {
    displs[k] = total;
    total += counts[k];
  }
  std::vector<std::uint64_t> all(total);
  MPI_Gatherv(mine.data(), count, MPI_UINT64_T, all.data(), counts.data(), displs.data(), MPI_UINT64_T, 0,
              MPI_COMM_WORLD);
  return all;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  if (argc < 4) {
    if (rank == 0) std::fprintf(stderr, "usage: mpi_bench FAMILY TETS RATIO [THREADS] [--compare] [--former-borders] [--count-shares]\n");
    MPI_Finalize();
    return 2;
  }
  topotet::GenerateOptions g;
  g.family = argv[1];
  g.target_tets = std::stoull(argv[2]);
  const double ratio = std::stod(argv[3]);
  const int threads = argc > 4 && argv[4][0] != '-' ? std::stoi(argv[4]) : 0;
  bool compare = false, restrict_later = false, count_shares = false;
  for (int i = 4; i < argc; ++i) {
    compare = compare || std::strcmp(argv[i], "--compare") == 0;
    if (std::strcmp(argv[i], "--former-borders") == 0) restrict_later = true;
    if (std::strcmp(argv[i], "--count-shares") == 0) count_shares = true;
  }

  topotet::MeshData input;
  if (rank == 0) input = topotet::generate_mesh(g);
  topotet::mpi::DistributedMesh part = rank == 0 ? topotet::mpi::from_whole(input) : topotet::mpi::DistributedMesh{};
  const auto t0 = std::chrono::steady_clock::now();
  topotet::mpi::distribute(MPI_COMM_WORLD, part);
  const double distribute_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Peak memory per rank after the distribution, before simplify: what reading and spreading the
  // mesh took (VmHWM, bytes), against simplify's own peak (Result::peak_rss_per_rank).
  const std::uint64_t rss_distributed = peak_rss_bytes();
  std::vector<std::uint64_t> rss_distributed_per_rank(ranks);
  MPI_Gather(&rss_distributed, 1, MPI_UINT64_T, rss_distributed_per_rank.data(), 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  topotet::mpi::Options options;
  options.simplify.target_vertex_ratio = ratio;
  options.simplify.num_threads = threads;
  options.later_passes_on_former_borders = restrict_later;
  options.shares_by_cost = !count_shares;
  // Each input vertex's pass-1 owner, and below the output vertex it ended in (by global id).
  std::vector<std::uint64_t> owners;
  for (std::size_t v = 0; v < part.global_ids.size(); ++v)
    if (part.owner[v] == rank) owners.insert(owners.end(), {part.global_ids[v], static_cast<std::uint64_t>(rank)});
  const std::vector<topotet::mpi::GlobalId> input_ids = part.global_ids;
  const topotet::mpi::Result r = topotet::mpi::simplify(MPI_COMM_WORLD, part, options);
  std::vector<std::uint64_t> merged;
  for (std::size_t v = 0; v < input_ids.size(); ++v) merged.insert(merged.end(), {input_ids[v], r.vertex_map[v]});
  const std::vector<std::uint64_t> all_owners = gather_u64(owners, ranks), all_merged = gather_u64(merged, ranks);
  std::vector<topotet::mpi::GlobalId> ids;
  const topotet::MeshData out = topotet::mpi::gather(MPI_COMM_WORLD, part, 0, &ids);
  // The border marks, by global id, to rank 0.
  std::vector<topotet::mpi::GlobalId> touched_ids;
  for (std::size_t v = 0; v < part.global_ids.size(); ++v)
    if (r.touched_border[v]) touched_ids.push_back(part.global_ids[v]);
  const std::vector<topotet::mpi::GlobalId> all = gather_u64(touched_ids, ranks);
  if (rank == 0) {
    std::unordered_map<topotet::mpi::GlobalId, topotet::VertId> index;
    for (topotet::VertId o = 0; o < ids.size(); ++o) index[ids[o]] = o;
    std::vector<std::uint8_t> touched(out.vertex_count(), 0);
    for (auto g2 : all) touched[index.at(g2)] = 1;
    Json j = {{"family", g.family},        {"tets_in", input.tet_count()}, {"ratio", ratio},
              {"ranks", ranks},            {"shares", count_shares ? "count" : "cost"},            {"threads", threads},
              {"status", topotet::to_string(r.report.status)},
              {"distribute_seconds", distribute_seconds}, {"simplify_seconds", r.report.seconds}};
    Json passes = Json::array();
    for (const auto& p : r.passes)
      passes.push_back({{"seconds", p.seconds},
                        {"simplify_seconds", p.simplify_seconds},
                        {"trial_seconds", p.trial_seconds},
                        {"partition_seconds", p.partition_seconds},
                        {"collapses", p.collapses},
                        {"frozen_vertices", p.frozen_vertices},
                        {"migrated_tets", p.migrated_tets},
                        {"bytes_sent", p.bytes_sent}});
    j["passes"] = passes;
    j["peak_rss_bytes_per_rank"] = r.peak_rss_per_rank;
    j["peak_rss_bytes_after_distribute_per_rank"] = rss_distributed_per_rank;
    j["mpi"] = measure(input, out, &touched);
    if (compare) {
      topotet::TetMesh mesh = topotet::build_tet_mesh(input);
      topotet::SimplifyOptions o;
      o.target_vertices = r.report.vertices_after;  // the same target as the distributed run reached
      o.num_threads = threads;
      const auto s0 = std::chrono::steady_clock::now();
      std::vector<topotet::VertId> shm_map;
      (void)topotet::simplify(mesh, o, shm_map);
      j["shm_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
      const topotet::MeshData shm_out = mesh.to_mesh_data();
      j["shm"] = measure(input, shm_out, nullptr);
      std::vector<int> by_rank(input.vertex_count(), -1), by_border(input.vertex_count(), -1);
      for (std::size_t k = 0; k < all_owners.size(); k += 2) by_rank[all_owners[k]] = static_cast<int>(all_owners[k + 1]);
      for (std::size_t k = 0; k < all_merged.size(); k += 2) by_border[all_merged[k]] = touched[index.at(all_merged[k + 1])];
      Json parts = Json::array();
      for (int k = 0; k < ranks; ++k)
        parts.push_back({{"rank", k},
                         {"input_vertices", std::count(by_rank.begin(), by_rank.end(), k)},
                         {"mpi_rms_rel", class_rms(input, out, by_rank, k)},
                         {"shm_rms_rel", class_rms(input, shm_out, by_rank, k)}});
      Json borders = Json::array();
      for (int k = 0; k < 2; ++k)
        borders.push_back({{"merged_into_border_vertex", k == 1},
                           {"input_vertices", std::count(by_border.begin(), by_border.end(), k)},
                           {"mpi_rms_rel", class_rms(input, out, by_border, k)},
                           {"shm_rms_rel", class_rms(input, shm_out, by_border, k)}});
      j["breakdown"] = {{"by_pass1_rank", parts}, {"by_border", borders}};
    }
    std::printf("%s\n", j.dump().c_str());
  }
  MPI_Finalize();
  return 0;
}
