// slab: five thin material layers (1..5 from the bottom) stacked in z, 2 to 5 cells thick.
//
// Thin layers are the point: collapses must keep each layer from pinching through. nz is fixed by
// the layer thicknesses, so nx and ny alone grow with the target.
// Substructures:
//  - ref r triangles (r = 1..4): the interface between layers r and r + 1, an open disc whose
//    boundary lies on the box; it is a plane (its vertices jitter within it only);
//  - ref r segments: a chain of grid edges lying on interface r: ref 1 along x from box face to box
//    face, ref 2 along y inside, ref 3 along the in-plane grid diagonal, ref 4 an L (x then -y).
#include <algorithm>
#include <cmath>

#include "generate/freudenthal_grid.h"

namespace topotet::gen {
namespace {

constexpr std::array<std::uint32_t, 5> kThickness = {2, 3, 5, 4, 2};

}  // namespace

MeshData generate_slab(std::uint64_t target_tets, std::uint64_t seed) {
  // Below 4 cells across, the polylines no longer fit inside the interfaces.
  check_target("slab", target_tets, 2000);
  std::array<std::uint32_t, 5> top{};  // z level of each layer's top face
  std::uint32_t z = 0;
  for (std::size_t l = 0; l < kThickness.size(); ++l) top[l] = z += kThickness[l];
  const FreudenthalGrid grid(choose_cells(target_tets, {1.0, 1.0, 1.0}, z));
  const Cells& n = grid.cells();

  MeshData mesh;
  build_tets(
      grid,
      [&](const glm::dvec3& c) {
        std::int32_t layer = 1;
        while (c.z > top[layer - 1]) ++layer;
        return layer;
      },
      mesh);
  // The interfaces stay planes: their vertices jitter within them only.
  set_jittered_positions(grid, seed, mesh, {top.begin(), top.end() - 1});
  // Layers only touch their neighbours, so the lower material names the interface.
  add_interface_triangles(grid, [](std::int32_t lower, std::int32_t) { return lower; }, mesh);

  const auto at = [](std::uint32_t cells, double fraction) {
    return static_cast<std::uint32_t>(std::lround(fraction * cells));
  };
  add_chain(grid, {0, at(n[1], 1.0 / 3), top[0]}, {1, 0, 0}, n[0], 1, mesh);
  add_chain(grid, {at(n[0], 0.5), 1, top[1]}, {0, 1, 0}, n[1] - 2, 2, mesh);
  add_chain(grid, {1, 1, top[2]}, {1, 1, 0}, std::min(n[0], n[1]) - 2, 3, mesh);
  const std::uint32_t y4 = at(n[1], 2.0 / 3);
  add_chain(grid, {1, y4, top[3]}, {1, 0, 0}, n[0] - 3, 4, mesh);
  add_chain(grid, {n[0] - 2, y4, top[3]}, {0, -1, 0}, y4 - 1, 4, mesh);

  add_feature_field(grid, mesh);
  return mesh;
}

}  // namespace topotet::gen
