// cube-sphere: a ball (material 2) in a cube (material 1).
//
// Substructures, all on the lattice so their topology depends on the grid size only:
//  - ref 1 triangles: the ball's surface (faces between materials 1 and 2), a closed sphere;
//  - ref 2 triangles: a square patch of the grid plane z = level, above the ball, in material 1,
//    touching neither the ball nor the box boundary (an open disc);
//  - ref 10 triangles: the box boundary (a sphere), so the boundary carries a surface too;
//  - ref 1 segments: a chain of grid edges along x from one cell inside the box face x = 0 to the
//    ball's centre; it pierces the ball's surface at one vertex, nearly perpendicular to it;
//  - corners: the 8 box corners.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "generate/freudenthal_grid.h"

namespace topotet::gen {

MeshData generate_cube_sphere(std::uint64_t target_tets, std::uint64_t seed) {
  // Below ~8 cells a side the ball and the patch above it no longer fit apart.
  check_target("cube-sphere", target_tets, 3000);
  const FreudenthalGrid grid(choose_cells(target_tets, {1.0, 1.0, 1.0}));
  const Cells& n = grid.cells();
  const double n_min = std::min({n[0], n[1], n[2]});

  // The ball sits low in the box to leave room for the patch above it; the small offsets keep it
  // off the lattice's symmetry planes (x is set below).
  glm::dvec3 center(0.5 * n[0], 0.5 * n[1] - 0.09, 0.42 * n[2] + 0.05);
  const double radius = 0.27 * n_min;
  // The polyline runs along x on the grid line nearest the centre. The 6 tets around an x edge
  // have centroids 1/4, 1/2 and 3/4 of the way along it, so a surface crossing the line within
  // 1/4 cell of an edge's middle cuts through its tets and the edge lies on the interface. Shift
  // the ball along x so that the line meets the sphere exactly at a lattice point: the crossing
  // is then a single vertex, with every tet around the edges on either side on one side of it.
  const std::array<std::uint32_t, 3> line = {1, static_cast<std::uint32_t>(std::lround(center.y)),
                                             static_cast<std::uint32_t>(std::lround(center.z))};
  const double dy = line[1] - center.y, dz = line[2] - center.z;
  const double half_chord = std::sqrt(radius * radius - dy * dy - dz * dz);
  center.x = std::round(center.x - half_chord) + half_chord;

  MeshData mesh;
  build_tets(
      grid,
      [&](const glm::dvec3& c) {
        const glm::dvec3 d = c - center;
        return d.x * d.x + d.y * d.y + d.z * d.z < radius * radius ? 2 : 1;
      },
      mesh);
  repair_pinches(grid, 2, 1, mesh);
  set_jittered_positions(grid, seed, mesh);

  add_interface_triangles(grid, [](std::int32_t, std::int32_t) { return 1; }, mesh);

  // The patch goes at least a cell above the highest ball vertex.
  std::uint32_t top = 0;
  const std::uint64_t tets_per_layer = 6ull * n[0] * n[1];
  for (std::size_t t = 0; t < mesh.tet_count(); ++t) {
    if (mesh.tet_material[t] == 2) top = std::max(top, static_cast<std::uint32_t>(t / tets_per_layer) + 1);
  }
  const std::uint32_t level = std::max(top + 1, static_cast<std::uint32_t>(std::lround(0.85 * n[2])));
  if (level + 1 > n[2]) throw std::logic_error("cube-sphere: no room for the patch above the ball");
  const auto at = [](std::uint32_t cells, double fraction) {
    return static_cast<std::uint32_t>(std::lround(fraction * cells));
  };
  add_plane_patch(grid, 2, level, {at(n[0], 0.25), at(n[1], 0.25)}, {at(n[0], 0.75), at(n[1], 0.75)}, 2, mesh);

  add_boundary_triangles(grid, 10, mesh);

  add_chain(grid, line, {1, 0, 0}, static_cast<std::uint32_t>(std::lround(center.x)) - line[0], 1, mesh);

  add_box_corners(grid, mesh);
  add_feature_field(grid, mesh);
  return mesh;
}

}  // namespace topotet::gen
