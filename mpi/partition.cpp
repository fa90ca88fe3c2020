#include "partition.h"

#include <algorithm>
#include <array>
#include <climits>
#include <numeric>
#include <string>
#include <tuple>

#include <metis.h>

#include "exchange.h"

namespace topotet::mpi::detail {

namespace {

struct Face {
  std::array<std::uint32_t, 3> v;  // dense vertex numbers, sorted
  std::uint32_t tet;
  bool operator<(const Face& o) const { return v != o.v ? v < o.v : tet < o.tet; }
};

// Rank 0's part: parts for all gathered tets. from_rank[t] = the rank tet t is on now.
std::vector<idx_t> cut(const std::vector<std::array<GlobalId, 4>>& tets, const std::vector<std::uint8_t>& hot,
                       const std::vector<int>& from_rank, int ranks, std::int32_t seed) {
  const std::size_t n = tets.size();
  std::vector<idx_t> part(n, 0);
  if (ranks == 1 || n == 0) return part;
  std::vector<GlobalId> ids;
  ids.reserve(4 * n);
  for (const auto& t : tets) ids.insert(ids.end(), t.begin(), t.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::vector<Face> faces;
  faces.reserve(4 * n);
  for (std::uint32_t t = 0; t < n; ++t) {
    std::array<std::uint32_t, 4> d;
    for (int k = 0; k < 4; ++k)
      d[k] = static_cast<std::uint32_t>(std::lower_bound(ids.begin(), ids.end(), tets[t][k]) - ids.begin());
    for (int skip = 0; skip < 4; ++skip) {
      Face f{{}, t};
      int j = 0;
      for (int k = 0; k < 4; ++k)
        if (k != skip) f.v[j++] = d[k];
      std::sort(f.v.begin(), f.v.end());
      faces.push_back(f);
    }
  }
  std::vector<GlobalId>().swap(ids);
  std::sort(faces.begin(), faces.end());
  std::vector<idx_t> xadj(n + 1, 0);
  for (std::size_t i = 0; i + 1 < faces.size(); ++i)
    if (faces[i].v == faces[i + 1].v) {
      ++xadj[faces[i].tet + 1];
      ++xadj[faces[i + 1].tet + 1];
    }
  std::partial_sum(xadj.begin(), xadj.end(), xadj.begin());
  std::vector<idx_t> adjncy(xadj.back()), adjwgt(xadj.back());
  std::vector<idx_t> fill(xadj.begin(), xadj.end() - 1);
  for (std::size_t i = 0; i + 1 < faces.size(); ++i)
    if (faces[i].v == faces[i + 1].v) {
      const std::uint32_t a = faces[i].tet, b = faces[i + 1].tet;
      const idx_t w = hot[a] || hot[b] ? kPendingFaceWeight : 1;
      adjncy[fill[a]] = static_cast<idx_t>(b);
      adjwgt[fill[a]++] = w;
      adjncy[fill[b]] = static_cast<idx_t>(a);
      adjwgt[fill[b]++] = w;
    }
  std::vector<Face>().swap(faces);
  idx_t nvtxs = static_cast<idx_t>(n), ncon = 1, nparts = ranks, edgecut = 0;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = seed;
  options[METIS_OPTION_NUMBERING] = 0;
  const int status = METIS_PartGraphKway(&nvtxs, &ncon, xadj.data(), adjncy.data(), nullptr, nullptr, adjwgt.data(),
                                         &nparts, nullptr, nullptr, options, &edgecut, part.data());
  if (status != METIS_OK) throw std::runtime_error("METIS_PartGraphKway failed (status " + std::to_string(status) + ")");
  // Part p goes to the rank holding most of its tets (greedy on the largest overlaps; ties by
  // part then rank), so that a repartition moves few tets.
  std::vector<std::uint64_t> overlap(static_cast<std::size_t>(ranks) * ranks, 0);
  for (std::size_t t = 0; t < n; ++t) ++overlap[static_cast<std::size_t>(part[t]) * ranks + from_rank[t]];
  std::vector<std::tuple<std::uint64_t, int, int>> pairs;
  for (int p = 0; p < ranks; ++p)
    for (int r = 0; r < ranks; ++r) pairs.emplace_back(overlap[static_cast<std::size_t>(p) * ranks + r], p, r);
  std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) {
    if (std::get<0>(a) != std::get<0>(b)) return std::get<0>(a) > std::get<0>(b);
    return std::make_pair(std::get<1>(a), std::get<2>(a)) < std::make_pair(std::get<1>(b), std::get<2>(b));
  });
  std::vector<int> rank_of_part(ranks, -1);
  std::vector<bool> taken(ranks, false);
  for (const auto& [count, p, r] : pairs)
    if (rank_of_part[p] < 0 && !taken[r]) {
      rank_of_part[p] = r;
      taken[r] = true;
    }
  for (idx_t& p : part) p = rank_of_part[p];
  return part;
}

}  // namespace

std::vector<int> partition(MPI_Comm comm, const DistributedMesh& mesh, const std::vector<std::uint8_t>& marks,
                           std::int32_t seed, std::uint64_t* bytes_sent) {
  const int ranks = size_of(comm), me = rank_of(comm);
  const MeshData& d = mesh.local;
  if (ranks == 1) return std::vector<int>(d.tet_count(), 0);
  constexpr int kTetBytes = 4 * sizeof(GlobalId) + 1;
  Packer p;
  for (std::size_t t = 0; t < d.tet_count(); ++t) {
    std::uint8_t hot = 0;
    for (VertId v : d.tets[t]) {
      p.put(mesh.global_ids[v]);
      if (!marks.empty() && (marks[v] & kFrozenLastPass)) hot = 1;
    }
    p.put(hot);
  }
  agree_or_throw(comm, p.bytes().size() <= static_cast<std::size_t>(INT_MAX), "a part is too large to gather its graph");
  const int my_count = static_cast<int>(d.tet_count());
  std::vector<int> counts(ranks), byte_counts(ranks), displs(ranks), tet_displs(ranks);
  MPI_Gather(&my_count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  long long total = 0;
  for (int r = 0; r < ranks; ++r) {
    tet_displs[r] = static_cast<int>(total);
    byte_counts[r] = counts[r] * kTetBytes;
    displs[r] = static_cast<int>(total * kTetBytes);
    total += counts[r];
  }
  if (me == 0) agree_or_throw(comm, total * kTetBytes <= INT_MAX, "the coarse graph is too large to gather on rank 0");
  else agree_or_throw(comm, true, "");
  std::vector<char> all(me == 0 ? static_cast<std::size_t>(total) * kTetBytes : 0);
  if (me != 0 && bytes_sent != nullptr) *bytes_sent += p.bytes().size();
  MPI_Gatherv(p.bytes().data(), static_cast<int>(p.bytes().size()), MPI_BYTE, all.data(), byte_counts.data(),
              displs.data(), MPI_BYTE, 0, comm);
  std::vector<idx_t> parts;
  std::string error;
  if (me == 0) {
    std::vector<std::array<GlobalId, 4>> tets(total);
    std::vector<std::uint8_t> hot(total);
    std::vector<int> from_rank(total);
    Unpacker u(all.data(), all.size());
    for (long long t = 0; t < total; ++t) {
      u.get_array(tets[t].data(), 4);
      hot[t] = u.get<std::uint8_t>();
    }
    std::vector<char>().swap(all);
    for (int r = 0; r < ranks; ++r) std::fill(from_rank.begin() + tet_displs[r], from_rank.begin() + tet_displs[r] + counts[r], r);
    try {
      parts = cut(tets, hot, from_rank, ranks, seed);
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  agree_or_throw(comm, error.empty(), error);
  static_assert(sizeof(idx_t) == sizeof(int), "Debian's METIS uses 32-bit idx_t");
  std::vector<int> mine(d.tet_count());
  if (me == 0 && bytes_sent != nullptr) *bytes_sent += (total - counts[0]) * sizeof(int);
  MPI_Scatterv(parts.data(), counts.data(), tet_displs.data(), MPI_INT, mine.data(), my_count, MPI_INT, 0, comm);
  return mine;
}

}  // namespace topotet::mpi::detail
