// Mesh quality statistics (compute_quality) and field error (compare_fields).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "../metrics/fast_angle.h"  // the private fast atan2, tested against libm
#include "mesh/glm_convert.h"
#include "test_meshes.h"
#include "topotet/error.h"
#include "topotet/generate.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/surface_distance.h"
#include "topotet/simplify.h"
#include "topotet/threads.h"

namespace topotet {
namespace {

using testing::make_grid;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = 180.0 / kPi;

MeshData tets_from(std::vector<glm::dvec3> positions, std::vector<std::array<VertId, 4>> tets) {
  MeshData d;
  for (const glm::dvec3& p : positions) d.positions.push_back(from_glm(p));
  d.tets = std::move(tets);
  d.tet_material.assign(d.tets.size(), 1);
  return d;
}

// Positively oriented regular tet of edge 2*sqrt(2).
MeshData regular_tet() { return tets_from({{1, 1, 1}, {-1, 1, -1}, {1, -1, -1}, {-1, -1, 1}}, {{0, 1, 2, 3}}); }

MeshData corner_tet() { return tets_from({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 1, 2, 3}}); }

// An unjittered or jittered n^3 Freudenthal grid scaled to [0, side]^3.
MeshData box_grid(int n, double side, double jitter, std::uint64_t seed = 1) {
  MeshData d = make_grid(n, n, n, [](int, int, int) { return 1; }, jitter, seed).data;
  for (auto& p : d.positions) p = from_glm(to_glm(p) * (side / n));
  return d;
}

template <class Fn>
void add_field(MeshData& d, const std::string& name, int components, Fn&& fn) {
  VertexField f{name, components, {}};
  for (const auto& p : d.positions)
    for (int c = 0; c < components; ++c) f.values.push_back(fn(to_glm(p), c));
  d.fields.push_back(std::move(f));
}

template <class Fn>
auto with_threads(int threads, Fn&& fn) {
  decltype(fn()) result{};
  run_with_thread_limit(threads, [&] { result = fn(); });
  return result;
}

// ---------------------------------------------------------------- quality

TEST(Quality, RegularTet) {
  const QualityStats q = compute_quality(regular_tet());
  EXPECT_EQ(q.tet_count, 1u);
  EXPECT_EQ(q.inverted, 0u);
  EXPECT_EQ(q.zero_volume, 0u);
  const double dihedral = std::acos(1.0 / 3.0) * kDeg;  // 70.5288
  EXPECT_EQ(q.dihedral_deg.count, 6u);
  EXPECT_NEAR(q.dihedral_deg.min, dihedral, 1e-12);
  EXPECT_NEAR(q.dihedral_deg.max, dihedral, 1e-12);
  EXPECT_NEAR(q.dihedral_deg.mean, 70.528779365509308, 1e-12);
  EXPECT_NEAR(q.dihedral_deg.std_dev, 0.0, 1e-6);
  EXPECT_EQ(q.face_deg.count, 12u);
  EXPECT_NEAR(q.face_deg.min, 60.0, 1e-12);
  EXPECT_NEAR(q.face_deg.max, 60.0, 1e-12);
  EXPECT_NEAR(q.face_deg.std_dev, 0.0, 1e-6);
  EXPECT_EQ(q.solid_sr.count, 4u);
  EXPECT_NEAR(q.solid_sr.mean, std::acos(23.0 / 27.0), 1e-12);  // 0.5513 sr
  EXPECT_NEAR(q.solid_sr.mean, 0.5513, 1e-4);
  EXPECT_NEAR(q.solid_sr.std_dev, 0.0, 1e-6);
  EXPECT_EQ(q.mean_ratio.count, 1u);
  EXPECT_NEAR(q.mean_ratio.min, 1.0, 1e-12);
  EXPECT_NEAR(q.mean_ratio.mean, 1.0, 1e-12);
}

TEST(Quality, RightCornerTet) {
  const QualityStats q = compute_quality(corner_tet());
  // Dihedral: 90 deg at the three edges through the corner, acos(1/sqrt 3) = 54.7356 at the others.
  const double far = std::acos(1.0 / std::sqrt(3.0)) * kDeg;
  EXPECT_NEAR(q.dihedral_deg.min, far, 1e-12);
  EXPECT_NEAR(q.dihedral_deg.max, 90.0, 1e-12);
  EXPECT_NEAR(q.dihedral_deg.mean, (90.0 + far) / 2.0, 1e-12);
  EXPECT_NEAR(q.dihedral_deg.std_dev, (90.0 - far) / 2.0, 1e-12);  // two equal halves
  // Solid: an octant (pi/2) at the corner; the others 2 atan(1 / (3 + 2 sqrt 2)) = 0.339837.
  EXPECT_NEAR(q.solid_sr.max, kPi / 2.0, 1e-12);
  EXPECT_NEAR(q.solid_sr.min, 0.3398369094541219, 1e-12);
  // Gauss-Bonnet for a tet: sum of solid angles = 2 * sum of dihedral angles - 4 pi.
  const double solid_sum = 4.0 * q.solid_sr.mean, dihedral_sum = 6.0 * q.dihedral_deg.mean / kDeg;
  EXPECT_NEAR(solid_sum, 2.0 * dihedral_sum - 4.0 * kPi, 1e-12);
  // Faces: three right isosceles triangles (90, 45, 45) and one equilateral one.
  EXPECT_NEAR(q.face_deg.min, 45.0, 1e-12);
  EXPECT_NEAR(q.face_deg.max, 90.0, 1e-12);
  EXPECT_NEAR(q.face_deg.mean, 60.0, 1e-12);
  EXPECT_NEAR(q.face_deg.std_dev, std::sqrt(4050.0 / 12.0), 1e-12);  // 18.3712
  // Mean ratio 12 (3 * 1/6)^(2/3) / (3 * 1 + 3 * 2).
  EXPECT_NEAR(q.mean_ratio.mean, 12.0 * std::pow(0.5, 2.0 / 3.0) / 9.0, 1e-12);  // 0.839947
  EXPECT_EQ(q.inverted, 0u);
}

TEST(Quality, InvertedAndFlatTetsCounted) {
  MeshData d = tets_from({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.3, 0.3, 0}},
                         {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 1, 2, 4}});
  const QualityStats q = compute_quality(d);
  EXPECT_EQ(q.tet_count, 3u);
  EXPECT_EQ(q.inverted, 1u);
  EXPECT_EQ(q.zero_volume, 1u);
  // Angles ignore orientation: the inverted tet has the corner tet's angles; the flat one has
  // dihedral angles of 0 and 180 deg and a solid angle of 2 pi at its interior vertex.
  EXPECT_NEAR(q.dihedral_deg.min, 0.0, 1e-9);
  EXPECT_NEAR(q.dihedral_deg.max, 180.0, 1e-9);
  EXPECT_NEAR(q.solid_sr.max, 2.0 * kPi, 1e-9);
  EXPECT_NEAR(q.mean_ratio.min, 0.0, 1e-12);
  EXPECT_NEAR(q.mean_ratio.max, compute_quality(corner_tet()).mean_ratio.max, 1e-15);
}

TEST(Quality, NearlyFlatTetIsZeroVolumeOnlyWithinRounding) {
  // (0.1, 0.2, 0.7) lies on the plane x + y + z = 1 up to the rounding of its decimal
  // coordinates: double precision cannot tell the sign of that tet. Lifted by 1e-6 it can.
  auto d = tets_from({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.1, 0.2, 0.7}}, {{0, 1, 2, 3}});
  EXPECT_EQ(compute_quality(d).zero_volume, 1u);
  d.positions[3] = from_glm(to_glm(d.positions[3]) + glm::dvec3(1e-6));  // away from the origin: positive orientation
  EXPECT_EQ(compute_quality(d).zero_volume, 0u);
  EXPECT_EQ(compute_quality(d).inverted, 0u);
  d.positions[3] = from_glm(to_glm(d.positions[3]) - glm::dvec3(2e-6));
  EXPECT_EQ(compute_quality(d).inverted, 1u);
  // An exact tiny volume is not rounding: 1e-30 above an axis-aligned plane is certified.
  d.positions[3] = {0.3, 0.3, 1e-30};
  d.positions[2] = {0, 0, 0};
  EXPECT_EQ(compute_quality(d).zero_volume, 0u);
}

TEST(Quality, EmptyMeshAndBadIndex) {
  const QualityStats q = compute_quality(MeshData{});
  EXPECT_EQ(q.tet_count, 0u);
  EXPECT_EQ(q.dihedral_deg.count, 0u);
  MeshData bad = corner_tet();
  bad.tets[0][2] = 99;
  EXPECT_THROW(compute_quality(bad), InputError);
}

TEST(Quality, KuhnGridHasCongruentTets) {
  // Every Kuhn tet of a unit cube: edges 1, 1, 1, sqrt 2, sqrt 2, sqrt 3, so mean ratio
  // 12 (1/2)^(2/3) / 10, the same for all; face angles always average 60 deg.
  const QualityStats q = compute_quality(box_grid(6, 6.0, 0.0));
  EXPECT_EQ(q.tet_count, 6u * 216u);
  EXPECT_NEAR(q.mean_ratio.min, 12.0 * std::pow(0.5, 2.0 / 3.0) / 10.0, 1e-12);
  EXPECT_NEAR(q.mean_ratio.std_dev, 0.0, 1e-7);
  EXPECT_NEAR(q.face_deg.mean, 60.0, 1e-9);
  EXPECT_EQ(q.inverted, 0u);
  EXPECT_EQ(q.zero_volume, 0u);
  // Kuhn tet 0, x, x+y, x+y+z: dihedral 45 deg at the first and last unit edges of the path,
  // 90 at the middle one and at both sqrt 2 edges, 60 at the diagonal.
  EXPECT_NEAR(q.dihedral_deg.min, 45.0, 1e-9);
  EXPECT_NEAR(q.dihedral_deg.max, 90.0, 1e-9);
  EXPECT_NEAR(q.dihedral_deg.mean, 70.0, 1e-9);
  EXPECT_NEAR(q.dihedral_deg.std_dev, std::sqrt(2550.0 / 6.0), 1e-9);
}

TEST(Quality, SameBitsForAnyThreadCount) {
  const MeshData d = box_grid(24, 1.0, 0.2, 7);  // 83k tets, ~20 blocks
  const QualityStats one = with_threads(1, [&] { return compute_quality(d); });
  const QualityStats two = with_threads(2, [&] { return compute_quality(d); });
  const QualityStats dflt = compute_quality(d);
  EXPECT_TRUE(one == two);
  EXPECT_TRUE(one == dflt);
  EXPECT_NEAR(one.face_deg.mean, 60.0, 1e-9);
}

// The reference the fast quality code replaced: libm's atan2 at every angle (all 12 face angles
// directly) and two-pass mean and variance over all samples.
struct ReferenceStats {
  std::vector<double> dihedral, solid, face;
  static SampleStats of(const std::vector<double>& x) {
    SampleStats s;
    s.count = x.size();
    double sum = 0.0;
    for (double v : x) sum += v;
    s.mean = sum / static_cast<double>(x.size());
    double sq = 0.0;
    for (double v : x) sq += (v - s.mean) * (v - s.mean);
    s.std_dev = std::sqrt(sq / static_cast<double>(x.size()));
    s.min = *std::min_element(x.begin(), x.end());
    s.max = *std::max_element(x.begin(), x.end());
    return s;
  }
};

ReferenceStats reference_angles(const MeshData& d) {
  const auto angle = [](const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
  };
  ReferenceStats r;
  for (const auto& t : d.tets) {
    const glm::dvec3 p[4] = {to_glm(d.positions[t[0]]), to_glm(d.positions[t[1]]), to_glm(d.positions[t[2]]),
                             to_glm(d.positions[t[3]])};
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        int k = 0;
        while (k == i || k == j) ++k;
        const int l = 6 - i - j - k;
        const glm::dvec3 e = p[j] - p[i];
        r.dihedral.push_back(angle(glm::cross(e, p[k] - p[i]), glm::cross(e, p[l] - p[i])) * kDeg);
      }
    for (int i = 0; i < 4; ++i) {
      const glm::dvec3 a = p[(i + 1) % 4] - p[i], b = p[(i + 2) % 4] - p[i], c = p[(i + 3) % 4] - p[i];
      const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
      const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
      r.solid.push_back(2.0 * std::atan2(std::abs(glm::dot(a, glm::cross(b, c))), den));
    }
    for (int f = 0; f < 4; ++f) {
      const int v[3] = {(f + 1) % 4, (f + 2) % 4, (f + 3) % 4};
      for (int c = 0; c < 3; ++c)
        r.face.push_back(angle(p[v[(c + 1) % 3]] - p[v[c]], p[v[(c + 2) % 3]] - p[v[c]]) * kDeg);
    }
  }
  return r;
}

void expect_close(const SampleStats& got, const SampleStats& want, double tolerance, const char* what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(got.count, want.count);
  EXPECT_NEAR(got.mean, want.mean, tolerance * std::max(1.0, std::abs(want.mean)));
  EXPECT_NEAR(got.std_dev, want.std_dev, tolerance * std::max(1.0, want.std_dev));
  EXPECT_NEAR(got.min, want.min, tolerance * std::max(1.0, std::abs(want.min)));
  EXPECT_NEAR(got.max, want.max, tolerance * std::max(1.0, std::abs(want.max)));
}

TEST(Quality, MatchesTheLibmReferenceOnJitteredAndDegenerateTets) {
  MeshData d = box_grid(10, 1.0, 0.35, 3);  // strongly jittered: slivers, obtuse faces
  // Flat, needle and collapsed tets: angles of 0 and 180 degrees.
  const auto n = static_cast<VertId>(d.positions.size());
  d.positions.push_back({0, 0, 0});
  d.positions.push_back({1, 0, 0});
  d.positions.push_back({2, 0, 0});
  d.positions.push_back({0, 1, 0});
  d.tets.push_back({n, n + 1, n + 2, n + 3});  // three collinear vertices, all four coplanar
  d.tets.push_back({n, n + 1, n + 3, n + 3});  // a repeated vertex
  const QualityStats q = compute_quality(d);
  const ReferenceStats r = reference_angles(d);
  expect_close(q.dihedral_deg, ReferenceStats::of(r.dihedral), 1e-11, "dihedral");
  expect_close(q.solid_sr, ReferenceStats::of(r.solid), 1e-11, "solid");
  expect_close(q.face_deg, ReferenceStats::of(r.face), 1e-11, "face");
}

TEST(Quality, OwnAtan2AgreesWithLibm) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double worst = 0.0;
  const auto check = [&](double y, double x) {
    const double got = metrics::detail::atan2_nonnegative(y, x);
    const double want = (y == 0.0 && x == 0.0) ? 0.0 : std::atan2(y, x);
    worst = std::max(worst, std::abs(got - want));
  };
  for (int i = 0; i < 1000000; ++i) {
    const double scale = std::pow(10.0, 12.0 * unit(rng));
    check(std::abs(unit(rng)) * scale, unit(rng) * scale);
  }
  for (double y : {0.0, 1e-300, 1e-12, 0.5, 1.0, 1e12})
    for (double x : {-1e12, -1.0, -1e-12, -0.0, 0.0, 1e-300, 1e-12, 1.0, 1e12}) check(y, x);
  // Switch points of the reduction, and both sides of them.
  for (double t : {0.09849140335716425, 0.3033466836073424, 0.5345111359507916, 0.8206787908286602, 1.0})
    for (double s : {1.0 - 1e-15, 1.0, 1.0 + 1e-15}) {
      check(t * s, 1.0);
      check(1.0, t * s);
      check(t * s, -1.0);
    }
  EXPECT_LT(worst, 1e-15);
  std::printf("[ atan2 ] largest difference from std::atan2: %.2e rad\n", worst);
}

// ---------------------------------------------------------------- field error

TEST(FieldError, IdenticalMeshesHaveNoError) {
  MeshData d = box_grid(6, 1.0, 0.15);
  add_field(d, "f", 1, [](const glm::dvec3& p, int) { return std::sin(3 * p.x) * p.y + p.z * p.z; });
  const FieldError e = compare_fields(d, d);
  ASSERT_EQ(e.components.size(), 1u);
  const ComponentError& c = e.components[0];
  EXPECT_EQ(c.field, "f");
  EXPECT_EQ(c.original_to_simplified.samples, d.positions.size());
  EXPECT_EQ(c.simplified_to_original.samples, d.positions.size());
  EXPECT_EQ(c.original_to_simplified.max_abs, 0.0);
  EXPECT_EQ(c.simplified_to_original.max_abs, 0.0);
  EXPECT_EQ(e.worst_rms_rel, 0.0);
  EXPECT_EQ(e.original_in_simplified.outside, 0u);
  EXPECT_TRUE(e.unmatched_fields.empty());
}

TEST(FieldError, LinearFieldsAreReproduced) {
  MeshData fine = box_grid(12, 1.0, 0.2, 3);
  MeshData coarse = box_grid(5, 1.0, 0.25, 11);
  auto linear = [](const glm::dvec3& p, int c) { return 1.0 + (c + 2.0) * p.x - 3.0 * p.y + (0.5 - c) * p.z; };
  add_field(fine, "v", 3, linear);
  add_field(coarse, "v", 3, linear);
  const FieldError e = compare_fields(fine, coarse);
  ASSERT_EQ(e.components.size(), 3u);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(e.components[c].component, c);
    EXPECT_GT(e.components[c].range, 1.0);
    EXPECT_LT(e.components[c].original_to_simplified.max_rel, 1e-12);
    EXPECT_LT(e.components[c].simplified_to_original.max_rel, 1e-12);
  }
  EXPECT_LT(e.worst_max_rel, 1e-12);
  EXPECT_EQ(e.original_in_simplified.points, fine.positions.size());
  EXPECT_EQ(e.simplified_in_original.points, coarse.positions.size());
  EXPECT_EQ(e.original_in_simplified.outside, 0u);  // same box: boundary points are on faces
  EXPECT_EQ(e.simplified_in_original.outside, 0u);
}

// f = x^2 on an unjittered grid of spacing h: every Kuhn tet has its vertices at two x levels
// a and a + h, so the linear interpolant is exactly (x - a)(a + h - x) above f.
double expected_quadratic_rms(const MeshData& fine, double h) {
  double sum = 0.0;
  for (const auto& a3 : fine.positions) {
    const glm::dvec3 p = to_glm(a3);
    const double a = std::floor(p.x / h + 1e-12) * h;
    const double err = (p.x - a) * (a + h - p.x);
    sum += err * err;
  }
  return std::sqrt(sum / static_cast<double>(fine.positions.size()));
}

TEST(FieldError, QuadraticFieldMatchesAnalyticErrorAndDecreasesWithRefinement) {
  auto square = [](const glm::dvec3& p, int) { return p.x * p.x; };
  MeshData fine = box_grid(12, 12.0, 0.0);  // spacing 1
  add_field(fine, "f", 1, square);
  double last_rms = 1e300;
  for (const int n : {3, 6}) {  // spacing 4 then 2, nested in the fine grid
    MeshData coarse = box_grid(n, 12.0, 0.0);
    add_field(coarse, "f", 1, square);
    const FieldError e = compare_fields(fine, coarse);
    ASSERT_EQ(e.components.size(), 1u);
    const ComponentError& c = e.components[0];
    const double h = 12.0 / n;
    EXPECT_NEAR(c.range, 144.0, 1e-12);
    EXPECT_NEAR(c.original_to_simplified.rms, expected_quadratic_rms(fine, h), 1e-9);
    EXPECT_NEAR(c.original_to_simplified.max_abs, h * h / 4.0, 1e-9);
    EXPECT_NEAR(c.original_to_simplified.max_rel, h * h / 4.0 / 144.0, 1e-12);
    EXPECT_LT(c.simplified_to_original.max_abs, 1e-9);  // coarse vertices are fine vertices
    const double n_fine = static_cast<double>(fine.positions.size());
    const double n_coarse = static_cast<double>(coarse.positions.size());
    EXPECT_NEAR(c.rms_both, c.original_to_simplified.rms * std::sqrt(n_fine / (n_fine + n_coarse)), 1e-9);
    EXPECT_LT(c.rms_both, last_rms / 3.0);  // O(h^2)
    last_rms = c.rms_both;
  }
}

TEST(FieldError, FieldsMatchedByNameAndComponentCount) {
  MeshData a = box_grid(4, 1.0, 0.1);
  MeshData b = box_grid(3, 1.0, 0.1, 5);
  auto lin = [](const glm::dvec3& p, int c) { return p.x + c * p.y; };
  add_field(a, "temperature", 1, lin);
  add_field(a, "velocity", 3, lin);
  add_field(a, "pressure", 1, lin);
  add_field(b, "velocity", 3, lin);  // other order
  add_field(b, "pressure", 3, lin);  // other component count
  add_field(b, "extra", 1, lin);
  add_field(b, "temperature", 1, [](const glm::dvec3& p, int) { return p.x + 0.5; });
  const FieldError e = compare_fields(a, b);
  ASSERT_EQ(e.components.size(), 4u);
  EXPECT_EQ(e.components[0].field, "temperature");
  EXPECT_NEAR(e.components[0].original_to_simplified.rms, 0.5, 1e-12);
  EXPECT_NEAR(e.components[0].simplified_to_original.max_abs, 0.5, 1e-12);
  EXPECT_NEAR(e.components[0].rms_both, 0.5, 1e-12);
  EXPECT_NEAR(e.components[0].rms_both_rel, 0.5 / e.components[0].range, 1e-12);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(e.components[1 + c].field, "velocity");
    EXPECT_EQ(e.components[1 + c].component, c);
    EXPECT_LT(e.components[1 + c].rms_both, 1e-12);
  }
  EXPECT_EQ(e.unmatched_fields, (std::vector<std::string>{"pressure", "extra"}));
  EXPECT_NEAR(e.worst_rms_rel, e.components[0].rms_both_rel, 0.0);
}

TEST(FieldError, NoCommonFieldOrNoTets) {
  MeshData a = box_grid(2, 1.0, 0.0);
  MeshData b = a;
  add_field(a, "x", 1, [](const glm::dvec3& p, int) { return p.x; });
  const FieldError e = compare_fields(a, b);
  EXPECT_TRUE(e.components.empty());
  EXPECT_EQ(e.unmatched_fields, std::vector<std::string>{"x"});
  EXPECT_EQ(e.original_in_simplified.points, 0u);
  add_field(b, "x", 1, [](const glm::dvec3& p, int) { return p.x; });
  b.tets.clear();
  EXPECT_TRUE(compare_fields(a, b).components.empty());
  b = a;
  a.fields[0].values.pop_back();
  EXPECT_THROW(compare_fields(a, b), InputError);
  a.fields[0].name = "y";  // unmatched fields are not read, so not checked
  EXPECT_NO_THROW(compare_fields(a, b));
}

TEST(FieldError, PointsOutsideUseTheClosestPoint) {
  // The simplified box shrank to [0.04, 3.96]^3: boundary vertices of the original lie outside
  // it and take the simplified field at their projection onto the box.
  auto f = [](const glm::dvec3& p, int) { return p.x + 2.0 * p.y - 0.5 * p.z; };
  MeshData orig = box_grid(4, 4.0, 0.1, 2);
  MeshData simp = box_grid(4, 4.0, 0.15, 9);
  for (auto& p : simp.positions) p = from_glm(glm::dvec3(2.0) + 0.98 * (to_glm(p) - glm::dvec3(2.0)));
  add_field(orig, "f", 1, f);
  add_field(simp, "f", 1, f);
  const FieldError e = compare_fields(orig, simp);
  ASSERT_EQ(e.components.size(), 1u);
  double sum = 0.0, worst = 0.0, far = 0.0;
  std::size_t outside = 0;
  for (const auto& a3 : orig.positions) {
    const glm::dvec3 p = to_glm(a3);
    const glm::dvec3 q = glm::clamp(p, glm::dvec3(0.04), glm::dvec3(3.96));
    const double err = f(p, 0) - f(q, 0);
    sum += err * err;
    worst = std::max(worst, std::abs(err));
    if (q != p) ++outside, far = std::max(far, glm::length(q - p));
  }
  EXPECT_EQ(e.original_in_simplified.outside, outside);
  EXPECT_EQ(outside, 125u - 27u);
  EXPECT_NEAR(e.original_in_simplified.max_outside_distance, far, 1e-12);
  EXPECT_NEAR(far, 0.04 * std::sqrt(3.0), 1e-12);
  const ComponentError& c = e.components[0];
  EXPECT_NEAR(c.original_to_simplified.rms, std::sqrt(sum / orig.positions.size()), 1e-12);
  EXPECT_NEAR(c.original_to_simplified.max_abs, worst, 1e-12);
  EXPECT_EQ(e.simplified_in_original.outside, 0u);
  EXPECT_LT(c.simplified_to_original.max_abs, 1e-12);

  // Far away too (a translated copy): still the closest point, found by the ring search.
  MeshData moved = simp;
  for (auto& p : moved.positions) p[0] += 10.0;
  const FieldError m = compare_fields(orig, moved);
  EXPECT_EQ(m.original_in_simplified.outside, orig.positions.size());
  EXPECT_NEAR(m.original_in_simplified.max_outside_distance, std::sqrt(10.04 * 10.04 + 2 * 0.04 * 0.04), 1e-9);
}

TEST(FieldError, RandomPointsNearAndFarFromAConvexMesh) {
  // Query points scattered in [-3, 4]^3 around a jittered mesh of the unit cube (convex, so the
  // closest point of the mesh is the clamp onto the cube): checks the ring search against the
  // exact answer at every distance, inside and outside the grid.
  MeshData cloud;
  std::uint64_t key = 12345;
  auto rnd = [&] { return static_cast<double>(testing::splitmix64(++key) >> 11) * 0x1.0p-53; };
  for (int t = 0; t < 1000; ++t) {
    for (int i = 0; i < 4; ++i) cloud.positions.push_back({-3.0 + 7.0 * rnd(), -3.0 + 7.0 * rnd(), -3.0 + 7.0 * rnd()});
    const VertId b = static_cast<VertId>(4 * t);
    cloud.tets.push_back({b, b + 1, b + 2, b + 3});  // any shape: only its vertices are queried
  }
  MeshData cube = box_grid(6, 1.0, 0.2, 21);
  auto f = [](const glm::dvec3& p, int) { return 2.0 * p.x - p.y + 3.0 * p.z; };
  add_field(cloud, "f", 1, f);
  add_field(cube, "f", 1, f);
  const FieldError e = compare_fields(cloud, cube);
  double sum = 0.0, worst = 0.0, far = 0.0;
  std::size_t outside = 0;
  for (const auto& a3 : cloud.positions) {
    const glm::dvec3 p = to_glm(a3);
    const glm::dvec3 q = glm::clamp(p, glm::dvec3(0.0), glm::dvec3(1.0));
    const double err = f(p, 0) - f(q, 0);
    sum += err * err;
    worst = std::max(worst, std::abs(err));
    if (q != p) ++outside, far = std::max(far, glm::length(q - p));
  }
  ASSERT_EQ(e.components.size(), 1u);
  EXPECT_EQ(e.original_in_simplified.points, 4000u);
  EXPECT_EQ(e.original_in_simplified.outside, outside);
  EXPECT_GT(outside, 3900u);
  EXPECT_NEAR(e.original_in_simplified.max_outside_distance, far, 1e-12);
  EXPECT_NEAR(e.components[0].original_to_simplified.rms, std::sqrt(sum / 4000.0), 1e-9);
  EXPECT_NEAR(e.components[0].original_to_simplified.max_abs, worst, 1e-9);
}

TEST(FieldError, UnusedVerticesAreNotSampled) {
  MeshData a = box_grid(3, 1.0, 0.1);
  a.positions.push_back({5, 5, 5});  // referenced by no tet
  add_field(a, "f", 1, [](const glm::dvec3& p, int) { return p.x; });
  const FieldError e = compare_fields(a, a);
  EXPECT_EQ(e.original_in_simplified.points, a.positions.size() - 1);
  EXPECT_NEAR(e.components[0].range, 1.0, 1e-12);
  EXPECT_EQ(e.components[0].rms_both, 0.0);
}

TEST(FieldError, SameBitsForAnyThreadCount) {
  MeshData fine = box_grid(20, 1.0, 0.2, 4);
  MeshData coarse = box_grid(7, 1.0, 0.25, 8);
  for (auto& p : coarse.positions) p = from_glm(glm::dvec3(0.5) + 0.999 * (to_glm(p) - glm::dvec3(0.5)));  // some outside
  auto f = [](const glm::dvec3& p, int c) { return std::sin(4 * p.x + c) * std::cos(3 * p.y) + p.z * p.z; };
  add_field(fine, "f", 2, f);
  add_field(coarse, "f", 2, f);
  const FieldError one = with_threads(1, [&] { return compare_fields(fine, coarse); });
  const FieldError two = with_threads(2, [&] { return compare_fields(fine, coarse); });
  const FieldError dflt = compare_fields(fine, coarse);
  EXPECT_TRUE(one == two);
  EXPECT_TRUE(one == dflt);
  EXPECT_GT(one.original_in_simplified.outside, 0u);
  EXPECT_GT(one.worst_rms_rel, 0.0);
}

// ---------------------------------------------------------------- timing

// Few simplified vertices in a big original are located by a sweep over the original's tets, the
// other direction by the Embree hierarchy. Swapping the meshes swaps the methods for the same
// points, so both must give the same errors to the last bit, including the points outside (the
// coarse box is larger: its boundary vertices take the closest tet).
TEST(FieldError, SweepAndHierarchyLocateAlike) {
  MeshData fine = box_grid(14, 1.0, 0.25, 4), coarse = box_grid(4, 1.03, 0.2, 8);
  for (auto& p : coarse.positions) p = from_glm(to_glm(p) - glm::dvec3(0.015));
  const auto f = [](const glm::dvec3& p, int c) { return std::cos(4.0 * p.y) * p.x + c * p.z; };
  add_field(fine, "f", 2, f);
  add_field(coarse, "f", 2, f);
  ASSERT_LT(coarse.positions.size() * 4, fine.tets.size());  // compare_fields(fine, coarse) sweeps
  const FieldError swept = compare_fields(fine, coarse), hierarchy = compare_fields(coarse, fine);
  ASSERT_EQ(swept.components.size(), 2u);
  for (std::size_t c = 0; c < 2; ++c) {
    EXPECT_EQ(swept.components[c].simplified_to_original.rms, hierarchy.components[c].original_to_simplified.rms);
    EXPECT_EQ(swept.components[c].simplified_to_original.max_abs, hierarchy.components[c].original_to_simplified.max_abs);
  }
  EXPECT_TRUE(swept.simplified_in_original == hierarchy.original_in_simplified);
  EXPECT_GT(swept.simplified_in_original.outside, 0u);
}

TEST(FieldError, PreparedReferenceGivesCompareFieldsForEveryMesh) {
  MeshData fine = box_grid(10, 1.0, 0.2, 3), coarse = box_grid(4, 1.0, 0.1, 5), other = box_grid(6, 1.0, 0.15, 9);
  const auto f = [](const glm::dvec3& p, int c) { return std::sin(3.0 * p.x) * p.y + c * p.z * p.z; };
  for (MeshData* m : {&fine, &coarse, &other}) add_field(*m, "f", 2, f);
  const FieldErrorReference reference(fine);
  for (int round = 0; round < 2; ++round) {  // the locator built for the first comparison serves the next
    EXPECT_TRUE(reference.compare(coarse) == compare_fields(fine, coarse));
    EXPECT_TRUE(reference.compare(other) == compare_fields(fine, other));
  }
  EXPECT_GT(reference.compare(coarse).worst_rms_rel, 0.0);
}

// ---------------------------------------------------------------- surface distance, report mode

// A generated cube-sphere whose tets are relabelled by the cell of a coarse grid around their
// centroid (a few dozen materials: many interfaces, as in polycrystals), simplified to 30%.
std::pair<MeshData, MeshData> many_material_pair() {
  GenerateOptions g;
  g.target_tets = 6000;
  MeshData in = generate_mesh(g);
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : in.positions) lo = glm::min(lo, to_glm(p)), hi = glm::max(hi, to_glm(p));
  for (std::size_t t = 0; t < in.tets.size(); ++t) {
    glm::dvec3 c(0.0);
    for (VertId v : in.tets[t]) c += to_glm(in.positions[v]) / 4.0;
    const glm::dvec3 cell = glm::min(glm::dvec3(2.999), 3.0 * (c - lo) / (hi - lo));
    in.tet_material[t] = 1 + static_cast<std::int32_t>(cell.x) + 3 * static_cast<std::int32_t>(cell.y) +
                         9 * static_cast<std::int32_t>(cell.z);
  }
  TetMesh mesh = build_tet_mesh(in);
  SimplifyOptions options;
  options.target_vertex_ratio = 0.3;
  const Status status = simplify(mesh, options).status;  // many materials may stop it early
  EXPECT_TRUE(status == Status::kOk || status == Status::kStoppedEarly);
  return {std::move(in), mesh.to_mesh_data()};
}

TEST(SurfaceDistanceReport, OverallValuesAgreeWithTheAccurateModeWithinTheSamplingErrors) {
  const auto [in, out] = many_material_pair();
  const SurfaceDistance accurate = surface_distance(in, out);  // every label within 1e-3 diag / sqrt 3
  const SurfaceDistance report = surface_distance(in, out, report_surface_distance_options());
  ASSERT_GT(accurate.labels.size(), 20u);
  ASSERT_EQ(report.labels.size(), accurate.labels.size());
  const double slack = accurate.sampling_error + report.sampling_error;
  EXPECT_NEAR(report.original_to_simplified, accurate.original_to_simplified, slack);
  EXPECT_NEAR(report.simplified_to_original, accurate.simplified_to_original, slack);
  EXPECT_NEAR(report.hausdorff, accurate.hausdorff, slack);
  EXPECT_GT(report.hausdorff, 0.0);
  // Neither mode overestimates: a label's report value is below its truth, which is within the
  // accurate mode's sampling error of the accurate value.
  for (std::size_t g = 0; g < report.labels.size(); ++g) {
    SCOPED_TRACE(report.labels[g].name());
    EXPECT_LE(report.labels[g].original_to_simplified, accurate.labels[g].original_to_simplified + accurate.sampling_error);
    EXPECT_LE(report.labels[g].simplified_to_original, accurate.labels[g].simplified_to_original + accurate.sampling_error);
    EXPECT_EQ(report.labels[g].original_primitives, accurate.labels[g].original_primitives);
    EXPECT_EQ(report.labels[g].simplified_primitives, accurate.labels[g].simplified_primitives);
  }
  EXPECT_LT(report.samples, accurate.samples);
  // The spacing follows the input's resolution (16 pieces per triangle) when that is coarser.
  EXPECT_GE(report.sample_spacing, 1e-3 * report.diagonal);
  EXPECT_DOUBLE_EQ(report.sampling_error, report.sample_spacing / std::sqrt(3.0));
}

TEST(SurfaceDistanceReport, SameResultForAnyThreadCount) {
  const auto [in, out] = many_material_pair();
  for (const SurfaceDistanceOptions& options : {report_surface_distance_options(), SurfaceDistanceOptions{}}) {
    const SurfaceDistance one = with_threads(1, [&] { return surface_distance(in, out, options); });
    const SurfaceDistance two = with_threads(2, [&] { return surface_distance(in, out, options); });
    EXPECT_EQ(one.hausdorff, two.hausdorff);
    EXPECT_EQ(one.samples, two.samples);
    ASSERT_EQ(one.labels.size(), two.labels.size());
    for (std::size_t g = 0; g < one.labels.size(); ++g) {
      EXPECT_EQ(one.labels[g].original_to_simplified, two.labels[g].original_to_simplified);
      EXPECT_EQ(one.labels[g].simplified_to_original, two.labels[g].simplified_to_original);
      EXPECT_EQ(one.labels[g].original_samples, two.labels[g].original_samples);
    }
  }
}

TEST(SurfaceDistanceReport, IdenticalMeshesAreAtDistanceZeroWithFewSamples) {
  const auto [in, out] = many_material_pair();
  const SurfaceDistance d = surface_distance(in, in, report_surface_distance_options());
  EXPECT_LE(d.hausdorff, 1e-12 * d.diagonal);  // midpoints are exact up to rounding
  EXPECT_EQ(d.unmatched_labels, 0u);
  std::size_t primitives = 0;
  for (const LabelDistance& l : d.labels) primitives += l.original_primitives;
  // Exact matches refine every piece down to the spacing: the resolution bound keeps that linear.
  EXPECT_LT(d.samples, 40 * primitives);
}

TEST(MetricsTiming, MillionTets) {
  using Clock = std::chrono::steady_clock;
  auto seconds = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  auto f = [](const glm::dvec3& p, int) { return std::sin(0.2 * p.x) * std::cos(0.15 * p.y) + 0.01 * p.z * p.z; };
  MeshData fine = box_grid(55, 55.0, 0.2, 1);    // 998,250 tets
  MeshData coarse = box_grid(29, 55.0, 0.2, 2);  // 146,334 tets
  add_field(fine, "f", 1, f);
  add_field(coarse, "f", 1, f);

  auto t0 = Clock::now();
  const QualityStats q = compute_quality(fine);
  const double t_quality = seconds(t0);
  t0 = Clock::now();
  const FieldError e = compare_fields(fine, coarse);
  const double t_fields = seconds(t0);
  std::printf("[ timing ] compute_quality %zu tets: %.3f s; compare_fields %zu vs %zu tets: %.3f s (%d threads)\n",
              fine.tets.size(), t_quality, fine.tets.size(), coarse.tets.size(), t_fields,
              current_thread_limit());
  std::printf("[ timing ] dihedral %.2f+-%.2f deg, rms_both_rel %.2e, outside %zu/%zu\n", q.dihedral_deg.mean,
              q.dihedral_deg.std_dev, e.worst_rms_rel, e.original_in_simplified.outside,
              e.original_in_simplified.points);
  EXPECT_EQ(q.tet_count, 998250u);
  ASSERT_EQ(e.components.size(), 1u);
  EXPECT_GT(e.worst_rms_rel, 0.0);
  EXPECT_LT(e.worst_rms_rel, 0.01);
  EXPECT_LT(t_quality, 10.0);  // generous: shared machines; the printout is the measurement
  EXPECT_LT(t_fields, 10.0);
}

}  // namespace
}  // namespace topotet
