// The parallel engine: rounds of independent collapses, deterministic for any thread count.
//
//   quadrics, orders <- CostModel(mesh); every vertex is dirty
//   round r = 1, 2, ... while live vertices > target:
//     1. evaluate (parallel over the dirty vertices a): a's proposal is its cheapest edge ab among
//        the edges it owns (b > a) and has not banned, by cost only. A vertex whose neighbourhood
//        changed only through the survivor u of a nearby collapse re-costs the one edge au.
//     2. verify (parallel over the proposals at or below the round's threshold: a sampled
//        quantile of all proposal costs, about the cheapest round_fraction): run the whole kernel
//        (geometry, link conditions of K and K~, quality, tolerance) on a's edges in cost order
//        until one passes, banning the ones that fail, or the next one costs more than the
//        threshold. A verified proposal stays verified until a collapse changes the star of one
//        of its ends (changed_round), so most proposals are checked once, just before they
//        compete, and the many that are superseded first are never checked at all.
//     3. select: the verified proposals at or below the threshold, sorted by (cost, a, b), at most
//        live - target of them, reserve their stencils St(a) ∪ St(b) (vertices) by rank; a
//        proposal wins iff it owns its whole stencil (several passes, see reserve()): winners'
//        stencils are disjoint.
//     4. apply (parallel over winners): collapse with the verified placement (the stencil is
//        untouched since the verification, so it still holds), then mark the stencil: its
//        vertices' stars changed (changed_round = r), u and the vertices whose proposal went
//        through u or v re-propose, lower neighbours of u re-cost their edge to u.
//   stop when the target is reached or no proposal is left (after one refresh that lifts all bans)
//
// Why the output is bit-identical for any thread count: every proposal and verification is a pure
// function of the mesh at the start of its phase and of the vertex's own state; the threshold is
// computed from a sample taken in vertex order; ranks come from a total order; reservations keep
// the minimum; the collapses of one round touch disjoint data. Only side-table slot numbers depend
// on the schedule, and they are never part of the output (compaction renumbers them in tet order).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "collapse.h"
#include "cost.h"
#include "engines.h"
#include "parallel/filter.h"
#include "parallel/for_range.h"
#include "parallel/scratch.h"
#include "probe_set.h"

namespace topotet::detail {
namespace {

constexpr std::uint32_t kFree = std::numeric_limits<std::uint32_t>::max();
constexpr double kNoCost = std::numeric_limits<double>::infinity();
// Reservation passes per round (see reserve()). Most winners come from the first few passes.
constexpr int kReservationPasses = 8;
// Banned edges are remembered as bits over a vertex's owned neighbours (sorted), which stay the
// same until the vertex's star changes; that is exactly when bans are lifted.
constexpr int kBanBits = 32;

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Vertex a's proposal: the edge ab (b > a) it would collapse. Edges are ordered by the cost of
// their cheapest placement; a verified proposal also carries the placement that passed the kernel
// (the first acceptable one in cost order) and its cost, which is what it competes with. The
// runner-up edge is kept when known, so that losing the best edge (it went through a collapsed
// vertex) rarely needs a full re-proposal.
struct Proposal {
  double cost = kNoCost;         // cheapest placement of edge (a, b); kNoCost = no proposal
  double second_cost = kNoCost;  // cheapest placement of the runner-up edge (a, second)
  VertId b = kInvalid;
  VertId second = kInvalid;          // kInvalid = runner-up unknown (or none)
  std::uint32_t verified_round = 0;  // round of the last successful verification; 0 = never
  std::int8_t placement = -1;        // verified: index into CostModel::candidates(a, b)
  // The cost the proposal competes with (the verified placement's, once verified) is kept in
  // Rounds::rank_cost_, where the round's scans read it.

  void set_best(double c, VertId x) {
    cost = c;
    b = x;
    placement = -1;
  }
};

// (cost, b) order among one vertex's edges: ties go to the lower id.
bool cheaper(double c1, VertId b1, double c2, VertId b2) { return c1 != c2 ? c1 < c2 : b1 < b2; }

// What a vertex must do in the next evaluate phase.
enum class Dirty : std::uint8_t { kClean, kFull, kEdge };

struct Ranked {
  double cost;
  VertId a, b;
  std::uint32_t slot = 0;  // select: position of a in the round's candidate list (not part of the order)
  bool operator<(const Ranked& o) const { return cost != o.cost ? cost < o.cost : (a != o.a ? a < o.a : b < o.b); }
};

struct EdgeCost {
  double cost;      // of the edge's cheapest placement
  VertId b;
  int owned_index;  // position among the owned neighbours (ban bit)
};

struct ThreadScratch {
  CollapseScratch collapse;
  CollapseCandidate cands[4];
  std::vector<VertId> nbrs;
  std::vector<EdgeCost> edges;
  std::vector<std::uint32_t> edge_order;
  std::vector<double> fields;
  std::vector<VertId> stencil;
  std::vector<VertId> stencil_pool;  // stencils of the proposals this thread verified this round
  std::vector<VertId> stencil_slots;  // probe set storage for stencil_of
  std::vector<VertId> marked;  // vertices the apply phase made dirty
  std::array<std::uint64_t, kCollapseReasonCount> rejected{};
  std::uint64_t evaluations = 0, checks = 0;
};

// The neighbours b > a: the edges a owns.
void neighbours_above(const TetMesh& mesh, VertId a, std::vector<VertId>& out) {
  mesh.neighbours(a, out);
  out.erase(out.begin(), std::upper_bound(out.begin(), out.end(), a));
}

// The vertices of St(a) ∪ St(b), each once, in the (deterministic) order the incidence chains
// list them. Repeats are dropped with a probe set on the stack: a per-vertex mark array would
// cost a cache miss per vertex on large meshes.
void stencil_of(const TetMesh& mesh, VertId a, VertId b, std::vector<VertId>& out, std::vector<VertId>& slots) {
  slots.resize(probe_slots_for(4 * (static_cast<std::size_t>(mesh.v2t_count[a]) + mesh.v2t_count[b])));
  ProbeSet<VertId> seen(slots);
  out.clear();
  for (VertId x : {a, b})
    mesh.for_each_tet_of(x, [&](TetId t) {
      for (VertId y : mesh.tets[t])
        if (seen.insert(y).second) out.push_back(y);
    });
}

class Rounds {
 public:
  Rounds(TetMesh& mesh, const SimplifyOptions& options, const CollapseOptions& kernel, std::uint64_t target,
         Report& report)
      : mesh_(mesh),
        options_(options),
        kernel_(kernel),
        target_(target),
        report_(report),
        cost_(mesh, options),
        scratch_([&] {
          ThreadScratch s;
          s.fields.resize(static_cast<std::size_t>(mesh.field_stride()));
          return s;
        }) {
    const std::size_t nv = mesh.positions.size();
    proposal_.resize(nv);
    rank_cost_.assign(nv, kNoCost);
    dirty_.assign(nv, Dirty::kFull);
    dirty_partner_.assign(nv, kInvalid);
    bans_.assign(nv, 0);
    changed_round_.assign(nv, 0);
    claimed_.assign(nv, 0);
    owner_.reset(new std::atomic<std::uint32_t>[nv]);
    for (std::size_t v = 0; v < nv; ++v) owner_[v].store(kFree, std::memory_order_relaxed);
    parallel::filter_map(
        nv, dirty_list_, [&](std::size_t v) { return !mesh.is_dead_vertex(static_cast<VertId>(v)); },
        [](std::size_t v) { return static_cast<VertId>(v); });
    refs_used_ = static_cast<std::uint32_t>(mesh.refs_table.size());
    live_ = mesh.live_vertex_count();
  }

  void run() {
    Progress progress(options_, live_, target_);
    bool refreshed_since_collapse = false;
    while (live_ > target_) {
      ++round_;
      RoundStats stats;
      auto t0 = Clock::now();
      evaluate(stats);
      stats.phase_seconds[0] = since(t0);

      t0 = Clock::now();
      collect_proposals(stats);
      stats.phase_seconds[1] = since(t0);
      if (candidates_.empty()) {
        // Bans are lifted only where a star changes, and an edge can become legal through a change
        // at its other end alone: before giving up, look at every edge once more.
        if (!refreshed_since_collapse) {
          refresh();
          refreshed_since_collapse = true;
          continue;
        }
        report_.status = Status::kStoppedEarly;
        report_.message = "no legal collapse left";
        break;
      }

      t0 = Clock::now();
      verify(stats);
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
      apply(stats);
      stats.phase_seconds[2] = since(t0);

      if (stats.collapses > 0) refreshed_since_collapse = false;
      for (int k = 0; k < 4; ++k) report_.phase_seconds[k] += stats.phase_seconds[k];
      report_.round_stats.push_back(stats);
      ++report_.rounds;
      if (!progress.update(live_)) {
        report_.status = Status::kCancelled;
        report_.message = "cancelled by on_progress";
        break;
      }
    }
    for (const ThreadScratch& s : scratch_) {
      for (int k = 0; k < kCollapseReasonCount; ++k) report_.rejected[k] += s.rejected[k];
      report_.evaluations += s.evaluations;
      report_.legality_checks += s.checks;
    }
  }

 private:
  // --- 1. evaluate: costs only -------------------------------------------------------------------
  void evaluate(RoundStats& stats) {
    parallel::for_range<std::size_t>(0, dirty_list_.size(), 64, "evaluate", [&](std::size_t begin, std::size_t end) {
      ThreadScratch& s = scratch_.local();
      for (std::size_t i = begin; i < end; ++i) {
        const VertId a = dirty_list_[i];
        if (mesh_.is_dead_vertex(a)) continue;
        if (dirty_[a] == Dirty::kFull || !update_edge(a, dirty_partner_[a], s)) full_proposal(a, s);
        publish(a);
        dirty_[a] = Dirty::kClean;
      }
    });
    stats.evaluated = dirty_list_.size();
    dirty_list_.clear();
  }

  // Costs of every owned, unbanned, allowed edge of a into s.edges.
  void cost_owned_edges(VertId a, ThreadScratch& s) {
    neighbours_above(mesh_, a, s.nbrs);
    s.edges.clear();
    for (std::size_t k = 0; k < s.nbrs.size(); ++k) {
      if (is_banned(a, static_cast<int>(k))) continue;
      ++s.evaluations;
      const double c = cost_.edge_cost(mesh_, a, s.nbrs[k], s.collapse.link);
      if (std::isfinite(c)) s.edges.push_back({c, s.nbrs[k], static_cast<int>(k)});
    }
  }

  bool is_banned(VertId a, int owned_index) const {
    // Edges past the ban bits cannot be banned; a vertex that needs to is exhausted instead.
    return bans_[a] == ~0u || (owned_index < kBanBits && ((bans_[a] >> owned_index) & 1u));
  }

  // a's best and runner-up edges, from scratch.
  void full_proposal(VertId a, ThreadScratch& s) {
    cost_owned_edges(a, s);
    Proposal p;
    for (const EdgeCost& e : s.edges) {
      const double c = e.cost;
      if (cheaper(c, e.b, p.cost, p.b)) {
        p.second_cost = p.cost;
        p.second = p.b;
        p.set_best(c, e.b);
      } else if (cheaper(c, e.b, p.second_cost, p.second)) {
        p.second_cost = c;
        p.second = e.b;
      }
    }
    proposal_[a] = p;
  }

  // After a's proposal changed without a verification: it competes with its edge's cost.
  void publish(VertId a) {
    if (proposal_[a].placement < 0) rank_cost_[a] = proposal_[a].cost;
  }

  // After a collapse that kept u (and removed some v): the edge au changed cost and edges to dead
  // vertices are gone; a's other edges kept their costs. Updates best and runner-up from what is
  // known; false when that is not enough (the best is gone and the runner-up is unknown).
  bool update_edge(VertId a, VertId u, ThreadScratch& s) {
    Proposal& p = proposal_[a];
    const auto stale = [&](VertId x) { return x == kInvalid || x == u || mesh_.is_dead_vertex(x); };
    if (stale(p.b)) {
      if (stale(p.second)) return false;
      p.set_best(p.second_cost, p.second);  // the runner-up was the cheapest of the others
      p.second = kInvalid;                   // and what comes after it is not known
      p.second_cost = kNoCost;
    } else if (p.second != kInvalid && stale(p.second)) {
      p.second = kInvalid;
      p.second_cost = kNoCost;
    }
    p.placement = -1;
    if (u > a && !mesh_.is_dead_vertex(u)) {  // a owns au: re-cost it
      ++s.evaluations;
      const double c = cost_.edge_cost(mesh_, a, u, s.collapse.link);
      if (std::isfinite(c)) {
        if (cheaper(c, u, p.cost, p.b)) {
          p.second_cost = p.cost;
          p.second = p.b;
          p.set_best(c, u);
        } else if (p.second != kInvalid && cheaper(c, u, p.second_cost, p.second)) {
          p.second_cost = c;
          p.second = u;
        }
      }
    }
    return true;
  }

  // --- 2. threshold and verification -------------------------------------------------------------
  bool is_verified(VertId a) const {
    const Proposal& p = proposal_[a];
    return p.placement >= 0 && p.verified_round > changed_round_[a] && p.verified_round > changed_round_[p.b];
  }
  Ranked ranked(VertId a) const { return Ranked{rank_cost_[a], a, proposal_[a].b}; }

  // The round's threshold and the proposals below it (candidates_, in vertex order).
  void collect_proposals(RoundStats& stats) {
    threshold_ = quantile(options_.round_fraction, stats.serial_seconds);
    const std::size_t nv = proposal_.size();
    parallel::filter_map(
        nv, candidates_, [&](std::size_t a) { return rank_cost_[a] <= threshold_.cost && ranked(static_cast<VertId>(a)) < threshold_; },
        [](std::size_t a) { return static_cast<VertId>(a); });
  }

  // The key below which about `fraction` of the proposals lie: a sample of the proposals taken at
  // evenly spaced vertex ids (so it does not depend on the schedule) is sorted and its key at the
  // wanted quantile is the threshold. An exact selection would be a sequential O(n) pass per
  // round. The smallest sampled proposal always passes, so a round with a sample is never empty;
  // without one (very few proposals left) everything competes.
  Ranked quantile(double fraction, double& serial_seconds) {
    const auto t0 = Clock::now();
    constexpr std::size_t kSampleSize = 4096;
    const std::size_t nv = proposal_.size();
    const std::size_t stride = std::max<std::size_t>(1, live_ / kSampleSize);
    sample_.clear();
    for (std::size_t a = 0; a < nv; a += stride)
      if (std::isfinite(rank_cost_[a])) sample_.push_back(ranked(static_cast<VertId>(a)));
    const std::size_t q = std::clamp<std::size_t>(
        static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(sample_.size()))), 1, sample_.size());
    if (q >= sample_.size()) {
      serial_seconds += since(t0);
      return Ranked{kNoCost, kInvalid, kInvalid};
    }
    std::nth_element(sample_.begin(), sample_.begin() + static_cast<std::ptrdiff_t>(q), sample_.end());
    serial_seconds += since(t0);
    return sample_[q];
  }

  bool below_threshold(double cost, VertId a, VertId b) const { return Ranked{cost, a, b} < threshold_; }

  void verify(RoundStats&) {
    // The proposals that compete this round; some were verified in an earlier round and are still.
    for (ThreadScratch& s : scratch_) s.stencil_pool.clear();
    stored_.assign(candidates_.size(), StoredStencil{});
    parallel::for_range<std::size_t>(0, candidates_.size(), 16, "verify", [&](std::size_t begin, std::size_t end) {
      ThreadScratch& s = scratch_.local();
      for (std::size_t i = begin; i < end; ++i) {
        const VertId a = candidates_[i];
        if (is_verified(a)) continue;
        verify_vertex(a, s);
        publish(a);
        if (proposal_[a].verified_round == round_) keep_stencil(i, s);
      }
    });
  }

  // Full kernel check of a's edges in cost order, from its current proposal on (see the header).
  void verify_vertex(VertId a, ThreadScratch& s) {
    Proposal& p = proposal_[a];
    // Fast path: the proposed edge passes (its costs are recomputed: they may have changed through
    // the other end's quadric or orders since the proposal was made).
    {
      ++s.evaluations;
      const int n = cost_.candidates(mesh_, a, p.b, s.cands, s.collapse.link);
      if (n > 0) p.set_best(s.cands[0].cost, p.b);
      if (n > 0 && below_threshold(p.cost, a, p.b)) {
        const int chosen = check(a, p.b, s.cands, n, s);
        if (chosen >= 0) {
          verified(p, s.cands[chosen].cost, chosen);
          return;
        }
        ban_index(a, owned_index(a, p.b, s));
      } else if (n > 0) {
        return;  // costlier than it was: competes in a later round
      }
    }
    // The runner-up, when known, is the next edge in cost order: one more evaluation, not all.
    const VertId runner_up = p.second;
    if (runner_up != kInvalid && !mesh_.is_dead_vertex(runner_up) && !is_banned(a, owned_index(a, runner_up, s))) {
      ++s.evaluations;
      const int n = cost_.candidates(mesh_, a, runner_up, s.cands, s.collapse.link);
      if (n > 0) {
        p = Proposal{};
        p.set_best(s.cands[0].cost, runner_up);
        if (!below_threshold(p.cost, a, runner_up)) return;
        const int chosen = check(a, runner_up, s.cands, n, s);
        if (chosen >= 0) {
          verified(p, s.cands[chosen].cost, chosen);
          return;
        }
        ban_index(a, owned_index(a, runner_up, s));
      }
    }
    // Both failed: walk the others in cost order.
    cost_owned_edges(a, s);
    s.edge_order.resize(s.edges.size());
    for (std::uint32_t k = 0; k < s.edges.size(); ++k) s.edge_order[k] = k;
    std::sort(s.edge_order.begin(), s.edge_order.end(), [&](std::uint32_t x, std::uint32_t y) {
      return cheaper(s.edges[x].cost, s.edges[x].b, s.edges[y].cost, s.edges[y].b);
    });
    for (std::size_t k = 0; k < s.edge_order.size(); ++k) {
      const EdgeCost& e = s.edges[s.edge_order[k]];
      p = Proposal{};
      p.set_best(e.cost, e.b);
      if (k + 1 < s.edge_order.size()) {
        const EdgeCost& next = s.edges[s.edge_order[k + 1]];
        p.second_cost = next.cost;
        p.second = next.b;
      }
      if (!below_threshold(p.cost, a, e.b)) return;
      ++s.evaluations;
      const int n = cost_.candidates(mesh_, a, e.b, s.cands, s.collapse.link);
      const int chosen = check(a, e.b, s.cands, n, s);
      if (chosen >= 0) {
        verified(p, s.cands[chosen].cost, chosen);
        return;
      }
      ban_index(a, e.owned_index);
    }
    p = Proposal{};
  }

  // The stencil of the edge just verified, from the stars the kernel gathered (still in cache),
  // kept for select(): most proposals that compete were verified in the same round.
  void keep_stencil(std::size_t candidate, ThreadScratch& s) {
    const CollapseScratch& c = s.collapse;
    s.stencil_slots.resize(probe_slots_for(4 * (c.star_u.size() + c.star_v.size())));
    ProbeSet<VertId> seen(s.stencil_slots);
    const std::size_t offset = s.stencil_pool.size();
    for (const auto* star : {&c.star_u, &c.star_v})
      for (TetId t : *star)
        for (VertId y : mesh_.tets[t])
          if (seen.insert(y).second) s.stencil_pool.push_back(y);
    stored_[candidate] = {&s, static_cast<std::uint32_t>(offset), static_cast<std::uint32_t>(s.stencil_pool.size() - offset)};
  }

  void verified(Proposal& p, double cost, int placement) {
    p.verified_round = round_;
    p.placement = static_cast<std::int8_t>(placement);
    rank_cost_[&p - proposal_.data()] = cost;
  }

  int check(VertId a, VertId b, const CollapseCandidate* cands, int n, ThreadScratch& s) {
    Placement placements[4];
    for (int i = 0; i < n; ++i) placements[i] = {cands[i].u, cands[i].v, cands[i].p};
    ++s.checks;
    cost_.hint_orders(a, b, s.collapse.link);
    return first_acceptable(mesh_, placements, n, kernel_, s.collapse, &s.rejected);
  }

  // Position of b among a's owned neighbours (sorted): the bit that bans edge ab.
  int owned_index(VertId a, VertId b, ThreadScratch& s) const {
    neighbours_above(mesh_, a, s.nbrs);
    return static_cast<int>(std::lower_bound(s.nbrs.begin(), s.nbrs.end(), b) - s.nbrs.begin());
  }

  void ban_index(VertId a, int owned_index) {
    if (owned_index < kBanBits)
      bans_[a] |= 1u << owned_index;
    else
      bans_[a] = ~0u;  // exhausted: no proposal until the star of a changes
  }

  // --- 3. select: rank, stencils, reservations ---------------------------------------------------
  // Returns false when the cheapest verified collapse costs more than max_cost (stop).
  bool select(RoundStats& stats) {
    parallel::filter_map(
        candidates_.size(), ranked_,
        [&](std::size_t i) {
          const VertId a = candidates_[i];
          return is_verified(a) && ranked(a) < threshold_;
        },
        [&](std::size_t i) {
          Ranked r = ranked(candidates_[i]);
          r.slot = static_cast<std::uint32_t>(i);
          return r;
        });
    parallel::sort(ranked_.begin(), ranked_.end());
    if (ranked_.size() > live_ - target_) ranked_.resize(live_ - target_);  // sorted: the cheapest stay
    stats.candidates = ranked_.size();
    if (options_.max_cost > 0.0) {
      if (!ranked_.empty() && ranked_.front().cost > options_.max_cost) return false;
      while (!ranked_.empty() && ranked_.back().cost > options_.max_cost) ranked_.pop_back();
    }
    gather_stencils(stats);
    reserve(stats);
    return true;
  }

  // Each candidate's stencil (the vertices of St(a) ∪ St(b)), flattened: each goes into a fixed
  // slot first; the rare one that does not fit is gathered again once the exact sizes are known.
  void gather_stencils(RoundStats& stats) {
    const std::size_t n = ranked_.size();
    constexpr std::uint32_t kSlot = 192;
    slots_.resize(n * kSlot);
    stencil_offsets_.assign(n + 1, 0);
    parallel::for_range<std::size_t>(0, n, 256, "gather_stencils", [&](std::size_t b, std::size_t e) {
      ThreadScratch& s = scratch_.local();
      for (std::size_t i = b; i < e; ++i) {
        const StoredStencil& kept = stored_[ranked_[i].slot];
        if (kept.owner != nullptr) {
          const VertId* begin = kept.owner->stencil_pool.data() + kept.offset;
          s.stencil.assign(begin, begin + kept.size);
        } else {
          stencil_of(mesh_, ranked_[i].a, ranked_[i].b, s.stencil, s.stencil_slots);
        }
        stencil_offsets_[i + 1] = static_cast<std::uint32_t>(s.stencil.size());
        if (s.stencil.size() <= kSlot) std::copy(s.stencil.begin(), s.stencil.end(), slots_.begin() + i * kSlot);
      }
    });
    const auto serial_start = Clock::now();
    sizes_.assign(stencil_offsets_.begin() + 1, stencil_offsets_.end());
    for (std::size_t i = 0; i < n; ++i) stencil_offsets_[i + 1] += stencil_offsets_[i];
    stencils_.resize(stencil_offsets_[n]);
    stats.serial_seconds += since(serial_start);
    parallel::for_range<std::size_t>(0, n, 1024, "flatten_stencils", [&](std::size_t b, std::size_t e) {
      ThreadScratch& s = scratch_.local();
      for (std::size_t i = b; i < e; ++i) {
        if (sizes_[i] <= kSlot) {
          std::copy_n(slots_.begin() + i * kSlot, sizes_[i], stencils_.begin() + stencil_offsets_[i]);
        } else if (const StoredStencil& kept = stored_[ranked_[i].slot]; kept.owner != nullptr) {
          const VertId* begin = kept.owner->stencil_pool.data() + kept.offset;
          std::copy(begin, begin + kept.size, stencils_.begin() + stencil_offsets_[i]);
        } else {
          stencil_of(mesh_, ranked_[i].a, ranked_[i].b, s.stencil, s.stencil_slots);
          std::copy(s.stencil.begin(), s.stencil.end(), stencils_.begin() + stencil_offsets_[i]);
        }
      }
    });
  }

  // Reservation passes: in each pass every undecided candidate whose stencil touches no earlier
  // winner reserves its stencil (atomic min of its rank per vertex); those that own their whole
  // stencil win and claim it. Repeating the pass converges towards the lexicographically first
  // maximal independent set in rank order; every pass is a function of the ranks alone.
  void reserve(RoundStats& stats) {
    const std::size_t n = ranked_.size();
    enum : std::uint8_t { kUndecided, kWon, kBlocked };
    state_.assign(n, kUndecided);
    for (int pass = 0; pass < kReservationPasses; ++pass) {
      parallel::for_range<std::size_t>(0, n, 256, "reserve", [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          if (state_[i] != kUndecided) continue;
          bool blocked = false;
          for (std::uint32_t k = stencil_offsets_[i]; k < stencil_offsets_[i + 1] && !blocked; ++k)
            blocked = claimed_[stencils_[k]] != 0;
          if (blocked) {
            state_[i] = kBlocked;
            continue;
          }
          const std::uint32_t rank = static_cast<std::uint32_t>(i);
          for (std::uint32_t k = stencil_offsets_[i]; k < stencil_offsets_[i + 1]; ++k) {
            // Relaxed atomic min: only the final minimum matters, read after the loop has joined.
            std::atomic<std::uint32_t>& o = owner_[stencils_[k]];
            std::uint32_t cur = o.load(std::memory_order_relaxed);
            while (rank < cur && !o.compare_exchange_weak(cur, rank, std::memory_order_relaxed)) {
            }
          }
        }
      });
      std::atomic<std::uint64_t> new_winners{0};
      parallel::for_range<std::size_t>(0, n, 1024, "check_reservations", [&](std::size_t b, std::size_t e) {
        std::uint64_t won = 0;
        for (std::size_t i = b; i < e; ++i) {
          if (state_[i] != kUndecided) continue;
          bool ok = true;
          for (std::uint32_t k = stencil_offsets_[i]; k < stencil_offsets_[i + 1] && ok; ++k)
            ok = owner_[stencils_[k]].load(std::memory_order_relaxed) == i;
          if (ok) {
            state_[i] = kWon;
            ++won;
          }
        }
        new_winners.fetch_add(won, std::memory_order_relaxed);
      });
      // Winners claim their stencils (disjoint: plain writes); every reservation is released.
      parallel::for_range<std::size_t>(0, n, 1024, "claim_and_release", [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          if (state_[i] == kBlocked) continue;
          for (std::uint32_t k = stencil_offsets_[i]; k < stencil_offsets_[i + 1]; ++k) {
            owner_[stencils_[k]].store(kFree, std::memory_order_relaxed);
            if (state_[i] == kWon) claimed_[stencils_[k]] = 1;
          }
        }
      });
      if (new_winners.load() == 0) break;
    }
    parallel::filter_map(
        n, winners_, [&](std::size_t i) { return state_[i] == kWon; },
        [](std::size_t i) { return static_cast<std::uint32_t>(i); });
    stats.winners = winners_.size();
    // A collapse can take at most |St(u)| + |St(v)| new side-table slots, and none when both ends
    // are interior (no flagged face or edge through them: collapse() changes no flag).
    const auto serial_start = Clock::now();
    std::size_t star_tets = 0;
    for (std::uint32_t i : winners_) {
      const VertId a = ranked_[i].a, b = ranked_[i].b;
      if (!cost_.known_interior(a) || !cost_.known_interior(b)) star_tets += mesh_.v2t_count[a] + mesh_.v2t_count[b];
    }
    reserve_refs_headroom(mesh_, refs_used_, star_tets);
    stats.serial_seconds += since(serial_start);
  }

  // --- 4. apply ----------------------------------------------------------------------------------
  void apply(RoundStats& stats) {
    std::atomic<std::uint64_t> applied{0};
    applied_cost_.assign(winners_.size(), -1.0);
    parallel::for_range<std::size_t>(0, winners_.size(), 16, "apply", [&](std::size_t b, std::size_t e) {
      ThreadScratch& s = scratch_.local();
      std::uint64_t n_applied = 0;
      for (std::size_t w = b; w < e; ++w) {
        const std::uint32_t i = winners_[w];
        const Ranked& r = ranked_[i];
        const int n = cost_.candidates(mesh_, r.a, r.b, s.cands, s.collapse.link);
        const int chosen = proposal_[r.a].placement;
        // The stencil has not changed since the verification, so neither have the candidates.
        if (chosen < 0 || chosen >= n || s.cands[chosen].cost != r.cost)
          throw std::logic_error("parallel rounds: a verified proposal changed before it was applied");
        const CollapseCandidate& c = s.cands[chosen];
        cost_.fields_at(mesh_, c, s.fields.data());
        collapse(mesh_, c.u, c.v, c.p, s.fields.data(), s.collapse, refs_used_);
        cost_.on_collapse(mesh_, c.u, c.v, s.collapse.star_uv);
        applied_cost_[w] = c.cost;
        ++n_applied;
        mark_stencil(c, stencils_.data() + stencil_offsets_[i], stencils_.data() + stencil_offsets_[i + 1], s);
      }
      applied.fetch_add(n_applied, std::memory_order_relaxed);
    });
    stats.collapses = applied.load();
    for (double c : applied_cost_) report_.max_cost = std::max(report_.max_cost, c);
    report_.collapses += stats.collapses;
    live_ -= stats.collapses;
    for (ThreadScratch& s : scratch_) {
      dirty_list_.insert(dirty_list_.end(), s.marked.begin(), s.marked.end());
      s.marked.clear();
    }
  }

  // After collapse u <- v: which proposals of the stencil (old St(u) ∪ St(v)) must be redone.
  // Every stencil vertex's star changed, so its verification is void (changed_round). Costs
  // changed only on edges at u (Q_u grew, u moved): u re-proposes from scratch, as do vertices
  // with bans (lifted now: the star changed) or no proposal; a lower neighbour x < u owns xu and
  // re-costs it; a vertex whose best or runner-up went through u or v updates them
  // (update_edge). Every other vertex keeps its proposal. Stencils of one round are disjoint, so
  // every write here is to this winner's own vertices.
  void mark_stencil(const CollapseCandidate& c, const VertId* begin, const VertId* end, ThreadScratch& s) {
    for (const VertId* it = begin; it != end; ++it) {
      const VertId x = *it;
      claimed_[x] = 0;
      changed_round_[x] = round_;
      if (x == c.v) {
        rank_cost_[x] = kNoCost;  // removed
        continue;
      }
      const Proposal& p = proposal_[x];
      const bool full = x == c.u || !std::isfinite(p.cost) || bans_[x] != 0;
      bans_[x] = 0;
      if (full) {
        dirty_[x] = Dirty::kFull;
      } else if (x < c.u || p.b == c.u || p.b == c.v || p.second == c.u || p.second == c.v) {
        dirty_[x] = Dirty::kEdge;  // x owns xu, or its best or runner-up went through u or v
        dirty_partner_[x] = c.u;
      } else {
        continue;  // x's own edges kept their costs (xu is owned by u, which re-proposes)
      }
      s.marked.push_back(x);
    }
    // Feature vertices of the removed tets may change order (CostModel::on_collapse marks them
    // stale), and with it the placements and costs of their edges. Their proposals are updated
    // like the others' and not redone: an order change is rare, and verification always works
    // from fresh costs, so a stale ranking costs a little quality, never safety.
    for (TetId t : s.collapse.star_uv)
      for (VertId x : mesh_.tets[t])
        if (x != c.v && !cost_.known_interior(x) && dirty_[x] == Dirty::kClean) {
          s.marked.push_back(x);
          dirty_[x] = Dirty::kEdge;
          dirty_partner_[x] = c.u;
        }
  }

  // Lifts every ban and re-proposes every vertex (used once before stopping).
  void refresh() {
    const std::size_t nv = proposal_.size();
    std::fill(bans_.begin(), bans_.end(), 0u);
    parallel::filter_map(
        nv, dirty_list_, [&](std::size_t v) { return !mesh_.is_dead_vertex(static_cast<VertId>(v)); },
        [](std::size_t v) { return static_cast<VertId>(v); });
    for (VertId v : dirty_list_) dirty_[v] = Dirty::kFull;
  }

  TetMesh& mesh_;
  const SimplifyOptions& options_;
  const CollapseOptions& kernel_;
  const std::uint64_t target_;
  Report& report_;
  CostModel cost_;
  parallel::PerThread<ThreadScratch> scratch_;

  std::uint32_t round_ = 0;
  std::uint64_t live_ = 0;
  std::uint32_t refs_used_ = 0;
  Ranked threshold_{kNoCost, kInvalid, kInvalid};

  // Per vertex.
  std::vector<Proposal> proposal_;
  // The cost a's proposal competes with: its verified placement's, else its edge's; kNoCost for
  // none or a dead vertex. 8 bytes per vertex for the scans of every round.
  std::vector<double> rank_cost_;
  std::vector<Dirty> dirty_;
  std::vector<VertId> dirty_partner_;  // Dirty::kEdge: the survivor u of the edge to re-cost
  std::vector<std::uint32_t> bans_;    // bit k: the k-th owned neighbour's edge failed; ~0 = all
  std::vector<std::uint32_t> changed_round_;  // last round a collapse changed the vertex's star
  std::vector<std::uint8_t> claimed_;         // in the stencil of a winner of the current round
  std::unique_ptr<std::atomic<std::uint32_t>[]> owner_;

  // Per round.
  std::vector<VertId> dirty_list_;
  std::vector<Ranked> ranked_, sample_;
  std::vector<VertId> candidates_;
  struct StoredStencil {  // where verify() left a candidate's stencil (owner == nullptr: nowhere)
    const ThreadScratch* owner = nullptr;
    std::uint32_t offset = 0, size = 0;
  };
  std::vector<StoredStencil> stored_;  // [position in candidates_]
  std::vector<std::uint32_t> stencil_offsets_, sizes_;
  std::vector<VertId> stencils_, slots_;
  std::vector<std::uint8_t> state_;
  std::vector<std::uint32_t> winners_;
  std::vector<double> applied_cost_;
};

}  // namespace

void simplify_parallel(TetMesh& mesh, const SimplifyOptions& options, const CollapseOptions& kernel,
                       std::uint64_t target, Report& report) {
  Rounds rounds(mesh, options, kernel, target, report);
  rounds.run();
}

}  // namespace topotet::detail
