// MeshModel: the validated working model the simplifier edits in place. Internal: the public
// TetMesh (topotet/tet_mesh.h) is a handle that owns one, so that users see accessors while the
// engine works on the arrays directly (no indirection in the hot loops: kernels take MeshModel&).
//
// Structure of arrays with 32-bit ids (see ../shared/DESIGN.md, "Data"):
//   vertices: positions, interleaved field values, a ref, a state byte (pinned / dead);
//   tets:     4 vertex ids (positively oriented), material id, a 16-bit flags word;
//   side table: refs of flagged faces/edges, one SubstructureRefs record per flagged tet;
//   incidence: vertex -> tets as a chain of CSR chunks (see below).
//
// Substructures are never stored as triangle or edge lists: a tet's flags word says which of its
// faces lie on a surface (listed triangle or material interface) and which of its edges lie on a
// polyline (paper 000 §4.1). Boundary faces are not flagged: a face is on the boundary iff only one
// tet has it, which the kernel sees from the stars it reads anyway.
//
// Vertex -> tet incidence: every vertex starts owning one chunk of the CSR array holding exactly
// its initial star. A collapse u <- v gives v's chunks to u (linking them after u's), and
// St(u) after the collapse is never larger than |St(u)| + |St(v)|, so it always fits: a collapse
// never allocates, and two collapses with disjoint stencils never touch the same chunk. The tets
// of a vertex are packed into its chain in order; `v2t_count` says how many there are.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "topotet/mesh_data.h"
#include "topotet/tet_mesh.h"

namespace topotet {

using TetFlags = std::uint16_t;

namespace tet_flag {
inline constexpr int kSurfaceFaceShift = 0;   // bit f: face f (opposite local vertex f) is on a surface
inline constexpr int kPolylineEdgeShift = 4;  // bit 4+e: local edge e (kTetEdges[e]) is on a polyline
inline constexpr TetFlags kSurfaceFaces = 0xF;
inline constexpr TetFlags kPolylineEdges = 0x3F << kPolylineEdgeShift;
inline constexpr TetFlags kDead = 1u << 10;   // tombstone: removed by a collapse
}  // namespace tet_flag

// Local edge e joins local vertices kTetEdges[e][0] and kTetEdges[e][1].
inline constexpr std::array<std::array<int, 2>, 6> kTetEdges = {
    {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};
// Face f (opposite local vertex f), listed with the orientation that points out of the tet.
inline constexpr std::array<std::array<int, 3>, 4> kTetFaces = {
    {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}}};

constexpr bool is_surface_face(TetFlags f, int face) {
  return (f >> (tet_flag::kSurfaceFaceShift + face)) & 1u;
}
constexpr bool is_polyline_edge(TetFlags f, int edge) {
  return (f >> (tet_flag::kPolylineEdgeShift + edge)) & 1u;
}
constexpr int local_edge_index(int a, int b) {  // a != b in 0..3
  const int lo = a < b ? a : b, hi = a < b ? b : a;
  return lo == 0 ? hi - 1 : (lo == 1 ? hi + 1 : 5);
}

// Ref of a flagged face that is a material interface the input did not list. Such faces are
// substructure faces for the kernel but are not written back as triangles.
inline constexpr std::int32_t kImplicitInterfaceRef = INT32_MIN;
// Ref of a flagged edge that is a sharp feature found by detect_features (topotet/features.h):
// a polyline edge for the kernel, written back only when asked (MeshExportOptions).
inline constexpr std::int32_t kFeatureCurveRef = INT32_MIN + 2;

// A face listed several times with different refs (Gmsh writes one triangle per surface, and a face
// may lie on several model surfaces), or an edge on several polylines, carries ONE stand-in ref
// that stands for the whole set. For the kernel the stand-in is just another label: where a
// shared patch meets a patch of one of its surfaces, the labels differ, so the seam is a feature
// curve (link_condition.h). Every labelled patch, and every seam, then keeps its topology, and so
// does each listed surface, which is a union of such patches along such seams. to_mesh_data()
// writes the face back once per ref of its set. Stand-ins are the smallest values from
// kFirstStandInRef up that no listed triangle (segment) uses, so they never collide with a ref.
inline constexpr std::int32_t kFirstStandInRef = INT32_MIN + 16;  // below: internal labels (kImplicitInterfaceRef, ...)
struct SharedRefs {
  std::int32_t stand_in = 0;
  std::vector<std::int32_t> refs;  // sorted, distinct, at least two
  friend bool operator==(const SharedRefs&, const SharedRefs&) = default;
};

// Refs of the flagged faces and edges of one tet (entries of unflagged ones are meaningless).
struct SubstructureRefs {
  std::array<std::int32_t, 4> face{};
  std::array<std::int32_t, 6> edge{};
  std::uint8_t ridge_mask = 0;  // bit e: local edge e is a MEDIT ridge
};

namespace vertex_state {
inline constexpr std::uint8_t kPinned = 1u << 0;    // never moves, never removed
inline constexpr std::uint8_t kCorner = 1u << 1;    // listed as MEDIT Corner / Gmsh point
inline constexpr std::uint8_t kRequired = 1u << 2;  // listed as MEDIT RequiredVertex
inline constexpr std::uint8_t kFeatureCorner = 1u << 3;  // pinned by detect_features (a corner)
// Frozen: no collapse may touch it, not even as the end that stays (kPinned still allows that).
// Distributed runs (mpi/) freeze the vertices a rank shares with others: a collapse is decided
// locally only when the whole stars of both its ends are local, which a non-frozen end guarantees.
inline constexpr std::uint8_t kFrozen = 1u << 4;
// Reshaped: the vertex survived a collapse or was moved after them, so no tet through it is a tet
// of the input as it was. The optimisation after the collapses (optimize/) works on such tets only.
inline constexpr std::uint8_t kReshaped = 1u << 5;
inline constexpr std::uint8_t kDead = 1u << 7;      // removed by a collapse
}  // namespace vertex_state

namespace detail {

struct MeshModel {
  // --- vertices ---
  std::vector<glm::dvec3> positions;      // [vert]
  std::vector<double> field_values;       // [vert * field_stride() + k]
  std::vector<FieldInfo> fields;          // layout of field_values
  std::vector<GroupName> group_names;     // carried from MeshData to to_mesh_data() unchanged
  std::vector<std::int32_t> vertex_refs;  // [vert]
  std::vector<std::uint8_t> vertex_states;  // [vert] vertex_state bits
  // [vert] the vertex a dead vertex merged into (collapse u <- v sets merged_into[v] = u); kInvalid
  // for live vertices. Empty unless simplify() was asked for a vertex map: only it fills and reads it.
  std::vector<VertId> merged_into;

  // --- tets ---
  std::vector<std::array<VertId, 4>> tets;  // [tet], positively oriented
  std::vector<std::int32_t> material;       // [tet]
  std::vector<TetFlags> flags;              // [tet]
  std::vector<std::uint32_t> tet_refs_slot;  // [tet] index into refs_table, kInvalid if none
  std::vector<SubstructureRefs> refs_table;  // side table (mmg's xTetra)
  std::vector<SharedRefs> shared_face_refs;  // stand-in refs of faces on several surfaces, by stand_in
  std::vector<SharedRefs> shared_edge_refs;  // the same for edges on several polylines

  // --- incidence: chained CSR (see the file comment) ---
  std::vector<std::uint32_t> v2t_offsets;  // [vert + 1] chunk c = [v2t_offsets[c], v2t_offsets[c+1])
  std::vector<std::uint32_t> v2t_next;     // [vert] next chunk in the chain, kInvalid at the end
  std::vector<std::uint32_t> v2t_count;    // [vert] number of tets of the vertex
  std::vector<TetId> v2t;                  // [4 * tets at build]

  std::size_t vertex_capacity() const { return positions.size(); }
  std::size_t tet_capacity() const { return tets.size(); }
  std::size_t live_vertex_count() const;
  std::size_t live_tet_count() const;
  int field_stride() const;  // doubles per vertex in field_values

  bool is_dead_tet(TetId t) const { return flags[t] & tet_flag::kDead; }
  bool is_dead_vertex(VertId v) const { return vertex_states[v] & vertex_state::kDead; }
  bool is_pinned(VertId v) const { return vertex_states[v] & vertex_state::kPinned; }
  bool is_frozen(VertId v) const { return vertex_states[v] & vertex_state::kFrozen; }
  bool is_reshaped(VertId v) const { return vertex_states[v] & vertex_state::kReshaped; }
  // A tet the collapses (or the optimisation) made or moved: one of its vertices is reshaped.
  bool is_reshaped_tet(TetId t) const {
    const auto& tv = tets[t];
    return (vertex_states[tv[0]] | vertex_states[tv[1]] | vertex_states[tv[2]] | vertex_states[tv[3]]) &
           vertex_state::kReshaped;
  }

  // Calls f(tet) for every live tet incident to v, in chain order.
  template <class F>
  void for_each_tet_of(VertId v, F&& f) const {
    std::uint32_t remaining = v2t_count[v];
    for (std::uint32_t c = v; remaining != 0; c = v2t_next[c]) {
      const std::uint32_t begin = v2t_offsets[c];
      const std::uint32_t n = std::min(remaining, v2t_offsets[c + 1] - begin);
      for (std::uint32_t i = 0; i < n; ++i) f(v2t[begin + i]);
      remaining -= n;
    }
  }

  // The vertices sharing a live tet with v (v excluded), sorted and unique; `out` is cleared first.
  void neighbours(VertId v, std::vector<VertId>& out) const;
  // The same restricted to the vertices above v (the edges v owns), each once, in the order the
  // star meets them (not sorted: for callers whose result does not depend on the order).
  void neighbours_above(VertId v, std::vector<VertId>& out) const;
 private:
  template <class Keep>
  void gather_neighbours(VertId v, std::vector<VertId>& out, Keep&& keep) const;

 public:

  // Bytes held by the model's arrays (capacity, not size: what the process really pays).
  std::size_t memory_bytes() const;

  // The interchange form of the live part: vertices and tets renumbered densely in their current
  // order, listed triangles/segments recovered from the flags (each once per ref, sorted; a face
  // with a stand-in ref once per ref of its set), implicit interfaces and detected features
  // omitted (unless `options` asks for the features), corners/required vertices and fields kept.
  MeshData to_mesh_data(const MeshExportOptions& options = {}) const;
};

}  // namespace detail

using detail::MeshModel;

// build_tet_mesh without the handle (topotet/tet_mesh.h documents the checks and the errors).
MeshModel build_mesh_model(const MeshData& data, const BuildOptions& options = {}, BuildNotes* notes = nullptr);

// The length of the diagonal of the bounding box of the live vertices; 0 for none.
double bounding_box_diagonal(const MeshModel& mesh);

// Rebuilds the incidence of the live tets (used after compaction).
void rebuild_incidence(MeshModel& mesh);

// Drops dead tets and vertices, renumbering densely in the current order (deterministic), then
// rebuilds the incidence and packs the side table.
void compact(MeshModel& mesh);

// Drops dead tets only (vertex ids, and everything keyed by them, stay), then rebuilds the
// incidence. Whatever is keyed by tet ids (field bounds, coverage) is invalid afterwards.
void compact_tets(MeshModel& mesh);

}  // namespace topotet
