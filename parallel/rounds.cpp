// The parallel engine: rounds of independent collapses, deterministic for any thread count.
//
//   quadrics, orders <- CostModel(mesh); every vertex is dirty
//   while live vertices > target:
//     1. evaluate (parallel over dirty vertices a): a proposes its cheapest collapse that passes
//        the geometric checks (inversion, quality, tolerance) among the edges ab it owns (b > a)
//        and has not banned; clean vertices keep their proposal
//     2. select: keep about the cheapest round_fraction of the proposals (a sampled quantile of
//        (cost, a, b) as threshold, at most live - target), sorted by (cost, a, b) -> rank;
//        gather each one's stencil St(a) ∪ St(b) (its vertices);
//        owner[x] = min rank over the kept proposals whose stencil holds x (atomic min);
//        a proposal wins iff it owns its whole stencil (deterministic reservations: the set is
//        a function of the ranks only, not of the schedule; winners' stencils are disjoint)
//     3. apply (parallel over winners): check full legality (link conditions included) on the
//        current mesh and collapse; disjoint stencils mean no locks. A winner that fails bans its
//        edge at its owner until the owner's neighbourhood changes again
//     4. after a collapse u <- v, update the proposals of its stencil: u, the vertices of the
//        removed tets (their orders may change) and any vertex whose proposal involved u or v, had
//        none, or had bans are re-proposed from scratch; every other stencil vertex x only had
//        its edge to u change cost, so only the edge xu is re-evaluated and compared with x's
//        current proposal (an edge whose legality changed meanwhile is caught when applied)
//   stop when no vertex has a proposal (no legal collapse left) or the target is reached
//
// Why the output is bit-identical for any thread count: proposals are pure functions of the mesh
// at the start of the round; ranks come from a total order; reservations keep the minimum; the
// collapses of one round touch disjoint data. Only side-table slot numbers depend on the schedule,
// and they are never part of the output (compaction renumbers them in tet order).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "collapse.h"
#include "cost.h"
#include "engines.h"
#include "parallel/filter.h"
#include "parallel/for_range.h"
#include "parallel/scratch.h"

namespace topotet::detail {
namespace {

constexpr std::uint32_t kFree = std::numeric_limits<std::uint32_t>::max();
// Reservation passes per round (see select). Most winners come from the first few passes.
constexpr int kReservationPasses = 8;

struct Proposal {
  double cost = std::numeric_limits<double>::infinity();  // infinity = no legal collapse
  VertId b = kInvalid;                                      // the other end (b > a)
};

struct Ranked {
  double cost;
  VertId a, b;
  bool operator<(const Ranked& o) const {
    return cost != o.cost ? cost < o.cost : (a != o.a ? a < o.a : b < o.b);
  }
};

struct StencilMarks {
  std::vector<std::uint32_t> mark;  // per vertex: the generation that last listed it
  std::uint32_t generation = 0;
};

struct ThreadScratch {
  CollapseScratch collapse;
  CollapseCandidate cands[4];
  std::vector<VertId> nbrs;
  std::vector<std::pair<double, std::uint32_t>> order;  // (cost, index into all)
  std::vector<CollapseCandidate> all;
  std::vector<double> fields;
  std::vector<VertId> stencil;
  StencilMarks stencil_marks;
  std::array<std::uint64_t, kCollapseReasonCount> rejected{};
};

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The neighbours b > a: the edges a owns.
void neighbours_above(const TetMesh& mesh, VertId a, std::vector<VertId>& out) {
  mesh.neighbours(a, out);
  out.erase(out.begin(), std::upper_bound(out.begin(), out.end(), a));
}

// The vertices of St(a) ∪ St(b), each once, in the (deterministic) order the incidence chains
// list them. Duplicates are dropped with per-thread generation marks rather than a sort: this runs
// for every candidate of every round and the sort was a quarter of the engine's time.
void stencil_of(const TetMesh& mesh, VertId a, VertId b, std::vector<VertId>& out, StencilMarks& marks) {
  if (marks.mark.size() < mesh.positions.size()) {
    marks.mark.assign(mesh.positions.size(), 0);
    marks.generation = 0;
  }
  if (++marks.generation == 0) {  // wrapped around: old marks could collide
    std::fill(marks.mark.begin(), marks.mark.end(), 0);
    marks.generation = 1;
  }
  out.clear();
  for (VertId x : {a, b})
    mesh.for_each_tet_of(x, [&](TetId t) {
      for (VertId y : mesh.tets[t])
        if (marks.mark[y] != marks.generation) {
          marks.mark[y] = marks.generation;
          out.push_back(y);
        }
    });
}

// a's cheapest legal collapse over the edges it owns: edges in order of their cheapest placement,
// the first edge with an acceptable placement wins.
Proposal propose(const TetMesh& mesh, CostModel& cost, const CollapseOptions& kernel, VertId a,
                 const std::array<VertId, 2>& banned, ThreadScratch& s, std::uint64_t& evals, std::uint64_t& checks) {
  neighbours_above(mesh, a, s.nbrs);
  s.nbrs.erase(std::remove_if(s.nbrs.begin(), s.nbrs.end(), [&](VertId b) { return b == banned[0] || b == banned[1]; }),
               s.nbrs.end());
  s.all.clear();
  s.order.clear();
  for (VertId b : s.nbrs) {
    ++evals;
    const int n = cost.candidates(mesh, a, b, s.cands, s.collapse.link);
    if (n == 0) continue;
    s.order.push_back({s.cands[0].cost, static_cast<std::uint32_t>(s.all.size())});
    for (int i = 0; i < 4; ++i) s.all.push_back(s.cands[std::min(i, n - 1)]);  // 4 slots per edge
    s.all.back().placement = n;  // the last slot's placement field is unused: keep the count there
  }
  std::sort(s.order.begin(), s.order.end());  // ties by index: deterministic
  Placement placements[4];
  for (const auto& [c, first] : s.order) {
    const int n = s.all[first + 3].placement;
    for (int i = 0; i < n; ++i) placements[i] = {s.all[first + i].u, s.all[first + i].v, s.all[first + i].p};
    ++checks;
    // Geometry only: most rejections are inversions; the link conditions are checked for winners.
    const int chosen = first_acceptable(mesh, placements, n, kernel, s.collapse, &s.rejected, false);
    if (chosen >= 0) {
      const CollapseCandidate& cand = s.all[first + chosen];
      return {cand.cost, cand.u == a ? cand.v : cand.u};
    }
  }
  return {};
}

// The proposal of a through the single edge ab (whichever end owns it is a, b > a), or none.
Proposal propose_edge(const TetMesh& mesh, CostModel& cost, const CollapseOptions& kernel, VertId a, VertId b,
                      ThreadScratch& s, std::uint64_t& evals, std::uint64_t& checks) {
  if (b == kInvalid || mesh.is_dead_vertex(b)) return {};
  ++evals;
  const int n = cost.candidates(mesh, a, b, s.cands, s.collapse.link);
  if (n == 0) return {};
  Placement placements[4];
  for (int i = 0; i < n; ++i) placements[i] = {s.cands[i].u, s.cands[i].v, s.cands[i].p};
  ++checks;
  const int chosen = first_acceptable(mesh, placements, n, kernel, s.collapse, &s.rejected, false);
  if (chosen < 0) return {};
  return {s.cands[chosen].cost, b};
}

// Keeps (about) the cheapest `fraction` of the proposals, sorted by rank. The cut is a sampled
// quantile: an evenly spaced sample of the list (which is in vertex order, so the sample does not
// depend on the schedule) is sorted and its key at the wanted quantile becomes a threshold; the
// list is then filtered and sorted in parallel. An exact nth_element would be a sequential O(n)
// pass per round, the largest Amdahl term of the rounds. Adds the time of the sequential
// part (the sample) to serial_seconds.
void keep_cheapest(std::vector<Ranked>& ranked, double fraction, std::vector<Ranked>& sample, std::vector<Ranked>& kept,
                   double& serial_seconds) {
  const std::size_t n = ranked.size();
  const std::size_t want = std::clamp<std::size_t>(
      static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(n))), 1, n);
  if (want < n) {
    const auto t0 = Clock::now();
    constexpr std::size_t kSampleSize = 4096;
    const std::size_t stride = std::max<std::size_t>(1, n / kSampleSize);
    sample.clear();
    for (std::size_t i = 0; i < n; i += stride) sample.push_back(ranked[i]);
    std::sort(sample.begin(), sample.end());
    // q >= 1: the smallest sampled proposal always stays, so a round never comes out empty.
    const std::size_t q = std::clamp<std::size_t>(
        static_cast<std::size_t>(std::ceil(static_cast<double>(want) / static_cast<double>(n) *
                                           static_cast<double>(sample.size()))),
        1, sample.size() - 1);
    const Ranked threshold = sample[q];
    serial_seconds += since(t0);
    parallel::filter_map(n, kept, [&](std::size_t i) { return ranked[i] < threshold; },
                         [&](std::size_t i) { return ranked[i]; });
    ranked.swap(kept);
  }
  parallel::sort(ranked.begin(), ranked.end());
}

}  // namespace

void simplify_parallel(TetMesh& mesh, const SimplifyOptions& options, const CollapseOptions& kernel,
                       std::uint64_t target, Report& report) {
  const std::size_t nv = mesh.positions.size();
  CostModel cost(mesh, options);
  parallel::PerThread<ThreadScratch> scratch([&] {
    ThreadScratch s;
    s.fields.resize(static_cast<std::size_t>(mesh.field_stride()));
    return s;
  });

  std::vector<Proposal> proposal(nv);
  enum : std::uint8_t { kClean = 0, kFull = 1, kEdgeOnly = 2 };
  std::vector<std::uint8_t> dirty(nv, kFull);
  std::vector<VertId> dirty_partner(nv, kInvalid);  // kEdgeOnly: the survivor u of the edge to look at
  std::vector<std::uint8_t> claimed(nv, 0);  // in the stencil of a winner of the current round
  std::vector<std::array<VertId, 2>> banned(nv, {kInvalid, kInvalid});  // edges that failed at apply
  std::vector<std::uint8_t> exhausted(nv, 0);  // more failures than ban slots: no proposal
  std::unique_ptr<std::atomic<std::uint32_t>[]> owner(new std::atomic<std::uint32_t>[nv]);
  for (std::size_t v = 0; v < nv; ++v) owner[v].store(kFree, std::memory_order_relaxed);
  std::vector<VertId> dirty_list;
  std::vector<Ranked> ranked, sample, kept;
  std::vector<std::uint32_t> stencil_offsets;
  std::vector<VertId> stencils, slots;
  std::vector<std::uint32_t> winners;
  std::uint32_t refs_used = static_cast<std::uint32_t>(mesh.refs_table.size());

  std::uint64_t live = mesh.live_vertex_count();
  Progress progress(options, live, target);
  while (live > target) {
    RoundStats round;
    // --- 1. evaluate ---
    auto t0 = Clock::now();
    parallel::filter_map(
        nv, dirty_list, [&](std::size_t v) { return dirty[v] && !mesh.is_dead_vertex(static_cast<VertId>(v)); },
        [](std::size_t v) { return static_cast<VertId>(v); });
    std::atomic<std::uint64_t> evals{0}, checks{0};
    parallel::for_range<std::size_t>(0, dirty_list.size(), 64, "evaluate", [&](std::size_t b, std::size_t e) {
      ThreadScratch& s = scratch.local();
      std::uint64_t ev = 0, ch = 0;
      for (std::size_t i = b; i < e; ++i) {
        const VertId a = dirty_list[i];
        if (exhausted[a]) {
          proposal[a] = {};
        } else if (dirty[a] == kFull) {
          proposal[a] = propose(mesh, cost, kernel, a, banned[a], s, ev, ch);
        } else {
          const Proposal p = propose_edge(mesh, cost, kernel, a, dirty_partner[a], s, ev, ch);
          if (p.cost < proposal[a].cost || (p.cost == proposal[a].cost && p.b < proposal[a].b)) proposal[a] = p;
        }
        dirty[a] = kClean;
      }
      evals.fetch_add(ev, std::memory_order_relaxed);  // counters only: relaxed
      checks.fetch_add(ch, std::memory_order_relaxed);
    });
    report.evaluations += evals.load();
    report.legality_checks += checks.load();
    round.evaluated = dirty_list.size();
    round.phase_seconds[0] = since(t0);

    // --- 2. select ---
    t0 = Clock::now();
    parallel::filter_map(
        nv, ranked,
        [&](std::size_t a) { return !mesh.is_dead_vertex(static_cast<VertId>(a)) && std::isfinite(proposal[a].cost); },
        [&](std::size_t a) { return Ranked{proposal[a].cost, static_cast<VertId>(a), proposal[a].b}; });
    if (ranked.empty()) {
      report.status = Status::kStoppedEarly;
      report.message = "no legal collapse left";
      break;
    }
    keep_cheapest(ranked, options.round_fraction, sample, kept, round.serial_seconds);
    if (ranked.size() > live - target) ranked.resize(live - target);  // sorted: the cheapest stay
    std::size_t keep = ranked.size();
    if (options.max_cost > 0.0 && ranked.front().cost > options.max_cost) {
      report.status = Status::kStoppedEarly;
      report.message = "the cheapest remaining collapse costs more than max_cost";
      break;
    }
    if (options.max_cost > 0.0) {
      while (keep > 1 && ranked[keep - 1].cost > options.max_cost) --keep;
      ranked.resize(keep);
    }
    round.candidates = keep;
    // Stencils, flattened: each candidate's sorted stencil goes into a fixed slot; the rare one
    // that does not fit is gathered again once the exact sizes are known.
    constexpr std::uint32_t kSlot = 192;
    slots.resize(keep * kSlot);
    stencil_offsets.assign(keep + 1, 0);
    parallel::for_range<std::size_t>(0, keep, 256, "gather_stencils", [&](std::size_t b, std::size_t e) {
      ThreadScratch& s = scratch.local();
      for (std::size_t i = b; i < e; ++i) {
        stencil_of(mesh, ranked[i].a, ranked[i].b, s.stencil, s.stencil_marks);
        stencil_offsets[i + 1] = static_cast<std::uint32_t>(s.stencil.size());
        if (s.stencil.size() <= kSlot) std::copy(s.stencil.begin(), s.stencil.end(), slots.begin() + i * kSlot);
      }
    });
    auto serial_start = Clock::now();
    std::vector<std::uint32_t> sizes(stencil_offsets.begin() + 1, stencil_offsets.end());
    for (std::size_t i = 0; i < keep; ++i) stencil_offsets[i + 1] += stencil_offsets[i];
    stencils.resize(stencil_offsets[keep]);
    round.serial_seconds += since(serial_start);
    parallel::for_range<std::size_t>(0, keep, 1024, "flatten_stencils", [&](std::size_t b, std::size_t e) {
      ThreadScratch& s = scratch.local();
      for (std::size_t i = b; i < e; ++i) {
        if (sizes[i] <= kSlot) {
          std::copy_n(slots.begin() + i * kSlot, sizes[i], stencils.begin() + stencil_offsets[i]);
        } else {
          stencil_of(mesh, ranked[i].a, ranked[i].b, s.stencil, s.stencil_marks);
          std::copy(s.stencil.begin(), s.stencil.end(), stencils.begin() + stencil_offsets[i]);
        }
      }
    });
    // Reservation passes: in each pass every undecided candidate whose stencil touches no earlier
    // winner reserves its stencil (atomic min of its rank per vertex); those that own their whole
    // stencil win and claim it. Repeating the pass converges towards the lexicographically first
    // maximal independent set in rank order; every pass is a function of the ranks alone.
    enum : std::uint8_t { kUndecided, kWon, kBlocked };
    std::vector<std::uint8_t> state(keep, kUndecided);
    for (int pass = 0; pass < kReservationPasses; ++pass) {
      parallel::for_range<std::size_t>(0, keep, 256, "reserve", [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          if (state[i] != kUndecided) continue;
          bool blocked = false;
          for (std::uint32_t k = stencil_offsets[i]; k < stencil_offsets[i + 1] && !blocked; ++k)
            blocked = claimed[stencils[k]] != 0;
          if (blocked) {
            state[i] = kBlocked;
            continue;
          }
          const std::uint32_t rank = static_cast<std::uint32_t>(i);
          for (std::uint32_t k = stencil_offsets[i]; k < stencil_offsets[i + 1]; ++k) {
            // Relaxed atomic min: only the final minimum matters, read after the loop has joined.
            std::atomic<std::uint32_t>& o = owner[stencils[k]];
            std::uint32_t cur = o.load(std::memory_order_relaxed);
            while (rank < cur && !o.compare_exchange_weak(cur, rank, std::memory_order_relaxed)) {
            }
          }
        }
      });
      std::atomic<std::uint64_t> new_winners{0};
      parallel::for_range<std::size_t>(0, keep, 1024, "check_reservations", [&](std::size_t b, std::size_t e) {
        std::uint64_t n = 0;
        for (std::size_t i = b; i < e; ++i) {
          if (state[i] != kUndecided) continue;
          bool ok = true;
          for (std::uint32_t k = stencil_offsets[i]; k < stencil_offsets[i + 1] && ok; ++k)
            ok = owner[stencils[k]].load(std::memory_order_relaxed) == i;
          if (ok) {
            state[i] = kWon;
            ++n;
          }
        }
        new_winners.fetch_add(n, std::memory_order_relaxed);
      });
      // Winners claim their stencils (disjoint: plain writes); every reservation is released.
      parallel::for_range<std::size_t>(0, keep, 1024, "claim_and_release", [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          if (state[i] == kBlocked) continue;
          for (std::uint32_t k = stencil_offsets[i]; k < stencil_offsets[i + 1]; ++k) {
            owner[stencils[k]].store(kFree, std::memory_order_relaxed);
            if (state[i] == kWon) claimed[stencils[k]] = 1;
          }
        }
      });
      if (new_winners.load() == 0) break;
    }
    parallel::filter_map(
        keep, winners, [&](std::size_t i) { return state[i] == kWon; },
        [](std::size_t i) { return static_cast<std::uint32_t>(i); });
    round.winners = winners.size();
    // Each collapse can take at most |St(u)| + |St(v)| new side-table slots.
    serial_start = Clock::now();
    std::size_t star_tets = 0;
    for (std::uint32_t i : winners) star_tets += mesh.v2t_count[ranked[i].a] + mesh.v2t_count[ranked[i].b];
    reserve_refs_headroom(mesh, refs_used, star_tets);
    round.serial_seconds += since(serial_start);
    round.phase_seconds[1] = since(t0);

    // --- 3. apply ---
    t0 = Clock::now();
    std::atomic<std::uint64_t> applied{0}, apply_checks{0};
    std::vector<double> applied_cost(winners.size(), -1.0);
    parallel::for_range<std::size_t>(0, winners.size(), 16, "apply", [&](std::size_t b, std::size_t e) {
      ThreadScratch& s = scratch.local();
      std::uint64_t n_applied = 0, n_checks = 0;
      for (std::size_t w = b; w < e; ++w) {
        const Ranked& r = ranked[winners[w]];
        const int n = cost.candidates(mesh, r.a, r.b, s.cands, s.collapse.link);
        Placement placements[4];
        for (int i = 0; i < n; ++i) placements[i] = {s.cands[i].u, s.cands[i].v, s.cands[i].p};
        cost.hint_orders(r.a, r.b, s.collapse.link);
        const int chosen = first_acceptable(mesh, placements, n, kernel, s.collapse, &s.rejected);
        ++n_checks;
        if (chosen >= 0) {
          const CollapseCandidate& c = s.cands[chosen];
          cost.fields_at(mesh, c, s.fields.data());
          collapse(mesh, c.u, c.v, c.p, s.fields.data(), s.collapse, refs_used);
          cost.on_collapse(mesh, c.u, c.v, s.collapse.star_uv);
          applied_cost[w] = c.cost;
          ++n_applied;
          // The neighbourhood changed: update the stencil's proposals next round (see step 4
          // above) and lift earlier bans there (owned data: disjoint writes).
          for (std::uint32_t k = stencil_offsets[winners[w]]; k < stencil_offsets[winners[w] + 1]; ++k) {
            const VertId x = stencils[k];
            const bool full = x == c.u || proposal[x].b == c.u || proposal[x].b == c.v ||
                              !std::isfinite(proposal[x].cost) || banned[x][0] != kInvalid || exhausted[x];
            if (full || x > c.u) {
              dirty[x] = full ? kFull : kClean;  // x > u: the edge xu is owned (and re-proposed) by u
            } else {
              dirty[x] = kEdgeOnly;
              dirty_partner[x] = c.u;
            }
            banned[x] = {kInvalid, kInvalid};
            exhausted[x] = 0;
          }
          // Around the removed tets the orders of feature vertices may change, and with them the
          // placements and costs of all their edges. Interior vertices stay interior (see
          // CostModel::on_collapse): the update above covers them.
          for (TetId t : s.collapse.star_uv)
            for (VertId x : mesh.tets[t])
              if (x != c.v && !cost.known_interior(x)) dirty[x] = kFull;
        } else {
          // Nothing changed; only the owner proposes again, without this edge. An owner out of
          // ban slots waits until a collapse changes its neighbourhood.
          dirty[r.a] = kFull;
          std::array<VertId, 2>& ban = banned[r.a];
          if (ban[0] == kInvalid)
            ban[0] = r.b;
          else if (ban[1] == kInvalid)
            ban[1] = r.b;
          else
            exhausted[r.a] = 1;
        }
        for (std::uint32_t k = stencil_offsets[winners[w]]; k < stencil_offsets[winners[w] + 1]; ++k)
          claimed[stencils[k]] = 0;
      }
      applied.fetch_add(n_applied, std::memory_order_relaxed);
      apply_checks.fetch_add(n_checks, std::memory_order_relaxed);
    });
    round.collapses = applied.load();
    report.legality_checks += apply_checks.load();
    for (double c : applied_cost) report.max_cost = std::max(report.max_cost, c);
    report.collapses += round.collapses;
    live -= round.collapses;
    round.phase_seconds[2] = since(t0);

    for (int k = 0; k < 4; ++k) report.phase_seconds[k] += round.phase_seconds[k];
    report.round_stats.push_back(round);
    ++report.rounds;
    if (!progress.update(live)) {
      report.status = Status::kCancelled;
      report.message = "cancelled by on_progress";
      break;
    }
  }
  for (const ThreadScratch& s : scratch)
    for (int k = 0; k < kCollapseReasonCount; ++k) report.rejected[k] += s.rejected[k];
}

}  // namespace topotet::detail
