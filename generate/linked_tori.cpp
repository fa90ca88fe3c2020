// linked-tori: two solid tori (materials 2 and 3) linked like chain links, in a box (material 1).
//
// Torus A lies in the plane z = cz around the z axis through a = (ax, cy, cz); torus B lies in the
// plane y = cy around the y axis through b = a + (R, 0, 0). Each core circle (radius R) passes
// through the other's centre; the tubes (radius r ~ 0.3 R) stay R - 2r >= 2 cells apart.
// Substructures:
//  - ref 1 / ref 2 triangles: the surfaces of A / B (faces between materials 1-2 / 1-3), tori;
//  - ref 1 segments: the grid line y = cy, z = cz across the box, face to face. It
//    lies in both tori's planes and passes through both holes; on the way it pierces each tube
//    twice (A, B, A, B), through the tube's core and perpendicular to its surface, so it meets the
//    interfaces at exactly 8 vertices and never runs along them.
//
// Resolution: a tube one or two tets across pinches; R >= 5 cells and r >= 1.5 cells (the
// minimum target guarantees it) keep the digitized tori solid, and repair_pinches removes the
// occasional non-manifold vertex of the digitization. The test checks that both surfaces are
// connected manifold tori (Euler characteristic 0) across sizes.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "generate/freudenthal_grid.h"

namespace topotet::gen {
namespace {

constexpr double kTubeRatio = 0.3;
constexpr double kMargin = 1.0;  // cells between the tori and the box: a tet reaches 0.93 from its centroid
constexpr int kMinMajor = 5;     // R in cells

// Distance from p to the circle of radius `radius` around `axis` through `center`.
double circle_distance(glm::dvec3 p, const glm::dvec3& center, int axis, double radius) {
  p -= center;
  const double along = p[axis];
  p[axis] = 0.0;
  const double radial = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z) - radius;
  return std::sqrt(radial * radial + along * along);
}

}  // namespace

MeshData generate_linked_tori(std::uint64_t target_tets, std::uint64_t seed) {
  check_target("linked-tori", target_tets, 36000);
  // The tori's bounding box is (3R + 2r) x (2R + 2r) x (2R + 2r).
  const double span_x = 3 + 2 * kTubeRatio, span_yz = 2 + 2 * kTubeRatio;
  const FreudenthalGrid grid(choose_cells(target_tets, {span_x, span_yz, span_yz}));
  const Cells& n = grid.cells();

  // The polyline is the grid line (y, z) = (cy, cz) and meets the tubes at x = ax + {-R, 0, R, 2R}
  // +- r. The 6 tets around an x edge have centroids 1/4, 1/2 and 3/4 along it, so a crossing
  // within 1/4 cell of an edge's middle would put that edge on the interface. With R an integer,
  // r a half-integer (or integer) and ax chosen to match, every crossing is at a lattice point,
  // 1/4 cell clear of the centroids on either side.
  const std::uint32_t cy = n[1] / 2, cz = n[2] / 2;
  int big = 0;
  double tube = 0, ax = 0;
  for (int R = static_cast<int>(std::min({n[0] / span_x, n[1] / span_yz, n[2] / span_yz})) + 1; R >= kMinMajor; --R) {
    const double r = std::round(2 * kTubeRatio * R) / 2;
    const double reach = R + r + kMargin;  // from a torus's centre to the box, in its plane
    if (cy < reach || cy + reach > n[1] || cz < reach || cz + reach > n[2]) continue;
    // ax - R - r >= margin and ax + 2R + r <= nx - margin; crossings at lattice points need
    // ax + r to be an integer. Take the admissible ax nearest the middle.
    const double lo = kMargin + R + r, hi = n[0] - kMargin - 2 * R - r;
    double x = std::round(0.5 * (lo + hi) + r) - r;
    if (x < lo) x += 1;
    if (x > hi) x -= 1;
    if (x < lo || x > hi) continue;
    big = R;
    tube = r;
    ax = x;
    break;
  }
  if (big == 0) throw std::logic_error("linked-tori: grid too small for the tori");
  const glm::dvec3 a(ax, cy, cz);
  const glm::dvec3 b = a + glm::dvec3(big, 0.0, 0.0);

  MeshData mesh;
  build_tets(
      grid,
      [&](const glm::dvec3& c) {
        if (circle_distance(c, a, 2, big) < tube) return 2;
        if (circle_distance(c, b, 1, big) < tube) return 3;
        return 1;
      },
      mesh);
  repair_pinches(grid, 2, 1, mesh);
  repair_pinches(grid, 3, 1, mesh);
  set_jittered_positions(grid, seed, mesh);
  add_interface_triangles(
      grid,
      [](std::int32_t lower, std::int32_t higher) {
        if (lower != 1) throw std::logic_error("linked-tori: the tori touch");
        return higher - 1;
      },
      mesh);
  add_chain(grid, {0, cy, cz}, {1, 0, 0}, n[0], 1, mesh);
  add_feature_field(grid, mesh);
  return mesh;
}

}  // namespace topotet::gen
