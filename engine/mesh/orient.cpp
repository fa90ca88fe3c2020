#include "mesh/orient.h"

#include <cmath>
#include <limits>

namespace topotet {

int orient3d_sign(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  const double adx = b.x - a.x, ady = b.y - a.y, adz = b.z - a.z;
  const double bdx = c.x - a.x, bdy = c.y - a.y, bdz = c.z - a.z;
  const double cdx = d.x - a.x, cdy = d.y - a.y, cdz = d.z - a.z;
  const double m1 = bdy * cdz, m2 = bdz * cdy;
  const double m3 = bdz * cdx, m4 = bdx * cdz;
  const double m5 = bdx * cdy, m6 = bdy * cdx;
  const double det = adx * (m1 - m2) + ady * (m3 - m4) + adz * (m5 - m6);
  const double permanent = std::fabs(adx) * (std::fabs(m1) + std::fabs(m2)) +
                           std::fabs(ady) * (std::fabs(m3) + std::fabs(m4)) +
                           std::fabs(adz) * (std::fabs(m5) + std::fabs(m6));
  // Shewchuk's orient3d errboundA. The differences b-a etc. are themselves rounded; the bound
  // below is for exact differences, so we widen it 4x to cover their relative error (each
  // difference carries at most eps relative error, the products at most three of them).
  constexpr double eps = std::numeric_limits<double>::epsilon() * 0.5;
  constexpr double bound = 4.0 * (7.0 + 56.0 * eps) * eps;
  if (!(std::isfinite(det))) return 0;
  if (det > bound * permanent) return 1;
  if (-det > bound * permanent) return -1;
  return 0;
}

double signed_volume6(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  const glm::dvec3 u = b - a, v = c - a, w = d - a;
  return u.x * (v.y * w.z - v.z * w.y) + u.y * (v.z * w.x - v.x * w.z) + u.z * (v.x * w.y - v.y * w.x);
}

}  // namespace topotet
