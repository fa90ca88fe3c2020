// Deterministic procedural meshes for tests, benchmarks and `topotet demo`.
//
// Every family is built on a jittered Freudenthal (Kuhn) grid: a box of nx*ny*nz cubes, each split
// into 6 tets around its main diagonal, interior vertices jittered by a bounded amount that keeps
// every tet positively oriented with a good shape. Materials and substructures are planted by
// classifying tets and grid faces/edges, so every interface is made of mesh faces and every
// polyline of mesh edges. The same (family, target_tets, seed) gives the same MeshData on every
// machine and thread count.
//
//  cube-sphere  : material 1 = cube, material 2 = ball in it (closed interface surface, ref 1),
//                 an open surface patch embedded in the cube (ref 2), a polyline (ref 1) that
//                 pierces the ball's surface, boundary faces listed with ref 10.
//  slab         : five thin material layers (2-5 tets thick), interfaces listed (refs 1..4),
//                 polylines lying on the interfaces (refs 1..4).
//  linked-tori  : two linked solid tori (materials 2 and 3) in a box (material 1), interfaces
//                 (refs 1, 2), a polyline (ref 1) threading both tori.
// Each carries a smooth scalar field "f" with a few sharp features.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet {

struct GenerateOptions {
  std::string family = "cube-sphere";
  std::uint64_t target_tets = 100000;  // the result has about this many tets (within ~10%)
  std::uint64_t seed = 1;
};

// Throws InputError for an unknown family or a target below the family's minimum.
MeshData generate_mesh(const GenerateOptions& options);

const std::vector<std::string>& generator_families();

}  // namespace topotet
