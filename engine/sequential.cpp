// The sequential reference simplifier: one priority queue of edges, cheapest collapse first
// (paper 001 §5; the timestamps of §5.3).
//
//   quadrics, orders  <- CostModel(mesh)
//   heap              <- every edge ab with its cheapest placement cost, stamped now
//   while live vertices > target and heap not empty (an empty heap is refilled with every edge
//   when the driver relaxes a limit that held them: engines.h, relax_limits.h):
//       pop the cheapest entry (cost, a, b, stamp)
//       if a or b is dead, or changed after `stamp`: skip it   (a fresher entry exists)
//       if cost > max_cost: stop
//       for each placement (u <- v at p) of ab, cheapest first:
//           if may_collapse(u, v, p): collapse; Q_u += Q_v; stamp u; push every edge of u; break
//           else count the rejection reason
//
// An edge whose cheapest placement is illegal goes back into the heap with the cost of the
// placement the kernel accepted when that costs clearly more than the next edge (see below); the
// entry remembers the accepted placement and when it was checked, and if nothing in St(a) ∪ St(b)
// has changed when it comes out again, that placement is taken without a second check (the
// kernel reads only those stars, the same argument as the parallel engine's is_verified).
// Entries are ordered by (cost, a, b), so the result does not depend on heap internals. An edge
// whose every placement is illegal is dropped and its ends are "parked"; when a later collapse
// touches a parked vertex (it lies in the collapse's stencil), all its edges are pushed again,
// so legality is re-examined wherever the mesh changed.
#include <algorithm>
#include <queue>
#include <vector>

#include "kernel/collapse.h"
#include "cost/cost.h"
#include "engines.h"

namespace topotet::detail {
namespace {

struct Entry {
  double cost;
  VertId a, b;
  std::uint32_t stamp;
  // 0, or the clock when the kernel accepted placement `checked & 7` of this edge, times 8: the
  // entry stays 24 bytes (the heap holds an entry per edge). Clocks from 2^29 on are not kept.
  std::uint32_t checked = 0;
  bool operator>(const Entry& o) const {
    return cost != o.cost ? cost > o.cost : (a != o.a ? a > o.a : b > o.b);
  }
};

}  // namespace

void simplify_sequential(MeshModel& mesh, const SimplifyOptions& options, const CollapseOptions& kernel_options,
                         FieldBounds* bounds, std::uint64_t target, Report& report, CollapseLog* log,
                         const FinishStep& finish, const RelaxStep& relax) {
  CostModel cost(mesh, options, kernel_options.surfaces);
  CollapseScratch scratch;
  CollapseCandidate cands[kMaxCandidates];
  std::vector<VertId> nbrs, stencil;
  std::vector<double> fields(static_cast<std::size_t>(mesh.field_stride()));
  std::vector<double> candidate_fields;  // the field error check's values at each placement
  std::vector<std::uint32_t> stamp(mesh.positions.size(), 0);
  // The clock of the last collapse whose stencil held the vertex: its star changed then.
  std::vector<std::uint32_t> changed(mesh.positions.size(), 0);
  constexpr std::uint32_t kMaxCheckedClock = (1u << 29) - 1;
  // Edges dropped as illegal, remembered at both ends (up to kParked partners per vertex; past
  // that the vertex overflows and all its edges are offered again).
  constexpr int kParked = 3;
  std::vector<std::array<VertId, kParked>> parked(mesh.positions.size());
  for (auto& p : parked) p.fill(kInvalid);
  std::vector<std::uint8_t> parked_overflow(mesh.positions.size(), 0);
  auto park = [&](VertId x, VertId partner) {
    for (VertId& slot : parked[x])
      if (slot == kInvalid || slot == partner) {
        slot = partner;
        return;
      }
    parked_overflow[x] = 1;
  };
  std::uint32_t clock = 1;
  std::uint32_t refs_used = static_cast<std::uint32_t>(mesh.refs_table.size());

  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  auto push = [&](VertId a, VertId b) {
    if (a > b) std::swap(a, b);
    ++report.evaluations;
    if (cost.candidates(mesh, a, b, cands, scratch.link) > 0) heap.push({cands[0].cost, a, b, clock});
  };
  auto push_every_edge = [&] {
    for (VertId a = 0; a < mesh.positions.size(); ++a) {
      if (mesh.is_dead_vertex(a)) continue;
      mesh.neighbours(a, nbrs);
      for (VertId b : nbrs)
        if (b > a) push(a, b);
    }
  };
  push_every_edge();

  std::uint64_t live = mesh.live_vertex_count();
  Progress progress(options, live, target);
  std::uint64_t next_progress = 256;
  std::uint64_t collapses_at_last_look = 0;  // report.collapses when every edge was last offered
  const auto offer_every_edge_again = [&] {
    for (auto& p : parked) p.fill(kInvalid);
    std::fill(parked_overflow.begin(), parked_overflow.end(), 0);
    push_every_edge();
    collapses_at_last_look = report.collapses;
  };
  while (live > target) {
    if (heap.empty()) {
      // An edge offered no placement when it was pushed (the orders of its ends forbade it) is
      // pushed again only with its end's new star; before stopping or relaxing, every edge gets
      // one more look, as in the parallel engine: relax_limits' census takes the engine's
      // refusals as a look at every edge (engines.h).
      if (report.collapses != collapses_at_last_look) {
        offer_every_edge_again();
        continue;
      }
      // A limit the caller lets relax held the edges left: the driver relaxed it (engines.h);
      // every edge is offered once more under it.
      if (!relax || !relax(cost)) break;
      // Flips at a stall (flip_at_stall.h) appended refs records past the collapses' headroom.
      refs_used = std::max(refs_used, static_cast<std::uint32_t>(mesh.refs_table.size()));
      offer_every_edge_again();
      continue;
    }
    const Entry e = heap.top();
    heap.pop();
    if (mesh.is_dead_vertex(e.a) || mesh.is_dead_vertex(e.b) || stamp[e.a] > e.stamp || stamp[e.b] > e.stamp)
      continue;
    if (options.max_cost > 0.0 && e.cost > options.max_cost) {
      report.status = Status::kStoppedEarly;
      report.message = "the cheapest remaining collapse costs more than max_cost";
      break;
    }
    const int n = cost.candidates(mesh, e.a, e.b, cands, scratch.link);
    ++report.evaluations;
    int chosen = -1;
    const std::uint32_t checked_at = e.checked >> 3;
    if (e.checked != 0 && changed[e.a] <= checked_at && changed[e.b] <= checked_at &&
        static_cast<int>(e.checked & 7) < n && cands[e.checked & 7].cost == e.cost) {
      // Re-ranked, and St(a) ∪ St(b) untouched since the kernel accepted this placement: the same
      // candidates, the same verdict (the field bounds of the stars are unchanged too). The stars
      // are gathered for the stencil below.
      chosen = static_cast<int>(e.checked & 7);
      gather_stars(mesh, cands[chosen].u, cands[chosen].v, scratch);
    } else {
      Placement placements[kMaxCandidates];
      for (int i = 0; i < n; ++i) placements[i] = placement_of(cands[i]);
      if (bounds != nullptr && bounds->has_limit()) set_placement_fields(mesh, cost, cands, n, placements, candidate_fields);
      ++report.legality_checks;
      cost.hint_orders(e.a, e.b, scratch.link);
      chosen = first_acceptable(mesh, placements, n, kernel_options, scratch, &report.rejected);
    }
    if (chosen < 0) {
      park(e.a, e.b);  // look again when something around them changes
      park(e.b, e.a);
      continue;
    }
    // The edge was ranked by its cheapest placement; when that one is illegal and the legal one
    // costs more than the next edge in the heap, the edge goes back with its true cost (as the
    // parallel engine ranks by the chosen placement's cost). Collapsing it at once cut the
    // corners of boxes (a costly midpoint across a crease) while cheap collapses were waiting.
    // Only a clear loss (twice the next edge's cost) is worth the second check the edge gets when
    // it comes back out of the heap: re-ranking every small excess cost 60% more kernel checks.
    // The accepted placement is remembered: an edge left alone until it comes back out is not
    // checked again (most of them; the others had their stars changed by a collapse meanwhile).
    if (cands[chosen].cost > e.cost && !heap.empty() && cands[chosen].cost > 2.0 * heap.top().cost) {
      const std::uint32_t checked = clock <= kMaxCheckedClock ? clock << 3 | static_cast<std::uint32_t>(chosen) : 0;
      heap.push({cands[chosen].cost, e.a, e.b, e.stamp, checked});
      continue;
    }
    {
      const CollapseCandidate& c = cands[chosen];
      stencil.clear();
      for (const auto* star : {&scratch.star_u, &scratch.star_v})
        for (TetId t : *star)
          for (VertId x : mesh.tets[t]) stencil.push_back(x);
      std::sort(stencil.begin(), stencil.end());
      stencil.erase(std::unique(stencil.begin(), stencil.end()), stencil.end());
      cost.fields_at(mesh, c, fields.data());
      reserve_refs_headroom(mesh, refs_used, scratch.star_u.size() + scratch.star_v.size());
      if (log != nullptr) {
        log->begin_batch(1);
        log->record(0, mesh, c.u, c.v, c.p, fields.data(), c.cost);
      }
      const float star_bound = collapse(mesh, c.u, c.v, c.p, fields.data(), scratch, refs_used, bounds, kernel_options.coverage);
      if (log != nullptr) {
        log->depend(0, scratch.star_u, scratch.star_v);
        if (bounds != nullptr) log->bound(0, star_bound);
        log->end_batch();
      }
      cost.on_collapse(mesh, c.u, c.v);
      report.max_cost = std::max(report.max_cost, c.cost);
      ++report.collapses;
      --live;
      stamp[c.u] = ++clock;
      for (VertId x : stencil) changed[x] = clock;
      mesh.neighbours(c.u, nbrs);
      for (VertId x : nbrs) push(c.u, x);
      // Edges rejected earlier near this collapse may have become legal: offer them again.
      for (VertId x : stencil) {
        if (x == c.u || mesh.is_dead_vertex(x)) continue;
        if (parked_overflow[x]) {
          parked_overflow[x] = 0;
          parked[x].fill(kInvalid);
          stamp[x] = clock;  // supersedes x's live entries: no duplicates
          mesh.neighbours(x, nbrs);
          for (VertId y : nbrs) push(x, y);
          continue;
        }
        for (VertId& y : parked[x]) {
          // A parked edge has no live entry (it was dropped), so pushing it makes no duplicate.
          if (y != kInvalid && !mesh.is_dead_vertex(y) && y != c.u) push(x, y);
          y = kInvalid;
        }
      }
    }
    if (report.collapses >= next_progress) {
      next_progress += 256;
      if (!progress.update(live)) {
        report.status = Status::kCancelled;
        report.message = "cancelled by on_progress";
        return;
      }
    }
  }
  progress.update(live);
  if (live > target && report.status == Status::kOk) {
    report.status = Status::kStoppedEarly;
    report.message = "no legal collapse left";
  }
  if (finish) finish(cost);
}

}  // namespace topotet::detail
