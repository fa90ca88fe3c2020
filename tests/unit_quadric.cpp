// Garland–Zhou quadrics: distances to simplices in R^(3+k), position-only feature quadrics, and
// the minimisers the cost model places vertices with.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "quadric.h"

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

TEST(Quadric, OneFieldTetQuadricEqualsTheGeneralOne) {
  // The closed form (normal (grad f, -1)) against Gram-Schmidt, on random and on thin tets.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    double pts[4 * kN];
    for (double& x : pts) x = u(rng);
    if (trial % 4 == 0)
      for (int d = 0; d < 3; ++d) pts[3 * kN + d] = pts[d] + 1e-4 * u(rng);  // a sliver
    double general[quadric_size(kN)] = {}, closed[quadric_size(kN)] = {};
    quadric_add_simplex(general, kN, pts, 4, 0.7);
    quadric_add_tet_one_field(closed, pts, 0.7);
    for (int i = 0; i < quadric_size(kN); ++i)
      EXPECT_NEAR(closed[i], general[i], 1e-9 * (1.0 + std::fabs(general[i]))) << "trial " << trial << " entry " << i;
  }
}

TEST(Quadric, FlatTetAddsNothingInClosedForm) {
  const double pts[4 * kN] = {0, 0, 0, 1, 1, 0, 0, 2, 0, 1, 0, 3, 1, 1, 0, 4};  // all in z = 0
  double q[quadric_size(kN)] = {};
  quadric_add_tet_one_field(q, pts, 1.0);
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
