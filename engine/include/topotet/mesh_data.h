// MeshData: the plain interchange form of a tetrahedral mesh with embedded substructures.
//
// Readers produce it, writers consume it, generators build it, and the topology checker in
// metrics/ reads it. It carries no derived data (no adjacency, no flags): TetMesh (tet_mesh.h) is
// the validated working model built from it, and TetMesh::to_mesh_data() gives it back.
//
// Conventions shared by every producer and consumer:
//  - vertex indices are 0-based here (MEDIT and Gmsh files are 1-based; the readers convert);
//  - tets are positively oriented (det[p1-p0, p2-p0, p3-p0] > 0) after TetMesh validation; readers
//    keep the file's order;
//  - `triangles` and `segments` are the substructures the file lists, each with its ref
//    (MEDIT reference, Gmsh physical tag; 0 when the file gives none);
//  - material interfaces that the file does not list are NOT added here: they are implied by
//    `tet_material` and derived where needed (TetMesh flags them; the checker derives them itself).
#pragma once

#include <array>
#include <compare>
#include <cstdint>
#include <string>
#include <vector>

namespace topotet {

using VertId = std::uint32_t;
using TetId = std::uint32_t;
inline constexpr std::uint32_t kInvalid = ~0u;

struct Triangle {
  std::array<VertId, 3> v{};
  std::int32_t ref = 0;
  friend bool operator==(const Triangle&, const Triangle&) = default;
};

struct Segment {
  std::array<VertId, 2> v{};
  std::int32_t ref = 0;
  friend bool operator==(const Segment&, const Segment&) = default;
};

// A per-vertex field. `components` is 1 for a scalar, 3 for a vector, 6 for a symmetric tensor
// (MEDIT .sol types 1, 2, 3); values are interleaved: values[vertex * components + c].
// The simplifier treats every component as one scalar to preserve.
struct VertexField {
  std::string name;
  int components = 1;
  std::vector<double> values;
  friend bool operator==(const VertexField&, const VertexField&) = default;
};

// How a per-tet array is carried onto the tets of a simplified mesh (topotet/cell_fields.h).
//  - kIntensive: a density-like real value (pressure, temperature, conductivity): the new tet gets
//    the volume-weighted average of the original tets it covers.
//  - kCategorical: a label (integer arrays: region ids, flags): the new tet gets the value that
//    holds the largest part of its volume (ties: the smaller value).
//  - kExtensive: an amount per tet (mass, heat, cell count): the new tets share it out by
//    overlap volume so that the sum over all tets is conserved.
// Readers give integer-typed arrays kCategorical and real ones kIntensive; kExtensive is never
// read from a file: the user names those arrays (CellRemapOptions, `--extensive NAME`).
enum class CellFieldKind : std::uint8_t { kIntensive, kCategorical, kExtensive };

// A per-tet field: values[tet * components + c], as VertexField per vertex. Kept aligned with
// MeshData::tets by every reader (cells that are left out take their values with them).
struct CellField {
  std::string name;
  int components = 1;
  CellFieldKind kind = CellFieldKind::kIntensive;
  std::vector<double> values;
  friend bool operator==(const CellField&, const CellField&) = default;
};

// The name of a group of refs (Gmsh $PhysicalNames): dim 1 segment refs, 2 triangle refs,
// 3 materials. Kept so that names survive .msh in -> out; MEDIT has no names.
struct GroupName {
  int dim = 0;
  std::int32_t ref = 0;
  std::string name;
  friend bool operator==(const GroupName&, const GroupName&) = default;
  friend auto operator<=>(const GroupName&, const GroupName&) = default;
};

struct MeshData {
  std::vector<std::array<double, 3>> positions;  // [vert] x, y, z
  std::vector<std::int32_t> vertex_refs;       // [vert] MEDIT vertex ref; empty = all 0
  std::vector<std::array<VertId, 4>> tets;     // [tet]
  std::vector<std::int32_t> tet_material;      // [tet] region / material id (MEDIT ref, Gmsh physical)
  std::vector<Triangle> triangles;             // listed surface substructure faces
  std::vector<Segment> segments;               // listed polyline edges
  std::vector<std::uint32_t> ridges;           // MEDIT `Ridges`: indices into `segments`
  std::vector<VertId> corners;                 // MEDIT `Corners`, Gmsh point entities: pinned
  std::vector<VertId> required_vertices;       // MEDIT `RequiredVertices`: pinned
  std::vector<VertexField> fields;             // per-vertex fields (.sol SolAtVertices, $NodeData)
  std::vector<GroupName> group_names;          // sorted by (dim, ref); at most one per (dim, ref)
  std::vector<CellField> cell_fields;          // per-tet fields (VTK CellData, $ElementData, SolAtTetrahedra)

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t tet_count() const { return tets.size(); }
  friend bool operator==(const MeshData&, const MeshData&) = default;
};

}  // namespace topotet
