// The dihedral angle floor (SimplifyOptions::min_dihedral): the smallest dihedral angle of a tet,
// as the square of its sine, which the collapses and the optimisation compare against a floor.
//
// At edge e between faces with normals n1, n2 (cross products, |n| = 2 x area) of a tet with
// det = 6 x volume, sin(theta_e) = det |e| / (|n1| |n2|), so
//     sin^2(theta_e) = det^2 |e|^2 / (|n1|^2 |n2|^2)
// needs no square root or trigonometry. The sine is small near 0 and near 180 degrees alike: a
// floor of 5 degrees also refuses a dihedral above 175 (a cap or a sliver, which has both; an
// angle near 180 is what breaks a finite element's interpolation, the maximum angle condition).
//
// The screen. Most tets are far from the floor, and the mean ratio is already computed for every
// tet a placement moves. A tet with a dihedral angle under 5 degrees (or over 175) has a mean
// ratio under 0.2472: the supremum found by a hill climb over 20,000 tets constrained to a
// dihedral <= 5 degrees (and never exceeded by 6 million random tets, isotropic or stretched up to
// 100:1). So above kDihedralScreen (0.25) in mean ratio the test is skipped, for floors up to
// kScreenedFloorDegrees; above that every tet is tested.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace topotet {

inline constexpr double kDihedralScreen = 0.25;           // mean ratio
inline constexpr double kScreenedFloorDegrees = 5.0;

// min over the six edges of sin^2 of the dihedral angle of tet abcd (any orientation); 0 for a
// flat or degenerate tet.
inline double min_dihedral_sine_sq(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  const glm::dvec3 ab = b - a, ac = c - a, ad = d - a, bc = c - b, bd = d - b, cd = d - c;
  // Face normals, each named by the corner it is opposite to.
  const glm::dvec3 na = glm::cross(bc, bd), nb = glm::cross(ac, ad), nc = glm::cross(ab, ad), nd = glm::cross(ab, ac);
  const double det = glm::dot(ad, nd);
  const double a2 = glm::dot(na, na), b2 = glm::dot(nb, nb), c2 = glm::dot(nc, nc), d2 = glm::dot(nd, nd);
  if (!(a2 > 0.0 && b2 > 0.0 && c2 > 0.0 && d2 > 0.0)) return 0.0;
  const double det2 = det * det;
  // Edge xy is shared by the faces opposite the two other corners.
  double worst = det2 * glm::dot(ab, ab) / (c2 * d2);
  worst = std::min(worst, det2 * glm::dot(ac, ac) / (b2 * d2));
  worst = std::min(worst, det2 * glm::dot(ad, ad) / (b2 * c2));
  worst = std::min(worst, det2 * glm::dot(bc, bc) / (a2 * d2));
  worst = std::min(worst, det2 * glm::dot(bd, bd) / (a2 * c2));
  worst = std::min(worst, det2 * glm::dot(cd, cd) / (a2 * b2));
  return worst;
}

// The floor as the kernel and the optimisation use it: sin^2 of the angle, and the (mean ratio)^3
// at and above which a tet needs no test (2: every tet is tested).
struct DihedralFloor {
  double sine_sq = 0.0;    // 0: no floor
  double screen_q3 = 2.0;

  static DihedralFloor degrees(double angle) {
    DihedralFloor f;
    if (!(angle > 0.0)) return f;
    const double s = std::sin(angle * 3.14159265358979323846 / 180.0);
    f.sine_sq = s * s;
    f.screen_q3 = angle <= kScreenedFloorDegrees ? kDihedralScreen * kDihedralScreen * kDihedralScreen : 2.0;
    return f;
  }
  bool active() const { return sine_sq > 0.0; }
};

}  // namespace topotet
