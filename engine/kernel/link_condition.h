// Link conditions for collapsing an edge ab of K while preserving the topology of K and of every
// embedded substructure (paper 000 §3, Algorithm 1; paper 001 §4.6 and §5.2).
//
// Orders. Every simplex containing a gets an order in 0..3 from St(a) alone, for two filtrations
// K = B0 ⊇ B1 ⊇ B2 ⊇ B3:
//   K~ (substructures): a face is order 1 if it is special: a listed surface face, a material
//      interface, or a boundary face. Its label is (ref, the two materials or material+boundary).
//      An edge is order 2 if it is on a polyline, or has 1 or >= 3 special faces, or has 2 special
//      faces with different labels (a seam between two refs: we treat it as a feature curve,
//      an over-estimate that only forbids collapses); order 1 with 2 special faces of one label;
//      else 0. A vertex is order 3 if pinned, if its order-2 edges are not exactly two with equal
//      labels, or if the special faces around it are not shaped like a surface point (one cycle in
//      its link, order 1) or a curve point (k arcs joining the two curve neighbours, order 2); else
//      the highest order of its edges. Everything we cannot classify as a plain surface or curve
//      point is order 3 (over-estimate, allowed: paper 001 §5.2 does the same).
//   K  (the mesh alone, paper 001 §4.6): the same rules where only boundary faces are special and
//      all labels are equal, without pinned vertices.
// Unlike paper 000's single extended complex, faces on the boundary keep order 1 even when they are
// also substructure faces, so one filtration never hides the other; we still check both.
//
// Conditions. With these orders, the three link conditions Lk_i(a) ∩ Lk_i(b) = Lk_i(ab) in
// B_i ∪ ω·B_{i+1} (i = 0, 1, 2) unfold into the following tests (x, y, z vertices of K):
//   (A) every common neighbour x of a and b spans a triangle abx of K;
//   (B) every edge xy with triangles axy and bxy spans a tet abxy;
//   (C) no triangle xyz with tets axyz and bxyz;
//   (D) ord a >= 1 and ord b >= 1  =>  ord ab >= 1          (ω in Lk_0)
//   (E) ord ax >= 1 and ord bx >= 1  =>  abx is special     (ωx in Lk_0, x in Lk_1)
//   (F) no xy with axy and bxy both special                  (ωxy in Lk_0, xy in Lk_1)
//   (G) ord a >= 2 and ord b >= 2  =>  ord ab = 2           (ω in Lk_1)
//   (H) no x with ord ax = 2 and ord bx = 2                  (ωx in Lk_1, x in Lk_2)
//   (I) not both ord a = 3 and ord b = 3                     (ω in Lk_2)
// (A)-(C) are the non-ω part of Lk_0 and are shared by both filtrations.
#pragma once

#include <cstdint>
#include <vector>

#include "mesh/mesh_model.h"

namespace topotet {

enum class LinkResult : std::uint8_t { kOk, kLinkK, kLinkKtilde };

// What the classification of one vertex found, for both filtrations.
struct VertexOrders {
  std::uint8_t k = 0;       // order in K's own filtration (boundary only)
  std::uint8_t ktilde = 0;  // order in the substructure filtration
};

// Per-thread scratch: the vectors keep their capacity, so steady-state calls do not allocate.
struct LinkScratch {
  struct FaceRec {  // face (a, x, y) of a tet of St(a), x < y
    std::uint64_t key;  // x << 32 | y: sorting on one integer is what makes classification fast
    TetId tet;
    std::uint8_t local_face;
    VertId x() const { return static_cast<VertId>(key >> 32); }
    VertId y() const { return static_cast<VertId>(key); }
  };
  struct Label {
    std::int32_t ref, m0, m1;
    bool operator==(const Label&) const = default;
    bool operator<(const Label& o) const {
      return ref != o.ref ? ref < o.ref : (m0 != o.m0 ? m0 < o.m0 : m1 < o.m1);
    }
  };
  struct SpecialFace {  // special face (a, x, y) in the K~ filtration
    VertId x, y;
    Label label;
    bool boundary;
  };
  struct Neighbour {  // edge (a, x)
    VertId x;
    std::uint8_t count[2];  // special faces containing ax: [0] K, [1] K~
    std::uint8_t order[2];
    bool polyline;
    bool mixed_labels;
    std::int32_t polyline_ref;
    Label first_label;
  };
  struct VertexData {
    // The vertex classify_vertex filled this with (kInvalid: none, or only its neighbours).
    VertId vertex = kInvalid;
    std::vector<FaceRec> recs;
    std::vector<SpecialFace> special;      // K~-special faces at a (boundary ones flagged)
    std::vector<Neighbour> neighbours;     // sorted by x
    bool non_manifold = false;             // a face of St(a) has more than two tets
    VertexOrders orders;
  };
  VertexData a, b;
  // Set by ReuseClassifications (below): a check may use a slot that already holds the
  // classification of one of its ends.
  bool reuse_classified = false;
  // Optional hint from a caller that caches orders (CostModel): vertices known to have order 0 in
  // the substructure filtration. Such a vertex has no special face and no polyline edge, hence
  // order 0 in K's filtration too, so its classification is skipped (only its neighbour list is
  // built). kInvalid = no hint. Consumed (reset) by every check_link_conditions call.
  std::array<VertId, 2> known_interior{kInvalid, kInvalid};
  char failed_test = 0;  // after a failed check: which of (A)-(I) failed ('A'..'I'), for reports
  int failed_filtration = 0;  // 0 = K, 1 = K~
  std::vector<Label> labels_x1, labels_x2;
  std::vector<VertId> tmp_vertices;
  struct FaceGroup {  // the records of one face through a (indices into VertexData::recs)
    std::uint32_t count, first, second, last_flagged;
  };
  std::vector<FaceGroup> face_groups;
  std::vector<std::uint64_t> face_slots;   // probe set storage for the face grouping
  std::vector<VertId> vertex_slots;        // probe set storage for the neighbours
  std::vector<std::pair<VertId, std::int32_t>> polyline_ends;  // polyline edges at the vertex
  std::vector<std::uint32_t> slot_group;   // face slot -> index into face_groups
  std::vector<VertId> common;  // common neighbours of a and b (other than a, b)
  std::vector<std::uint64_t> pairs_a, pairs_b, pairs_ab;
  std::vector<std::array<VertId, 3>> faces_a, faces_b;
};

// Within its scope, the mesh must not change: check_link_conditions then uses a slot of `scratch`
// that already holds one of its ends' classification, from an earlier check in the scope, instead
// of classifying it again. Where the checks of one scope share vertices (a vertex's edges tried in
// turn by the engine's verify phase; the census looking at each edge from both ends), most of the
// classifications repeat: polycrystal 30k, 74,555 of them made 8% of the run. The slots are
// forgotten when the scope opens and closes: the mesh may have changed outside it.
class ReuseClassifications {
 public:
  explicit ReuseClassifications(LinkScratch& scratch) : scratch_(scratch) {
    scratch_.a.vertex = scratch_.b.vertex = kInvalid;
    scratch_.reuse_classified = true;
  }
  ~ReuseClassifications() {
    scratch_.a.vertex = scratch_.b.vertex = kInvalid;
    scratch_.reuse_classified = false;
  }
  ReuseClassifications(const ReuseClassifications&) = delete;
  ReuseClassifications& operator=(const ReuseClassifications&) = delete;

 private:
  LinkScratch& scratch_;
};

// Classifies vertex a from its star (fills scratch data; returns its orders).
VertexOrders classify_vertex(const MeshModel& mesh, VertId a, LinkScratch::VertexData& data, LinkScratch& scratch);

// True when a has order 0 in both filtrations, decided without building its link: a is not
// pinned, no face or edge of St(a) through a is flagged, and every face through a has exactly two
// tets (none on the boundary, none non-manifold). Equivalent to vertex_orders(a).ktilde == 0 (the
// classification gives order 0 exactly when a has no special face, no polyline edge and is not
// pinned), at a fraction of the cost; used to skip the classification of the many interior vertices.
bool is_interior_vertex(const MeshModel& mesh, VertId a);

// Orders of vertex a, for callers outside the kernel (cost, placement, tests).
VertexOrders vertex_orders(const MeshModel& mesh, VertId a, LinkScratch& scratch);

// Evaluates (A)-(I) for edge ab. `stab` must be St(a) ∩ St(b) (the tets containing ab, non-empty).
LinkResult check_link_conditions(const MeshModel& mesh, VertId a, VertId b, const std::vector<TetId>& stab,
                                 LinkScratch& scratch);

}  // namespace topotet
