// Collapse cost and placement: Garland–Zhou quadrics over positions and fields (paper 002 §4,
// paper 001 §5.1), with placements that respect the vertex classification.
//
// Coordinates are normalised so that the bounding box diagonal is 1 and every field component
// spans [0, 1] (its range; see "Field scaling" below). Each vertex carries the sum of
//   - for every incident tet, the squared error of the new vertex's field values against the tet's
//     linear interpolant, sum over components c of w_c (f_c - L_c(x))^2 (quadric_add_field_simplex:
//     the "vertical" distance), with w_c the component's field weight (SimplifyOptions::
//     field_weights) times the tet's share of one sample (below);
//   - for every incident boundary, interface or listed surface face, its plane quadric (position
//     only) weighted by boundary_weight, and the same field term over the interpolant of a tet
//     through the face, weighing kFeatureFieldWeight tets (the face's own interpolant, constant
//     along its normal, made a linear field cost something off the face's plane);
//   - for every incident polyline edge, its line quadric (position only), weighted by
//     polyline_weight.
// After a collapse u <- v, Q_u += Q_v (the standard Garland–Heckbert accumulation).
//
// Why these terms (issue #11; LOX post 513k tets to 30%, parallel engine, field 0, RMS relative to
// the range pooled over both directions, against VTK's vtkUnstructuredGridQuadricDecimation
// 0.0014 at the same vertex count; the step-by-step numbers below were measured while building
// the model, on the engine before the rewritten rounds; docs/performance.md has the current ones):
//   - Vertical, not orthogonal, distance. The 3-flat of a tet in R^(3+k) measured orthogonally
//     gives (f - L(x))^2 / (1 + |grad f|^2): in normalised units the gradient of a boundary layer
//     is in the hundreds, so the steepest parts of a field, where the error is made, cost 1e-4
//     of what they should and were collapsed first. 0.0158 -> 0.0031. VTK's tet quadric is the
//     vertical one too (the 4D normal scaled by 1 / volume).
//   - One sample per tet, not the tet's volume. The field error is measured at the vertices (paper
//     001 ch. 7), and a graded mesh puts its vertices where the field needs them: 42% of LOX's
//     vertices lie within 0.1 (of 30) of the post. Weighted by volume that layer is almost free
//     to collapse; weighted per tet every input vertex counts as much as the error measure says.
//     0.0031 -> 0.00031. Within a vertex's star the star's weight is shared by volume (slivers
//     count little); on a uniform mesh both weightings are the same (cube-sphere, Bucky: within
//     2%). All weights are multiplied by the mean tet volume, so costs keep the units of before
//     (max_cost).
//   - The feature field term. A boundary vertex has about half the tets of an interior one, so its
//     field error weighed half; kFeatureFieldWeight = 3 tets per face (a boundary vertex has about 6
//     faces and 12 tets where an interior one has 24 tets) gives it back. LOX 30%: max error
//     0.0217 -> 0.0025, RMS 0.00031 -> 0.00024; weights 1..4 within 3%.
//   - The feature quadrics measure position only (quadric_add_simplex_positions): built in
//     R^(3+k) they would also pin the field along every feature with the feature's penalty, which
//     kept nearly all boundary vertices and left the interior's field short of them. Their weight
//     is relative to the local size: boundary_weight x area x (a_ref / a)^2, with a the vertex's
//     mean face area and a_ref the face of the regular tet of the mean volume (polylines: length x
//     (e_ref / l)^3), so that moving a surface by a given fraction of its local edge length costs
//     the same everywhere, as the per-sample field term does; on a uniform mesh this is the
//     area-weighted quadric of before.
// Field scaling: each component by its range, so that the cost adds up the squared errors
// relative to the range, the unit every report prints (field_error.h). By standard deviation the
// balance between fields moves toward those with a few extreme values (LOX, three fields at 30%:
// each field's RMS relative to a run preserving it alone 2.1 / 1.4 / 1.6 by range, 1.6 / 1.9 /
// 1.2 by standard deviation, not better overall), and the balance with the geometry moves with
// the field's distribution (LOX 30%: max error 0.0028 -> 0.0216, a corner of the post cut).
// Unscaled, the balance would depend on the fields' units.
// Balancing the fields by their own achievable error (weights 1 / RMS alone^2, taken from the
// single-field runs) only moves error between them (LOX 30%: 2.01 / 1.43 / 1.51 -> 1.63 / 1.69 /
// 1.25 times the single-field RMS): three fields within 1.2x of their own runs need about 1.33x
// the vertices of one (docs/performance.md, "Field accuracy").
//
// Placement of the merged vertex (ord = order in the substructure filtration, link_condition.h):
//   ord a > ord b : a stays where it is (a vertex on a feature never leaves it);
//   equal, 0      : the quadric's optimum when well conditioned and near the edge, else the best of
//                   the endpoints and the midpoint;
//   equal, 1      : the same where the surface is curved at both ends, else the best of the
//                   endpoints and the midpoint. On a curved surface the midpoint of a chord lies
//                   inside it and an endpoint leaves the chords of its neighbours inside too, so
//                   the tolerance H binds early; the optimum of the surface's plane quadrics sits
//                   near the surface, on either side, and spends about half as much of H (mmg's
//                   torus 13.3% -> 10.9% of the vertices, simnibs sphere3 22.9% -> 16.2%, field
//                   rms at 10% of the families -1..-6%). A plane keeps its vertices exactly on it:
//                   the optimum of a flat fan drifts off it by ~1e-5 (tet and field terms), and a
//                   flat face of a part must stay flat (curved_ below);
//   equal, 2      : the best of the endpoints and the midpoint (the midpoint of a curve edge stays
//                   on the piecewise-linear curve);
//   pinned vertices never move; two order-3 ends never collapse (link condition (I)).
// Where a placement fixes the position (an endpoint, the midpoint) the cost takes the field values
// the quadric likes best at that position (its minimum over the field coordinates).
// Field components pinned on an isosurface (SimplifyOptions::isosurfaces, field_pins.h) take the
// pinned value whatever the placement, and two vertices pinned to different values never merge.
// The values the new vertex gets (fields_at) are 3/4 of the quadric's and 1/4 of the mesh's field
// interpolated at the new position (kFieldBlend). The quadric's value is the best fit over the
// vertex's whole region, which is what the error at the original vertices wants, but at a peak or
// a ridge the tets' planes meet above the field and the vertex overshoots it: the error at the
// new vertices themselves (simplified -> original) grows. Bucky ball at 10%: 0.0298 -> 0.0228 in
// that direction (VTK 0.0265), 0.0216 -> 0.0232 in the other (VTK 0.0335). The values never feed
// back into the costs (they are recomputed from the quadric), so this moves no collapse.
// A vertex that stays where it is (placement at u, pinned or not) keeps its own values: they are
// the field sampled at that very point, where a fit over its region can only add error. Measured
// on tests/unit_field_accuracy.cpp when features stopped pinning sphere-scale creases (so fewer
// vertices kept exact values): surface vertices' rms 0.0200 -> 0.0134 and the largest vertex
// error of the quadratic field 4.12 -> 2.51 (parallel, 5%), for +1..5% of the symmetric rms on the
// parallel engine (+12..18% on the sequential reference). Components with weight 0 (and any past
// the 16th) are interpolated only.
// A small length term (1e-6 |ab|^3) breaks ties between zero-cost collapses in favour of short
// edges, which keeps tets well shaped when there is no field to preserve.
// The size term (SimplifyOptions::size_weight = w; issue #26 item 5) is the same length term made
// strong enough to rank: every placement of edge ab costs w x 9.43 x |ab|^3 more, 9.43 =
// 4 x 20 / (6 sqrt 2): a regular tet of edge l has volume l^3 / (6 sqrt 2), about 20 of them lie
// around an edge of length l, and the tet quadrics count each input tet at its 4 vertices, so the
// quadric error of a relative field error e everywhere around the edge is about 9.43 e^2 |ab|^3,
// and w = e^2 says which error the size is worth. Why this form:
//   - the error alone ranks by what is cheap, not by where vertices are dense: interior vertices
//     and flat faces cost nothing, while the plane quadrics and the tolerance hold curved surfaces,
//     so a run leaves a dense surface over a coarse interior, with slivers between (Gmsh cube in a
//     sphere at 10%: boundary edges 0.31x the interior's, 4.1% of the tets under 10 degrees; with
//     w = 3e-4: 0.52x and 0.6%; docs/performance.md "Even sizes"); shortest-first among small
//     errors grades the sizes evenly;
//   - the cube of the length, not the square: quadric errors add up over the input samples an edge
//     stands for, about l^3 of them, so with l^3 the balance between size and error is the same at
//     every stage of a run and every mesh size (it is independent of the mean tet volume, so parts
//     of one mesh simplified apart (topotet::mpi) rank alike too); the error of a curved field or
//     surface grows faster with l (~ l^7) and takes over where the shape needs vertices;
//   - the edge's own length, not the longest edge a collapse makes: a pure function of the two
//     end positions, as cheap as the tie break and the same for every thread count. The same
//     amount is added to every placement of the edge, so it ranks edges and never changes which
//     placement is chosen, nor the kernel's checks: no guarantee depends on it.
// The tie break is the size term with w = 1.06e-7.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "kernel/collapse.h"
#include "kernel/link_condition.h"
#include "mesh/mesh_model.h"
#include "cost/quadric.h"
#include "topotet/simplify.h"

namespace topotet {

// The placements candidates() gives for one edge, at most: the two endpoints, the midpoint and
// the optimum, then two fallbacks (below).
inline constexpr int kMaxCandidates = 6;

struct CollapseCandidate {
  VertId u = kInvalid, v = kInvalid;  // v merges into u
  glm::dvec3 p{0.0};                  // new position of u (mesh units)
  double cost = 0.0;                  // normalised units
  int placement = 0;                  // 0 = at u, 1 = midpoint, 2 = quadric optimum, 3 = along the edge
  // A quality fallback: tried only when a placement before it was refused by a quality floor
  // (Placement::quality_fallback).
  bool fallback = false;
  double x[kMaxQuadricDim];           // the placement in normalised quadric coordinates
};

class CostModel {
 public:
  // Builds every vertex's quadric and order (parallel over vertices, deterministic). With the
  // tolerance's reference, a vertex it does not list as on a surface or polyline, and not pinned,
  // is interior (order 0) without a look at its star: SurfaceReference::on_surface stays exact for
  // the whole run, since the kernel lets no such vertex absorb a surface vertex.
  CostModel(const MeshModel& mesh, const SimplifyOptions& options, const SurfaceReference* surfaces = nullptr);

  int dimension() const { return n_; }

  // Placements for edge ab, cheapest first (at most 4), then, where the edge's ends may both move
  // (equal orders, neither pinned), the two quality fallbacks at a quarter and three quarters of
  // the edge (kMaxCandidates in all). Returns 0 when the orders forbid the
  // collapse outright (both ends order 3, or a pinned end that would have to move).
  int candidates(const MeshModel& mesh, VertId a, VertId b, CollapseCandidate out[kMaxCandidates], LinkScratch& scratch);

  // The cost of edge ab's cheapest placement (candidates()[0].cost, up to rounding: the optimum,
  // when it is a candidate, is taken as the cheapest without evaluating the others); infinity
  // when the orders forbid the collapse. For ranking edges; candidates() for checking them.
  double edge_cost(const MeshModel& mesh, VertId a, VertId b, LinkScratch& scratch);

  // Field values (mesh units, field_stride() of them) for u after collapsing with candidate c.
  void fields_at(const MeshModel& mesh, const CollapseCandidate& c, double* out) const;

  // Field values (mesh units) for vertex v moved to p without a collapse (optimize/smooth.h): as
  // fields_at for a placement at p, from v's own quadric and the mesh's field at p in v's star.
  void fields_at_point(const MeshModel& mesh, VertId v, const glm::dvec3& p, double* out) const;
  // v's quadric error were it at p with the best field values there (normalised units, as costs).
  double point_cost(const MeshModel& mesh, VertId v, const glm::dvec3& p) const;
  // Bookkeeping after v moved (and took new field values) without a collapse: its normalised
  // coordinates follow. Writes only v's record.
  void on_move(const MeshModel& mesh, VertId v) { normalise(mesh, v, coordinates(v)); }
  // Asks the memory system for what edge_cost / candidates will read about v (see prefetch.h).
  void prefetch(VertId v) const;

  // Bookkeeping after mesh collapse(u <- v): Q_u += Q_v, and u's order is recomputed on demand
  // (every other vertex keeps its order: see cost.cpp). Writes only u's quadric and order byte.
  void on_collapse(const MeshModel& mesh, VertId u, VertId v);

  // The substructures lost curves (drop_features_below, features.h): every vertex that was not interior
  // is classified again when next asked (an order kept from before could only over-estimate, which
  // is legal but keeps former curve vertices on their curve).
  void forget_orders();
  // The cached order of v, or nullopt when it is to be recomputed (for tests).
  std::optional<std::uint8_t> known_order(VertId v) const {
    const std::uint8_t o = orders_[v].load(std::memory_order_relaxed);
    return o >= 4 ? std::nullopt : std::optional<std::uint8_t>(o);
  }

  // Order of v in the substructure filtration (cached; thread-safe for distinct or equal v:
  // concurrent recomputations write the same value).
  std::uint8_t order(const MeshModel& mesh, VertId v, LinkScratch& scratch);

  // True when v is known to be of order 0 (interior: on no feature). Interior stays interior
  // through every legal collapse, so the answer never goes stale.
  bool known_interior(VertId v) const { return orders_[v].load(std::memory_order_relaxed) == 0; }

  // Tells the kernel which ends of edge ab are known to be of order 0 (LinkScratch::known_interior).
  void hint_orders(VertId a, VertId b, LinkScratch& scratch) const {
    scratch.known_interior[0] = orders_[a].load(std::memory_order_relaxed) == 0 ? a : kInvalid;
    scratch.known_interior[1] = orders_[b].load(std::memory_order_relaxed) == 0 ? b : kInvalid;
  }

  std::size_t memory_bytes() const;

  // v's quadric (quadric_doubles() values), for SimplifyOptions::quadrics_out.
  int quadric_doubles() const { return quadric_size(n_); }
  const double* quadric_of(VertId v) const { return quadric(v); }

 private:
  // kN > 0: the quadric dimension n_ fixed at compile time; 0: read at run time.
  template <int kN>
  struct EdgeQuadric;
  template <int kN>
  int candidates_n(const MeshModel& mesh, VertId a, VertId b, CollapseCandidate out[kMaxCandidates], LinkScratch& scratch);
  template <int kN>
  double edge_cost_n(const MeshModel& mesh, VertId a, VertId b, LinkScratch& scratch);
  void normalise(const MeshModel& mesh, VertId v, double* x) const;
  // The field part of every vertex's quadric (the constructor's first step; cost.cpp says why so).
  void add_star_field_quadrics(const MeshModel& mesh, double v_ref, const std::vector<double>& weights);
  // x = p normalised, with the field values v's quadric likes best there (fields_at_point, point_cost).
  void best_at_point(const MeshModel& mesh, VertId v, const glm::dvec3& p, double* x) const;

  int n_ = 3;             // quadric dimension
  int stride_ = 0;        // mesh field stride
  double length_weight_ = 0.0;  // x |ab|^3 (normalised) on every placement of ab: tie break + size term
  std::vector<int> component_;  // quadric field coordinate -> mesh field component
  glm::dvec3 origin_{0.0};
  double inv_diag_ = 1.0;
  std::vector<double> field_min_, field_scale_;  // per quadric field component
  // Per vertex, side by side: its quadric (quadric_size(n_) doubles), then its normalised
  // coordinates (n_ doubles). A candidate edge reads one record per end.
  std::vector<double> records_;
  std::size_t record_size_ = 0;
  double* quadric(VertId v) { return &records_[v * record_size_]; }
  const double* quadric(VertId v) const { return &records_[v * record_size_]; }
  double* coordinates(VertId v) { return &records_[v * record_size_ + quadric_size(n_)]; }
  const double* coordinates(VertId v) const { return &records_[v * record_size_ + quadric_size(n_)]; }
  std::unique_ptr<std::atomic<std::uint8_t>[]> orders_;  // 0xFF = stale
  // Per vertex: 1 when the surface around it is not one plane (its fan at the start, or either
  // part it was merged from). Flat surfaces keep their vertices on the plane exactly.
  std::unique_ptr<std::uint8_t[]> curved_;
  // Whether edge ab (both ends of order `order`) may move to the quadric's optimum: inside a
  // material always; on a surface only where it is curved at both ends (see the placement rules).
  bool optimum_allowed(VertId a, VertId b, std::uint8_t order) const {
    return order == 0 || (order == 1 && curved_[a] != 0 && curved_[b] != 0);
  }
  const SurfaceReference* surfaces_ = nullptr;           // see the constructor
  bool is_interior(const MeshModel& mesh, VertId v) const {
    return surfaces_ != nullptr ? !surfaces_->on_surface(v) && !mesh.is_pinned(v) : is_interior_vertex(mesh, v);
  }
  std::size_t vertex_count_ = 0;
  // Per vertex, the field components pinned on an isosurface (field_pins.h); empty when none are.
  std::vector<std::uint32_t> pins_;
  // True when a and b are pinned in one component to different values: they must not merge.
  bool pins_conflict(const MeshModel& mesh, VertId a, VertId b) const;
  // Sets the pinned components of out (the survivor of u <- v) to the pinned values.
  void apply_pins(const MeshModel& mesh, VertId u, VertId v, double* out) const;
};

// The kernel's view of candidate c (collapse.h): v into u at p, tried as a quality fallback if it
// is one; no field values (set_placement_fields adds them where the field bounds need them).
inline Placement placement_of(const CollapseCandidate& c) { return {c.u, c.v, c.p, nullptr, c.fallback}; }

// Points placements[i].fields at fields_at(cands[i]) (stored in `storage`), for the kernel's field
// error check (CollapseOptions::field_bounds): it must see the values collapse() will write.
void set_placement_fields(const MeshModel& mesh, const CostModel& cost, const CollapseCandidate* cands, int n,
                          Placement* placements, std::vector<double>& storage);

}  // namespace topotet
