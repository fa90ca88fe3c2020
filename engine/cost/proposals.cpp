// Per-vertex collapse proposals (see proposals.h).
#include "cost/proposals.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace topotet::detail {
namespace {


// (cost, b) order among one vertex's edges: ties go to the lower id.
bool cheaper(double c1, VertId b1, double c2, VertId b2) { return c1 != c2 ? c1 < c2 : b1 < b2; }

// Inserts edge (a, b) of cost c into best and runner-up. The runner-up stays unknown when it was
// (an unknown edge might come between).
void insert_edge(double c, VertId b, double& best_cost, VertId& best, double& second_cost, VertId& second) {
  if (cheaper(c, b, best_cost, best)) {
    second_cost = best_cost;
    second = best;
    best_cost = c;
    best = b;
  } else if (second != kInvalid && cheaper(c, b, second_cost, second)) {
    second_cost = c;
    second = b;
  }
}

}  // namespace

void Proposals::clear_lifted(Bans& bans) {
  for (std::size_t k = 0; k < bans.edge.size(); ++k)
    if (bans.lifted >> k & 1) bans.edge[k] = kInvalid;
  bans.certified &= static_cast<std::uint8_t>(~bans.lifted);
  bans.lifted = 0;
}

Proposals::Proposals(const MeshModel& mesh, CostModel& cost, const CollapseOptions& kernel)
    : mesh_(mesh),
      cost_(cost),
      kernel_(kernel),
      verify_kernel_(kernel),
      prove_kernel_(kernel),
      screen_kernel_(kernel),
      proposals_(mesh.vertex_capacity()),
      rank_cost_(mesh.vertex_capacity(), kNoCost),
      bans_(mesh.vertex_capacity()),
      changed_round_(mesh.vertex_capacity(), 0),
      costed_round_(mesh.vertex_capacity(), 0) {
  kernel_changed();
  if (kernel.surfaces != nullptr) screen_in_verify_.assign(mesh.vertex_capacity(), 0);
}

void Proposals::kernel_changed() {
  verify_kernel_ = kernel_;
  prove_kernel_ = kernel_;
  screen_kernel_ = kernel_;
  verify_kernel_.prove_tolerance = false;
  prove_kernel_.screen_tolerance = false;
  screen_kernel_.screen_only = true;
}

void Proposals::set(VertId a, const Proposal& p) {
  proposals_[a] = p;
  rank_cost_[a] = p.cost;
}

// --- costs -----------------------------------------------------------------------------------

void Proposals::cost_owned_edges(VertId a, ProposalScratch& s) {
  // Unsorted: the best and runner-up below, and verify()'s order, are taken by the total order
  // (cost, b), whatever the order the edges come in.
  mesh_.neighbours_above(a, s.nbrs);
  for (VertId b : s.nbrs) cost_.prefetch(b);  // the records' cache misses overlap
  costed_round_[a] = round_;
  s.edges.clear();
  for (std::size_t k = 0; k < s.nbrs.size(); ++k) {
    if (is_banned(a, s.nbrs[k])) continue;
    ++s.evaluations;
    const double c = cost_.edge_cost(mesh_, a, s.nbrs[k], s.collapse.link);
    if (std::isfinite(c)) s.edges.push_back({c, s.nbrs[k]});
  }
}

void Proposals::propose(VertId a, ProposalScratch& s) {
  cost_owned_edges(a, s);
  clear_lifted(bans_[a]);  // their edges were costed with the others
  Proposal p;
  for (const ProposalScratch::EdgeCost& e : s.edges) {
    if (cheaper(e.cost, e.b, p.cost, p.b)) {
      p.second_cost = p.cost;
      p.second = p.b;
      p.set_best(e.cost, e.b);
    } else if (cheaper(e.cost, e.b, p.second_cost, p.second)) {
      p.second_cost = e.cost;
      p.second = e.b;
    }
  }
  set(a, p);
}

bool Proposals::update(VertId a, VertId u, ProposalScratch& s) {
  Proposal p = proposals_[a];
  restore_lifted_bans(a, p, u);
  const auto stale = [&](VertId x) { return x == kInvalid || x == u || mesh_.is_dead_vertex(x); };
  if (stale(p.b)) {
    if (stale(p.second)) return false;
    p.set_best(p.second_cost, p.second);  // the runner-up was the cheapest of the others,
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
      const VertId before = p.b;
      double best_cost = p.cost;
      VertId best = p.b;
      insert_edge(c, u, best_cost, best, p.second_cost, p.second);
      if (best != before) p.set_best(best_cost, best);
    }
  }
  set(a, p);
  return true;
}

// --- the kernel ------------------------------------------------------------------------------

bool Proposals::is_verified(VertId a) const {
  const Proposal& p = proposals_[a];
  return p.placement >= 0 && p.verified_round > changed_round_[a] && p.verified_round > changed_round_[p.b];
}

bool Proposals::is_banned(VertId a, VertId b) const {
  const Bans& bans = bans_[a];
  if (bans.exhausted) return true;
  for (std::size_t k = 0; k < bans.edge.size(); ++k)
    if (bans.edge[k] == b && !(bans.lifted >> k & 1)) return true;
  return false;
}

void Proposals::ban(VertId a, VertId b, double cost, const CollapseScratch::Refusal* refusal) {
  Bans& bans = bans_[a];
  for (std::size_t k = 0; k < bans.edge.size(); ++k)
    // A lifted slot is free: a fresh failure before update() forgets the lifted edge, which the
    // next proposal from scratch finds again.
    if (bans.edge[k] == kInvalid || (bans.lifted >> k & 1)) {
      const std::uint8_t bit = static_cast<std::uint8_t>(1u << k);
      bans.edge[k] = b;
      bans.cost[k] = static_cast<float>(cost);
      bans.round[k] = round_;
      bans.lifted &= static_cast<std::uint8_t>(~bit);
      if (refusal != nullptr && refusal->certified) {
        bans.certified |= bit;
        bans.witness[k] = refusal->witness;
      } else {
        bans.certified &= static_cast<std::uint8_t>(~bit);
      }
      return;
    }
  bans.exhausted = true;  // a vertex whose edges keep failing waits until its star changes
  bans.tried_round = 0;   // verify() dates it if it tries every edge
}

void Proposals::restore_lifted_bans(VertId a, Proposal& p, VertId u) {
  Bans& bans = bans_[a];
  if (bans.lifted == 0) return;
  double best_cost = p.cost, second_cost = p.second_cost;
  VertId best = p.b, second = p.second;
  const auto restored = [&](std::size_t k) {
    const VertId b = bans.edge[k];
    return (bans.lifted >> k & 1) && b != kInvalid && b != u && !mesh_.is_dead_vertex(b);
  };
  if (best == kInvalid) {
    // No proposal: the banned edges were all the edges left (those still banned stay out), so
    // best and runner-up are exact.
    second_cost = kNoCost;
    second = kInvalid;
    for (std::size_t k = 0; k < bans.edge.size(); ++k) {
      if (!restored(k)) continue;
      const VertId b = bans.edge[k];
      if (cheaper(bans.cost[k], b, best_cost, best)) {
        second_cost = best_cost;
        second = best;
        best_cost = bans.cost[k];
        best = b;
      } else if (cheaper(bans.cost[k], b, second_cost, second)) {
        second_cost = bans.cost[k];
        second = b;
      }
    }
  } else {
    for (std::size_t k = 0; k < bans.edge.size(); ++k)
      if (restored(k)) insert_edge(bans.cost[k], bans.edge[k], best_cost, best, second_cost, second);
  }
  if (best != p.b) p.set_best(best_cost, best);
  p.second_cost = second_cost;
  p.second = second;
  clear_lifted(bans);
}

int Proposals::check(VertId a, VertId b, int n, ProposalScratch& s) {
  Placement placements[kMaxCandidates];
  for (int i = 0; i < n; ++i) placements[i] = placement_of(s.cands[i]);
  if (kernel_.field_bounds != nullptr && kernel_.field_bounds->has_limit()) set_placement_fields(mesh_, cost_, s.cands, n, placements, s.fields);
  ++s.checks;
  cost_.hint_orders(a, b, s.collapse.link);
  const bool screened = all_screen_in_verify_ || (!screen_in_verify_.empty() && screen_in_verify_[a]);
  return first_acceptable(mesh_, placements, n, screened ? screen_kernel_ : verify_kernel_, s.collapse, &s.rejected);
}

int Proposals::prove(VertId a, ProposalScratch& s) {
  Proposal& p = proposals_[a];
  const int from = p.placement;
  const SurfaceReference* surfaces = kernel_.surfaces;
  if (surfaces == nullptr || (!surfaces->on_surface(a) && !surfaces->on_surface(p.b))) return from;  // nothing deferred
  const int n = cost_.candidates(mesh_, a, p.b, s.cands, s.collapse.link);
  if (from < 0 || from >= n) throw std::logic_error("parallel rounds: a verified proposal changed before it was proved");
  // The verified placement is proved whatever it is (a quality fallback was reached then); the ones
  // after it keep their rule.
  Placement placements[kMaxCandidates];
  for (int i = from; i < n; ++i) placements[i - from] = placement_of(s.cands[i]);
  placements[0].quality_fallback = false;
  if (kernel_.field_bounds != nullptr && kernel_.field_bounds->has_limit())
    set_placement_fields(mesh_, cost_, s.cands + from, n - from, placements, s.fields);
  ++s.checks;
  // The link conditions passed in the verification, on this same stencil: not again.
  const int k = first_acceptable(mesh_, placements, n - from, prove_kernel_, s.collapse, &s.rejected, false);
  if (k < 0) {
    screen_in_verify_[a] = 1;
    ban(a, p.b, p.cost, nullptr);  // a tolerance refusal: not certified
    p.placement = -1;
    rank_cost_[a] = p.cost;
    return -1;
  }
  p.placement = static_cast<std::int8_t>(from + k);
  rank_cost_[a] = s.cands[from + k].cost;
  return from + k;
}

// Makes ab a's proposal (runner-up as given) with fresh costs and, if it ranks below the
// threshold, runs the kernel on it. True when the search is over: ab was verified, or it ranks
// above the threshold (it competes in a later round). False when ab failed (now banned) or is
// forbidden: the caller tries the next edge.
bool Proposals::try_edge(VertId a, VertId b, const Ranked& threshold, std::uint32_t round, ProposalScratch& s) {
  ++s.evaluations;
  const int n = cost_.candidates(mesh_, a, b, s.cands, s.collapse.link);
  if (n == 0) return false;
  Proposal p = proposals_[a];
  p.set_best(s.cands[0].cost, b);
  set(a, p);
  if (!(Ranked{p.cost, a, b} < threshold)) return true;
  const int chosen = check(a, b, n, s);
  if (chosen < 0) {
    ban(a, b, p.cost, &s.collapse.refusal);
    return false;
  }
  proposals_[a].verified_round = round;
  proposals_[a].placement = static_cast<std::int8_t>(chosen);
  rank_cost_[a] = s.cands[chosen].cost;
  return true;
}

void Proposals::verify(VertId a, const Ranked& threshold, std::uint32_t round, ProposalScratch& s) {
  // The proposed edge, then the runner-up (the next in cost order when known: one evaluation, not
  // all), then every other edge in cost order.
  const VertId proposed = proposals_[a].b, runner_up = proposals_[a].second;
  if (try_edge(a, proposed, threshold, round, s)) return;
  proposals_[a].second = kInvalid;
  if (runner_up != kInvalid && !mesh_.is_dead_vertex(runner_up) && !is_banned(a, runner_up) &&
      try_edge(a, runner_up, threshold, round, s))
    return;
  const bool listed_all = !bans_[a].exhausted;  // every edge not in a slot is in s.edges
  cost_owned_edges(a, s);
  s.edge_order.resize(s.edges.size());
  for (std::uint32_t k = 0; k < s.edges.size(); ++k) s.edge_order[k] = k;
  std::sort(s.edge_order.begin(), s.edge_order.end(), [&](std::uint32_t x, std::uint32_t y) {
    return cheaper(s.edges[x].cost, s.edges[x].b, s.edges[y].cost, s.edges[y].b);
  });
  for (std::size_t k = 0; k < s.edge_order.size(); ++k) {
    Proposal p;
    const ProposalScratch::EdgeCost& e = s.edges[s.edge_order[k]];
    if (k + 1 < s.edge_order.size()) {
      const ProposalScratch::EdgeCost& next = s.edges[s.edge_order[k + 1]];
      p.second_cost = next.cost;
      p.second = next.b;
    }
    set(a, p);
    if (try_edge(a, e.b, threshold, round, s)) return;
  }
  set(a, Proposal{});
  // Every edge failed: in its slot, or in this call (refresh_if_stale dates the ones not kept).
  if (listed_all && bans_[a].exhausted) bans_[a].tried_round = round;
}

// --- after a collapse ------------------------------------------------------------------------

Proposals::Redo Proposals::star_changed(VertId x, VertId u, VertId v, std::uint32_t round,
                                        const std::vector<TetId>& star_u, const std::vector<TetId>& star_v) {
  changed_round_[x] = round;
  const Proposal& p = proposals_[x];
  Bans& bans = bans_[x];
  // u's edges all changed.
  if (x == u) {
    bans = Bans{};
    return Redo::kPropose;
  }
  // Failed edges may be legal now: update() puts them back (their costs are kept). A certified
  // ban stays while the collapse touched neither its far end nor its witnesses (proposals.h).
  const auto touched = [&](TetId t) {
    return t != kInvalid && (std::binary_search(star_u.begin(), star_u.end(), t) ||
                             std::binary_search(star_v.begin(), star_v.end(), t));
  };
  for (std::size_t k = 0; k < bans.edge.size(); ++k) {
    const VertId b = bans.edge[k];
    if (b == kInvalid || (bans.lifted >> k & 1)) continue;
    const bool holds = (bans.certified >> k & 1) && b != u && b != v && !touched(bans.witness[k][0]) &&
                       !touched(bans.witness[k][1]);
    if (!holds) bans.lifted |= static_cast<std::uint8_t>(1u << k);
  }
  // An exhausted vertex forgot some of its failed edges: it proposes from scratch, past the bans
  // that still hold.
  if (bans.exhausted) {
    bans.exhausted = false;
    bans.tried_round = 0;
    clear_lifted(bans);
    return Redo::kPropose;
  }
  if (bans.lifted != 0) return Redo::kUpdate;
  if (!std::isfinite(p.cost)) return Redo::kPropose;
  // x owns xu, or its best or runner-up went through u or v.
  if (x < u || p.b == u || p.b == v || p.second == u || p.second == v) return Redo::kUpdate;
  return Redo::kNothing;  // xu is owned by u, which re-proposes; x's own edges kept their costs
}

void Proposals::removed(VertId v, std::uint32_t round) {
  changed_round_[v] = round;
  set(v, Proposal{});
}

void Proposals::lift_all_bans() { std::fill(bans_.begin(), bans_.end(), Bans{}); }  // then everyone proposes

bool Proposals::refresh_if_stale(VertId a, ProposalScratch& s) {
  Bans& bans = bans_[a];
  // An exhausted vertex knows when its edges outside the slots failed only if its last
  // verification tried them all (tried_round).
  if (bans.lifted != 0 || (bans.exhausted && bans.tried_round == 0)) {
    bans = Bans{};
    return true;
  }
  // A collapse in round r changes stars in its apply phase, after that round's verifications and
  // costings: a change in the round a verdict was made may postdate it (>=).
  bool stale = false;
  mesh_.neighbours_above(a, s.nbrs);
  for (const VertId b : s.nbrs) {
    std::uint32_t since = bans.exhausted ? bans.tried_round : costed_round_[a];
    std::size_t slot = bans.edge.size();
    for (std::size_t k = 0; k < bans.edge.size(); ++k)
      if (bans.edge[k] == b) {
        slot = k;
        since = bans.round[k];
      }
    if (changed_round_[b] < since) continue;
    stale = true;
    if (bans.exhausted) {  // which of its other edges failed is not known: all again
      bans = Bans{};
      return true;
    }
    if (slot < bans.edge.size()) {
      bans.edge[slot] = kInvalid;
      bans.certified &= static_cast<std::uint8_t>(~(1u << slot));
    }
  }
  return stale;
}

std::size_t Proposals::memory_bytes() const {
  return proposals_.capacity() * sizeof(Proposal) + rank_cost_.capacity() * sizeof(double) +
         bans_.capacity() * sizeof(Bans) + (changed_round_.capacity() + costed_round_.capacity()) * sizeof(std::uint32_t) +
         screen_in_verify_.capacity();
}

void Proposals::release() {
  std::vector<Proposal>().swap(proposals_);
  std::vector<double>().swap(rank_cost_);
  std::vector<Bans>().swap(bans_);
  std::vector<std::uint32_t>().swap(changed_round_);
  std::vector<std::uint32_t>().swap(costed_round_);
  std::vector<std::uint8_t>().swap(screen_in_verify_);
}

}  // namespace topotet::detail
