// The geometric tolerance check of the kernel: "does the surface around the collapsed vertex stay
// within H of the ORIGINAL surface of the same label?" (issue #6, like MMG's -hausd).
//
// SurfaceReference is built once from the input mesh, before any collapse, and never changes:
//   - every special face of the input, once: boundary faces, material interfaces and listed
//     triangles, each with its label (ref, material pair) as the link conditions form it
//     (link_condition.cpp): listed ref or kUnlistedRef, and the two materials, or the material
//     and kOutsideMaterial for a boundary face;
//   - every polyline edge of the input with its ref;
//   - one Embree 3 scene: a triangle geometry per face label and a user geometry (segments) per
//     polyline ref, so that the geometry id IS the label. Closest-point queries go through
//     rtcPointQuery, whose callback skips primitives of other geometries and measures the exact
//     point-triangle (point-segment) distance in double precision on the original coordinates
//     (Embree only prunes with its float boxes; the query radius is widened by the float rounding
//     of the coordinates so that pruning never loses a primitive).
// Queries are const and keep their state on the caller's stack: any number of threads may query
// one reference concurrently.
//
// The kernel check (placement_within_tolerance, called by first_acceptable in collapse.cpp) for
// v merged into u, u moved to p, with h the tolerance. For every special face (polyline edge) of
// St(u) ∪ St(v) that survives the collapse and moves (contains exactly one of u, v):
//   screen    p, the centroid and the midpoints of the edges at p of each new triangle (the
//             midpoint of each new segment) within h: a point beyond h is a real violation, and
//             most refusals take only these few queries;
//   reverse   the old positions of u and v (when they differ from p) within h of the new
//             triangles (segments) around p of every label they carried (cheap, exact);
//   forward   a proof that EVERY point of each new triangle p x y is within h of the original
//             surface of its label (surface_tolerance.cpp, triangle_within). A piece of the
//             triangle (the whole at first) is accepted by the first of these that holds:
//               - Lipschitz: its centre within h - r, r the centre's distance to its farthest
//                 corner (the distance to a fixed set is 1-Lipschitz);
//               - flat patch: its shadow on a nearly flat patch of the original (flat_patches.h)
//                 lies in the patch's shadow, and its corners' distances to the patch plane plus
//                 the patch's deviation are within h (one step for a large triangle over many
//                 small coplanar ones: boxes, CAD faces);
//               - one primitive: one original triangle within h of all its corners (the distance
//                 to a triangle is convex);
//               - crease: two original triangles across an edge, the piece cut by the plane
//                 bisecting them, each part within h of its own triangle (curved surfaces made of
//                 flat facets, where pieces straddle facet edges);
//             otherwise it is split in four, down to r = h / 8 or 64 pieces, where the placement
//             is refused. Likewise every point of a new segment p x, and, when px is on the
//             border of its label's surface (one face of that label: the rim of an open surface,
//             or a seam between two labels), every point of px against the original border;
//   coverage  (surface_coverage.h, called after this check by collapse.cpp) the original
//             triangles and polyline segments that the moving faces (edges) held find a new face
//             (edge) within h of all their corners, cut where needed.
// What this guarantees, by induction over the collapses (every face a collapse changes contains p,
// so every changed face is checked whole, and unchanged faces keep their position):
//   - simplified -> original: every point of the simplified boundary, interfaces, listed surfaces,
//     polylines and label borders is within h of the original of its label;
//   - original -> simplified: every point of the original boundary, interfaces, listed surfaces
//     and polylines (feature curves included) is within h of the simplified one of its label.
// Both are proofs, not samplings: an independent dense measurement can only find less (up to the
// rounding of double arithmetic, ~1e-9 h).
// Faces whose label does not exist in the original (cannot happen with the link conditions on;
// a safety net) are refused. An interior vertex may not absorb a surface vertex (the cost model
// never proposes it: it keeps the vertex of higher order), so that the per-vertex "on a surface"
// bit of the original is an exact early out: collapses of two interior vertices cost one lookup.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "mesh/mesh_model.h"

namespace topotet {

struct FlatPatches;
struct SpecialFaces;

// A face of a tet: the tet and the face's local index (opposite that corner).
struct FaceHolder {
  TetId tet;
  std::uint8_t local;
};

// Label of a special face: the same notion as LinkScratch::Label (link_condition.h).
struct SurfaceLabel {
  std::int32_t ref, m0, m1;  // m0 <= m1
  friend bool operator==(const SurfaceLabel&, const SurfaceLabel&) = default;
  friend auto operator<=>(const SurfaceLabel&, const SurfaceLabel&) = default;
};
inline constexpr std::int32_t kUnlistedRef = INT32_MIN + 1;  // special face without a listed ref
inline constexpr std::int32_t kOutsideMaterial = INT32_MIN;  // the outer side of a boundary face

// Raw input of a reference: positions plus labelled triangles and segments (geometry ids dense,
// triangles first). SurfaceReference::from_mesh fills it from a MeshModel; benchmarks fill it
// directly.
struct SurfaceSoup {
  std::vector<glm::dvec3> positions;
  std::vector<std::array<VertId, 3>> triangles;
  std::vector<std::uint32_t> triangle_label;  // [triangle] face label id, < face_labels
  std::vector<std::array<VertId, 2>> segments;
  std::vector<std::uint32_t> segment_label;   // [segment] polyline label id, < polyline_labels
  std::uint32_t face_labels = 0, polyline_labels = 0;
};

class SurfaceReference {
 public:
  // The special faces and polyline edges of the live part of `mesh` (see the file comment). With a
  // tolerance h > 0, also the flat patches the check proves large triangles with (vertices within
  // h / 2 of their planes: build_flat_patches).
  static std::unique_ptr<SurfaceReference> from_mesh(const MeshModel& mesh, double tolerance = 0.0);
  // The same from the mesh's special faces, found beforehand (the driver shares them with the
  // feature detection).
  static std::unique_ptr<SurfaceReference> from_mesh(const MeshModel& mesh, double tolerance,
                                                     const SpecialFaces& special);
  // From raw primitives (benchmarks, tests): geometry ids are the soup's label ids; there are no
  // label values to look up and no border geometries.
  explicit SurfaceReference(SurfaceSoup soup);
  ~SurfaceReference();
  SurfaceReference(const SurfaceReference&) = delete;
  SurfaceReference& operator=(const SurfaceReference&) = delete;

  // Dense ids: face labels 0..face_label_count()-1, polyline refs after them, then the border
  // curve of each face label (its edges with exactly one face of that label). -1 if absent.
  int face_label_id(const SurfaceLabel& label) const;
  int polyline_label_id(std::int32_t ref) const;
  int border_label_id(int face_label) const {
    return static_cast<int>(face_labels_.size() + polyline_refs_.size()) + face_label;
  }
  std::size_t face_label_count() const { return face_labels_.size(); }
  std::size_t triangle_count() const { return soup_.triangles.size(); }
  std::size_t segment_count() const { return soup_.segments.size(); }

  // Was vertex v on a special face or polyline edge of the original? (ids of the input mesh)
  bool on_surface(VertId v) const { return v < on_surface_.size() && on_surface_[v] != 0; }
  // Where each triangle of the soup was taken from (from_mesh only; empty otherwise).
  const std::vector<FaceHolder>& triangle_holders() const { return holders_; }
  // The same for the polyline segments (the first ones of the soup; local = tet edge index).
  const std::vector<FaceHolder>& segment_holders() const { return segment_holders_; }
  const SurfaceSoup& soup() const { return soup_; }

  // Is some primitive of `label` (a geometry id) within distance h of p? Stops at the first hit.
  bool within(const glm::dvec3& p, int label, double h) const;
  // The same search, answering with the primitive it stopped at (a soup triangle or segment
  // within h of p), or kInvalid when there is none.
  std::uint32_t any_within(const glm::dvec3& p, int label, double h) const;
  // Is one primitive of `label` within h of every one of the `count` points? Then, the distance to
  // a fixed triangle (segment) being convex, the whole triangle (segment) they span is within h.
  bool within_one(const glm::dvec3* corners, int count, int label, double h) const;
  // Distance from p to the closest primitive of `label`, or +infinity if none is within max_distance.
  double distance(const glm::dvec3& p, int label, double max_distance) const;

  // Finds the nearly flat patches of the original surfaces (flat_patches.h), their vertices within
  // max_deviation of their planes. Call before sharing the reference between threads.
  void build_flat_patches(double max_deviation);
  // Is every point of the triangle `corners` within h of the original surface of face label
  // `label`, by projection onto one flat patch (flat_patches.h)? False when there are no patches,
  // or when this argument does not apply (the caller then splits the triangle).
  bool within_by_patch(const std::array<glm::dvec3, 3>& corners, int label, double h, std::uint32_t nearest) const;
  // The same question answered with two original triangles across one edge (a crease of a curved
  // surface made of flat facets): the triangle is cut by the plane that bisects the crease, and
  // each part is within h of its own facet (convexity, see surface_tolerance.cpp). Needs the
  // patches (their triangle adjacency).
  bool within_by_crease(const std::array<glm::dvec3, 3>& corners, int label, double h, std::uint32_t nearest) const;
  // The same with the original triangles a few edges around `nearest`, the piece cut where the
  // nearest of them changes (facet_cover.h). Needs the patches (their triangle adjacency).
  bool within_by_facets(const std::array<glm::dvec3, 3>& corners, double h, std::uint32_t nearest) const;
  // The soup triangle of face label `label` nearest to p within max_distance (kInvalid: none),
  // and its distance. `nearest` above is this triangle for the piece's centre.
  // `hint` (a soup triangle near p, or kInvalid) only speeds the search up; ties in distance go to the
  // lower index, so the answer is the same with any hint.
  std::uint32_t nearest_triangle(const glm::dvec3& p, int label, double max_distance, double* distance,
                                 std::uint32_t hint = kInvalid) const;
  // Is every corner of q within h of soup triangle k (so all of q, by convexity)?
  bool triangle_holds(std::uint32_t k, const std::array<glm::dvec3, 3>& q, double h) const;

 private:
  struct Embree;
  SurfaceSoup soup_;
  std::vector<SurfaceLabel> face_labels_;       // sorted; index = geometry id
  std::vector<std::int32_t> polyline_refs_;     // sorted; index + face_labels_.size() = geometry id
  std::vector<std::uint8_t> on_surface_;
  std::vector<FaceHolder> holders_;          // [soup triangle]
  std::vector<FaceHolder> segment_holders_;  // [soup polyline segment]
  double slack_ = 0.0;  // float rounding of the coordinates Embree prunes with
  std::unique_ptr<Embree> embree_;
  std::unique_ptr<FlatPatches> patches_;
};

// The special faces and polyline edges at u or v of one edge's stencil, gathered once per edge.
struct SurfaceStencil {
  struct Face {
    std::array<VertId, 3> v;  // old vertex ids, sorted
    int label;                // face label id, -1 if absent from the reference
    FaceHolder holder;        // a tet outside St(uv) that has it (kInvalid: none)
  };
  struct Edge {
    std::array<VertId, 2> v;
    int label;
    FaceHolder holder;  // a tet outside St(uv) that has it, local = edge index (kInvalid: none)
  };
  // A face through u or v in one tet of the stars (key: its sorted vertices).
  struct FaceRec {
    std::array<VertId, 3> key;
    TetId tet;
    std::uint8_t local_face;
  };
  std::vector<FaceRec> recs;
  // Scratch of gather_surface_stencil: the records of one face are chained (next_rec) from their
  // group's head; faces through u and faces through v alone are keyed in two probe tables by
  // their two other vertices.
  std::vector<std::uint32_t> next_rec, group_head;
  std::vector<std::uint64_t> face_slots[2];
  std::vector<std::uint32_t> slot_group[2];
  std::vector<Face> faces;
  std::vector<Edge> edges;
  // Original triangles held near the stencil (SurfaceCoverage::held_triangles; empty without a
  // coverage): a point within h of one of its label's is within h of the surface, no search needed.
  std::vector<std::uint32_t> near_triangles;
  // The original triangles the searches of this stencil's checks answered with, the latest first
  // (placement_within_tolerance; at most kFoundTriangles): the points a check asks are close
  // together, and one that answered for a point often answers for the next. Emptied with
  // near_triangles; a stale one would still be an original triangle within h (only slower).
  std::vector<std::uint32_t> found_triangles;
  // Per placement: the new triangles / segments around p (positions) with their labels.
  struct NewFace {
    std::array<glm::dvec3, 3> pts;  // p first
    std::array<VertId, 2> others;   // the vertices other than p
    int label;
    FaceHolder holder;  // the tet (outside St(uv)) that has the face after the collapse; kInvalid: none
  };
  struct NewEdge {
    std::array<glm::dvec3, 2> pts;  // p first
    int label;
    VertId other;       // the vertex other than p
    FaceHolder holder;  // the tet that has the edge after the collapse (local: edge index)
  };
  std::vector<NewFace> new_faces;
  std::vector<NewEdge> new_edges;
};

// Fills `out` from St(u) ∪ St(v) (sorted tet ids; star_uv = their intersection).
void gather_surface_stencil(const MeshModel& mesh, const SurfaceReference& reference, VertId u, VertId v,
                            const std::vector<TetId>& star_u, const std::vector<TetId>& star_v,
                            const std::vector<TetId>& star_uv, SurfaceStencil& out);

// The new triangles and segments around p (stencil.new_faces, new_edges) for this placement.
// False when one of their labels is absent from the reference (the placement is refused).
bool new_surface_around(const MeshModel& mesh, VertId u, VertId v, const glm::dvec3& p, SurfaceStencil& stencil);

// The kernel check (see the file comment). `stencil` must have been gathered for edge uv (either
// direction). Returns true when p is acceptable. `screen`: first look at a few points of each new
// triangle, which refuses most failing placements cheaply but only adds queries to one that
// passes; the answer is the same either way (the proofs refuse every point beyond h too).
bool placement_within_tolerance(const MeshModel& mesh, const SurfaceReference& reference, double h, VertId u,
                                VertId v, const glm::dvec3& p, SurfaceStencil& stencil, bool screen = true,
                                bool proofs = true);
// proofs = false: the screen and the reverse check only (true means "not refused yet", not a
// proof; CollapseOptions::screen_only).

// Exact squared distances (double precision), shared by the reference and the kernel check.
double squared_distance_to_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                    const glm::dvec3& c);
double squared_distance_to_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b);
// The normal, towards facet (a b o1), of the plane that holds edge ab and bisects the crease
// between facets (a b o1) and (a b o2): the difference of the two unit directions from the edge
// into each facet, orthogonal to it (defined for coplanar facets, where their sum vanishes). Zero
// for a degenerate edge. The crease test's cut, and the facet cover's (facet_cover.h).
glm::dvec3 crease_normal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& o1, const glm::dvec3& o2);

}  // namespace topotet
