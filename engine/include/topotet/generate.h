// Deterministic procedural meshes for tests, benchmarks and `topotet demo`.
//
// Every family is built on a jittered Freudenthal (Kuhn) grid: a box of nx*ny*nz cubes (cubic
// cells, longest side 1), each split into 6 tets around its main diagonal, vertices jittered by at
// most 0.15 cell (tangentially on the box faces, which stay flat), which keeps every tet
// positively oriented with all dihedral angles above 25 degrees. Materials are planted by
// classifying tet centroids on the unjittered lattice, so every interface is made of mesh faces,
// and the listed polylines are chains of grid edges. The topology depends on the grid size only;
// the seed moves positions only. The same (family, target_tets, seed) gives the same MeshData on
// every run (single-threaded; the jitter is splitmix64 of (seed, vertex)).
// Listed triangles: every face between two materials, normal from the higher material to the
// lower, plus the surfaces below.
//
//  cube-sphere  : material 1 = cube, material 2 = ball in it (closed interface surface, ref 1),
//                 an open square patch of a grid plane above the ball, in the cube, touching
//                 neither the ball nor the boundary (ref 2), a grid-line polyline (ref 1) that
//                 pierces the ball's surface at one vertex, boundary faces listed with ref 10, the
//                 8 box corners as corners. At least 3000 tets.
//  slab         : five thin material layers 1..5 (2, 3, 5, 4, 2 cells thick; nz = 16 fixed, nx and
//                 ny grow), interfaces listed (ref r between layers r and r+1), polylines lying on
//                 the interfaces (refs 1..4). At least 2000 tets.
//  linked-tori  : two linked solid tori (materials 2 and 3) in a box (material 1), interfaces
//                 (refs 1, 2), a polyline (ref 1) along the grid line through both centres, which
//                 passes through both holes and pierces each tube twice. At least 36000 tets (the
//                 tubes need a radius of 1.5 cells or more to stay solid).
// Each carries a scalar field "f": smooth sin/cos plus a steep tanh front and a narrow Gaussian
// peak.
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
