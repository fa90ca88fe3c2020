// The parallel engine: rounds of independent collapses, deterministic for any thread count.
//
//   quadrics, orders <- CostModel(mesh); every vertex proposes (proposals.h)
//   round r = 1, 2, ... while live vertices > target:
//     1. evaluate (parallel over the dirty vertices): each re-proposes from scratch, or only
//        updates its proposal, as the last round's collapses asked (costs only, no kernel)
//     2. threshold: a sampled quantile of the proposal costs, about the cheapest round_fraction
//        (divided by the last round's verification pass rate: next_fraction()); the proposals
//        below it are this round's candidates
//     3. verify (parallel over candidates): the kernel on a candidate's edges in cost order,
//        unless it is still verified from an earlier round (no collapse touched its stars since);
//        all of it but the tolerance proof, the dearest check, which only winners need
//     4. select: the verified candidates below the threshold, sorted by (cost, a, b), at most
//        live - target; their stencils (the vertices of St(a) ∪ St(b)) are reserved by rank
//        (parallel/reservations.h): the winners' stencils are disjoint
//        prove (parallel over winners): the tolerance proof of the verified placement (or of the
//        edge's next ones); a winner that fails it gives its stencil back and proposes again
//     5. apply (parallel over winners): collapse with the proved placement (the stencil is
//        untouched since the verification, so the check still holds), update the quadrics, and
//        tell the stencil's vertices that their stars changed (which of them must re-propose)
//   stop when the target is reached or no proposal is left (after one look at the edges whose
//   refusals may be out of date, and, when the driver relaxes a limit that held the vertices left,
//   a look at every edge: relax_limits.h)
//
// Why the output is bit-identical for any thread count: every proposal and verification is a pure
// function of the mesh at the start of its phase and of the vertex's own state; the threshold is
// computed from a sample taken at fixed vertex ids; ranks come from a total order; reservations
// keep the minimum; the collapses of one round touch disjoint data. Only side-table slot numbers
// depend on the schedule, and they are never part of the output (compaction renumbers them).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "kernel/collapse.h"
#include "cost/cost.h"
#include "engines.h"
#include "parallel/filter.h"
#include "parallel/for_range.h"
#include "parallel/reservations.h"
#include "parallel/scratch.h"
#include "topotet/round_log.h"
#include "mesh/prefetch.h"
#include "mesh/probe_set.h"
#include "cost/proposals.h"

namespace topotet::detail {
namespace {

// Reservation passes per round. Most winners come from the first few passes.
constexpr int kReservationPasses = 8;

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// What a vertex must do in the next evaluate phase.
enum class Dirty : std::uint8_t { kClean, kPropose, kUpdate };

struct ThreadScratch {
  ProposalScratch proposal;
  std::vector<double> fields;
  std::vector<VertId> stencil, stencil_slots;  // stencil_of's output and probe set storage
  std::vector<VertId> stencil_pool;            // stencils of the candidates verified this round
  std::vector<VertId> marked;                  // vertices the apply phase made dirty
  std::vector<std::pair<VertId, Proposals::Redo>> redo;  // one collapse's stencil
  // The coverage placements of the winners proved this round (prove()): the first coverage_count
  // are in use. The apply phase commits them instead of placing the items again.
  struct KeptCoverage {
    CollapseScratch::CoverageFor placement;
    CoverageScratch coverage;
  };
  std::vector<KeptCoverage> coverage_pool;
  std::size_t coverage_count = 0;
};

// Where verify() left a candidate's stencil (owner == nullptr: nowhere).
struct StoredStencil {
  const ThreadScratch* owner = nullptr;
  std::uint32_t offset = 0, size = 0;
};

// What prove() found for a winner: the placement to apply (-1: none passed) and where it left the
// coverage placement it computed (owner == nullptr: none, an interior collapse).
struct Proven {
  int placement = -1;
  ThreadScratch* owner = nullptr;
  std::uint32_t coverage = 0;  // index in owner->coverage_pool
};

// The vertices of St(a) ∪ St(b) (or of the given tets), each once, in the (deterministic) order
// the tets list them. Repeats are dropped with a probe set on the stack: a per-vertex mark array
// would cost a cache miss per vertex on large meshes.
template <class Tets>
void stencil_vertices(const MeshModel& mesh, const Tets& tets, std::size_t tet_count, std::vector<VertId>& out,
                      std::vector<VertId>& slots) {
  slots.resize(probe_slots_for(4 * tet_count));
  ProbeSet<VertId> seen(slots);
  tets([&](TetId t) {
    for (VertId y : mesh.tets[t])
      if (seen.insert(y).second) out.push_back(y);
  });
}

void stencil_of(const MeshModel& mesh, VertId a, VertId b, std::vector<VertId>& out, std::vector<VertId>& slots) {
  out.clear();
  prefetch_star(mesh, a);
  prefetch_star(mesh, b);
  stencil_vertices(
      mesh,
      [&](auto&& f) {
        mesh.for_each_tet_of(a, f);
        mesh.for_each_tet_of(b, f);
      },
      static_cast<std::size_t>(mesh.v2t_count[a]) + mesh.v2t_count[b], out, slots);
}

class Rounds {
 public:
  Rounds(MeshModel& mesh, const SimplifyOptions& options, const CollapseOptions& kernel, FieldBounds* bounds,
         std::uint64_t target, Report& report, CollapseLog* log, const RelaxStep& relax)
      : relax_(relax),
        mesh_(mesh),
        bounds_(bounds),
        coverage_(kernel.coverage),
        log_(log),
        options_(options),
        target_(target),
        report_(report),
        cost_(mesh, options, kernel.surfaces),
        proposals_(mesh, cost_, kernel),
        reservations_(mesh.vertex_capacity()),
        scratch_([&] {
          ThreadScratch s;
          s.fields.resize(static_cast<std::size_t>(mesh.field_stride()));
          return s;
        }),
        dirty_(mesh.vertex_capacity(), Dirty::kPropose),
        dirty_partner_(mesh.vertex_capacity(), kInvalid) {
    parallel::filter_map(
        mesh.vertex_capacity(), dirty_list_, [&](std::size_t v) { return !mesh.is_dead_vertex(static_cast<VertId>(v)); },
        [](std::size_t v) { return static_cast<VertId>(v); });
    refs_used_ = static_cast<std::uint32_t>(mesh.refs_table.size());
    live_ = mesh.live_vertex_count();
  }

  void run() {
    Progress progress(options_, live_, target_);
    bool refreshed_since_collapse = false;
    while (live_ > target_) {
      ++round_;
      proposals_.begin_round(round_);
      // Coverage results kept for the apply phase are valid within a round only (collapse.h).
      for (ThreadScratch& s : scratch_) s.proposal.collapse.coverage_for.u = kInvalid;
      RoundStats stats;
      auto t0 = Clock::now();
      evaluate(stats);
      stats.phase_seconds[0] = since(t0);

      t0 = Clock::now();
      threshold(stats);
      stats.phase_seconds[1] = since(t0);
      if (candidates_.empty()) {
        // Bans are lifted only where a star changes, and an edge can become legal through a change
        // at its other end alone: before giving up, look again at the edges whose other end
        // changed since they failed (refresh_stale).
        if (!refreshed_since_collapse) {
          refreshed_since_collapse = true;
          if (refresh_stale()) continue;
        }
        // A limit the caller lets relax held the vertices left: the driver relaxed it; every edge
        // gets one more look under it (and if none passes, the next relaxation is asked for).
        if (relax_ && relax_(cost_)) {
          proposals_.kernel_changed();
          // Flips at a stall (flip_at_stall.h) appended refs records past the collapses' headroom.
          refs_used_ = std::max(refs_used_, static_cast<std::uint32_t>(mesh_.refs_table.size()));
          refresh();
          continue;
        }
        report_.status = Status::kStoppedEarly;
        report_.message = "no legal collapse left";
        break;
      }

      t0 = Clock::now();
      verify();
      stats.phase_seconds[0] += since(t0);

      t0 = Clock::now();
      const bool below_max_cost = select(stats);
      stats.phase_seconds[1] += since(t0);
      if (!below_max_cost) {
        report_.status = Status::kStoppedEarly;
        report_.message = "the cheapest remaining collapse costs more than max_cost";
        break;
      }

      t0 = Clock::now();
      prove(stats);
      stats.phase_seconds[0] += since(t0);

      t0 = Clock::now();
      apply(stats);
      stats.phase_seconds[2] = since(t0);

      if (stats.collapses > 0) refreshed_since_collapse = false;
      fraction_ = next_fraction(stats.collapses);
      for (int k = 0; k < 4; ++k) report_.phase_seconds[k] += stats.phase_seconds[k];
      if (options_.round_log) options_.round_log->push_back(stats);
      ++report_.rounds;
      if (!progress.update(live_)) {
        report_.status = Status::kCancelled;
        report_.message = "cancelled by on_progress";
        break;
      }
    }
    for (const ThreadScratch& s : scratch_) {
      for (int k = 0; k < kCollapseReasonCount; ++k) report_.rejected[k] += s.proposal.rejected[k];
      report_.evaluations += s.proposal.evaluations;
      report_.legality_checks += s.proposal.checks;
    }
  }

 private:
  // --- 1. evaluate -------------------------------------------------------------------------------
  void evaluate(RoundStats& stats) {
    parallel::for_range<std::size_t>(0, dirty_list_.size(), 64, "evaluate", [&](std::size_t begin, std::size_t end) {
      ThreadScratch& s = scratch_.local();
      for (std::size_t i = begin; i < end; ++i) {
        const VertId a = dirty_list_[i];
        if (i + 2 < end) prefetch_star(mesh_, dirty_list_[i + 2]);  // overlap the next stars' misses
        if (mesh_.is_dead_vertex(a)) continue;
        if (dirty_[a] == Dirty::kPropose || !proposals_.update(a, dirty_partner_[a], s.proposal))
          proposals_.propose(a, s.proposal);
        dirty_[a] = Dirty::kClean;
      }
    });
    stats.evaluated = dirty_list_.size();
    dirty_list_.clear();
  }

  // The share of the proposals that competes in the next round. round_fraction asks for the
  // cheapest 1.5% of the *legal* collapses, but most of the cheapest proposals are illegal (they
  // invert a tet or break a link condition: on LOX at 2%, 90-96% of the proposals below the
  // threshold failed their verification after the first third of the run), so a fixed share of
  // the proposals let a round apply ~0.1% of the vertices and the run took 3,131 rounds. The
  // share is divided by the last round's pass rate (verified / competing, at least 1/16, at most
  // doubled or halved from one round to the next): the legal collapses a round takes are still
  // the cheapest ones, as the sequential order takes the cheapest legal one, and a failed
  // verification bans its edge, a check the sequential engine would make too. LOX: 3,131 -> 687
  // rounds, the families at 100k 1.6-2.3x fewer, field error and dihedral spread within 2% (but
  // sphere3's spread after the light optimisation: +9%; docs/performance.md).
  // A round without a collapse (the end of a run that the tolerance or the quality stops: the
  // cheapest proposals all fail) doubles the share: polycrystal 100k once spent 1,950 of its
  // 2,442 rounds without a collapse. The share is a function of counts, so the rounds stay the
  // same for every thread count.
  double next_fraction(std::uint64_t collapses) const {
    if (collapses == 0) return std::min(1.0, 2.0 * fraction_);
    const double wanted = options_.round_fraction / std::max(pass_rate_, 1.0 / 16.0);
    return std::clamp(wanted, std::max(options_.round_fraction, 0.5 * fraction_), std::min(1.0, 2.0 * fraction_));
  }

  // --- 2. threshold ------------------------------------------------------------------------------
  // The round's threshold and the proposals below it (candidates_, in vertex order).
  void threshold(RoundStats& stats) {
    threshold_ = sampled_quantile(fraction_, stats.serial_seconds);
    const double* rank_costs = proposals_.rank_costs();
    const double threshold_cost = threshold_.cost;
    parallel::filter_map_sparse(
        mesh_.vertex_capacity(), candidates_,
        [&](std::size_t begin, std::size_t end) {  // a branch-free pass over 8 costs skips most blocks
          int below = 0;
          if (end - begin == 8) {
            for (int k = 0; k < 8; ++k) below += rank_costs[begin + k] <= threshold_cost;  // unrolled
          } else {
            for (std::size_t a = begin; a < end; ++a) below += rank_costs[a] <= threshold_cost;
          }
          return below != 0;
        },
        [&](std::size_t a) {
          const VertId x = static_cast<VertId>(a);
          // (An infinite threshold lets every proposal compete, but never a vertex without one.)
          return std::isfinite(proposals_.rank_cost(x)) && proposals_.rank_cost(x) <= threshold_.cost &&
                 proposals_.ranked(x) < threshold_;
        },
        [](std::size_t a) { return static_cast<VertId>(a); });
  }

  // The key below which about `fraction` of the proposals lie: a sample of the proposals taken at
  // evenly spaced vertex ids (so it does not depend on the schedule) and its key at the wanted
  // quantile. An exact selection would be a sequential O(n) pass per round. The smallest sampled
  // proposal always passes, so a round with a sample is never empty; without one (very few
  // proposals left) everything competes.
  Ranked sampled_quantile(double fraction, double& serial_seconds) {
    const auto t0 = Clock::now();
    constexpr std::size_t kSampleSize = 4096;
    const std::size_t nv = mesh_.vertex_capacity();
    const std::size_t stride = std::max<std::size_t>(1, live_ / kSampleSize);
    sample_.clear();
    for (std::size_t a = 0; a < nv; a += stride)
      if (std::isfinite(proposals_.rank_cost(static_cast<VertId>(a)))) sample_.push_back(proposals_.ranked(static_cast<VertId>(a)));
    const std::size_t q = std::clamp<std::size_t>(
        static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(sample_.size()))), 1, sample_.size());
    Ranked key{kNoCost, kInvalid, kInvalid};
    if (q < sample_.size()) {
      std::nth_element(sample_.begin(), sample_.begin() + static_cast<std::ptrdiff_t>(q), sample_.end());
      key = sample_[q];
    }
    serial_seconds += since(t0);
    return key;
  }

  // --- 3. verify ---------------------------------------------------------------------------------
  void verify() {
    for (ThreadScratch& s : scratch_) s.stencil_pool.clear();
    stored_.assign(candidates_.size(), StoredStencil{});
    parallel::for_range<std::size_t>(0, candidates_.size(), 16, "verify", [&](std::size_t begin, std::size_t end) {
      ThreadScratch& s = scratch_.local();
      // The mesh does not change until apply(): a candidate tries its edges in turn, each with it
      // as one end.
      const ReuseClassifications reuse(s.proposal.collapse.link);
      for (std::size_t i = begin; i < end; ++i) {
        const VertId a = candidates_[i];
        if (i + 1 < end) {  // the next candidate's edge, while this one is checked
          const Ranked next = proposals_.ranked(candidates_[i + 1]);
          for (VertId x : {next.a, next.b}) {
            cost_.prefetch(x);
            prefetch_star(mesh_, x);
          }
        }
        if (proposals_.is_verified(a)) continue;
        proposals_.verify(a, threshold_, round_, s.proposal);
        if (proposals_.is_verified(a)) keep_stencil(i, s);
      }
    });
  }

  // The stencil of the edge just verified, from the stars the kernel gathered (still in cache),
  // kept for select(): most candidates that compete were verified in the same round.
  void keep_stencil(std::size_t candidate, ThreadScratch& s) {
    const CollapseScratch& c = s.proposal.collapse;
    const std::size_t offset = s.stencil_pool.size();
    stencil_vertices(
        mesh_,
        [&](auto&& f) {
          for (TetId t : c.star_u) f(t);
          for (TetId t : c.star_v) f(t);
        },
        c.star_u.size() + c.star_v.size(), s.stencil_pool, s.stencil_slots);
    stored_[candidate] = {&s, static_cast<std::uint32_t>(offset), static_cast<std::uint32_t>(s.stencil_pool.size() - offset)};
  }

  // --- 4. select ---------------------------------------------------------------------------------
  // Returns false when the cheapest verified collapse costs more than max_cost (stop).
  bool select(RoundStats& stats) {
    parallel::filter_map(
        candidates_.size(), ranked_,
        [&](std::size_t i) {
          const VertId a = candidates_[i];
          return proposals_.is_verified(a) && proposals_.ranked(a) < threshold_;
        },
        [&](std::size_t i) {
          Ranked r = proposals_.ranked(candidates_[i]);
          r.slot = static_cast<std::uint32_t>(i);
          return r;
        });
    pass_rate_ = candidates_.empty() ? 1.0 : static_cast<double>(ranked_.size()) / static_cast<double>(candidates_.size());
    parallel::sort(ranked_.begin(), ranked_.end());
    if (ranked_.size() > live_ - target_) ranked_.resize(live_ - target_);  // sorted: the cheapest stay
    if (options_.max_cost > 0.0) {
      if (!ranked_.empty() && ranked_.front().cost > options_.max_cost) return false;
      while (!ranked_.empty() && ranked_.back().cost > options_.max_cost) ranked_.pop_back();
    }
    stats.candidates = ranked_.size();
    gather_stencils(stats);
    reservations_.select(stencil_offsets_, stencils_, kReservationPasses, winners_);
    stats.winners = winners_.size();
    reserve_side_table(stats);
    return true;
  }

  // Each candidate's stencil, flattened: each goes into a fixed slot first; the rare one that
  // does not fit is copied again once the exact sizes are known.
  void gather_stencils(RoundStats& stats) {
    const std::size_t n = ranked_.size();
    constexpr std::uint32_t kSlot = 192;
    slots_.resize(n * kSlot);
    stencil_offsets_.assign(n + 1, 0);
    const auto stencil_into = [&](std::size_t i, ThreadScratch& s) -> const std::vector<VertId>& {
      const StoredStencil& kept = stored_[ranked_[i].slot];
      if (kept.owner != nullptr) {
        const VertId* begin = kept.owner->stencil_pool.data() + kept.offset;
        s.stencil.assign(begin, begin + kept.size);
      } else {
        stencil_of(mesh_, ranked_[i].a, ranked_[i].b, s.stencil, s.stencil_slots);
      }
      return s.stencil;
    };
    parallel::for_range<std::size_t>(0, n, 64, "gather_stencils", [&](std::size_t b, std::size_t e) {
      ThreadScratch& s = scratch_.local();
      for (std::size_t i = b; i < e; ++i) {
        const std::vector<VertId>& stencil = stencil_into(i, s);
        stencil_offsets_[i + 1] = static_cast<std::uint32_t>(stencil.size());
        if (stencil.size() <= kSlot) std::copy(stencil.begin(), stencil.end(), slots_.begin() + i * kSlot);
      }
    });
    const auto serial_start = Clock::now();
    sizes_.assign(stencil_offsets_.begin() + 1, stencil_offsets_.end());
    for (std::size_t i = 0; i < n; ++i) stencil_offsets_[i + 1] += stencil_offsets_[i];
    stencils_.resize(stencil_offsets_[n]);
    stats.serial_seconds += since(serial_start);
    parallel::for_range<std::size_t>(0, n, 256, "flatten_stencils", [&](std::size_t b, std::size_t e) {
      ThreadScratch& s = scratch_.local();
      for (std::size_t i = b; i < e; ++i) {
        if (sizes_[i] <= kSlot) {
          std::copy_n(slots_.begin() + i * kSlot, sizes_[i], stencils_.begin() + stencil_offsets_[i]);
        } else {
          const std::vector<VertId>& stencil = stencil_into(i, s);
          std::copy(stencil.begin(), stencil.end(), stencils_.begin() + stencil_offsets_[i]);
        }
      }
    });
  }

  // A collapse can take at most |St(u)| + |St(v)| new side-table slots, and none when both ends
  // are interior (no flagged face or edge through them: collapse() changes no flag).
  void reserve_side_table(RoundStats& stats) {
    const auto serial_start = Clock::now();
    std::size_t star_tets = 0;
    for (std::uint32_t i : winners_) {
      const VertId a = ranked_[i].a, b = ranked_[i].b;
      if (!cost_.known_interior(a) || !cost_.known_interior(b)) star_tets += mesh_.v2t_count[a] + mesh_.v2t_count[b];
    }
    reserve_refs_headroom(mesh_, refs_used_, star_tets);
    stats.serial_seconds += since(serial_start);
  }

  // --- 4b. prove ---------------------------------------------------------------------------------
  // The tolerance proof of each winner (the verification deferred it: proposals.h, prove()), in
  // parallel over the winners, whose stencils are reserved and unchanged. A winner none of whose
  // placements passes gives its reservation back and proposes again in the next round; the others
  // keep their order, so the round stays the same for every thread count.
  void prove(RoundStats& stats) {
    proven_.assign(winners_.size(), Proven{});
    for (ThreadScratch& s : scratch_) s.coverage_count = 0;
    parallel::for_range<std::size_t>(0, winners_.size(), 16, "prove", [&](std::size_t b, std::size_t e) {
      ThreadScratch& s = scratch_.local();
      for (std::size_t w = b; w < e; ++w) {
        const Ranked& r = ranked_[winners_[w]];
        CollapseScratch& kernel = s.proposal.collapse;
        kernel.coverage_for.u = kInvalid;
        proven_[w].placement = proposals_.prove(r.a, s.proposal);
        if (proven_[w].placement < 0) {
          const std::uint32_t i = winners_[w];
          reservations_.release(stencils_.data() + stencil_offsets_[i], stencils_.data() + stencil_offsets_[i + 1]);
          mark(r.a, Dirty::kPropose, kInvalid, s);
          continue;
        }
        if (coverage_ == nullptr || kernel.coverage_for.u == kInvalid) continue;
        // Keep the coverage placement for apply(): placing the items again there would double
        // the price of the tolerance on every surface collapse.
        if (s.coverage_count == s.coverage_pool.size()) s.coverage_pool.emplace_back();
        ThreadScratch::KeptCoverage& kept = s.coverage_pool[s.coverage_count];
        kept.placement = kernel.coverage_for;
        swap_commit_state(kept.coverage, kernel.coverage);  // capacities are reused both ways
        kernel.coverage_for.u = kInvalid;
        proven_[w].owner = &s;
        proven_[w].coverage = static_cast<std::uint32_t>(s.coverage_count++);
      }
    });
    std::size_t kept = 0;
    for (std::size_t w = 0; w < winners_.size(); ++w)
      if (proven_[w].placement >= 0) {
        winners_[kept] = winners_[w];
        proven_[kept++] = proven_[w];
      }
    stats.winners_refused = winners_.size() - kept;
    // A round whose proofs refuse a quarter of its winners: the tolerance binds (a curved surface
    // near the end of a tolerance-limited run), and a refused winner costs a round per edge, where
    // the verification would try the vertex's next edges at once. From then on it proves them.
    if (4 * stats.winners_refused > winners_.size()) proposals_.screen_in_verify();
    winners_.resize(kept);
    proven_.resize(kept);
  }

  // What SurfaceCoverage::commit reads of a coverage placement.
  static void swap_commit_state(CoverageScratch& x, CoverageScratch& y) {
    std::swap(x.placed, y.placed);
    std::swap(x.targets, y.targets);
    std::swap(x.segment_placed, y.segment_placed);
    std::swap(x.segment_targets, y.segment_targets);
  }

  // The coverage placement prove() kept for winner w, back in the kernel's scratch (collapse()
  // commits it when it is for the same u, v and p; otherwise it places the items itself).
  static void restore_coverage(const Proven& proven, CollapseScratch& kernel) {
    kernel.coverage_for.u = kInvalid;
    if (proven.owner == nullptr) return;
    ThreadScratch::KeptCoverage& kept = proven.owner->coverage_pool[proven.coverage];
    swap_commit_state(kept.coverage, kernel.coverage);
    kernel.coverage_for = kept.placement;
  }

  // --- 5. apply ----------------------------------------------------------------------------------
  void apply(RoundStats& stats) {
    std::atomic<std::uint64_t> applied{0};
    applied_cost_.assign(winners_.size(), -1.0);
    if (log_ != nullptr) log_->begin_batch(winners_.size());
    parallel::for_range<std::size_t>(0, winners_.size(), 16, "apply", [&](std::size_t b, std::size_t e) {
      ThreadScratch& s = scratch_.local();
      std::uint64_t n_applied = 0;
      for (std::size_t w = b; w < e; ++w) {
        const std::uint32_t i = winners_[w];
        const Ranked& r = ranked_[i];
        if (w + 1 < e) {  // the next winner's stars and records, while this one collapses
          const Ranked& next = ranked_[winners_[w + 1]];
          for (VertId x : {next.a, next.b}) {
            cost_.prefetch(x);
            prefetch_star(mesh_, x);
          }
        }
        CollapseCandidate* cands = s.proposal.cands;
        CollapseScratch& kernel = s.proposal.collapse;
        const int n = cost_.candidates(mesh_, r.a, r.b, cands, kernel.link);
        const int chosen = proven_[w].placement;
        // The stencil has not changed since the verification, so neither have the candidates
        // (the proof may have moved on to a later placement of the same edge).
        if (chosen < 0 || chosen >= n || cands[chosen].cost < r.cost)
          throw std::logic_error("parallel rounds: a verified proposal changed before it was applied");
        const CollapseCandidate& c = cands[chosen];
        restore_coverage(proven_[w], kernel);
        cost_.fields_at(mesh_, c, s.fields.data());
        if (log_ != nullptr) log_->record(w, mesh_, c.u, c.v, c.p, s.fields.data(), c.cost);
        const float star_bound = collapse(mesh_, c.u, c.v, c.p, s.fields.data(), kernel, refs_used_, bounds_, coverage_);
        if (log_ != nullptr) {
          log_->depend(w, kernel.star_u, kernel.star_v);
          if (bounds_ != nullptr) log_->bound(w, star_bound);
        }
        cost_.on_collapse(mesh_, c.u, c.v);
        applied_cost_[w] = c.cost;
        ++n_applied;
        const VertId* first = stencils_.data() + stencil_offsets_[i];
        const VertId* last = stencils_.data() + stencil_offsets_[i + 1];
        mark_stencil(c, first, last, s);
        reservations_.release(first, last);
      }
      applied.fetch_add(n_applied, std::memory_order_relaxed);  // a count, read after the join
    });
    stats.collapses = applied.load();
    if (log_ != nullptr) log_->end_batch();
    for (double c : applied_cost_) stats.max_cost = std::max(stats.max_cost, c);
    report_.max_cost = std::max(report_.max_cost, stats.max_cost);
    report_.collapses += stats.collapses;
    live_ -= stats.collapses;
    for (ThreadScratch& s : scratch_) {
      dirty_list_.insert(dirty_list_.end(), s.marked.begin(), s.marked.end());
      s.marked.clear();
    }
  }

  // After collapse u <- v, every vertex of the stencil (old St(u) ∪ St(v)) had its star changed
  // (Proposals::star_changed says what it must redo). Feature vertices of the removed tets may
  // also change order (CostModel::on_collapse marks them stale), and with it the placements and
  // costs of their edges: their proposals are updated like the others' and not redone, since an
  // order change is rare and verification always works from fresh costs (a stale ranking costs a
  // little quality, never safety).
  // The work that only reads this stencil is done at once, while it is in cache: u re-proposes
  // (all its neighbours are in the stencil) and the updates re-cost edges xu. It gives the same
  // result as in the next evaluate phase, since no other winner of the round touches the stencil.
  // Proposals that need vertices outside it (from scratch, for x != u) wait for that phase.
  // Stencils of one round are disjoint, so every write here is to this winner's own vertices.
  void mark_stencil(const CollapseCandidate& c, const VertId* first, const VertId* last, ThreadScratch& s) {
    auto& redo = s.redo;
    redo.clear();
    for (const VertId* it = first; it != last; ++it) {
      const VertId x = *it;
      if (x == c.v)
        proposals_.removed(x, round_);
      else
        redo.push_back({x, proposals_.star_changed(x, c.u, c.v, round_, s.proposal.collapse.star_u, s.proposal.collapse.star_v)});
    }
    for (TetId t : s.proposal.collapse.star_uv)
      for (VertId x : mesh_.tets[t])
        if (x != c.v && !cost_.known_interior(x))
          for (auto& [y, what] : redo)
            if (y == x && what == Proposals::Redo::kNothing) what = Proposals::Redo::kUpdate;
    for (const auto& [x, what] : redo) {
      if (what == Proposals::Redo::kPropose) {
        if (x == c.u)
          proposals_.propose(x, s.proposal);
        else
          mark(x, Dirty::kPropose, c.u, s);
      } else if (what == Proposals::Redo::kUpdate && !proposals_.update(x, c.u, s.proposal)) {
        mark(x, Dirty::kPropose, c.u, s);
      }
    }
  }

  void mark(VertId x, Dirty what, VertId u, ThreadScratch& s) {
    dirty_[x] = what;
    dirty_partner_[x] = u;
    s.marked.push_back(x);
  }

  // Before stopping (or relaxing): the vertices whose refusals may be out of date propose again
  // (Proposals::refresh_if_stale: a ban whose far end changed its star since). The others' edges
  // were all refused since their stars last changed, so a look at every edge would refuse them
  // again (polycrystal 30k at 10%: 141,913 -> 104,641 legality checks, same output). Returns whether
  // any vertex proposes again.
  bool refresh_stale() {
    // The sparse filter calls its keep once per vertex (refresh_if_stale lifts bans as it goes).
    parallel::filter_map_sparse(
        mesh_.vertex_capacity(), dirty_list_, [](std::size_t, std::size_t) { return true; },
        [&](std::size_t v) {
          return !mesh_.is_dead_vertex(static_cast<VertId>(v)) &&
                 proposals_.refresh_if_stale(static_cast<VertId>(v), scratch_.local().proposal);
        },
        [](std::size_t v) { return static_cast<VertId>(v); });
    for (VertId v : dirty_list_) dirty_[v] = Dirty::kPropose;
    return !dirty_list_.empty();
  }

  // Lifts every ban and re-proposes every vertex (after a relaxation: every verdict is void).
  void refresh() {
    proposals_.lift_all_bans();
    parallel::filter_map(
        mesh_.vertex_capacity(), dirty_list_, [&](std::size_t v) { return !mesh_.is_dead_vertex(static_cast<VertId>(v)); },
        [](std::size_t v) { return static_cast<VertId>(v); });
    for (VertId v : dirty_list_) dirty_[v] = Dirty::kPropose;
  }

 public:
  CostModel& cost() { return cost_; }  // for the driver's finish step after the run (engines.h)

  // Frees everything but the cost model once the run is over: the finish step (stop diagnosis,
  // optimisation) allocates its own, and a run's peak memory was at its end (cube-sphere 1M: the
  // proposals' 12 MB under the optimisation's stars and grids).
  void release() {
    proposals_.release();
    std::vector<Dirty>().swap(dirty_);
    std::vector<VertId>().swap(dirty_partner_);
    std::vector<VertId>().swap(dirty_list_);
    std::vector<VertId>().swap(candidates_);
    std::vector<StoredStencil>().swap(stored_);
    std::vector<Ranked>().swap(ranked_);
    std::vector<Ranked>().swap(sample_);
    std::vector<std::uint32_t>().swap(stencil_offsets_);
    std::vector<std::uint32_t>().swap(sizes_);
    std::vector<VertId>().swap(stencils_);
    std::vector<VertId>().swap(slots_);
    std::vector<std::uint32_t>().swap(winners_);
    std::vector<Proven>().swap(proven_);
    std::vector<double>().swap(applied_cost_);
  }

 private:
  const RelaxStep& relax_;
  MeshModel& mesh_;
  FieldBounds* bounds_;  // nullptr = none; each collapse updates its own stencil's bounds
  SurfaceCoverage* coverage_;  // nullptr = none; each collapse moves its own stencil's surface items
  CollapseLog* log_;     // nullptr unless simplify_with_hierarchy records the collapses
  const SimplifyOptions& options_;
  const std::uint64_t target_;
  Report& report_;
  CostModel cost_;
  Proposals proposals_;
  parallel::Reservations reservations_;  // over vertex ids
  parallel::PerThread<ThreadScratch> scratch_;

  std::uint32_t round_ = 0;
  double pass_rate_ = 1.0;  // verified / competing proposals in the last round (select())
  double fraction_ = options_.round_fraction;  // the share of the proposals that compete (next_fraction())
  std::uint64_t live_ = 0;
  std::uint32_t refs_used_ = 0;
  Ranked threshold_{kNoCost, kInvalid, kInvalid};

  // Per vertex.
  std::vector<Dirty> dirty_;
  std::vector<VertId> dirty_partner_;  // the survivor u of the collapse that made the vertex dirty

  // Per round.
  std::vector<VertId> dirty_list_;
  std::vector<VertId> candidates_;
  std::vector<StoredStencil> stored_;  // [position in candidates_]
  std::vector<Ranked> ranked_, sample_;
  std::vector<std::uint32_t> stencil_offsets_, sizes_;
  std::vector<VertId> stencils_, slots_;
  std::vector<std::uint32_t> winners_;
  std::vector<Proven> proven_;  // [position in winners_]
  std::vector<double> applied_cost_;
};

}  // namespace

void simplify_parallel(MeshModel& mesh, const SimplifyOptions& options, const CollapseOptions& kernel,
                       FieldBounds* bounds, std::uint64_t target, Report& report, CollapseLog* log,
                       const FinishStep& finish, const RelaxStep& relax) {
  Rounds rounds(mesh, options, kernel, bounds, target, report, log, relax);
  rounds.run();
  rounds.release();
  if (finish && report.status != Status::kCancelled) finish(rounds.cost());
}

}  // namespace topotet::detail
