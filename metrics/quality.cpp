// compute_quality: per-tet angle samples, reduced deterministically.
//
// Determinism: the tet range is cut into blocks of kBlock tets, independent of the thread count;
// each block is summarised sequentially by whichever thread runs it, and the block summaries are
// merged in block order (Chan et al.'s pairwise update). The floating-point operations, and so the
// bits of the result, are then the same for any number of threads.
//
// Speed: angles come from metrics/fast_angle.h (not libm's atan2), the third corner angle of a
// face is pi minus the other two, and a block sums deviations from its first sample (no division
// per sample, as Welford's update needs).
#include "topotet/metrics/quality.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "mesh/glm_convert.h"
#include "fast_angle.h"
#include "parallel/reduce.h"
#include "topotet/error.h"

namespace topotet {
namespace {

constexpr std::size_t kBlock = 4096;
constexpr double kDeg = 180.0 / std::numbers::pi;

// Running count, sum of deviations from a shift (the first sample), their squares, min and max:
// within a block the shift keeps the sums small, so the variance loses no precision to cancellation.
struct ShiftedSums {
  std::uint64_t n = 0;
  double shift = 0.0, sum = 0.0, sum_sq = 0.0;
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();

  void add(double x) {
    if (n == 0) shift = x;
    ++n;
    const double d = x - shift;
    sum += d;
    sum_sq += d * d;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
};

// Count, mean, sum of squared deviations from the mean, min and max of a sample.
struct Moments {
  std::uint64_t n = 0;
  double mean = 0.0;
  double m2 = 0.0;
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();

  static Moments of(const ShiftedSums& s) {
    Moments m;
    if (s.n == 0) return m;
    const double n = static_cast<double>(s.n);
    m.n = s.n;
    m.mean = s.shift + s.sum / n;
    m.m2 = std::max(0.0, s.sum_sq - s.sum * (s.sum / n));
    m.lo = s.lo;
    m.hi = s.hi;
    return m;
  }

  // Chan, Golub & LeVeque's combination of two summaries (order-dependent only in rounding,
  // which is why blocks are merged in a fixed order).
  void merge(const Moments& o) {
    if (o.n == 0) return;
    if (n == 0) {
      *this = o;
      return;
    }
    const double na = static_cast<double>(n), nb = static_cast<double>(o.n);
    const double total = na + nb;
    const double delta = o.mean - mean;
    mean += delta * (nb / total);
    m2 += o.m2 + delta * delta * (na * nb / total);
    n += o.n;
    lo = std::min(lo, o.lo);
    hi = std::max(hi, o.hi);
  }

  SampleStats stats() const {
    SampleStats s;
    s.count = n;
    if (n == 0) return s;
    s.min = lo;
    s.max = hi;
    s.mean = mean;
    s.std_dev = std::sqrt(std::max(0.0, m2 / static_cast<double>(n)));
    return s;
  }
};

struct BlockSums {
  ShiftedSums dihedral, solid, face, mean_ratio;
  std::size_t inverted = 0, zero_volume = 0, under_10 = 0, under_5 = 0;
};

struct BlockSummary {
  Moments dihedral, solid, face, mean_ratio;
  std::size_t inverted = 0, zero_volume = 0, under_10 = 0, under_5 = 0;

  static BlockSummary of(const BlockSums& s) {
    return {Moments::of(s.dihedral), Moments::of(s.solid), Moments::of(s.face), Moments::of(s.mean_ratio),
            s.inverted, s.zero_volume, s.under_10, s.under_5};
  }
  void merge(const BlockSummary& o) {
    dihedral.merge(o.dihedral);
    solid.merge(o.solid);
    face.merge(o.face);
    mean_ratio.merge(o.mean_ratio);
    inverted += o.inverted;
    zero_volume += o.zero_volume;
    under_10 += o.under_10;
    under_5 += o.under_5;
  }
};


// Sign of det = u . (v x w), certified by Shewchuk's orient3d static bound o3derrboundA =
// (7 + 56 eps) eps times the permanent, which also covers the rounding of the differences
// u, v, w. Returns +1, -1, or 0 when double precision cannot certify the sign.
int certified_sign(const glm::dvec3& u, const glm::dvec3& v, const glm::dvec3& w, double det) {
  constexpr double eps = std::numeric_limits<double>::epsilon() / 2.0;  // 2^-53, Shewchuk's epsilon
  constexpr double errbound = (7.0 + 56.0 * eps) * eps;
  const double permanent = std::abs(u.x) * (std::abs(v.y * w.z) + std::abs(v.z * w.y)) +
                           std::abs(u.y) * (std::abs(v.z * w.x) + std::abs(v.x * w.z)) +
                           std::abs(u.z) * (std::abs(v.x * w.y) + std::abs(v.y * w.x));
  if (det > errbound * permanent) return 1;
  if (-det > errbound * permanent) return -1;
  return 0;
}

void add_tet(const std::array<glm::dvec3, 4>& p, BlockSums& s) {
  // Edge (i, j) and the other two vertices (k, l) of the tet: the 6 edges in a fixed order.
  static constexpr int kEdges[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                       {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
  // Every angle is atan2(y, x), for an angle between vectors a and b atan2(|a x b|, a . b): accurate
  // near 0 and pi (acos of a normalised dot is not), and 0, not NaN, when a vector is zero. The 18
  // pairs are gathered first and converted in one loop, whose independent iterations the
  // processor overlaps (each one alone is a chain of dependent steps).
  // 0-5 dihedral, 6-9 half solid angles, 10-17 two corner angles of each face.
  double y[18], x[18];
  const auto angle_pair = [&](int i, const glm::dvec3& a, const glm::dvec3& b) {
    y[i] = glm::length(glm::cross(a, b));
    x[i] = glm::dot(a, b);
  };
  // The dihedral angle at edge e = pj - pi is the angle between the normals e x (pk - pi) and
  // e x (pl - pi) of its two faces: both are perpendicular to e, and the cross product with e
  // rotates the projections of pk - pi and pl - pi (which span the dihedral) by the same 90 deg.
  for (int k = 0; k < 6; ++k) {
    const auto& e = kEdges[k];
    const glm::dvec3 edge = p[e[1]] - p[e[0]];
    angle_pair(k, glm::cross(edge, p[e[2]] - p[e[0]]), glm::cross(edge, p[e[3]] - p[e[0]]));
  }
  // Solid angle at vertex i, vectors a, b, c to the other three (van Oosterom & Strackee 1983).
  // atan2 keeps the quadrant: a negative denominator means the solid angle exceeds pi, which only
  // happens for (nearly) flat tets.
  for (int i = 0; i < 4; ++i) {
    const glm::dvec3 a = p[(i + 1) % 4] - p[i];
    const glm::dvec3 b = p[(i + 2) % 4] - p[i];
    const glm::dvec3 c = p[(i + 3) % 4] - p[i];
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    y[6 + i] = std::abs(glm::dot(a, glm::cross(b, c)));
    x[6 + i] = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
  }
  // Corner angles of the 4 faces: face f is the one opposite vertex f; at its first two corners
  // here, the third below.
  bool has_zero_edge[4];
  for (int f = 0; f < 4; ++f) {
    const glm::dvec3& a = p[(f + 1) % 4];
    const glm::dvec3& b = p[(f + 2) % 4];
    const glm::dvec3& c = p[(f + 3) % 4];
    const glm::dvec3 ab = b - a, ac = c - a, bc = c - b;
    angle_pair(10 + 2 * f, ab, ac);
    angle_pair(11 + 2 * f, -ab, bc);
    has_zero_edge[f] = glm::dot(ab, ab) == 0.0 || glm::dot(ac, ac) == 0.0 || glm::dot(bc, bc) == 0.0;
  }
  double angle[18];
  for (int i = 0; i < 18; ++i) angle[i] = metrics::detail::atan2_nonnegative(y[i], x[i]);

  double smallest = angle[0] * kDeg;
  for (int k = 0; k < 6; ++k) {
    s.dihedral.add(angle[k] * kDeg);
    smallest = std::min(smallest, angle[k] * kDeg);
  }
  if (smallest < 10.0) ++s.under_10;
  if (smallest < 5.0) ++s.under_5;
  for (int i = 0; i < 4; ++i) s.solid.add(2.0 * angle[6 + i]);
  // The third angle of a triangle is pi minus the other two, unless an edge has zero length (then
  // all three are 0).
  for (int f = 0; f < 4; ++f) {
    const double at_a = angle[10 + 2 * f], at_b = angle[11 + 2 * f];
    s.face.add(at_a * kDeg);
    s.face.add(at_b * kDeg);
    s.face.add(has_zero_edge[f] ? 0.0 : (std::numbers::pi - at_a - at_b) * kDeg);
  }

  const glm::dvec3 u = p[1] - p[0], v = p[2] - p[0], w = p[3] - p[0];
  const double det = glm::dot(u, glm::cross(v, w));  // 6 V
  const int sign = certified_sign(u, v, w, det);
  if (sign < 0) ++s.inverted;
  if (sign == 0) ++s.zero_volume;

  double sum_sq = 0.0;
  for (const auto& e : kEdges) {
    const glm::dvec3 d = p[e[1]] - p[e[0]];
    sum_sq += glm::dot(d, d);
  }
  // (3|V|)^(2/3) = cbrt(9 V^2) = cbrt(det^2 / 4).
  s.mean_ratio.add(sum_sq > 0.0 ? 12.0 * std::cbrt(det * det / 4.0) / sum_sq : 0.0);
}

}  // namespace

QualityStats compute_quality(const MeshData& mesh) {
  const std::size_t nt = mesh.tets.size();
  const std::size_t nv = mesh.positions.size();
  for (std::size_t t = 0; t < nt; ++t)
    for (const VertId v : mesh.tets[t])
      if (v >= nv)
        throw InputError("tet " + std::to_string(t) + ": vertex index " + std::to_string(v) +
                         " out of range [0, " + std::to_string(nv) + ")");

  const BlockSummary total = parallel::block_reduce(
      nt, kBlock, "quality_blocks", BlockSummary{},
      [&](std::size_t begin, std::size_t end) {
        BlockSums s;
        for (std::size_t t = begin; t < end; ++t) {
          const auto& tv = mesh.tets[t];
          add_tet({to_glm(mesh.positions[tv[0]]), to_glm(mesh.positions[tv[1]]), to_glm(mesh.positions[tv[2]]),
                   to_glm(mesh.positions[tv[3]])},
                  s);
        }
        return BlockSummary::of(s);
      },
      [](BlockSummary& into, const BlockSummary& block) { into.merge(block); });

  QualityStats q;
  q.tet_count = nt;
  q.dihedral_deg = total.dihedral.stats();
  q.solid_sr = total.solid.stats();
  q.face_deg = total.face.stats();
  q.mean_ratio = total.mean_ratio.stats();
  q.inverted = total.inverted;
  q.zero_volume = total.zero_volume;
  q.under_10_deg = total.under_10;
  q.under_5_deg = total.under_5;
  return q;
}

}  // namespace topotet
