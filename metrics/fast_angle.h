// Angles without libm's atan2, private to metrics/: the quality statistics take 18 angles per tet,
// and std::atan2 (correctly rounded, with special cases) dominated their cost.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

namespace topotet::metrics::detail {

// atan(t) for |t| <= tan(pi/32) ~ 0.0985 by its Taylor series up to t^13 / 13: the first term
// left out is below |t|^15 / 15 < 6e-17.
inline double atan_small(double t) {
  const double z = t * t;
  double p = 1.0 / 13.0;
  p = p * z - 1.0 / 11.0;
  p = p * z + 1.0 / 9.0;
  p = p * z - 1.0 / 7.0;
  p = p * z + 1.0 / 5.0;
  p = p * z - 1.0 / 3.0;
  return t + t * z * p;
}

// atan2(y, x) for y >= 0, in [0, pi], within a few 1e-16 of std::atan2 (tests/unit_metrics.cpp
// compares them). With lo = min(|x|, y), hi = max(|x|, y), atan(lo / hi) in [0, pi/4] is the
// series around the nearest c = tan(j pi/16), j = 0..4:
//   atan(lo / hi) = j pi/16 + atan((lo - c hi) / (hi + c lo)),
// one division, and the thresholds between the j are compared as products. (0, 0) gives 0 whatever
// the sign of x, as a degenerate angle should.
inline double atan2_nonnegative(double y, double x) {
  constexpr double kPi = std::numbers::pi;
  // tan(j pi/16), and the switch points tan((2j + 1) pi/32) between them.
  constexpr double kCentre[5] = {0.0, 0.198912367379658, 0.41421356237309503, 0.6681786379192989, 1.0};
  constexpr double kSwitch[4] = {0.09849140335716425, 0.3033466836073424, 0.5345111359507916, 0.8206787908286602};
  const double ax = std::abs(x);
  const double hi = std::max(ax, y), lo = std::min(ax, y);
  if (!(hi > 0.0)) return 0.0;
  const int j = (lo > kSwitch[0] * hi) + (lo > kSwitch[1] * hi) + (lo > kSwitch[2] * hi) + (lo > kSwitch[3] * hi);
  const double c = kCentre[j];
  double r = j * (kPi / 16.0) + atan_small((lo - c * hi) / (hi + c * lo));
  if (y > ax) r = kPi / 2.0 - r;
  if (x < 0.0) r = kPi - r;
  return r;
}

}  // namespace topotet::metrics::detail
