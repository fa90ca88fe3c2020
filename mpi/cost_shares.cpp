#include "cost_shares.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "exchange.h"

namespace topotet::mpi::detail {

namespace {

// Vertices a rank's curve removes at cost `t`: the rounds wholly below t, and the next round in
// proportion to where t falls between its predecessor's cost and its own.
double removed_at(const double* cost, const std::uint64_t* removed, std::size_t n, double t) {
  double prev_cost = 0.0, prev_removed = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (cost[k] > t) {
      const double span = cost[k] - prev_cost;
      const double f = span > 0.0 ? (t - prev_cost) / span : 0.0;
      return prev_removed + std::clamp(f, 0.0, 1.0) * (static_cast<double>(removed[k]) - prev_removed);
    }
    prev_cost = cost[k];
    prev_removed = static_cast<double>(removed[k]);
  }
  return prev_removed;
}

template <class T>
std::vector<T> all_gather_v(MPI_Comm comm, const std::vector<T>& mine, MPI_Datatype type, std::vector<int>& counts,
                            std::vector<int>& displs) {
  const int ranks = size_of(comm);
  int count = static_cast<int>(mine.size());
  counts.assign(ranks, 0);
  displs.assign(ranks, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  int total = 0;
  for (int r = 0; r < ranks; ++r) {
    displs[r] = total;
    total += counts[r];
  }
  std::vector<T> all(total);
  MPI_Allgatherv(mine.data(), count, type, all.data(), counts.data(), displs.data(), type, comm);
  return all;
}

}  // namespace

CostCurve curve_of(const std::vector<RoundStats>& rounds) {
  CostCurve curve;
  double cost = 0.0;
  std::uint64_t removed = 0;
  for (const RoundStats& r : rounds) {
    if (r.collapses == 0) continue;
    cost = std::max(cost, r.max_cost);
    removed += r.collapses;
    curve.cost.push_back(cost);
    curve.removed.push_back(removed);
  }
  return curve;
}

std::uint64_t share_by_cost(MPI_Comm comm, const CostCurve& mine, std::uint64_t total) {
  const int ranks = size_of(comm), me = rank_of(comm);
  std::vector<int> counts, displs;
  const std::vector<double> cost = all_gather_v(comm, mine.cost, MPI_DOUBLE, counts, displs);
  const std::vector<std::uint64_t> removed = all_gather_v(comm, mine.removed, MPI_UINT64_T, counts, displs);
  auto at = [&](int r, double t) { return removed_at(&cost[displs[r]], &removed[displs[r]], counts[r], t); };
  std::vector<std::uint64_t> most(ranks, 0);  // what each curve removes at all
  std::uint64_t possible = 0;
  double top = 0.0;
  for (int r = 0; r < ranks; ++r) {
    if (counts[r] > 0) {
      most[r] = removed[displs[r] + counts[r] - 1];
      top = std::max(top, cost[displs[r] + counts[r] - 1]);
    }
    possible += most[r];
  }
  if (possible <= total) return most[me];
  // The cost T at which the curves together remove `total`: bisection (the sum is non-decreasing
  // in T), the same steps on every rank.
  double lo = 0.0, hi = top;
  for (int step = 0; step < 200 && lo < hi; ++step) {
    const double mid = lo + (hi - lo) / 2;
    if (mid <= lo || mid >= hi) break;
    double sum = 0.0;
    for (int r = 0; r < ranks; ++r) sum += at(r, mid);
    (sum < static_cast<double>(total) ? lo : hi) = mid;
  }
  std::vector<std::uint64_t> share(ranks);
  std::uint64_t given = 0;
  for (int r = 0; r < ranks; ++r) {
    share[r] = std::min(most[r], static_cast<std::uint64_t>(std::floor(at(r, hi))));
    given += share[r];
  }
  // Rounding: take back from or hand out to the ranks in order, within what each curve allows.
  for (int r = 0; r < ranks && given > total; ++r) {
    const std::uint64_t back = std::min(share[r], given - total);
    share[r] -= back;
    given -= back;
  }
  for (int r = 0; r < ranks && given < total; ++r) {
    const std::uint64_t more = std::min(most[r] - share[r], total - given);
    share[r] += more;
    given += more;
  }
  return share[me];
}

CostUnits global_cost_units(MPI_Comm comm, const MeshData& part) {
  const int ranks = size_of(comm);
  std::size_t stride = 0;
  for (const VertexField& f : part.fields) stride += static_cast<std::size_t>(f.components);
  // The field layout is agreed on (agree_layout) among ranks with tets; a rank without any sends
  // an empty box and no fields.
  std::uint64_t my_stride = part.tets.empty() ? 0 : stride, max_stride = 0;
  MPI_Allreduce(&my_stride, &max_stride, 1, MPI_UINT64_T, MPI_MAX, comm);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Per rank: low corner (3), minus the high corner (3), field minima, minus the maxima.
  const std::size_t n = 6 + 2 * max_stride;
  std::vector<double> lows(n, kInf);
  for (const auto& p : part.positions)
    for (int k = 0; k < 3; ++k) {
      lows[k] = std::min(lows[k], static_cast<double>(p[k]));
      lows[3 + k] = std::min(lows[3 + k], -static_cast<double>(p[k]));
    }
  if (my_stride == max_stride) {
    std::size_t offset = 0;
    for (const VertexField& f : part.fields) {
      for (std::size_t i = 0; i < f.values.size(); ++i) {
        const std::size_t c = offset + i % static_cast<std::size_t>(f.components);
        lows[6 + c] = std::min(lows[6 + c], f.values[i]);
        lows[6 + max_stride + c] = std::min(lows[6 + max_stride + c], -f.values[i]);
      }
      offset += static_cast<std::size_t>(f.components);
    }
  }
  std::vector<double> low(n);
  MPI_Allreduce(lows.data(), low.data(), static_cast<int>(n), MPI_DOUBLE, MPI_MIN, comm);  // exact: a min
  // Volume and tet count per rank, gathered and summed in rank order (a reduction's order is not
  // promised, and a sum of doubles depends on it).
  double mine[2] = {0.0, static_cast<double>(part.tets.size())};
  for (const auto& t : part.tets) {
    const auto& a = part.positions[t[0]];
    double e[3][3];
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) e[j][k] = part.positions[t[j + 1]][k] - a[k];
    mine[0] += std::fabs(e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                         e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]));
  }
  std::vector<double> all(2 * ranks);
  MPI_Allgather(mine, 2, MPI_DOUBLE, all.data(), 2, MPI_DOUBLE, comm);
  double volume = 0.0, tets = 0.0;
  for (int r = 0; r < ranks; ++r) volume += all[2 * r], tets += all[2 * r + 1];

  CostUnits units;
  if (!(low[0] <= -low[3]) || tets == 0.0) return units;
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    units.origin[k] = low[k];
    d2 += (-low[3 + k] - low[k]) * (-low[3 + k] - low[k]);
  }
  units.diagonal = std::sqrt(d2);
  units.mean_tet_volume = volume / 6.0 / tets;
  if (!(units.mean_tet_volume > 0.0)) units.diagonal = 0.0;
  units.field_min.resize(stride);
  units.field_range.resize(stride);
  for (std::size_t c = 0; c < stride && stride == max_stride; ++c) {
    units.field_min[c] = low[6 + c];
    units.field_range[c] = -low[6 + max_stride + c] - low[6 + c];
  }
  return units;
}

}  // namespace topotet::mpi::detail
