// The facet cover proof of the tolerance check (engine/guarantees/facet_cover.h): every "yes" is
// checked against brute force on 2,000 random triangles over a bumpy surface, a triangle
// with a point beyond h is never proved, and the cover proves what one facet or one crease cannot
// (a triangle over the apex of a low cone).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <glm/geometric.hpp>

#include "guarantees/facet_cover.h"
#include "guarantees/flat_patches.h"
#include "guarantees/surface_tolerance.h"

namespace topotet {
namespace {

// A height field z = f(x, y) on an n x n grid of unit cells, each split in two triangles.
SurfaceSoup bumpy_grid(int n, double amplitude, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> bump(-amplitude, amplitude);
  SurfaceSoup soup;
  soup.face_labels = 1;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) soup.positions.push_back({double(i), double(j), bump(rng)});
  const auto id = [&](int i, int j) { return static_cast<VertId>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      soup.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      soup.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      soup.triangle_label.push_back(0);
      soup.triangle_label.push_back(0);
    }
  return soup;
}

double distance_to_soup(const SurfaceSoup& soup, const glm::dvec3& p) {
  double best = std::numeric_limits<double>::infinity();
  const auto& P = soup.positions;
  for (const auto& t : soup.triangles) best = std::min(best, squared_distance_to_triangle(p, P[t[0]], P[t[1]], P[t[2]]));
  return std::sqrt(best);
}

std::uint32_t nearest_by_brute_force(const SurfaceSoup& soup, const glm::dvec3& p) {
  double best = std::numeric_limits<double>::infinity();
  std::uint32_t at = kInvalid;
  const auto& P = soup.positions;
  for (std::uint32_t k = 0; k < soup.triangles.size(); ++k) {
    const auto& t = soup.triangles[k];
    const double d2 = squared_distance_to_triangle(p, P[t[0]], P[t[1]], P[t[2]]);
    if (d2 < best) {
      best = d2;
      at = k;
    }
  }
  return at;
}

// Random triangles a few cells wide near the surface; each "yes" must hold at 120 points of the
// triangle (its corners, edge midpoints and random points), measured against every triangle.
TEST(FacetCover, EveryProofHoldsAgainstBruteForce) {
  std::mt19937_64 rng(11);
  const SurfaceSoup soup = bumpy_grid(14, 0.25, rng);
  const FlatPatches patches = find_flat_patches(soup, 0.05);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int proved = 0, refused = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double h = 0.1 + 0.5 * unit(rng);
    const glm::dvec3 centre{3.0 + 8.0 * unit(rng), 3.0 + 8.0 * unit(rng), 0.0};
    const double size = 0.3 + 2.5 * unit(rng);
    std::array<glm::dvec3, 3> q;
    for (int k = 0; k < 3; ++k) {
      const double angle = 2.0944 * k + 0.6 * unit(rng);
      q[k] = centre + size * glm::dvec3(std::cos(angle), std::sin(angle), 0.0);
      q[k].z = (unit(rng) - 0.5) * 2.0 * h;  // around the mean height, bumps of +-0.25 below
    }
    const std::uint32_t nearest = nearest_by_brute_force(soup, (q[0] + q[1] + q[2]) / 3.0);
    if (!within_by_facets(soup, patches.neighbour, q, h, nearest)) {
      ++refused;
      continue;
    }
    ++proved;
    double worst = 0.0;
    for (int s = 0; s < 120; ++s) {
      double a = unit(rng), b = unit(rng);
      if (s < 3) a = s == 0, b = s == 1;               // the corners
      else if (s < 6) a = s == 3 ? 0.5 : 0.0, b = s == 5 ? 0.0 : 0.5;  // midpoints
      else if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
      const glm::dvec3 x = q[0] + a * (q[1] - q[0]) + b * (q[2] - q[0]);
      worst = std::max(worst, distance_to_soup(soup, x));
    }
    ASSERT_LE(worst, h * (1.0 + 1e-12)) << "trial " << trial << ": a proved triangle has a point beyond h";
  }
  // Not vacuous: both answers occur often.
  EXPECT_GT(proved, 200);
  EXPECT_GT(refused, 200);
}

// A corner beyond h of every candidate is never proved (the proof cannot be fooled by a far point).
TEST(FacetCover, ATriangleWithAPointBeyondTheToleranceIsRefused) {
  std::mt19937_64 rng(5);
  const SurfaceSoup soup = bumpy_grid(8, 0.0, rng);  // the plane z = 0
  const FlatPatches patches = find_flat_patches(soup, 0.05);
  const double h = 0.2;
  const std::array<glm::dvec3, 3> near{glm::dvec3(2, 2, 0.1), glm::dvec3(3.5, 2.3, -0.1), glm::dvec3(2.6, 3.4, 0.15)};
  const std::uint32_t nearest = nearest_by_brute_force(soup, (near[0] + near[1] + near[2]) / 3.0);
  EXPECT_TRUE(within_by_facets(soup, patches.neighbour, near, h, nearest));
  std::array<glm::dvec3, 3> far = near;
  far[2].z = 0.21;
  EXPECT_FALSE(within_by_facets(soup, patches.neighbour, far, h, nearest));
}

// A low cone of six facets around an apex raised by 0.3: a flat triangle at height 0.15 over the
// apex is within 0.15 of the cone everywhere, but no single facet holds its corners and no crease
// between two facets proves it; the cover cuts it into one part per facet.
TEST(FacetCover, ProvesATriangleOverAVertexWhereOneFacetOrOneCreaseCannot) {
  SurfaceSoup soup;
  soup.face_labels = 1;
  soup.positions.push_back({0.0, 0.0, 0.3});
  for (int k = 0; k < 6; ++k) soup.positions.push_back({std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 0.0});
  for (int k = 0; k < 6; ++k) {
    soup.triangles.push_back({0, static_cast<VertId>(1 + k), static_cast<VertId>(1 + (k + 1) % 6)});
    soup.triangle_label.push_back(0);
  }
  const SurfaceSoup copy = soup;
  const FlatPatches patches = find_flat_patches(soup, 0.05);
  const double h = 0.16;
  std::array<glm::dvec3, 3> q;
  for (int k = 0; k < 3; ++k) q[k] = {0.6 * std::cos(0.3 + 2.0944 * k), 0.6 * std::sin(0.3 + 2.0944 * k), 0.15};
  const std::uint32_t nearest = nearest_by_brute_force(copy, (q[0] + q[1] + q[2]) / 3.0);
  EXPECT_TRUE(within_by_facets(copy, patches.neighbour, q, h, nearest));

  SurfaceReference reference(std::move(soup));
  reference.build_flat_patches(0.05);
  for (std::uint32_t t = 0; t < 6; ++t) {
    EXPECT_FALSE(reference.triangle_holds(t, q, h)) << "facet " << t;
    EXPECT_FALSE(reference.within_by_crease(q, 0, h, t)) << "crease at facet " << t;
  }
  // And the truth, sampled: the largest distance is under h.
  double worst = 0.0;
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; i + j <= 40; ++j)
      worst = std::max(worst, distance_to_soup(copy, q[0] + (i / 40.0) * (q[1] - q[0]) + (j / 40.0) * (q[2] - q[0])));
  EXPECT_LE(worst, h);
}

}  // namespace
}  // namespace topotet
