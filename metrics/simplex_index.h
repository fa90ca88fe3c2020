// Global numbering of every simplex the topology checker needs, private to metrics/.
//
// Built once per check from the plain MeshData: the edges and triangles of the tets, of the listed
// triangles and of the listed segments each get one id, found by radix-sorting packed sorted-vertex
// keys (no map per simplex). Each complex of the report is then the closure of a list of top
// simplices, extracted with local ids by extract_closure.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "topotet/mesh_data.h"
#include "z2_homology.h"

namespace topotet::metrics::detail {

struct InterfaceFace {
  std::uint32_t face = 0;
  std::int32_t material_a = 0, material_b = 0;  // a < b
};

// Vertices and tets have internal ids. For big meshes vertices are renumbered along a Morton curve
// and tets sorted by their smallest vertex, so that simplices close in space get close ids: the
// sorts, the closures and the reductions then stay in cache (2x faster on real 1M-tet meshes,
// whose files number vertices in no spatial order). Small meshes keep the mesh's own ids.
struct SimplexIndex {
  std::uint32_t vertex_count = 0;
  std::vector<VertId> mesh2vertex;  // [mesh vertex] -> internal id; empty = identity
  std::vector<TetId> tet2mesh;      // [internal tet] -> mesh tet; empty = identity
  std::vector<std::array<VertId, 2>> edge2verts;         // [edge], sorted internal vertex ids
  std::vector<std::array<std::uint32_t, 3>> face2edges;  // [face]
  std::vector<std::array<std::uint32_t, 4>> tet2faces;   // [internal tet]; meaningful for kept tets
  std::vector<TetId> kept_tets;  // internal ids of the valid tets that are not a duplicate of an
                                 // earlier (lower mesh id) tet, increasing
  std::vector<std::uint32_t> triangle2face;  // [mesh triangle], kInvalid when invalid
  std::vector<std::uint32_t> segment2edge;   // [mesh segment], kInvalid when invalid
  std::vector<std::uint32_t> boundary_faces;     // faces of exactly one kept tet
  std::vector<InterfaceFace> interface_faces;    // faces of exactly two kept tets, materials differ
  std::uint64_t invalid_tet_count = 0;           // vertex out of range or repeated
  std::uint64_t invalid_triangle_count = 0;
  std::uint64_t invalid_segment_count = 0;
  std::uint64_t duplicate_tet_count = 0;         // same vertex set as an earlier tet
  std::uint64_t nonmanifold_face_count = 0;      // faces of more than two kept tets
  std::uint64_t unreferenced_vertex_count = 0;   // in no valid tet
  std::uint64_t detached_triangle_count = 0;     // valid listed triangles that are no tet's face
  std::uint64_t detached_segment_count = 0;      // valid listed segments that are no tet's edge

  VertId vertex_of(VertId mesh_vertex) const { return mesh2vertex.empty() ? mesh_vertex : mesh2vertex[mesh_vertex]; }
  TetId mesh_tet(TetId tet) const { return tet2mesh.empty() ? tet : tet2mesh[tet]; }
};

// Material of tet t; a missing tet_material entry (short or empty array) reads as 0.
inline std::int32_t material_of(const MeshData& mesh, TetId t) {
  return t < mesh.tet_material.size() ? mesh.tet_material[t] : 0;
}

// Throws std::length_error beyond about 700M tets (ids are 32-bit).
SimplexIndex build_simplex_index(const MeshData& mesh);

// Top simplices of one complex, as internal ids: kept tets, each at most once; faces, edges and
// vertices may repeat (the closure is a set).
struct TopSimplices {
  std::span<const TetId> tets;
  std::span<const std::uint32_t> faces;
  std::span<const std::uint32_t> edges;
  std::span<const VertId> vertices;
};

// Global id -> local id maps, stamped so that they need no clearing between complexes.
struct ClosureScratch {
  struct Slot {
    std::uint32_t stamp = 0;
    std::uint32_t local = 0;
  };
  std::uint32_t stamp = 0;
  std::vector<Slot> vertex_slots, edge_slots, face_slots;
  std::vector<std::uint32_t> edge_globals, face_globals;  // [local] -> global
};

// The closure of `tops` with local ids, in `out`.
void extract_closure(const SimplexIndex& index, const TopSimplices& tops, ClosureScratch& scratch,
                     LocalComplex& out);

}  // namespace topotet::metrics::detail
