// Deterministic procedural meshes for tests, benchmarks and `topotet demo`.
//
// Every family is built on a jittered Freudenthal (Kuhn) grid: a box of nx*ny*nz cubes (cubic
// cells, longest side 1), each split into 6 tets around its main diagonal, vertices jittered by at
// most 0.15 cell (tangentially on the box faces, which stay flat), which keeps every tet
// positively oriented with all dihedral angles above 25 degrees. Materials are planted by
// classifying tet centroids on the unjittered lattice, so every interface is made of mesh faces,
// and the listed polylines are chains of grid edges. The topology depends on the grid size (and
// polycrystal's cell count) only; the seed moves positions only. The same (family, target_tets, seed) gives the same MeshData on
// every run (single-threaded; the jitter is splitmix64 of (seed, vertex)).
// Listed triangles: every face between two materials (polycrystal: most of them), normal from the
// higher material to the lower, plus the surfaces below.
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
//  polycrystal  : a cube cut into C grains, materials 1..C (C = GenerateOptions::cells, by default
//                 one per ~4000 tets and at least 8; at most one per 500 tets): Voronoi cells of C
//                 sites decided by tet centroid (by cube centre along the box edges), then grown
//                 from the sites by steps that keep each cell a 3-ball, so every material is a
//                 ball (one component, no pinch, no tunnel, no cavity).
//                 Cells meet along triple junction curves and at quadruple points. The box
//                 boundary is listed with ref 1; each interface that is a disc gets its own ref
//                 (2, 3, ... in increasing material-pair order), except a quarter of them, left
//                 implicit (as are the few interfaces that are not discs); half of the triple
//                 junction curves that are simple paths of grid edges are listed as polylines
//                 (refs 1, 2, ...), with both ends pinned as corners, as are the 8 box corners.
//                 The sites come from a fixed stream, not from the seed. At least 20000 tets.
// Each carries a scalar field "f": smooth sin/cos plus a steep tanh front and a narrow Gaussian
// peak.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet {

struct GenerateOptions {
  std::string family = "cube-sphere";
  std::uint64_t target_tets = 100000;  // the result has about this many tets (within ~10%)
  std::uint64_t seed = 1;
  std::uint32_t cells = 0;  // polycrystal only: number of cells (materials); 0 = the family's default
};

// Throws InputError for an unknown family, a target below the family's minimum, or a cell count
// given to another family than polycrystal or too large for the target.
MeshData generate_mesh(const GenerateOptions& options);

const std::vector<std::string>& generator_families();

// Receives a generated mesh section by section, in the order a MEDIT file lists them, each
// begin_* with the section's count before its entries; vertices come with the value of the
// field "f" there. Lets a writer put a mesh larger than memory on disk.
class GenerateSink {
 public:
  virtual ~GenerateSink() = default;
  virtual void begin_vertices(std::uint64_t count) = 0;
  virtual void vertex(const std::array<double, 3>& position, double field_value) = 0;
  virtual void begin_tets(std::uint64_t count) = 0;
  virtual void tet(const std::array<VertId, 4>& v, std::int32_t material) = 0;
  virtual void begin_triangles(std::uint64_t count) = 0;
  virtual void triangle(const Triangle& t) = 0;
  virtual void begin_segments(std::uint64_t count) = 0;
  virtual void segment(const Segment& s) = 0;
  virtual void begin_corners(std::uint64_t count) = 0;
  virtual void corner(VertId v) = 0;
};

// True for the families generate_streamed can send (cube-sphere).
bool can_stream(const GenerateOptions& options);
// Sends exactly what generate_mesh(options) returns (same numbering, order and values) to `sink`,
// with memory independent of the mesh size for the tets, vertices and boundary: cube-sphere keeps
// only the box around its ball in memory (about 20 bytes per tet there). Throws like
// generate_mesh, and std::logic_error for a family that cannot stream.
void generate_streamed(const GenerateOptions& options, GenerateSink& sink);

}  // namespace topotet
