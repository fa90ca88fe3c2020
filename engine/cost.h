// Collapse cost and placement: Garland–Zhou quadrics over positions and fields (paper 002 §4,
// paper 001 §5.1), with placements that respect the vertex classification.
//
// Coordinates are normalised so that the bounding box diagonal is 1 and every field component
// spans [0, 1]: weights and costs then mean the same on every mesh. Each vertex carries the sum of
//   - the quadric of every incident tet's 3-flat in R^(3+k), weighted by its volume (field error);
//   - the plane quadric of every incident boundary or surface face, weighted by area x
//     boundary_weight (geometric error of interfaces and boundary);
//   - the line quadric of every incident polyline edge, weighted by length x polyline_weight.
// The feature quadrics measure position only (quadric_add_simplex_positions): built in R^(3+k)
// they would also pin the field along every feature with the feature's penalty, which kept nearly
// all boundary vertices and left the interior's field short of them (RMS field error on the
// 100k-tet cube-sphere at 10%: 0.034 -> 0.024 sequential, 0.028 -> 0.017 parallel).
// Where a placement fixes the position (an endpoint, the midpoint) the field values still come
// from the quadric: its minimum over the field coordinates at that position.
// After a collapse u <- v, Q_u += Q_v (the standard Garland–Heckbert accumulation).
//
// Placement of the merged vertex (ord = order in the substructure filtration, link_condition.h):
//   ord a > ord b : a stays where it is (a vertex on a feature never leaves it);
//   equal, 0      : the quadric's optimum when well conditioned and near the edge, else the best of
//                   the endpoints and the midpoint;
//   equal, 1 or 2 : the best of the endpoints and the midpoint (the midpoint of a surface or curve
//                   edge stays on the piecewise-linear feature);
//   pinned vertices never move; two order-3 ends never collapse (link condition (I)).
// A small length term (1e-6 |ab|^3) breaks ties between zero-cost collapses in favour of short
// edges, which keeps tets well shaped when there is no field to preserve.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "link_condition.h"
#include "quadric.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"

namespace topotet {

struct CollapseCandidate {
  VertId u = kInvalid, v = kInvalid;  // v merges into u
  glm::dvec3 p{0.0};                  // new position of u (mesh units)
  double cost = 0.0;                  // normalised units
  int placement = 0;                  // 0 = at u, 1 = midpoint, 2 = quadric optimum
  double x[kMaxQuadricDim];           // the placement in normalised quadric coordinates
};

class CostModel {
 public:
  // Builds every vertex's quadric and order (parallel over vertices, deterministic).
  CostModel(const TetMesh& mesh, const SimplifyOptions& options);

  int dimension() const { return n_; }

  // Placements for edge ab, cheapest first (at most 4). Returns 0 when the orders forbid the
  // collapse outright (both ends order 3, or a pinned end that would have to move).
  int candidates(const TetMesh& mesh, VertId a, VertId b, CollapseCandidate out[4], LinkScratch& scratch);

  // The cost of edge ab's cheapest placement (candidates()[0].cost, up to rounding: the optimum,
  // when it is a candidate, is taken as the cheapest without evaluating the others); infinity
  // when the orders forbid the collapse. For ranking edges; candidates() for checking them.
  double edge_cost(const TetMesh& mesh, VertId a, VertId b, LinkScratch& scratch);

  // Field values (mesh units, field_stride() of them) for u after collapsing with candidate c.
  void fields_at(const TetMesh& mesh, const CollapseCandidate& c, double* out) const;

  // Asks the memory system for what edge_cost / candidates will read about v (see prefetch.h).
  void prefetch(VertId v) const;

  // Bookkeeping after mesh collapse(u <- v): Q_u += Q_v, and the orders of u and of the vertices
  // of the removed tets `star_uv` are recomputed on demand. Writes only u's quadric and the order
  // bytes of vertices of St(uv), all inside the collapse's stencil.
  void on_collapse(const TetMesh& mesh, VertId u, VertId v, const std::vector<TetId>& star_uv);

  // Order of v in the substructure filtration (cached; thread-safe for distinct or equal v:
  // concurrent recomputations write the same value).
  std::uint8_t order(const TetMesh& mesh, VertId v, LinkScratch& scratch);

  // True when v is known to be of order 0 (interior: on no feature). Interior stays interior
  // through every legal collapse, so the answer never goes stale.
  bool known_interior(VertId v) const { return orders_[v].load(std::memory_order_relaxed) == 0; }

  // Tells the kernel which ends of edge ab are known to be of order 0 (LinkScratch::known_interior).
  void hint_orders(VertId a, VertId b, LinkScratch& scratch) const {
    scratch.known_interior[0] = orders_[a].load(std::memory_order_relaxed) == 0 ? a : kInvalid;
    scratch.known_interior[1] = orders_[b].load(std::memory_order_relaxed) == 0 ? b : kInvalid;
  }

  std::size_t memory_bytes() const;

 private:
  // kN > 0: the quadric dimension n_ fixed at compile time; 0: read at run time.
  template <int kN>
  struct EdgeQuadric;
  template <int kN>
  int candidates_n(const TetMesh& mesh, VertId a, VertId b, CollapseCandidate out[4], LinkScratch& scratch);
  template <int kN>
  double edge_cost_n(const TetMesh& mesh, VertId a, VertId b, LinkScratch& scratch);
  void normalise(const TetMesh& mesh, VertId v, double* x) const;

  int n_ = 3;             // quadric dimension
  int stride_ = 0;        // mesh field stride
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
  std::size_t vertex_count_ = 0;
};

}  // namespace topotet
