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
//   forward   these sample points of the new triangle p x y must be within h of the original
//             surface of the face's label: p, the centroid, and the points of a barycentric grid
//             of n subdivisions per edge off the unmoved edge xy (n = 2, the midpoints of px and
//             py, for triangles up to 4h long; 3 up to 8h; 4 beyond); of a new segment p x: p and
//             the midpoint; and when px is on the border of
//             its label's surface (one face of that label: the rim of an open surface, or a seam
//             between two labels), p and the midpoint must be within h of the original border;
//   reverse   the old positions of u and v (when they differ from p) must be within h of the new
//             triangles (segments) around p of every label they carried.
// What this guarantees, by induction over the collapses:
//   - every vertex, centroid and edge midpoint of the simplified boundary, interfaces and listed
//     surfaces is within h of the original surface of its label (and likewise for polylines).
//     (The corners and edge midpoints of a triangle are checked when its edges are made.) Other
//     points of a triangle are within h + r, r their distance to the nearest sample (distance is
//     1-Lipschitz): r <= longest edge / (n sqrt 3). On smooth surfaces the distance of a chord
//     peaks near the centroid; on rough ones (the jittered generated interfaces) the measured
//     simplified -> original distance exceeded h by up to ~20% before the grid was refined;
//   - each removed vertex was within h of the surface around the vertex that replaced it, at the
//     moment of its removal. It is not re-checked when that surface moves again later, so the
//     original -> simplified direction is only bounded through the forward checks: a closed
//     surface (or one whose rim is checked as a border curve) that stays within h of the original
//     cannot leave part of the original uncovered by much more than h without changing topology,
//     but this is not a proof; the metric (metrics/surface_distance.h) measures both directions.
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

#include "mesh_model.h"

namespace topotet {

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
  // The special faces and polyline edges of the live part of `mesh` (see the file comment).
  static std::unique_ptr<SurfaceReference> from_mesh(const MeshModel& mesh);
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

  // Is some primitive of `label` (a geometry id) within distance h of p? Stops at the first hit.
  bool within(const glm::dvec3& p, int label, double h) const;
  // Distance from p to the closest primitive of `label`, or +infinity if none is within max_distance.
  double distance(const glm::dvec3& p, int label, double max_distance) const;

 private:
  struct Embree;
  SurfaceSoup soup_;
  std::vector<SurfaceLabel> face_labels_;       // sorted; index = geometry id
  std::vector<std::int32_t> polyline_refs_;     // sorted; index + face_labels_.size() = geometry id
  std::vector<std::uint8_t> on_surface_;
  double slack_ = 0.0;  // float rounding of the coordinates Embree prunes with
  std::unique_ptr<Embree> embree_;
};

// The special faces and polyline edges at u or v of one edge's stencil, gathered once per edge.
struct SurfaceStencil {
  struct Face {
    std::array<VertId, 3> v;  // old vertex ids, sorted
    int label;                // face label id, -1 if absent from the reference
  };
  struct Edge {
    std::array<VertId, 2> v;
    int label;
  };
  struct FaceRec {
    std::array<VertId, 3> key;
    TetId tet;
    std::uint8_t local_face;
    bool operator<(const FaceRec& o) const { return key != o.key ? key < o.key : tet < o.tet; }
  };
  std::vector<FaceRec> recs;
  std::vector<Face> faces;
  std::vector<Edge> edges;
  // Per placement: the new triangles / segments around p (positions) with their labels.
  struct NewFace {
    std::array<glm::dvec3, 3> pts;  // p first
    std::array<VertId, 2> others;   // the vertices other than p
    int label;
  };
  struct NewEdge {
    std::array<glm::dvec3, 2> pts;  // p first
    int label;
  };
  std::vector<NewFace> new_faces;
  std::vector<NewEdge> new_edges;
};

// Fills `out` from St(u) ∪ St(v) (sorted tet ids; star_uv = their intersection).
void gather_surface_stencil(const MeshModel& mesh, const SurfaceReference& reference, VertId u, VertId v,
                            const std::vector<TetId>& star_u, const std::vector<TetId>& star_v,
                            const std::vector<TetId>& star_uv, SurfaceStencil& out);

// The kernel check (see the file comment). `stencil` must have been gathered for edge uv (either
// direction). Returns true when p is acceptable.
bool placement_within_tolerance(const MeshModel& mesh, const SurfaceReference& reference, double h, VertId u,
                                VertId v, const glm::dvec3& p, SurfaceStencil& stencil);

// Exact squared distances (double precision), shared by the reference and the kernel check.
double squared_distance_to_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                    const glm::dvec3& c);
double squared_distance_to_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b);

}  // namespace topotet
