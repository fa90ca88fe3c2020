// Where the materials of a grid mesh meet: the interface between each pair of materials, whether
// it is a disc, and the triple junction curves (the grid edges around which exactly three
// materials meet), for the polycrystal family to list as surfaces and polylines.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "generate/disc_test.h"
#include "generate/freudenthal_grid.h"

namespace topotet::gen {

// A face between two materials: the face of mesh.tets[tet] opposite local vertex `face`;
// `inward` is set when `tet` is the lower material, so that tet_face(mesh, tet, face, inward, ref)
// points from the higher material into the lower one, as add_interface_triangles does.
struct InterfaceFace {
  TetId tet;
  std::uint8_t face;
  bool inward;
};

struct Interface {
  std::int32_t lower, higher;  // materials
  std::uint32_t first_face, face_count;  // a range of CellJunctions::faces
  // A 2-disc: connected, every edge in at most two of its faces, every vertex's faces one fan,
  // Euler characteristic 1.
  bool is_disc;
};

struct JunctionCurve {
  std::array<std::int32_t, 3> materials;  // increasing
  // The curve's vertices in order, when its edges form one simple open path; empty otherwise.
  std::vector<VertId> path;
};

struct CellJunctions {
  std::vector<InterfaceFace> faces;      // grouped by interface
  std::vector<Interface> interfaces;     // by increasing (lower, higher)
  std::vector<JunctionCurve> curves;     // by increasing materials
};

// Reads mesh.tets and mesh.tet_material of a mesh built on `grid` (build_tets). The result is
// deterministic: it depends on the grid and the materials only.
CellJunctions find_cell_junctions(const FreudenthalGrid& grid, const MeshData& mesh);

}  // namespace topotet::gen
