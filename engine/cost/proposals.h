// Per-vertex collapse proposals of the parallel rounds (rounds.cpp).
//
// Vertex a proposes the edge ab it would collapse among the edges it owns (b > a): the cheapest
// by the cost of its cheapest placement (CostModel::edge_cost), skipping edges it has banned. The
// runner-up is kept when known, so that losing the best edge to a nearby collapse rarely needs a
// full re-proposal. Costs are cheap; the kernel check is not, so a proposal is *verified* (the
// whole kernel: geometry, link conditions, quality, tolerance) only when it is about to compete,
// and stays verified until a collapse changes the star of one of its ends. Edges that fail are
// banned until a's star changes.
//
// Every method works on vertex a's own state and reads the mesh: calls for distinct vertices may
// run concurrently while the mesh is not being changed. The after-collapse calls write the
// vertices of one collapse's stencil, which the rounds keep disjoint.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "kernel/collapse.h"
#include "cost/cost.h"
#include "mesh/mesh_model.h"

namespace topotet::detail {

inline constexpr double kNoCost = std::numeric_limits<double>::infinity();

// A proposal's place in a round: by cost, then by the ids (a total order).
struct Ranked {
  double cost;
  VertId a, b;
  std::uint32_t slot = 0;  // rounds.cpp: position of a in the round's candidate list (not ordered)
  bool operator<(const Ranked& o) const { return cost != o.cost ? cost < o.cost : (a != o.a ? a < o.a : b < o.b); }
};

// Per-thread working memory of the proposals; keeps capacity between calls.
struct ProposalScratch {
  struct EdgeCost {
    double cost;  // of the edge's cheapest placement
    VertId b;
  };
  CollapseScratch collapse;  // the kernel's; after a successful verify() it holds that edge's stars
  CollapseCandidate cands[kMaxCandidates];
  std::vector<VertId> nbrs;
  std::vector<EdgeCost> edges;
  std::vector<std::uint32_t> edge_order;
  std::array<std::uint64_t, kCollapseReasonCount> rejected{};
  std::vector<double> fields;  // the field error check's values at each placement
  std::uint64_t evaluations = 0, checks = 0;
};

class Proposals {
 public:
  Proposals(const MeshModel& mesh, CostModel& cost, const CollapseOptions& kernel);

  // --- costs ---
  // a's best and runner-up edges, from scratch.
  void propose(VertId a, ProposalScratch& s);
  // After a collapse that kept u (and removed some v) next to a: the edge au changed cost and
  // edges to dead vertices are gone; a's other edges kept their costs. Updates a's proposal from
  // what it knows; false when that is not enough (best gone, runner-up unknown): call propose().
  bool update(VertId a, VertId u, ProposalScratch& s);

  // --- the kernel ---
  // The kernel options were relaxed (SimplifyOptions::relax_tolerance, relax_quality): take them
  // again. The engine then has every vertex propose afresh (rounds.cpp, refresh), so no verdict of
  // the old options is reused (dropped feature curves change the link conditions too).
  void kernel_changed();
  // Verifies a's edges in cost order, from its proposal on, while they rank below `threshold`:
  // the first that passes becomes the verified proposal of round `round`; failures are banned.
  void verify(VertId a, const Ranked& threshold, std::uint32_t round, ProposalScratch& s);
  bool is_verified(VertId a) const;
  // Index into CostModel::candidates(a, b) of the verified placement.
  int placement(VertId a) const { return proposals_[a].placement; }
  // The verification leaves the tolerance proof out (CollapseOptions::prove_tolerance): a round's
  // winner a proves it here, for its verified placement and, if that one fails, for the next ones
  // of the same edge (the stencil is reserved and unchanged since the verification, so the link
  // conditions still hold). Returns the index of the placement that passes, or -1: the edge is
  // then banned and a must propose again.
  int prove(VertId a, ProposalScratch& s);
  // From now on every verification screens the tolerance (the rounds call it once the proof
  // refuses many winners: where the tolerance binds everywhere, deferring all of it only adds
  // rounds).
  void screen_in_verify() { all_screen_in_verify_ = true; }

  // --- ranking ---
  // The cost a competes with (its verified placement's, else its edge's); infinite for none.
  double rank_cost(VertId a) const { return rank_cost_[a]; }
  const double* rank_costs() const { return rank_cost_.data(); }  // [vertex], for scans
  Ranked ranked(VertId a) const { return Ranked{rank_cost_[a], a, proposals_[a].b}; }

  // --- after a collapse u <- v (apply phase) ---
  enum class Redo : std::uint8_t { kNothing, kUpdate, kPropose };
  // x's star changed in `round` (x in the collapse's stencil, x != v): its verification is void
  // and its bans are lifted, but for the certified ones the collapse left alone (the collapse's
  // old stars, sorted tet ids, tell). Says what x must redo in the next evaluate phase.
  Redo star_changed(VertId x, VertId u, VertId v, std::uint32_t round, const std::vector<TetId>& star_u,
                    const std::vector<TetId>& star_v);
  void removed(VertId v, std::uint32_t round);
  void lift_all_bans();
  // At a stall (no proposal left), for every vertex a in turn (calls for distinct vertices may run
  // concurrently): does a know a refusal that may be out of date? An edge ab's verdict is a
  // function of the stars of a and b (and of the kernel options); a's own star changes lift its
  // bans (star_changed), b's alone do not. So the bans whose far end b changed its star since they
  // were made are lifted, and so is every edge costed before b's change (its placements may have
  // become possible). True: a must propose again (the bans that still hold stay). An exhausted
  // vertex forgot which edges failed: it starts afresh.
  bool refresh_if_stale(VertId a, ProposalScratch& s);
  // The rounds call this before each round's evaluate phase: bans and costings are dated with it.
  void begin_round(std::uint32_t round) { round_ = round; }

  std::size_t memory_bytes() const;
  // Frees the per-vertex tables once the run is over (the optimisation after it allocates its own:
  // the peak memory of a run is otherwise at its end). No call but memory_bytes() after this.
  void release();

 private:
  struct Proposal {
    double cost = kNoCost;         // cheapest placement of edge (a, b); kNoCost = no proposal
    double second_cost = kNoCost;  // the runner-up edge (a, second)
    VertId b = kInvalid;
    VertId second = kInvalid;          // kInvalid = runner-up unknown (or none)
    std::uint32_t verified_round = 0;  // round of the last successful verification; 0 = never
    std::int8_t placement = -1;        // verified: index into CostModel::candidates(a, b)
    void set_best(double c, VertId x) {
      cost = c;
      b = x;
      placement = -1;
    }
  };

  void cost_owned_edges(VertId a, ProposalScratch& s);
  bool is_banned(VertId a, VertId b) const;
  int check(VertId a, VertId b, int n, ProposalScratch& s);
  bool try_edge(VertId a, VertId b, const Ranked& threshold, std::uint32_t round, ProposalScratch& s);
  void set(VertId a, const Proposal& p);

  const MeshModel& mesh_;
  CostModel& cost_;
  const CollapseOptions& kernel_;
  CollapseOptions verify_kernel_;  // kernel_ without the tolerance proof (prove() does it)
  CollapseOptions prove_kernel_;   // kernel_ without the screen: most winners pass their proof
  CollapseOptions screen_kernel_;  // kernel_ with the tolerance's screen only (collapse.h, screen_only)
  // Vertices a proof has refused once: they verify with the tolerance's screen from then on.
  // Where the tolerance binds (a curved surface near the end of a run), a winner refused after the
  // selection costs a round per edge, while the verification tries a's next edges at once; the
  // screen (a few point queries, the old corners against the new surface) refuses most of what
  // the proof would. The proof itself stays with the winners (prove()): a verification with it,
  // as before, proved the surface of every candidate, and most lose their reservation
  // (polycrystal 30k at 10%: 9.38G -> 8.22G instructions; sphere3 6.00G -> 4.86G).
  std::vector<std::uint8_t> screen_in_verify_;
  bool all_screen_in_verify_ = false;
  std::vector<Proposal> proposals_;
  std::vector<double> rank_cost_;             // read by every round's scans: 8 bytes per vertex
  // Edges that failed the kernel. When the vertex's star changes they are lifted: the next
  // update() puts them back among its candidates with the costs kept here (they did not change,
  // unless through u, which is re-costed anyway), so no full re-proposal is needed. A vertex with
  // more failures than slots is exhausted: it proposes nothing until its star changes, and then
  // from scratch (on meshes where most cheap collapses invert, this keeps the rounds from
  // checking the same hopeless edges again).
  // A certified ban (CollapseScratch::Refusal: every placement was inverted, or pushed below a
  // quality floor, by one of two witness tets) survives a star change that leaves its witnesses and its far end alone: its placements
  // depend only on the quadrics, positions and orders of its two ends, which a collapse u <- v
  // changes for u alone (cost.h, CostModel::on_collapse), and each placement still inverts its
  // witness. (Like every ban it is not lifted by a change at b alone, which x does not see; the
  // refresh before a run gives up looks at every edge again: rounds.cpp.) Measured at 10%, 2
  // threads: 47-80% of the kernel's refusals are certified; keeping those bans took 5-21% of the
  // legality checks off the real meshes of ../shared/data (docs/performance.md). Five slots, not
  // three: a vertex in a constrained tail fails more edges than three (torus: -10% checks).
  struct Bans {
    std::array<VertId, 5> edge{kInvalid, kInvalid, kInvalid, kInvalid, kInvalid};
    std::array<float, 5> cost{};  // ranking only: verification recomputes exact costs
    std::array<std::array<TetId, 2>, 5> witness{};  // for certified slots (kInvalid pads)
    std::array<std::uint32_t, 5> round{};  // when slot k's edge failed (refresh_if_stale)
    std::uint8_t certified = 0;  // bit k: slot k is certified
    std::uint8_t lifted = 0;     // bit k: slot k's edge is free again; update() restores it
    bool exhausted = false;
    // Exhausted: the round its last verification tried every edge and all failed (those past the
    // slots are not kept); 0 = not known (refresh_if_stale).
    std::uint32_t tried_round = 0;
  };
  std::vector<Bans> bans_;
  void restore_lifted_bans(VertId a, Proposal& p, VertId u);
  static void clear_lifted(Bans& bans);  // frees the lifted slots
  void ban(VertId a, VertId b, double cost, const CollapseScratch::Refusal* refusal);
  std::vector<std::uint32_t> changed_round_;  // last round a collapse changed the vertex's star
  std::vector<std::uint32_t> costed_round_;   // last round all the vertex's edges were costed
  std::uint32_t round_ = 0;                   // begin_round
};

}  // namespace topotet::detail
