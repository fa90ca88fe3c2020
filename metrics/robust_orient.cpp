// Orientation filter + exact fallback. See J. R. Shewchuk, "Adaptive Precision Floating-Point
// Arithmetic and Fast Robust Geometric Predicates" (1997): the error bound below is his
// o3derrboundA, and the expansion routines are his Grow-Expansion and Scale-Expansion with zero
// elimination. Only the exact stage is implemented (not his intermediate adaptive stages): it runs
// only when the filter fails, i.e. for (nearly) flat tets, which are rare in valid meshes.
#include "robust_orient.h"

#include <cmath>
#include <vector>

namespace topotet::metrics::detail {
namespace {

// An expansion: a sum of doubles, nonoverlapping, in increasing magnitude, without zeros. Its sign
// is the sign of its last (largest) component.
using Expansion = std::vector<double>;

// x + y == a + b exactly, x = fl(a + b) (Knuth's two-sum; valid for any a, b).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double b_virtual = x - a;
  const double a_virtual = x - b_virtual;
  y = (a - a_virtual) + (b - b_virtual);
}

// Dekker's fast two-sum; requires |a| >= |b| (or a == 0).
inline void fast_two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  y = b - (x - a);
}

// x + y == a * b exactly: the fused multiply-add computes the rounding error of the product
// exactly (barring underflow), which replaces Dekker's splitting.
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

Expansion difference(double a, double b) {
  double x = 0, y = 0;
  two_sum(a, -b, x, y);
  Expansion e;
  if (y != 0) e.push_back(y);
  if (x != 0) e.push_back(x);
  return e;
}

// e + b (Shewchuk's Grow-Expansion with zero elimination).
Expansion grow(const Expansion& e, double b) {
  Expansion h;
  h.reserve(e.size() + 1);
  double q = b;
  for (double component : e) {
    double sum = 0, err = 0;
    two_sum(q, component, sum, err);
    if (err != 0) h.push_back(err);
    q = sum;
  }
  if (q != 0) h.push_back(q);
  return h;
}

Expansion sum(const Expansion& e, const Expansion& f) {
  Expansion h = e;
  for (double component : f) h = grow(h, component);
  return h;
}

// e * b (Shewchuk's Scale-Expansion with zero elimination).
Expansion scale(const Expansion& e, double b) {
  Expansion h;
  if (e.empty() || b == 0) return h;
  h.reserve(2 * e.size());
  double q = 0, err = 0;
  two_product(e[0], b, q, err);
  if (err != 0) h.push_back(err);
  for (std::size_t i = 1; i < e.size(); ++i) {
    double product_hi = 0, product_lo = 0, s = 0;
    two_product(e[i], b, product_hi, product_lo);
    two_sum(q, product_lo, s, err);
    if (err != 0) h.push_back(err);
    fast_two_sum(product_hi, s, q, err);
    if (err != 0) h.push_back(err);
  }
  if (q != 0) h.push_back(q);
  return h;
}

Expansion product(const Expansion& e, const Expansion& f) {
  Expansion h;
  for (double component : f) h = sum(h, scale(e, component));
  return h;
}

Expansion negate(Expansion e) {
  for (double& component : e) component = -component;
  return e;
}

int sign(const Expansion& e) {
  if (e.empty()) return 0;
  return e.back() > 0 ? 1 : -1;
}

int orient3d_exact(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2,
                   const glm::dvec3& p3) {
  // Rows a, b, c of the determinant, each coordinate an exact two-component difference.
  const Expansion ax = difference(p1.x, p0.x), ay = difference(p1.y, p0.y), az = difference(p1.z, p0.z);
  const Expansion bx = difference(p2.x, p0.x), by = difference(p2.y, p0.y), bz = difference(p2.z, p0.z);
  const Expansion cx = difference(p3.x, p0.x), cy = difference(p3.y, p0.y), cz = difference(p3.z, p0.z);
  // Cofactor expansion along the first row.
  const Expansion minor_x = sum(product(by, cz), negate(product(bz, cy)));
  const Expansion minor_y = sum(product(bz, cx), negate(product(bx, cz)));
  const Expansion minor_z = sum(product(bx, cy), negate(product(by, cx)));
  return sign(sum(sum(product(ax, minor_x), product(ay, minor_y)), product(az, minor_z)));
}

}  // namespace

int orient3d_sign(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2,
                  const glm::dvec3& p3) {
  // Same expression and bound as Shewchuk's orient3d(p1, p2, p3, p0) stage A: the bound covers
  // the rounding of the differences as well as of the products and sums.
  const double adx = p1.x - p0.x, ady = p1.y - p0.y, adz = p1.z - p0.z;
  const double bdx = p2.x - p0.x, bdy = p2.y - p0.y, bdz = p2.z - p0.z;
  const double cdx = p3.x - p0.x, cdy = p3.y - p0.y, cdz = p3.z - p0.z;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * std::fabs(adz) +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * std::fabs(bdz) +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * std::fabs(cdz);
  if (!std::isfinite(permanent) || !std::isfinite(det)) return 0;
  constexpr double kEpsilon = 0x1p-53;  // half an ulp of 1: Shewchuk's "epsilon"
  constexpr double kErrBoundA = (7.0 + 56.0 * kEpsilon) * kEpsilon;
  const double err_bound = kErrBoundA * permanent;
  if (det > err_bound) return 1;
  if (-det > err_bound) return -1;
  return orient3d_exact(p0, p1, p2, p3);
}

}  // namespace topotet::metrics::detail
