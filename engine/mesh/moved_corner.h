// One corner of a tet moving while the other three stay: the geometric test every placement of a
// collapse (kernel/collapse.cpp) and every move of the smoothing (optimize/smooth.cpp) makes.
//
// Writing the moving corner second, (a, p, c, d) is an even permutation of the tet's corners
// (a, c, d = kTetFaces[corner] of the moving corner), so its orientation is
//     det[p - a, c - a, d - a] = (p - a) . ((c - a) x (d - a)),
// which is orient3d_sign(a, p, c, d) term by term: the cross product and the permanent's matching
// terms are the same for every p and are computed once. The certified sign is therefore exactly
// orient3d_sign's. Quality needs the six squared edge lengths, three of them fixed.
// Quality is (mean ratio)^3 = 15552 V^2 / S^3 = 432 det^2 / S^3 (S the sum of squared edge
// lengths): monotone in the mean ratio, and free of the cube root, which dominated the quality check.
#pragma once

#include <cmath>
#include <limits>

#include <glm/vec3.hpp>

#include "mesh/orient.h"

namespace topotet {

struct MovedCorner {
  glm::dvec3 a, c, d;        // the three fixed corners, in the order that makes (a, p, c, d) positive
  glm::dvec3 normal;         // (c - a) x (d - a), rounded exactly as orient3d_sign rounds it
  glm::dvec3 normal_bound;   // the matching terms of orient3d_sign's permanent
  double fixed_edges_sq;     // |c - a|^2 + |d - a|^2 + |d - c|^2
};

inline MovedCorner prepare_moved_corner(const glm::dvec3& a, const glm::dvec3& c, const glm::dvec3& d) {
  MovedCorner m;
  m.a = a;
  m.c = c;
  m.d = d;
  const double bdx = c.x - a.x, bdy = c.y - a.y, bdz = c.z - a.z;
  const double cdx = d.x - a.x, cdy = d.y - a.y, cdz = d.z - a.z;
  const double m1 = bdy * cdz, m2 = bdz * cdy, m3 = bdz * cdx, m4 = bdx * cdz, m5 = bdx * cdy, m6 = bdy * cdx;
  m.normal = {m1 - m2, m3 - m4, m5 - m6};
  m.normal_bound = {std::fabs(m1) + std::fabs(m2), std::fabs(m3) + std::fabs(m4), std::fabs(m5) + std::fabs(m6)};
  const double ex = d.x - c.x, ey = d.y - c.y, ez = d.z - c.z;
  m.fixed_edges_sq = (bdx * bdx + bdy * bdy + bdz * bdz) + (cdx * cdx + cdy * cdy + cdz * cdz) + (ex * ex + ey * ey + ez * ez);
  return m;
}

// The tet with its moving corner at p: false when it would be inverted or flat (sign not certainly
// positive; also for NaN and infinities), else its (mean ratio)^3 in `q3`.
inline bool moved_corner_quality(const MovedCorner& m, const glm::dvec3& p, double& q3) {
  constexpr double eps = std::numeric_limits<double>::epsilon() * 0.5;
  constexpr double bound = 4.0 * (7.0 + 56.0 * eps) * eps;  // orient3d_sign's (orient.cpp)
  const double adx = p.x - m.a.x, ady = p.y - m.a.y, adz = p.z - m.a.z;
  const double det = adx * m.normal.x + ady * m.normal.y + adz * m.normal.z;
  const double permanent =
      std::fabs(adx) * m.normal_bound.x + std::fabs(ady) * m.normal_bound.y + std::fabs(adz) * m.normal_bound.z;
  if (!(det > bound * permanent)) return false;
  const glm::dvec3 pc = p - m.c, pd = p - m.d;
  const double edges_sq = m.fixed_edges_sq + (adx * adx + ady * ady + adz * adz) +
                          (pc.x * pc.x + pc.y * pc.y + pc.z * pc.z) + (pd.x * pd.x + pd.y * pd.y + pd.z * pd.z);
  q3 = edges_sq > 0.0 ? 432.0 * det * det / (edges_sq * edges_sq * edges_sq) : 0.0;
  return true;
}

// (mean ratio)^3 of tet abcd, signed like its volume.
inline double mean_ratio_cubed(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  const double vol = signed_volume6(a, b, c, d) / 6.0;
  const glm::dvec3 e[6] = {b - a, c - a, d - a, c - b, d - b, d - c};
  double s = 0.0;
  for (const glm::dvec3& x : e) s += x.x * x.x + x.y * x.y + x.z * x.z;
  if (!(s > 0.0)) return 0.0;
  const double q3 = 15552.0 * vol * vol / (s * s * s);
  return vol < 0.0 ? -q3 : q3;
}

}  // namespace topotet
