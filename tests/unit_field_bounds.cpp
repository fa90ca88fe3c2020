// Field error bounds (issue #16, paper 003; engine/guarantees/field_bounds.h): the per-tet bounds the
// simplifier keeps with SimplifyOptions::track_field_bounds / max_field_error(_rel).
//
// What field_bounds.h guarantees, and what is checked here against the ORIGINAL mesh, on a box
// (flat boundary) and on the cube-sphere (curved boundary: original vertices end up outside the
// simplified mesh), for a linear, a quadratic and a sharp-front field, with both engines:
//   1. at every original vertex, |f - f~| <= the bound of a simplified tet holding it (of the
//      closest tets when it lies outside the simplified mesh);
//   2. densely (35 points per original tet: the barycentric lattice of order 4) on every original
//      tet whose four vertices lie in ONE simplified tet, |f - f~| <= that tet's bound; the test
//      also prints how far the dense error goes above the bounds on the other original tets (no
//      guarantee there: field_bounds.h);
//   3. the report's largest bound is at least the error compare_fields measures at the original
//      vertices;
//   4. with max_field_error E (absolute or relative) no bound, and no measured error at the
//      original vertices, exceeds E, the limit refused collapses (it was active), and no original
//      vertex is outside the output (a limit refuses that too);
//   5. the output, the bounds and the report's bound are identical for 1, 2 and 4 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "mesh/glm_convert.h"
#include "entry_points.h"
#include "guarantees/field_bounds.h"
#include "mesh/mesh_model.h"
#include "test_meshes.h"
#include "topotet/generate.h"
#include "topotet/metrics/field_error.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

using Field = std::function<double(const glm::dvec3&)>;
using Bary = std::array<double, 4>;

const Field kLinear = [](const glm::dvec3& p) { return 2.0 * p.x - 3.0 * p.y + 0.5 * p.z + 1.0; };
const Field kQuadratic = [](const glm::dvec3& p) {
  const glm::dvec3 d = p - glm::dvec3(0.4, 0.6, 0.5);
  return d.x * d.x + 2.0 * d.y * d.y - 0.5 * d.z * d.z + d.x * d.z;
};
const Field kFront = [](const glm::dvec3& p) { return std::tanh((p.x + 0.4 * p.y - 0.3 * p.z - 0.5) / 0.03) + 0.05 * p.z; };

// A jittered 8^3-cube box (3,072 tets) scaled to the unit cube, and a small cube-sphere.
MeshData box() {
  MeshData m = testing::make_grid(8, 8, 8, [](int, int, int) { return 1; }).data;
  for (auto& p : m.positions) p = from_glm(to_glm(p) / 8.0);
  return m;
}
MeshData cube_sphere() {
  GenerateOptions g;
  g.family = "cube-sphere";
  g.target_tets = 6000;
  g.seed = 5;
  MeshData m = generate_mesh(g);
  m.fields.clear();
  return m;
}

void set_field(MeshData& m, const Field& f) {
  VertexField field{"f", 1, {}};
  for (const auto& p : m.positions) field.values.push_back(f(to_glm(p)));
  m.fields.push_back(std::move(field));
}

struct Outcome {
  MeshData output;
  Report report;
};

Outcome run(const MeshData& input, Engine engine, SimplifyOptions options, double ratio = 0.15) {
  MeshModel mesh = build_mesh_model(input);
  options.target_vertex_ratio = ratio;
  options.engine = engine;
  if (options.max_field_error == 0.0 && options.max_field_error_rel == 0.0) options.track_field_bounds = true;
  Outcome r;
  r.report = simplify(mesh, options);
  r.output = mesh.to_mesh_data();
  return r;
}

bool barycentric(const MeshData& m, std::size_t t, const glm::dvec3& q, Bary& l) {
  const auto& tv = m.tets[t];
  const glm::dvec3 a = to_glm(m.positions[tv[0]]) - q, b = to_glm(m.positions[tv[1]]) - q, c = to_glm(m.positions[tv[2]]) - q,
                   d = to_glm(m.positions[tv[3]]) - q;
  auto det = [](const glm::dvec3& x, const glm::dvec3& y, const glm::dvec3& z) { return glm::dot(x, glm::cross(y, z)); };
  l = {det(b, c, d), -det(a, c, d), det(a, b, d), -det(a, b, c)};
  const double sum = l[0] + l[1] + l[2] + l[3];
  if (sum == 0.0) return false;
  for (double& x : l) x /= sum;
  return true;
}

double smallest(const Bary& l) { return std::min({l[0], l[1], l[2], l[3]}); }

// The simplified mesh's tets by a uniform grid of their boxes, for point location.
class Locator {
 public:
  explicit Locator(const MeshData& m) : m_(m) {
    lo_ = glm::dvec3(std::numeric_limits<double>::infinity());
    glm::dvec3 hi(-std::numeric_limits<double>::infinity());
    for (const auto& p : m.positions) lo_ = glm::min(lo_, to_glm(p)), hi = glm::max(hi, to_glm(p));
    lo_ -= 1e-6;
    cell_ = (glm::dvec3(hi) + 1e-6 - lo_) / double(kN);
    cells_.resize(kN * kN * kN);
    for (std::size_t t = 0; t < m.tets.size(); ++t) {
      glm::dvec3 a(std::numeric_limits<double>::infinity()), b(-std::numeric_limits<double>::infinity());
      for (VertId v : m.tets[t]) a = glm::min(a, to_glm(m.positions[v])), b = glm::max(b, to_glm(m.positions[v]));
      const auto ia = index(a), ib = index(b);
      for (int z = ia[2]; z <= ib[2]; ++z)
        for (int y = ia[1]; y <= ib[1]; ++y)
          for (int x = ia[0]; x <= ib[0]; ++x) cells_[(z * kN + y) * kN + x].push_back(static_cast<TetId>(t));
    }
  }
  // Tets holding q (smallest barycentric coordinate >= -1e-9), with its coordinates in each.
  void holding(const glm::dvec3& q, std::vector<std::pair<TetId, Bary>>& out) const {
    out.clear();
    const auto i = index(q);
    Bary l;
    for (TetId t : cells_[(i[2] * kN + i[1]) * kN + i[0]])
      if (barycentric(m_, t, q, l) && smallest(l) >= -1e-9) out.push_back({t, l});
  }

 private:
  static constexpr int kN = 24;
  std::array<int, 3> index(const glm::dvec3& p) const {
    std::array<int, 3> i{};
    for (int k = 0; k < 3; ++k) i[k] = std::clamp(int((p[k] - lo_[k]) / cell_[k]), 0, kN - 1);
    return i;
  }
  const MeshData& m_;
  glm::dvec3 lo_, cell_;
  std::vector<std::vector<TetId>> cells_;
};

double interpolate(const MeshData& m, std::size_t t, const Bary& l) {
  double f = 0.0;
  for (int i = 0; i < 4; ++i) f += l[i] * m.fields[0].values[m.tets[t][i]];
  return f;
}

// Checks 1 and 2 (see the top) for one run; returns the largest dense error over the original
// tets without a guarantee, relative to the largest bound (printed by the caller).
double check_against_original(const MeshData& input, const Outcome& r, const std::string& what) {
  const MeshData& out = r.output;
  const std::vector<float>& bound = r.report.tet_field_bound;
  EXPECT_EQ(bound.size(), out.tets.size()) << what;
  if (bound.size() != out.tets.size()) return 0.0;
  const Locator locator(out);
  std::vector<std::pair<TetId, Bary>> hold;
  // 1. Original vertices inside the simplified mesh.
  std::vector<TetId> vertex_tet(input.vertex_count(), kInvalid);  // the single tet holding it, if one
  std::size_t outside = 0;
  for (std::size_t v = 0; v < input.vertex_count(); ++v) {
    const glm::dvec3 q = to_glm(input.positions[v]);
    const double f = input.fields[0].values[v];
    locator.holding(q, hold);
    if (hold.empty()) {
      // Outside the simplified mesh (the curved boundary moved): the bound covers the value at
      // the closest point of the closest tet, which compare_fields measures (check 3).
      ++outside;
      continue;
    }
    double allowed = 0.0;
    for (const auto& entry : hold) allowed = std::max(allowed, double(bound[entry.first]));
    // All holding tets give the same value up to rounding (they share the face q lies on).
    EXPECT_LE(std::fabs(f - interpolate(out, hold[0].first, hold[0].second)), allowed) << what << ": original vertex " << v;
    if (hold.size() == 1) vertex_tet[v] = hold[0].first;
  }
  // 2. Dense points of the original tets lying in one simplified tet.
  std::size_t contained = 0;
  double worst_unguaranteed = 0.0, max_bound = 0.0;
  for (float b : bound) max_bound = std::max(max_bound, double(b));
  for (std::size_t t0 = 0; t0 < input.tets.size(); ++t0) {
    const auto& tv = input.tets[t0];
    const TetId t = vertex_tet[tv[0]];
    const bool in_one = t != kInvalid && vertex_tet[tv[1]] == t && vertex_tet[tv[2]] == t && vertex_tet[tv[3]] == t;
    contained += in_one;
    for (int a = 0; a <= 4; ++a)
      for (int b = 0; a + b <= 4; ++b)
        for (int c = 0; a + b + c <= 4; ++c) {
          const int d = 4 - a - b - c;
          const Bary w = {a / 4.0, b / 4.0, c / 4.0, d / 4.0};
          glm::dvec3 q(0.0);
          double f = 0.0;
          for (int i = 0; i < 4; ++i) q += w[i] * to_glm(input.positions[tv[i]]), f += w[i] * input.fields[0].values[tv[i]];
          if (in_one) {
            Bary l;
            EXPECT_TRUE(barycentric(out, t, q, l)) << what << ": flat simplified tet " << t;
            EXPECT_LE(std::fabs(f - interpolate(out, t, l)), double(bound[t])) << what << ": original tet " << t0;
          } else {
            locator.holding(q, hold);
            for (const auto& [s, l] : hold)
              worst_unguaranteed = std::max(worst_unguaranteed, std::fabs(f - interpolate(out, s, l)) - double(bound[s]));
          }
        }
  }
  EXPECT_GT(contained, 0u) << what << ": no original tet inside one simplified tet: check 2 checked nothing";
  std::printf("[ bounds ] %s: %zu original vertices outside, %zu of %zu original tets inside one simplified tet; "
              "elsewhere the dense error exceeds the local bound by up to %.3g of the largest bound\n",
              what.c_str(), outside, contained, input.tets.size(), max_bound > 0 ? worst_unguaranteed / max_bound : 0.0);
  return worst_unguaranteed;
}

struct Case {
  const char* name;
  Field field;
};

TEST(FieldBounds, BoundHoldsAtOriginalVerticesAndDenselyInContainedTets) {
  const std::vector<Case> fields = {{"linear", kLinear}, {"quadratic", kQuadratic}, {"front", kFront}};
  for (const auto& [mesh_name, base] : {std::pair<const char*, MeshData>{"box", box()}, {"cube-sphere", cube_sphere()}})
    for (const Case& c : fields) {
      MeshData input = base;
      set_field(input, c.field);
      for (Engine engine : {Engine::kParallel, Engine::kSequential}) {
        const std::string what = std::string(mesh_name) + " " + c.name + (engine == Engine::kParallel ? " parallel" : " sequential");
        const Outcome r = run(input, engine, {});
        ASSERT_NE(r.report.status, Status::kInvalidInput) << r.report.message;
        ASSERT_TRUE(r.report.field_bounds);
        ASSERT_EQ(r.report.field_bound.size(), 1u);
        check_against_original(input, r, what);
        // 3. The measured error at the original vertices (both inside and outside) is covered.
        const FieldError e = compare_fields(input, r.output);
        EXPECT_LE(e.components[0].original_to_simplified.max_abs, r.report.field_bound[0]) << what;
        if (c.name == std::string("linear")) EXPECT_LE(r.report.field_bound_rel, 1e-7) << what;  // rounding only
        else EXPECT_GT(r.report.field_bound_rel, 1e-4) << what;
      }
    }
}

// The verdict the CLI gives a run (field_bound_violations, metrics): none for the bounds the run
// kept, and a planted fault (the bounds halved, as if a collapse had under-estimated them) is caught.
TEST(FieldBounds, ViolationsAreFoundAgainstTheMeasuredError) {
  MeshData input = box();
  set_field(input, kFront);
  SimplifyOptions options;
  options.max_field_error_rel = 0.02;
  const Outcome r = run(input, Engine::kParallel, options, 0.1);
  ASSERT_TRUE(r.report.field_bounds);
  const FieldError e = compare_fields(input, r.output);
  ASSERT_EQ(e.original_in_simplified.outside, 0u);
  EXPECT_TRUE(field_bound_violations(e, r.report.field_bound).empty());
  std::vector<double> halved = r.report.field_bound;
  for (double& b : halved) b *= 0.5;
  ASSERT_GT(e.components[0].original_to_simplified.max_abs, halved[0]) << "the planted fault must be below the error";
  const std::vector<std::string> found = field_bound_violations(e, halved);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_NE(found[0].find("measured"), std::string::npos) << found[0];
}

TEST(FieldBounds, MaxFieldErrorIsNeverExceeded) {
  for (const Field& f : {kQuadratic, kFront}) {
    MeshData input = cube_sphere();
    set_field(input, f);
    for (Engine engine : {Engine::kParallel, Engine::kSequential}) {
      // Unlimited first, to pick limits that bind. The geometric tolerance is off in these runs,
      // so that only the field limit can stop them: with it on, both runs may stop on the
      // tolerance, and which one keeps more vertices then depends on the path, not on the limit.
      SimplifyOptions unlimited;
      unlimited.tolerance_rel = 0.0;
      const Outcome free_run = run(input, engine, unlimited, 0.05);
      const double free_rel = free_run.report.field_bound_rel;
      ASSERT_GT(free_rel, 0.0);
      for (const double fraction : {0.3}) {
        SimplifyOptions relative = unlimited;
        relative.max_field_error_rel = fraction * free_rel;
        const Outcome r = run(input, engine, relative, 0.05);
        ASSERT_NE(r.report.status, Status::kInvalidInput) << r.report.message;
        EXPECT_EQ(r.report.status, Status::kStoppedEarly) << "the limit should stop the run before 5%";
        EXPECT_GT(r.report.rejected_by(RejectReason::kFieldError), 0u);
        EXPECT_LE(r.report.field_bound_rel, relative.max_field_error_rel);
        const FieldError e = compare_fields(input, r.output);
        EXPECT_EQ(e.original_in_simplified.outside, 0u) << "under a limit no original vertex leaves the mesh";
        EXPECT_LE(e.components[0].original_to_simplified.max_rel, relative.max_field_error_rel);
        EXPECT_LE(e.components[0].original_to_simplified.max_abs, r.report.field_bound[0]);
        EXPECT_GT(r.report.vertices_after, free_run.report.vertices_after);
        // The same limit in field units.
        SimplifyOptions absolute = unlimited;
        absolute.max_field_error = relative.max_field_error_rel * e.components[0].range;
        const Outcome a = run(input, engine, absolute, 0.05);
        EXPECT_LE(a.report.field_bound[0], absolute.max_field_error);
        EXPECT_LE(compare_fields(input, a.output).components[0].original_to_simplified.max_abs, absolute.max_field_error);
      }
    }
  }
}

// The output, every tet's bound and the report's for 1, 2 and 4 threads, to 10%.
void expect_same_for_every_thread_count(const MeshData& input, SimplifyOptions options) {
  std::vector<Outcome> runs;
  for (int threads : {1, 2, 4}) {
    options.num_threads = threads;
    runs.push_back(run(input, Engine::kParallel, options, 0.1));
  }
  for (std::size_t i = 1; i < runs.size(); ++i) {
    EXPECT_EQ(runs[i].output.positions, runs[0].output.positions);
    EXPECT_EQ(runs[i].output.tets, runs[0].output.tets);
    EXPECT_EQ(runs[i].output.fields[0].values, runs[0].output.fields[0].values);
    EXPECT_EQ(runs[i].report.tet_field_bound, runs[0].report.tet_field_bound);
    EXPECT_EQ(runs[i].report.field_bound, runs[0].report.field_bound);
    EXPECT_EQ(runs[i].report.collapses, runs[0].report.collapses);
  }
}

TEST(FieldBounds, SameOutputAndBoundsForAnyThreadCount) {
  MeshData input = cube_sphere();
  set_field(input, kFront);
  SimplifyOptions options;
  options.max_field_error_rel = 0.05;
  expect_same_for_every_thread_count(input, options);
}

TEST(FieldBounds, OffByDefaultAndRefusesBadLimits) {
  MeshData input = box();
  set_field(input, kQuadratic);
  MeshModel mesh = build_mesh_model(input);
  const Report r = simplify(mesh, {});
  EXPECT_FALSE(r.field_bounds);
  EXPECT_TRUE(r.field_bound.empty() && r.tet_field_bound.empty());
  EXPECT_EQ(r.field_bounds_bytes, 0u);
  SimplifyOptions bad;
  bad.max_field_error = -1.0;
  MeshModel other = build_mesh_model(input);
  EXPECT_EQ(simplify(other, bad).status, Status::kInvalidInput);
  EXPECT_STREQ(to_string(RejectReason::kFieldError), "field_error");
}

// --- everywhere (SimplifyOptions::field_bound_mode, field_bounds.h "Everywhere") --------------------

// One collapse u <- v at the edge's midpoint (u's new values the mean), as the kernel hands it to
// the bounds: the star's tets with their moving corner, and St(uv).
struct OneCollapse {
  FieldBoundsScratch s;
  std::vector<TetId> removed, old_star;
};
OneCollapse star_of_collapse(const MeshModel& mesh, VertId u, VertId v) {
  OneCollapse c;
  for (VertId end : {u, v})
    mesh.for_each_tet_of(end, [&](TetId t) {
      const auto& tv = mesh.tets[t];
      const bool has_u = std::find(tv.begin(), tv.end(), u) != tv.end(), has_v = std::find(tv.begin(), tv.end(), v) != tv.end();
      if (end == v && has_u) return;  // seen from u
      c.old_star.push_back(t);
      if (has_u && has_v) {
        c.removed.push_back(t);
        return;
      }
      for (std::uint8_t k = 0; k < 4; ++k)
        if (tv[k] == end) c.s.star.push_back({t, k});
    });
  return c;
}

// The bounds of the new star after evaluate() against the error at `per_tet` random points of
// each new tet, located in the old star (which the new one tiles: an interior edge). Returns how
// many points exceed their tet's bound.
std::size_t dense_excess_of_one_collapse(const MeshModel& mesh, const FieldBounds& bounds, VertId u, VertId v, int per_tet,
                                         std::mt19937_64& rng, std::size_t& points) {
  OneCollapse c = star_of_collapse(mesh, u, v);
  const glm::dvec3 p = 0.5 * (mesh.positions[u] + mesh.positions[v]);
  const double at_p = 0.5 * (mesh.field_values[u] + mesh.field_values[v]);
  EXPECT_TRUE(bounds.evaluate(mesh, c.removed, u, p, &at_p, c.s, false));
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::size_t excess = 0;
  for (std::size_t i = 0; i < c.s.star.size(); ++i) {
    const auto& corner = c.s.corners[i];
    for (int n = 0; n < per_tet; ++n) {
      Bary w;
      double sum = 0.0;
      for (double& x : w) sum += (x = -std::log(1.0 - uniform(rng)));
      glm::dvec3 q(0.0);
      double simplified = 0.0;
      for (int k = 0; k < 4; ++k) q += (w[k] / sum) * corner[k], simplified += (w[k] / sum) * c.s.values[i][k][0];
      // The original field: the old star's tet holding q (the original mesh: no collapse yet).
      double original = std::numeric_limits<double>::quiet_NaN(), best = -1.0;
      for (TetId t : c.old_star) {
        Bary l;
        std::array<glm::dvec3, 4> pts;
        for (int k = 0; k < 4; ++k) pts[k] = mesh.positions[mesh.tets[t][k]];
        const glm::dvec3 a = pts[0] - q, b = pts[1] - q, cc = pts[2] - q, d = pts[3] - q;
        auto det = [](const glm::dvec3& x, const glm::dvec3& y, const glm::dvec3& z) { return glm::dot(x, glm::cross(y, z)); };
        l = {det(b, cc, d), -det(a, cc, d), det(a, b, d), -det(a, b, cc)};
        const double total = l[0] + l[1] + l[2] + l[3];
        for (double& x : l) x /= total;
        if (smallest(l) > best) {
          best = smallest(l);
          original = 0.0;
          for (int k = 0; k < 4; ++k) original += l[k] * mesh.field_values[mesh.tets[t][k]];
        }
      }
      EXPECT_GE(best, -1e-9) << "a point of the new star outside the old one";
      ++points;
      if (std::fabs(original - simplified) > c.s.bounds[i] * (1.0 + 1e-9) + 1e-12) ++excess;
    }
  }
  return excess;
}

// Interior edges of the box, in a fixed random order.
std::vector<std::pair<VertId, VertId>> interior_edges(const MeshModel& mesh, std::size_t count, std::uint64_t seed) {
  std::vector<std::uint8_t> boundary(mesh.vertex_capacity(), 0);
  for (VertId x = 0; x < mesh.vertex_capacity(); ++x) {
    const glm::dvec3& q = mesh.positions[x];
    for (int k = 0; k < 3; ++k) boundary[x] |= q[k] < 1e-9 || q[k] > 1.0 - 1e-9;
  }
  std::vector<std::pair<VertId, VertId>> edges;
  for (TetId t = 0; t < mesh.tets.size(); ++t)
    for (const auto& e : kTetEdges) {
      const VertId a = mesh.tets[t][e[0]], b = mesh.tets[t][e[1]];
      if (a < b && !boundary[a] && !boundary[b]) edges.push_back({a, b});
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::shuffle(edges.begin(), edges.end(), std::mt19937_64(seed));
  edges.resize(std::min(count, edges.size()));
  return edges;
}

// The overlay's bound holds at a million random points of the new stars of 40 collapses on the
// sharp front; with the crossings skipped (the planted fault) the same points find it too low.
TEST(FieldBoundsEverywhere, OneCollapseBoundHoldsDenselyAndTheCrossingsAreNeeded) {
  MeshData input = box();
  set_field(input, kFront);
  const MeshModel mesh = build_mesh_model(input);
  FieldBounds bounds(mesh, 0.0, 0.0), faulty(mesh, 0.0, 0.0);
  bounds.set_everywhere(mesh);
  faulty.set_everywhere(mesh);
  faulty.plant_fault_skip_crossings();
  std::size_t points = 0, excess = 0, fault_excess = 0, fault_points = 0;
  std::mt19937_64 rng(7), fault_rng(7);
  for (const auto& [u, v] : interior_edges(mesh, 40, 3)) {
    excess += dense_excess_of_one_collapse(mesh, bounds, u, v, 1000, rng, points);
    fault_excess += dense_excess_of_one_collapse(mesh, faulty, u, v, 1000, fault_rng, fault_points);
  }
  EXPECT_GE(points, 1000000u);
  EXPECT_EQ(excess, 0u);
  EXPECT_GT(fault_excess, 0u) << "the planted fault (crossings skipped) went unnoticed";
  std::printf("[ bounds ] one collapse, %zu points: %zu above the bound; crossings skipped: %zu above\n", points, excess,
              fault_excess);
}

// Whole runs: a million points inside the input (and its vertices) find no error above the bound
// of the output tet holding them (metrics' check_bounds_densely), where the vertex bound is
// exceeded between the vertices; the limit holds.
TEST(FieldBoundsEverywhere, WholeRunsHoldAtAMillionPoints) {
  for (const auto& [name, base] : {std::pair<const char*, MeshData>{"box", box()}, {"cube-sphere", cube_sphere()}}) {
    MeshData input = base;
    set_field(input, kFront);
    SimplifyOptions options;
    options.max_field_error_rel = 0.05;
    options.field_bound_mode = FieldBoundMode::kEverywhere;
    const Outcome r = run(input, Engine::kParallel, options, 0.1);
    ASSERT_EQ(r.report.status == Status::kInvalidInput, false) << r.report.message;
    EXPECT_EQ(r.report.field_bound_mode, FieldBoundMode::kEverywhere);
    EXPECT_LE(r.report.field_bound_rel, 0.05) << name;
    EXPECT_LT(r.report.vertices_after, input.vertex_count() / 2) << name << ": the mode must still simplify";
    const DenseBoundCheck dense = check_bounds_densely(input, r.output, r.report.tet_field_bound, 1000000, 11);
    EXPECT_EQ(dense.violations, 0u) << name << ": " << dense.first_violation;
    EXPECT_EQ(dense.outside, 0u) << name << ": the boundary may not move";
    EXPECT_LE(dense.worst_error_rel, 0.05 * (1 + 1e-9)) << name;
    // The vertex bound at the same limit: exceeded between the vertices (why the mode exists).
    SimplifyOptions vertices = options;
    vertices.field_bound_mode = FieldBoundMode::kVertices;
    const Outcome rv = run(input, Engine::kParallel, vertices, 0.1);
    const DenseBoundCheck dv = check_bounds_densely(input, rv.output, rv.report.tet_field_bound, 200000, 11);
    EXPECT_GT(dv.violations, 0u) << name << ": the vertex bound held everywhere; this test no longer shows the difference";
    std::printf("[ bounds ] %s: everywhere %zu -> %llu vertices, %llu points, worst %.4g of the range; vertices mode "
                "%llu vertices, worst %.4g, %llu points above their bound\n",
                name, input.vertex_count(), static_cast<unsigned long long>(r.report.vertices_after),
                static_cast<unsigned long long>(dense.points), dense.worst_error_rel,
                static_cast<unsigned long long>(rv.report.vertices_after), dv.worst_error_rel,
                static_cast<unsigned long long>(dv.violations));
  }
}

// The lists of original tets move in the parallel apply phase (scripts/tsan.sh runs this one).
TEST(FieldBoundsEverywhere, SameOutputAndBoundsForAnyThreadCount) {
  MeshData input = box();
  set_field(input, kFront);
  SimplifyOptions options;
  options.max_field_error_rel = 0.05;
  options.field_bound_mode = FieldBoundMode::kEverywhere;
  expect_same_for_every_thread_count(input, options);
}

TEST(FieldBoundsEverywhere, NeedsALimitAndIsNotOutOfCore) {
  MeshData input = box();
  set_field(input, kQuadratic);
  SimplifyOptions options;
  options.field_bound_mode = FieldBoundMode::kEverywhere;
  options.track_field_bounds = true;
  MeshModel mesh = build_mesh_model(input);
  const Report r = simplify(mesh, options);
  EXPECT_EQ(r.status, Status::kInvalidInput);
  EXPECT_NE(r.message.find("needs a limit"), std::string::npos) << r.message;
  // Out of core the passes carry samples (SimplifyOptions::field_samples), not the original tets.
  FieldBoundSamples carried;
  options.track_field_bounds = false;
  options.max_field_error_rel = 0.05;
  options.field_samples = &carried;
  MeshModel other = build_mesh_model(input);
  const Report ooc = simplify(other, options);
  EXPECT_EQ(ooc.status, Status::kInvalidInput);
  EXPECT_NE(ooc.message.find("not available out of core"), std::string::npos) << ooc.message;
  EXPECT_EQ(other.live_vertex_count(), input.vertex_count()) << "refused before any collapse";
  EXPECT_STREQ(to_string(FieldBoundMode::kEverywhere), "everywhere");
  EXPECT_STREQ(to_string(FieldBoundMode::kVertices), "vertices");
}

}  // namespace
}  // namespace topotet
