// Garland–Zhou quadrics: distances to simplices in R^(3+k), position-only feature quadrics, and
// the minimisers the cost model places vertices with.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "cost/quadric.h"

namespace topotet {
namespace {

constexpr int kN = 4;  // position + one field

TEST(Quadric, TetQuadricIsTheSquaredDistanceToItsFlat) {
  // A tet whose field is the linear function f = 2x + y: its 3-flat in R^4 is f - 2x - y = 0.
  const double pts[4 * kN] = {0, 0, 0, 0, 1, 0, 0, 2, 0, 1, 0, 1, 0, 0, 1, 0};
  double q[quadric_size(kN)] = {};
  quadric_add_simplex(q, kN, pts, 4, 3.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int i = 0; i < 100; ++i) {
    const double x[kN] = {u(rng), u(rng), u(rng), u(rng)};
    const double residual = x[3] - 2 * x[0] - x[1];
    EXPECT_NEAR(quadric_eval(q, kN, x), 3.0 * residual * residual / 6.0, 1e-12);  // |normal|^2 = 6
  }
}

TEST(Quadric, PositionQuadricIgnoresTheField) {
  // The plane z = 0 through a triangle whose field varies: only the height counts.
  const double pts[3 * kN] = {0, 0, 0, 5, 1, 0, 0, -3, 0, 1, 0, 9};
  double q[quadric_size(kN)] = {};
  quadric_add_simplex_positions(q, kN, pts, 3, 2.0);
  const double on_plane[kN] = {0.3, 0.4, 0.0, 123.0};
  const double above[kN] = {0.3, 0.4, 0.5, -7.0};
  EXPECT_NEAR(quadric_eval(q, kN, on_plane), 0.0, 1e-12);
  EXPECT_NEAR(quadric_eval(q, kN, above), 2.0 * 0.25, 1e-12);
  // The full R^4 quadric of the same triangle does charge a field off its 2-flat.
  double full[quadric_size(kN)] = {};
  quadric_add_simplex(full, kN, pts, 3, 2.0);
  EXPECT_GT(quadric_eval(full, kN, on_plane), 1.0);
}

TEST(Quadric, FieldMinimiserRecoversTheLinearFieldAtAFixedPosition) {
  // Two tets of the linear field f = 2x + y + 1: at any position the best field value is f there.
  const double a[4 * kN] = {0, 0, 0, 1, 1, 0, 0, 3, 0, 1, 0, 2, 0, 0, 1, 1};
  const double b[4 * kN] = {1, 1, 1, 4, 1, 0, 0, 3, 0, 1, 0, 2, 0, 0, 1, 1};
  double q[quadric_size(kN)] = {};
  quadric_add_simplex(q, kN, a, 4, 1.0);
  quadric_add_simplex(q, kN, b, 4, 0.5);
  double x[kN] = {0.25, 0.5, 0.125, -100.0};
  ASSERT_TRUE(quadric_minimize_fields(q, kN, x));
  EXPECT_DOUBLE_EQ(x[0], 0.25);  // the position is untouched
  EXPECT_DOUBLE_EQ(x[2], 0.125);
  EXPECT_NEAR(x[3], 2 * 0.25 + 0.5 + 1, 1e-12);
  EXPECT_NEAR(quadric_eval(q, kN, x), 0.0, 1e-12);
}

TEST(Quadric, FieldMinimiserRefusesWithoutFieldInformation) {
  // Only a position quadric: every field value is as good as any other.
  const double pts[3 * kN] = {0, 0, 0, 5, 1, 0, 0, -3, 0, 1, 0, 9};
  double q[quadric_size(kN)] = {};
  quadric_add_simplex_positions(q, kN, pts, 3, 1.0);
  double x[kN] = {0.1, 0.2, 0.3, 42.0};
  EXPECT_FALSE(quadric_minimize_fields(q, kN, x));
  EXPECT_EQ(x[3], 42.0);
  double q3[quadric_size(3)] = {};
  EXPECT_FALSE(quadric_minimize_fields(q3, 3, x));  // no field coordinates at all
}

TEST(Quadric, FullMinimiserFindsTheCommonPointOfThreePlanes) {
  double q[quadric_size(3)] = {};
  const double xy[9] = {0, 0, 1, 1, 0, 1, 0, 1, 1};   // z = 1
  const double yz[9] = {2, 0, 0, 2, 1, 0, 2, 0, 1};   // x = 2
  const double xz[9] = {0, -3, 0, 1, -3, 0, 0, -3, 1};  // y = -3
  quadric_add_simplex(q, 3, xy, 3, 1.0);
  quadric_add_simplex(q, 3, yz, 3, 1.0);
  quadric_add_simplex(q, 3, xz, 3, 1.0);
  double x[3] = {0, 0, 0};
  ASSERT_TRUE(quadric_minimize(q, 3, x));
  EXPECT_NEAR(x[0], 2, 1e-12);
  EXPECT_NEAR(x[1], -3, 1e-12);
  EXPECT_NEAR(x[2], 1, 1e-12);
  // Two parallel planes only: a whole line of minima, refused.
  double flat[quadric_size(3)] = {};
  quadric_add_simplex(flat, 3, xy, 3, 1.0);
  double y[3] = {5, 5, 5};
  EXPECT_FALSE(quadric_minimize(flat, 3, y));
}

TEST(Quadric, FieldTetQuadricIsTheOrthogonalOneTimesOnePlusGradientSquared) {
  // The vertical distance (f - L(x))^2 against the distance to the 3-flat in R^4 computed by
  // Gram-Schmidt: the same form scaled by |normal|^2 = 1 + |grad f|^2, on random and thin tets
  // (not slivers: there Gram-Schmidt loses the digits that the factor 1 + |grad f|^2 amplifies).
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    double pts[4 * kN];
    for (double& x : pts) x = u(rng);
    if (trial % 4 == 0)
      for (int d = 0; d < 3; ++d) pts[3 * kN + d] = pts[d] + 1e-2 * u(rng);  // a thin tet
    double orthogonal[quadric_size(kN)] = {}, vertical[quadric_size(kN)] = {};
    const double weight = 0.7;
    const double volume = quadric_add_field_simplex(vertical, kN, pts, 4, &weight);
    const glm::dvec3 p0(pts[0], pts[1], pts[2]), p1(pts[kN], pts[kN + 1], pts[kN + 2]),
        p2(pts[2 * kN], pts[2 * kN + 1], pts[2 * kN + 2]), p3(pts[3 * kN], pts[3 * kN + 1], pts[3 * kN + 2]);
    EXPECT_NEAR(volume, std::fabs(glm::dot(p1 - p0, glm::cross(p2 - p0, p3 - p0))) / 6.0, 1e-15);
    quadric_add_simplex(orthogonal, kN, pts, 4, weight * volume);
    // grad f from the vertical quadric itself: A(i, 3) = -w g_i, w = volume x weight.
    double g2 = 0.0;
    for (int i = 0; i < 3; ++i) g2 += std::pow(vertical[quadric_detail::tri_index(kN, i, 3)] / (weight * volume), 2);
    for (int i = 0; i < quadric_size(kN); ++i)
      EXPECT_NEAR(vertical[i], orthogonal[i] * (1.0 + g2), 1e-7 * (1.0 + std::fabs(vertical[i])))
          << "trial " << trial << " entry " << i;
  }
}

TEST(Quadric, FieldQuadricMeasuresEachComponentAgainstItsInterpolant) {
  // Three components on the unit corner tet (volume 1/6), weighted 1, 2 and 0: f0 = x,
  // f1 = 2y - z + 1, f2 = anything.
  constexpr int n = 6;
  const double corners[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  double pts[4 * n];
  for (int i = 0; i < 4; ++i) {
    const double *p = corners[i];
    const double row[n] = {p[0], p[1], p[2], p[0], 2 * p[1] - p[2] + 1, 7.0 * i};
    std::copy_n(row, n, pts + i * n);
  }
  const double weights[3] = {1.0, 2.0, 0.0};
  double q[quadric_size(n)] = {};
  EXPECT_DOUBLE_EQ(quadric_add_field_simplex(q, n, pts, 4, weights), 1.0 / 6.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int i = 0; i < 50; ++i) {
    double x[n];
    for (double& c : x) c = u(rng);
    const double e0 = x[3] - x[0], e1 = x[4] - (2 * x[1] - x[2] + 1);
    EXPECT_NEAR(quadric_eval(q, n, x), (e0 * e0 + 2.0 * e1 * e1) / 6.0, 1e-12);
  }
}

TEST(Quadric, FieldTriangleQuadricIsConstantAlongTheNormal) {
  // Triangle in z = 0 (area 1/2) with f = 3x - y: the interpolant extends unchanged along z.
  const double pts[3 * kN] = {0, 0, 0, 0, 1, 0, 0, 3, 0, 1, 0, -1};
  const double weight = 1.0;
  double q[quadric_size(kN)] = {};
  EXPECT_DOUBLE_EQ(quadric_add_field_simplex(q, kN, pts, 3, &weight), 0.5);
  const double on[kN] = {0.2, 0.7, 5.0, 3 * 0.2 - 0.7};
  const double off[kN] = {0.2, 0.7, -3.0, 3 * 0.2 - 0.7 + 0.4};
  EXPECT_NEAR(quadric_eval(q, kN, on), 0.0, 1e-12);
  EXPECT_NEAR(quadric_eval(q, kN, off), 0.5 * 0.4 * 0.4, 1e-12);
}

TEST(Quadric, FlatSimplicesAddNothingToTheFieldQuadric) {
  const double tet[4 * kN] = {0, 0, 0, 1, 1, 0, 0, 2, 0, 1, 0, 3, 1, 1, 0, 4};  // all in z = 0
  const double line[3 * kN] = {0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3};            // collinear
  const double weight = 1.0;
  double q[quadric_size(kN)] = {};
  EXPECT_EQ(quadric_add_field_simplex(q, kN, tet, 4, &weight), 0.0);
  EXPECT_EQ(quadric_add_field_simplex(q, kN, line, 3, &weight), 0.0);
  for (double x : q) EXPECT_EQ(x, 0.0);
}

TEST(Quadric, MinimiserRefusesAFlatQuadric) {
  // Plane quadrics of z = 0 only: the minimum is a whole plane, so there is no optimum to trust.
  const double pts[3 * kN] = {0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0};
  double q[quadric_size(kN)] = {};
  quadric_add_simplex_positions(q, kN, pts, 3, 1.0);
  double x[kN];
  EXPECT_FALSE(quadric_minimize(q, kN, x));
}

}  // namespace
}  // namespace topotet
