// topotet::mpi::simplify: passes of local simplification with frozen partition borders, each
// followed by a repartition that turns the frozen borders into interiors (see topotet/mpi.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "cost_shares.h"
#include "directory.h"
#include "entry_points.h"
#include "exchange.h"
#include "local_pass.h"
#include "migrate.h"
#include "partition.h"
#include "relax_limits.h"
#include "topotet/error.h"
#include "topotet/mpi.h"

namespace topotet::mpi {

namespace {

using detail::max_over_ranks;
using detail::rank_of;
using detail::size_of;
using detail::sum_over_ranks;
using Clock = std::chrono::steady_clock;

__extension__ typedef unsigned __int128 Wide;  // remove x removable can exceed 64 bits

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::uint64_t peak_rss_bytes() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      std::uint64_t kb = 0;
      status >> kb;
      return kb * 1024;
    }
  }
  return 0;
}

std::uint64_t owned_count(const DistributedMesh& mesh, int me) {
  return static_cast<std::uint64_t>(std::count(mesh.owner.begin(), mesh.owner.end(), me));
}

double global_diagonal(MPI_Comm comm, const MeshData& d) {
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-lo[0], -lo[1], -lo[2]};
  for (const auto& p : d.positions)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  double glo[3], ghi[3];
  MPI_Allreduce(lo, glo, 3, MPI_DOUBLE, MPI_MIN, comm);
  MPI_Allreduce(hi, ghi, 3, MPI_DOUBLE, MPI_MAX, comm);
  if (!(glo[0] <= ghi[0])) return 0.0;
  return std::sqrt((ghi[0] - glo[0]) * (ghi[0] - glo[0]) + (ghi[1] - glo[1]) * (ghi[1] - glo[1]) +
                   (ghi[2] - glo[2]) * (ghi[2] - glo[2]));
}

// This rank's part of `remove` vertices: proportional to its removable vertices over
// `denominator`, remainders to the lowest ranks (the same on every rank).
std::uint64_t share_of(MPI_Comm comm, std::uint64_t removable, std::uint64_t remove, std::uint64_t denominator) {
  const int ranks = size_of(comm), me = rank_of(comm);
  std::vector<std::uint64_t> all(ranks);
  MPI_Allgather(&removable, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, comm);
  std::uint64_t sum = 0;
  for (std::uint64_t x : all) sum += x;
  denominator = std::max(denominator, sum);
  if (denominator == 0) return 0;
  remove = std::min(remove, sum);
  std::vector<std::uint64_t> share(ranks);
  std::uint64_t given = 0;
  for (int r = 0; r < ranks; ++r) {
    share[r] = static_cast<std::uint64_t>(static_cast<Wide>(remove) * all[r] / denominator);
    given += share[r];
  }
  // The rounding left-overs (fewer than `ranks`), when the whole of `remove` is to be given.
  if (denominator == sum)
    for (int r = 0; r < ranks && given < remove; ++r)
      if (share[r] < all[r]) {
        ++share[r];
        ++given;
      }
  return share[me];
}

// Each counter summed over the ranks, in place (one all-reduce).
void sum_in_place(MPI_Comm comm, const std::vector<std::uint64_t*>& counters) {
  std::vector<std::uint64_t> counts, sums(counters.size());
  for (const std::uint64_t* c : counters) counts.push_back(*c);
  MPI_Allreduce(counts.data(), sums.data(), static_cast<int>(counts.size()), MPI_UINT64_T, MPI_SUM, comm);
  for (std::size_t k = 0; k < counters.size(); ++k) *counters[k] = sums[k];
}

// Counters summed over ranks, seconds and costs the largest.
void reduce_report(MPI_Comm comm, Report& r) {
  std::vector<std::uint64_t*> counters = {&r.collapses, &r.evaluations, &r.legality_checks, &r.rounds,
                                          &r.feature_edges, &r.feature_corners};
  for (std::uint64_t& x : r.rejected) counters.push_back(&x);
  sum_in_place(comm, counters);
  r.max_cost = max_over_ranks(comm, r.max_cost);
  for (double& s : r.phase_seconds) s = max_over_ranks(comm, s);
}

bool all_ranks(MPI_Comm comm, bool here) {
  int mine = here ? 1 : 0, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_LAND, comm);
  return all != 0;
}

// The census of the whole mesh at a stall: the sum of the parts' (each part's run takes its own
// when it stops early, frozen vertices left out: stop_diagnosis.h).
StopDiagnosis global_census(MPI_Comm comm, const StopDiagnosis& part) {
  StopDiagnosis d = part;  // its counts, summed below; its words are the part's alone
  d.is_filled = true;
  d.beyond_reach = false;
  d.dominant = "";
  d.dominant_share = 0.0;
  d.suggestion.clear();
  sum_in_place(comm, {&d.vertices, &d.topology, &d.pinned, &d.inversion, &d.quality, &d.tolerance, &d.field_error,
                      &d.collapsible, &d.pinned_corners, &d.pinned_required, &d.pinned_features, &d.pinned_other});
  return d;
}

// At a global stall, the in-core rule (relax_limits.h, choose_relaxation) on the whole mesh's
// census: H doubled, or both floors halved, for every rank alike (`local` is the same on every
// rank, and so is the census). The feature curves are not dropped over MPI: each part finds its
// own, and dropping them needs the curves of the whole mesh. Returns whether a limit relaxed.
bool relax_globally(MPI_Comm comm, const StopDiagnosis& part, std::uint64_t live, std::uint64_t target,
                    double diagonal, const SimplifyOptions& asked, SimplifyOptions& local, Report& report) {
  const StopDiagnosis d = topotet::detail::floors_at_lowest(global_census(comm, part), asked.relax_quality, report);
  const bool may_tolerance = asked.relax_tolerance && local.tolerance > 0.0 && local.tolerance < diagonal;
  const bool may_floors = asked.relax_quality && report.floors_may_relax();
  const topotet::detail::RelaxChoice choice = topotet::detail::choose_relaxation(d, live, target, may_tolerance, may_floors, false);
  if (choice == topotet::detail::RelaxChoice::kNone) return false;
  const double vertices = static_cast<double>(d.vertices);
  if (choice == topotet::detail::RelaxChoice::kTolerance) {
    report.relaxations.push_back({"tolerance", local.tolerance, 2.0 * local.tolerance, live, static_cast<double>(d.tolerance) / vertices});
    local.tolerance *= 2.0;
    report.tolerance = local.tolerance;
    return true;
  }
  topotet::detail::halve_floors(asked, live, static_cast<double>(d.quality) / vertices, report);
  local.min_dihedral = report.min_dihedral_used;
  local.min_quality = report.min_quality_used;
  return true;
}

bool is_failure(Status s) {
  return s == Status::kInvalidInput || s == Status::kOutOfMemory || s == Status::kInternalError || s == Status::kCancelled;
}

}  // namespace

Result simplify(MPI_Comm comm, DistributedMesh& mesh, const Options& options) {
  const auto start = Clock::now();
  const int me = rank_of(comm);
  Result result;
  Report& report = result.report;
  detail::check_part(comm, mesh);
  detail::agree_layout(comm, mesh);
  const SimplifyOptions& o = options.simplify;
  detail::agree_or_throw(comm, o.target_vertex_ratio > 0.0 && o.target_vertex_ratio <= 1.0 && options.max_passes >= 1,
                         "target_vertex_ratio must be in (0, 1] and max_passes >= 1");
  result.vertex_map = mesh.global_ids;

  std::uint64_t bytes = 0;
  detail::Sharing sharing = detail::find_sharing(comm, mesh.global_ids, &bytes);
  mesh.owner = sharing.owner;
  std::uint64_t global_vertices = sum_over_ranks(comm, owned_count(mesh, me));
  report.vertices_before = global_vertices;
  report.tets_before = sum_over_ranks(comm, mesh.local.tet_count());
  const std::uint64_t target = std::max<std::uint64_t>(
      4, o.target_vertices != 0 ? o.target_vertices
                                : static_cast<std::uint64_t>(std::llround(o.target_vertex_ratio * global_vertices)));
  // The tolerance is of the whole mesh's bounding box, not of a part's.
  SimplifyOptions local = o;
  const double diagonal = global_diagonal(comm, mesh.local);
  local.tolerance = o.tolerance > 0.0 ? o.tolerance : o.tolerance_rel * diagonal;
  // A part relaxing a limit alone would give the ranks different guarantees: the parts hold them
  // as given, and where the whole run stalls before its target the limits relax for every rank
  // alike, by the in-core rule on the whole mesh's census (relax_globally).
  local.relax_tolerance = false;
  local.relax_quality = false;
  local.relax_features = false;
  report.tolerance = report.tolerance_asked = local.tolerance;
  report.min_quality_used = report.min_quality_lowest = o.min_quality;
  report.min_dihedral_used = report.min_dihedral_lowest = o.min_dihedral;
  if (o.relax_quality) {  // the floors' lowest: of the whole input, as in core (relax_limits.h)
    topotet::detail::lowest_floors(mesh.local, o, report);
    double lowest[2] = {report.min_quality_lowest, report.min_dihedral_lowest}, global[2];
    MPI_Allreduce(lowest, global, 2, MPI_DOUBLE, MPI_MIN, comm);
    report.min_quality_lowest = global[0];
    report.min_dihedral_lowest = global[1];
  }
  // Per vertex: kFrozenLastPass (the partition should avoid it: pending), kFrozenOnce (sticky).
  std::vector<std::uint8_t> marks(mesh.local.vertex_count(), 0);

  bool unrestricted = false;
  // max_passes bounds the passes under each value of the limits (a relaxation starts a new count).
  for (int pass = 1, passes_here = 1; passes_here <= options.max_passes && global_vertices > target; ++pass, ++passes_here) {
    const auto pass_start = Clock::now();
    PassStats stats;
    stats.frozen_vertices = sum_over_ranks(comm, std::count(sharing.shared.begin(), sharing.shared.end(), 1));
    // Pass 1 removes from each vertex its fair share (the frozen ones' share waits for their
    // turn as interiors); later passes give what is left to the removable vertices, which are
    // (unless unrestricted) those frozen in an earlier pass.
    const bool restricted = options.later_passes_on_former_borders && pass >= 2 && !unrestricted;
    std::vector<std::uint8_t> keep;
    if (restricted) {
      keep.resize(marks.size());
      for (std::size_t v = 0; v < marks.size(); ++v) keep[v] = !sharing.shared[v] && !(marks[v] & detail::kFrozenOnce);
    }
    std::uint64_t removable = 0;
    for (std::size_t v = 0; v < marks.size(); ++v) removable += !sharing.shared[v] && (keep.empty() || !keep[v]);
    std::uint64_t share = share_of(comm, removable, global_vertices - target, pass == 1 ? global_vertices : 0);
    const std::uint64_t global_share = sum_over_ranks(comm, share);
    const auto simplify_start = Clock::now();
    // Costs in the whole mesh's units, so that the ranks' costs compare (cost_shares.h).
    const CostUnits units = detail::global_cost_units(comm, mesh.local);
    local.cost_units = units.diagonal > 0.0 ? &units : nullptr;
    std::string error;
    StopDiagnosis trial_census;  // the trial's, when it stopped early (relax_globally)
    // (One rank has nothing to split.)
    if (options.shares_by_cost && o.engine == Engine::kParallel && global_share > 0 && detail::size_of(comm) > 1) {
      // The trial (the part itself stays as it is): its curve of cost against removed vertices,
      // up to halfway between the count share and everything removable, and at most 1.5 times
      // the count share (a rank rarely needs more: should one, the others take the rest). The
      // last collapses of a part, where every candidate fails, are the slowest, and a later
      // pass's share is a small part of what it could remove (1M cube-sphere, 4 ranks, pass 2: a
      // trial to halfway took 10.3 s, the pass itself 2.2 s).
      std::vector<RoundStats> rounds;
      const std::uint64_t reach =
          std::min(share + (removable - std::min(share, removable)) / 2, share + share / 2);
      if (removable > 0) {
        try {
          SimplifyOptions trial = local;
          trial.round_log = &rounds;
          const Report t = detail::trial_part(mesh, sharing.shared, keep, trial, mesh.local.vertex_count() - reach);
          if (is_failure(t.status)) error = t.message;
          trial_census = t.stop;
        } catch (const std::exception& e) {
          error = e.what();
        }
      }
      detail::agree_or_throw(comm, error.empty(), error);
      share = detail::share_by_cost(comm, detail::curve_of(rounds), global_share);
      stats.trial_seconds = max_over_ranks(comm, since(simplify_start));
    }
    detail::LocalPass lp;
    if (share > 0) {
      try {
        lp = detail::simplify_part(mesh, sharing.shared, keep, local, mesh.local.vertex_count() - share);
        if (is_failure(lp.report.status)) error = lp.report.message;
      } catch (const std::exception& e) {
        error = e.what();
      }
    }
    detail::agree_or_throw(comm, error.empty(), error);
    stats.simplify_seconds = max_over_ranks(comm, since(simplify_start));
    add_run_counts(report, lp.report);
    detail::apply_merges(comm, lp.merges, result.vertex_map, &bytes);
    for (std::size_t v = 0; v < marks.size(); ++v)
      marks[v] = sharing.shared[v] ? detail::kFrozenLastPass | detail::kFrozenOnce : marks[v] & detail::kFrozenOnce;
    if (share > 0) {
      std::vector<std::uint8_t> carried(lp.origin.size());
      for (std::size_t v = 0; v < lp.origin.size(); ++v) carried[v] = marks[lp.origin[v]];
      marks = std::move(carried);
    }
    global_vertices = sum_over_ranks(comm, owned_count(mesh, me));
    stats.vertices_after = global_vertices;
    stats.collapses = sum_over_ranks(comm, lp.report.collapses);
    // A restricted pass that fell short hands over to unrestricted ones (the former borders left
    // may need their neighbours to move).
    const bool fell_short = restricted && 2 * stats.collapses < global_share;
    if (fell_short) unrestricted = true;
    // Without frozen vertices (one rank, or parts that share nothing) the pass saw the whole
    // problem: what it could not remove, no other partition would.
    const bool stopped = (stats.collapses == 0 && !fell_short) || stats.frozen_vertices == 0;
    const bool out_of_passes = passes_here == options.max_passes;
    // The limits may relax for the next passes where the run stops short (no collapse left, or
    // out of passes) or where every part stopped short of its share (each took its census then; a
    // part given no share this pass, its trial having removed nothing, has its trial's).
    const StopDiagnosis& census = lp.report.stop.is_filled ? lp.report.stop : trial_census;
    const bool every_part_stalled = all_ranks(comm, census.is_filled || removable == 0);
    const bool relaxed = global_vertices > target && (stopped || out_of_passes || every_part_stalled) &&
                         relax_globally(comm, census, global_vertices, target, diagonal, o, local, report);
    if (relaxed) passes_here = 0;
    const bool last = !relaxed && (global_vertices <= target || stopped || out_of_passes);
    if (!last) {
      const auto partition_start = Clock::now();
      const std::vector<int> dest = detail::partition(comm, mesh, marks, options.metis_seed, &bytes);
      stats.migrated_tets = sum_over_ranks(comm, detail::migrate(comm, mesh, marks, dest, &bytes));
      sharing = detail::find_sharing(comm, mesh.global_ids, &bytes);
      mesh.owner = sharing.owner;
      stats.partition_seconds = max_over_ranks(comm, since(partition_start));
    }
    stats.bytes_sent = sum_over_ranks(comm, bytes);
    bytes = 0;
    stats.seconds = max_over_ranks(comm, since(pass_start));
    result.passes.push_back(stats);
    if (last) break;
  }

  reduce_report(comm, report);
  report.vertices_after = global_vertices;
  report.tets_after = sum_over_ranks(comm, mesh.local.tet_count());
  report.status = global_vertices <= target ? Status::kOk : Status::kStoppedEarly;
  if (report.status == Status::kStoppedEarly)
    report.message = "stopped at " + std::to_string(global_vertices) + " vertices (target " + std::to_string(target) +
                     ") after " + std::to_string(result.passes.size()) + " passes" +
                     (result.passes.back().collapses == 0 ? ": no legal collapse left" : " (max_passes)");
  report.seconds = max_over_ranks(comm, since(start));
  result.touched_border.resize(marks.size());
  for (std::size_t v = 0; v < marks.size(); ++v) result.touched_border[v] = marks[v] & detail::kFrozenOnce ? 1 : 0;
  const std::uint64_t rss = peak_rss_bytes();
  result.peak_rss_per_rank.resize(size_of(comm));
  MPI_Allgather(&rss, 1, MPI_UINT64_T, result.peak_rss_per_rank.data(), 1, MPI_UINT64_T, comm);
  result.peak_rss_bytes = *std::max_element(result.peak_rss_per_rank.begin(), result.peak_rss_per_rank.end());
  return result;
}

}  // namespace topotet::mpi
