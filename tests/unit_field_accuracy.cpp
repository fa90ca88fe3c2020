// Field accuracy of the simplifier (issue #11): analytic fields over generated meshes, whose exact
// value is known everywhere, and the per-field weights of SimplifyOptions::field_weights.
//
//   - a linear field is reproduced to round-off at any ratio, by both engines, also on feature
//     vertices (boundary, interfaces, polylines, pins) and with several fields at once;
//   - for a quadratic field and a sharp front the error falls at every step as the ratio grows;
//   - feature vertices get values as good as interior ones, and pinned vertices keep theirs;
//   - field_weights: bad names and weights are refused, a zero weight leaves the collapses to the
//     other fields, a larger weight buys a field accuracy at the others' expense, and the output
//     stays the same for any thread count.
// Errors are measured at the simplified vertices against the exact field (the simplified ->
// original direction without interpolation error in the reference) and, through compare_fields,
// in both directions against the input mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "mesh/glm_convert.h"
#include "entry_points.h"
#include "mesh/mesh_model.h"
#include "test_meshes.h"
#include "topotet/generate.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

using Field = std::function<double(const glm::dvec3&)>;

// One material, nothing listed: a jittered 12^3-cube box (10,368 tets, 2,197 vertices) in [0, 12]^3.
MeshData plain_box() {
  return testing::make_grid(12, 12, 12, [](int, int, int) { return 1; }).data;
}

// The generated cube-sphere (two materials, a closed interface, an open patch, a polyline, a
// listed boundary and 8 pinned corners) in the unit cube.
MeshData featured_box() {
  GenerateOptions g;
  g.family = "cube-sphere";
  g.target_tets = 20000;
  g.seed = 3;
  MeshData m = generate_mesh(g);
  m.fields.clear();
  return m;
}

void set_field(MeshData& m, const std::string& name, const Field& f) {
  VertexField field{name, 1, {}};
  for (const auto& p : m.positions) field.values.push_back(f(to_glm(p)));
  m.fields.push_back(std::move(field));
}

struct Simplified {
  MeshData output;
  Report report;
};

Simplified simplify_data(const MeshData& input, double ratio, Engine engine = Engine::kParallel, SimplifyOptions options = {}) {
  MeshModel mesh = build_mesh_model(input);
  options.target_vertex_ratio = ratio;
  options.engine = engine;
  Simplified run;
  run.report = simplify(mesh, options);
  run.output = mesh.to_mesh_data();
  return run;
}

// Largest |value - exact| over the output's vertices, for field `index`.
double max_vertex_error(const MeshData& out, std::size_t index, const Field& exact) {
  double worst = 0.0;
  for (std::size_t v = 0; v < out.vertex_count(); ++v)
    worst = std::max(worst, std::fabs(out.fields[index].values[v] - exact(to_glm(out.positions[v]))));
  return worst;
}

// The same field error compare_fields reports: RMS over both directions, relative to the range.
double rms_both(const MeshData& input, const MeshData& output, std::size_t component = 0) {
  const FieldError e = compare_fields(input, output);
  return e.components.at(component).rms_both_rel;
}

const Field kLinear = [](const glm::dvec3& p) { return 2.0 * p.x - 3.0 * p.y + 0.5 * p.z + 1.0; };

TEST(FieldAccuracy, LinearFieldIsReproducedToRoundOffAtAnyRatio) {
  MeshData input = plain_box();
  set_field(input, "linear", kLinear);
  const double range = 2.0 * 12 + 3.0 * 12 + 0.5 * 12;
  for (Engine engine : {Engine::kParallel, Engine::kSequential})
    for (double ratio : {0.5, 0.2, 0.05}) {
      const Simplified run = simplify_data(input, ratio, engine);
      ASSERT_EQ(run.report.status, Status::kOk) << run.report.message;
      EXPECT_LE(max_vertex_error(run.output, 0, kLinear), 1e-11 * range) << "ratio " << ratio;
      const FieldError e = compare_fields(input, run.output);
      EXPECT_LE(e.worst_max_rel, 1e-11) << "ratio " << ratio;  // both directions, interpolated
    }
}

TEST(FieldAccuracy, LinearFieldIsReproducedOnFeatureVerticesAndWithSeveralFields) {
  MeshData input = featured_box();
  set_field(input, "linear", kLinear);
  set_field(input, "other", [](const glm::dvec3& p) { return -p.x + 4.0 * p.z; });
  VertexField vector{"vector", 3, {}};
  for (const auto& p : input.positions) vector.values.insert(vector.values.end(), {p[1], p[0] - p[2], 7.0});
  input.fields.push_back(vector);
  for (double ratio : {0.3, 0.1}) {
    const Simplified run = simplify_data(input, ratio);
    // The default tolerance may stop the run near the target (on this jittered sphere, at ~10.5%):
    // the field must be exact wherever the run stops.
    ASSERT_TRUE(run.report.status == Status::kOk ||
                (run.report.status == Status::kStoppedEarly && run.report.tolerance_limited))
        << run.report.message;
    EXPECT_LE(max_vertex_error(run.output, 0, kLinear), 1e-11) << "ratio " << ratio;
    const FieldError e = compare_fields(input, run.output);
    ASSERT_EQ(e.components.size(), 5u);
    EXPECT_LE(e.worst_max_rel, 1e-11) << "ratio " << ratio;
    std::string differences;
    EXPECT_TRUE(topotet::same_topology(topotet::compute_topology(input), topotet::compute_topology(run.output),
                                       &differences))
        << differences;
  }
}

// rms_both at each ratio, coarsest first; expects a strict fall at every step.
void expect_error_falls_as_the_ratio_grows(const Field& f, Engine engine) {
  MeshData input = plain_box();
  set_field(input, "f", f);
  double previous = std::numeric_limits<double>::infinity(), coarsest_vertex = 0.0, finest_vertex = 0.0;
  for (double ratio : {0.05, 0.1, 0.2, 0.4}) {
    const Simplified run = simplify_data(input, ratio, engine);
    ASSERT_EQ(run.report.status, Status::kOk) << run.report.message;
    const double error = rms_both(input, run.output);
    const double vertex_error = max_vertex_error(run.output, 0, f);
    std::printf("[ field ] %s ratio %.2f: rms both %.5f, largest vertex error %.5f\n",
                engine == Engine::kParallel ? "parallel" : "sequential", ratio, error, vertex_error);
    EXPECT_LT(error, previous) << "ratio " << ratio;
    // The largest vertex error is one vertex's luck at the coarse ratios (across a front it is
    // about half the jump wherever a coarse vertex sits on it, and moves by 2x from one ratio to
    // the next): only its overall fall is checked, from the coarsest to the finest ratio.
    if (ratio == 0.05) coarsest_vertex = vertex_error;
    EXPECT_GT(error, 0.0);
    previous = error;
    finest_vertex = vertex_error;
  }
  EXPECT_LT(finest_vertex, 0.5 * coarsest_vertex);
}

const Field kQuadratic = [](const glm::dvec3& p) {
  const glm::dvec3 d = p - glm::dvec3(5.0, 7.0, 6.0);
  return d.x * d.x + 2.0 * d.y * d.y - 0.5 * d.z * d.z + d.x * d.z;
};
// A tanh front a fifth of a cell wide across a tilted plane, plus a gentle slope.
const Field kFront = [](const glm::dvec3& p) {
  return std::tanh((p.x + 0.4 * p.y - 0.3 * p.z - 6.0) / 0.2) + 0.05 * p.z;
};

TEST(FieldAccuracy, QuadraticFieldErrorFallsAsTheRatioGrows) {
  expect_error_falls_as_the_ratio_grows(kQuadratic, Engine::kParallel);
  expect_error_falls_as_the_ratio_grows(kQuadratic, Engine::kSequential);
}

TEST(FieldAccuracy, SharpFrontErrorFallsAsTheRatioGrows) {
  expect_error_falls_as_the_ratio_grows(kFront, Engine::kParallel);
  expect_error_falls_as_the_ratio_grows(kFront, Engine::kSequential);
}

// Vertices of `m` on a feature: on the boundary, on a face between two materials, or pinned.
std::vector<char> feature_vertices(const MeshData& m) {
  std::vector<char> feature(m.vertex_count(), 0);
  std::vector<int> material(m.vertex_count(), std::numeric_limits<int>::min());
  std::multiset<std::array<VertId, 3>> faces;
  for (std::size_t t = 0; t < m.tet_count(); ++t) {
    for (VertId v : m.tets[t]) {
      if (material[v] == std::numeric_limits<int>::min()) material[v] = m.tet_material[t];
      if (material[v] != m.tet_material[t]) feature[v] = 1;
    }
    for (int f = 0; f < 4; ++f) {
      std::array<VertId, 3> key{m.tets[t][(f + 1) % 4], m.tets[t][(f + 2) % 4], m.tets[t][(f + 3) % 4]};
      std::sort(key.begin(), key.end());
      faces.insert(key);
    }
  }
  for (const auto& key : faces)
    if (faces.count(key) == 1)
      for (VertId v : key) feature[v] = 1;
  for (VertId v : m.corners) feature[v] = 1;
  return feature;
}

TEST(FieldAccuracy, FeatureVerticesAreAsAccurateAsInteriorOnes) {
  // Where a feature fixes the position (endpoints, midpoints, pins), the field values must not
  // pay for it: no larger error and no bias on feature vertices.
  MeshData input = featured_box();
  const Field f = [](const glm::dvec3& p) {
    return std::sin(4.0 * p.x) * std::cos(3.0 * p.y) + 0.5 * std::tanh((p.z - 0.45) / 0.05);
  };
  set_field(input, "f", f);
  for (double ratio : {0.3, 0.1}) {
    const Simplified run = simplify_data(input, ratio);
    // The default tolerance may stop the run near the target (on this jittered sphere, at ~10.5%):
    // the field must be exact wherever the run stops.
    ASSERT_TRUE(run.report.status == Status::kOk ||
                (run.report.status == Status::kStoppedEarly && run.report.tolerance_limited))
        << run.report.message;
    const std::vector<char> feature = feature_vertices(run.output);
    double sum2[2] = {0, 0}, sum[2] = {0, 0};
    std::size_t count[2] = {0, 0};
    for (std::size_t v = 0; v < run.output.vertex_count(); ++v) {
      const double e = run.output.fields[0].values[v] - f(to_glm(run.output.positions[v]));
      const int group = feature[v] ? 1 : 0;
      sum2[group] += e * e;
      sum[group] += e;
      ++count[group];
    }
    ASSERT_GT(count[0], 50u);  // at 10% the 20k-tet cube-sphere keeps ~60 interior vertices
    ASSERT_GT(count[1], 100u);
    const double rms_interior = std::sqrt(sum2[0] / count[0]), rms_feature = std::sqrt(sum2[1] / count[1]);
    const double bias_feature = sum[1] / count[1];
    std::printf("[ field ] ratio %.1f: %zu interior vertices rms %.5f, %zu feature vertices rms %.5f, bias %.6f\n", ratio,
                count[0], rms_interior, count[1], rms_feature, bias_feature);
    EXPECT_LE(rms_feature, 1.25 * rms_interior) << "ratio " << ratio;
    EXPECT_LE(std::fabs(bias_feature), 0.25 * rms_feature) << "ratio " << ratio;
    // Pinned vertices keep their input values exactly.
    for (VertId c : run.output.corners) EXPECT_EQ(run.output.fields[0].values[c], f(to_glm(run.output.positions[c])));
  }
}

TEST(FieldWeights, UnknownNamesAndBadWeightsAreInvalidInput) {
  MeshData input = plain_box();
  set_field(input, "f", kQuadratic);
  const MeshModel original = build_mesh_model(input);
  for (const auto& [name, weight] : std::vector<std::pair<std::string, double>>{
           {"no such field", 1.0}, {"f", -1.0}, {"f", std::numeric_limits<double>::quiet_NaN()},
           {"f", std::numeric_limits<double>::infinity()}}) {
    MeshModel mesh = original;
    SimplifyOptions options;
    options.field_weights[name] = weight;
    const Report report = simplify(mesh, options);
    EXPECT_EQ(report.status, Status::kInvalidInput) << name << " = " << weight;
    EXPECT_NE(report.message.find("field_weights"), std::string::npos) << report.message;
    EXPECT_TRUE(mesh.to_mesh_data() == original.to_mesh_data()) << "the mesh must be untouched";
  }
}

TEST(FieldWeights, ZeroWeightLeavesTheCollapsesToTheOtherFields) {
  // A field of weight 0 is carried but steers nothing: the mesh is the one simplified without it,
  // and its values are the interpolation of the input's (exact for a linear field).
  MeshData one = plain_box();
  set_field(one, "front", kFront);
  MeshData two = one;
  set_field(two, "linear", kLinear);
  SimplifyOptions options;
  options.field_weights["linear"] = 0.0;
  const Simplified a = simplify_data(one, 0.1);
  const Simplified b = simplify_data(two, 0.1, Engine::kParallel, options);
  ASSERT_EQ(b.report.status, Status::kOk) << b.report.message;
  EXPECT_TRUE(a.output.positions == b.output.positions);
  EXPECT_TRUE(a.output.tets == b.output.tets);
  EXPECT_TRUE(a.output.fields[0] == b.output.fields[0]);
  EXPECT_LE(max_vertex_error(b.output, 1, kLinear), 1e-11);
}

TEST(FieldWeights, ALargerWeightKeepsThatFieldCloser) {
  // Two fronts across different planes compete for the vertices; weighting one 10x must lower its
  // error and raise the other's.
  MeshData input = plain_box();
  set_field(input, "x_front", [](const glm::dvec3& p) { return std::tanh((p.x - 4.3) / 0.3); });
  set_field(input, "y_front", [](const glm::dvec3& p) { return std::tanh((p.y + 0.5 * p.z - 8.4) / 0.3); });
  const Simplified even = simplify_data(input, 0.1);
  SimplifyOptions options;
  options.field_weights["x_front"] = 10.0;
  const Simplified favoured = simplify_data(input, 0.1, Engine::kParallel, options);
  const double x_even = rms_both(input, even.output, 0), y_even = rms_both(input, even.output, 1);
  const double x_favoured = rms_both(input, favoured.output, 0), y_favoured = rms_both(input, favoured.output, 1);
  std::printf("[ field ] weights 1/1: x %.5f y %.5f; weights 10/1: x %.5f y %.5f\n", x_even, y_even, x_favoured,
              y_favoured);
  EXPECT_LT(x_favoured, 0.9 * x_even);
  EXPECT_GT(y_favoured, y_even);
}

TEST(FieldWeights, OutputIsIdenticalForEveryThreadCount) {
  MeshData input = featured_box();
  set_field(input, "a", kFront);
  set_field(input, "b", kQuadratic);
  SimplifyOptions options;
  options.field_weights["a"] = 3.0;
  options.field_weights["b"] = 0.5;
  MeshData reference;
  for (int threads : {1, 2, 4}) {
    options.num_threads = threads;
    const Simplified run = simplify_data(input, 0.15, Engine::kParallel, options);
    ASSERT_EQ(run.report.status, Status::kOk) << run.report.message;
    if (threads == 1)
      reference = run.output;
    else
      EXPECT_TRUE(run.output == reference) << "threads = " << threads << " differs from threads = 1";
  }
}

}  // namespace
}  // namespace topotet
