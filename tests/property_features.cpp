// Sharp features by angle (topotet/features.h): what detect_features finds on shapes whose
// features are known by construction, and that a default simplification keeps them: every input
// corner at its exact position, every sharp edge a straight chain of mesh edges from corner to
// corner, and (the shapes being polyhedra with planar interfaces) the volume of every material.
// The expected corners and curves come from the construction of each shape, not from the library.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>

#include <glm/geometric.hpp>

#include "mesh/glm_convert.h"
#include "entry_points.h"
#include "mesh/mesh_model.h"
#include "topotet/threads.h"
#include "test_meshes.h"
#include "topotet/features.h"
#include "topotet/generate.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

using Point = std::array<int, 3>;

struct Shape {
  const char* name;
  testing::Grid grid;
  std::vector<Point> corners;                 // grid points that must keep their position
  std::vector<std::pair<Point, Point>> lines;  // straight curves between two of the corners
};

glm::dvec3 at(const Point& p) { return glm::dvec3(p[0], p[1], p[2]); }

// The 8 corners and 12 edges of the box [lo, hi].
void add_box_features(Shape& s, Point lo, Point hi) {
  const int xs[2] = {lo[0], hi[0]}, ys[2] = {lo[1], hi[1]}, zs[2] = {lo[2], hi[2]};
  for (int x : xs)
    for (int y : ys)
      for (int z : zs) s.corners.push_back({x, y, z});
  for (int a : {0, 1})
    for (int b : {0, 1}) {
      s.lines.push_back({{xs[0], ys[a], zs[b]}, {xs[1], ys[a], zs[b]}});
      s.lines.push_back({{xs[a], ys[0], zs[b]}, {xs[a], ys[1], zs[b]}});
      s.lines.push_back({{xs[a], ys[b], zs[0]}, {xs[a], ys[b], zs[1]}});
    }
}

// A jittered box (boundary vertices move only along the boundary: faces stay planar, box edges
// straight), one material, nothing listed.
Shape box() {
  Shape s{"box", testing::make_grid(7, 6, 5, [](int, int, int) { return 1; }), {}, {}};
  add_box_features(s, {0, 0, 0}, {7, 6, 5});
  return s;
}

// The same box with its boundary listed as one surface (ref 10): the features are found on
// listed surfaces as on the plain boundary.
Shape listed_box() {
  Shape s = box();
  s.name = "listed_box";
  testing::add_box_boundary(s.grid, 10);
  return s;
}

// An L-shaped prism (the cubes with i >= 3 and j >= 3 left out): a reentrant (concave) edge.
// Not jittered: the jitter moves vertices by grid index, which would bend the inner faces.
Shape l_shape() {
  Shape s{"l_shape", testing::make_grid(6, 6, 4, [](int i, int j, int) { return i >= 3 && j >= 3 ? -1 : 1; }, 0.0),
          {},
          {}};
  const Point outline[6] = {{0, 0, 0}, {6, 0, 0}, {6, 3, 0}, {3, 3, 0}, {3, 6, 0}, {0, 6, 0}};
  for (int k = 0; k < 6; ++k) {
    const Point p = outline[k], q = outline[(k + 1) % 6];
    s.corners.push_back(p);
    s.corners.push_back({p[0], p[1], 4});
    s.lines.push_back({p, q});
    s.lines.push_back({{p[0], p[1], 4}, {q[0], q[1], 4}});
    s.lines.push_back({p, {p[0], p[1], 4}});
  }
  return s;
}

// A block of three materials whose interfaces nobody listed: x < 3 is material 1, the rest is
// material 2 below z = 2 and material 3 above. The box edges are sharp; where an interface meets
// the boundary the boundary faces change label (a seam, a curve already) and where the three
// materials meet runs a junction line; their ends on the box are corners.
Shape multi_material() {
  Shape s{"multi_material",
          testing::make_grid(6, 4, 4, [](int i, int, int k) { return i < 3 ? 1 : (k < 2 ? 2 : 3); }, 0.0),
          {},
          {}};
  add_box_features(s, {0, 0, 0}, {6, 4, 4});
  for (int y : {0, 4}) {
    s.corners.push_back({3, y, 0});
    s.corners.push_back({3, y, 4});
    s.corners.push_back({3, y, 2});
    s.corners.push_back({6, y, 2});
    s.lines.push_back({{3, y, 2}, {6, y, 2}});  // seam of the 2|3 interface on the boundary
    s.lines.push_back({{3, y, 0}, {3, y, 2}});  // seam of the 1|2 interface
    s.lines.push_back({{3, y, 2}, {3, y, 4}});  // seam of the 1|3 interface
  }
  for (int z : {0, 4}) {
    s.corners.push_back({3, 0, z});
    s.corners.push_back({3, 4, z});
    s.lines.push_back({{3, 0, z}, {3, 4, z}});
  }
  s.corners.push_back({6, 0, 2});
  s.corners.push_back({6, 4, 2});
  s.lines.push_back({{6, 0, 2}, {6, 4, 2}});
  s.lines.push_back({{3, 0, 2}, {3, 4, 2}});  // where the three materials meet
  // The box edges through the new corners are split there; the straight-chain check covers the
  // long edge and the corner check the points on it.
  return s;
}

std::map<std::int32_t, double> volume_by_material(const MeshData& d) {
  std::map<std::int32_t, double> out;
  for (std::size_t t = 0; t < d.tets.size(); ++t) {
    const auto& v = d.tets[t];
    const glm::dvec3 p0 = to_glm(d.positions[v[0]]);
    out[d.tet_material[t]] += std::fabs(glm::dot(to_glm(d.positions[v[1]]) - p0, glm::cross(to_glm(d.positions[v[2]]) - p0,
                                                                                              to_glm(d.positions[v[3]]) - p0))) / 6.0;
  }
  return out;
}

// Checks the output of one simplification of `shape`; returns the number of failures found (also
// reported through gtest when `expect`).
int check_features_kept(const Shape& shape, const MeshData& out, bool expect) {
  int failures = 0;
  std::set<std::array<double, 3>> positions;
  for (const auto& p : out.positions) positions.insert({p[0], p[1], p[2]});
  for (const Point& c : shape.corners) {
    if (positions.count({double(c[0]), double(c[1]), double(c[2])})) continue;
    ++failures;
    if (expect) ADD_FAILURE() << shape.name << ": corner (" << c[0] << ", " << c[1] << ", " << c[2] << ") moved";
  }
  std::set<std::pair<VertId, VertId>> edges;
  for (const auto& t : out.tets)
    for (const auto& e : kTetEdges) edges.insert(std::minmax(t[e[0]], t[e[1]]));
  for (const auto& [p, q] : shape.lines) {
    const glm::dvec3 a = at(p), b = at(q), ab = b - a;
    // The output vertices on segment pq, by their parameter along it.
    std::vector<std::pair<double, VertId>> on_line;
    for (VertId v = 0; v < out.positions.size(); ++v) {
      const glm::dvec3 d = to_glm(out.positions[v]) - a;
      const double t = glm::dot(d, ab) / glm::dot(ab, ab);
      if (t < -1e-12 || t > 1 + 1e-12 || glm::length(d - t * ab) > 1e-9) continue;
      on_line.push_back({t, v});
    }
    std::sort(on_line.begin(), on_line.end());
    bool ok = on_line.size() >= 2 && to_glm(out.positions[on_line.front().second]) == a &&
              to_glm(out.positions[on_line.back().second]) == b;
    for (std::size_t i = 0; ok && i + 1 < on_line.size(); ++i)
      ok = edges.count(std::minmax(on_line[i].second, on_line[i + 1].second)) != 0;
    if (ok) continue;
    ++failures;
    if (expect)
      ADD_FAILURE() << shape.name << ": the line (" << p[0] << "," << p[1] << "," << p[2] << ")-(" << q[0] << ","
                    << q[1] << "," << q[2] << ") is no longer a chain of edges";
  }
  const auto before = volume_by_material(shape.grid.data), after = volume_by_material(out);
  for (const auto& [m, v] : before) {
    const auto it = after.find(m);
    if (it != after.end() && std::fabs(it->second - v) <= 1e-9 * v) continue;
    ++failures;
    if (expect) ADD_FAILURE() << shape.name << ": material " << m << " volume " << v << " -> " << it->second;
  }
  return failures;
}

std::vector<Shape> shapes() { return {box(), listed_box(), l_shape(), multi_material()}; }

class FeaturesKept : public ::testing::TestWithParam<std::tuple<std::size_t, Engine>> {};

TEST_P(FeaturesKept, CornersStayAndSharpEdgesStayStraightChains) {
  const Shape shape = shapes()[std::get<0>(GetParam())];
  MeshModel mesh = build_mesh_model(shape.grid.data);
  SimplifyOptions options;  // the default feature angle
  options.engine = std::get<1>(GetParam());
  options.target_vertex_ratio = 0.1;
  const Report report = simplify(mesh, options);
  ASSERT_NE(report.status, Status::kInvalidInput) << report.message;
  EXPECT_GT(report.feature_edges, 0u);
  // Not vacuous: the mesh did shrink a lot.
  EXPECT_LT(report.vertices_after, report.vertices_before / 2) << shape.name;
  check_features_kept(shape, mesh.to_mesh_data(), /*expect=*/true);
  std::printf("[ features ] %-16s %s: %llu -> %llu vertices, %llu feature edges, %llu corners pinned\n", shape.name,
              options.engine == Engine::kSequential ? "sequential" : "parallel  ",
              (unsigned long long)report.vertices_before, (unsigned long long)report.vertices_after,
              (unsigned long long)report.feature_edges, (unsigned long long)report.feature_corners);
}

INSTANTIATE_TEST_SUITE_P(Shapes, FeaturesKept,
                         ::testing::Combine(::testing::Range<std::size_t>(0, 4),
                                            ::testing::Values(Engine::kSequential, Engine::kParallel)),
                         [](const ::testing::TestParamInfo<std::tuple<std::size_t, Engine>>& param) {
                           return std::string(shapes()[std::get<0>(param.param)].name) +
                                  (std::get<1>(param.param) == Engine::kSequential ? "_sequential" : "_parallel");
                         });

// The checks above can fail: a corner moved a little, or a box edge cut by a chamfer, is found.
TEST(Features, TheCheckFindsMovedCornersAndChamfers) {
  const Shape shape = box();
  EXPECT_EQ(check_features_kept(shape, shape.grid.data, /*expect=*/false), 0);
  MeshData moved = shape.grid.data;
  moved.positions[shape.grid.vid(7, 6, 5)][0] -= 0.1;  // a corner slides along an edge
  EXPECT_GT(check_features_kept(shape, moved, /*expect=*/false), 0);
  MeshData lost = shape.grid.data;
  lost.positions[shape.grid.vid(3, 0, 0)][1] += 0.05;
  lost.positions[shape.grid.vid(3, 0, 0)][2] += 0.05;  // an edge vertex leaves the edge
  EXPECT_GT(check_features_kept(shape, lost, /*expect=*/false), 0);
}

TEST(Features, DetectionFindsTheBoxEdgesAndCorners) {
  const Shape shape = box();  // 7 x 6 x 5 cubes: 4 * (7 + 6 + 5) grid edges on the box edges
  MeshModel mesh = build_mesh_model(shape.grid.data);
  const FeatureStats found = detect_features(mesh, 45.0);
  EXPECT_EQ(found.edges, 4u * (7 + 6 + 5));
  EXPECT_EQ(found.corners, 8u);
  for (const glm::ivec3 c : {glm::ivec3(0, 0, 0), glm::ivec3(7, 6, 5), glm::ivec3(7, 0, 5)})
    EXPECT_TRUE(mesh.is_pinned(shape.grid.vid(c.x, c.y, c.z)));
  EXPECT_FALSE(mesh.is_pinned(shape.grid.vid(3, 0, 0)));  // on an edge, not a corner
  // A second call finds nothing new: the edges are curves already.
  const FeatureStats again = detect_features(mesh, 45.0);
  EXPECT_EQ(again.edges, 0u);
  EXPECT_EQ(again.corners, 0u);
  // The features are not written back unless asked.
  EXPECT_TRUE(mesh.to_mesh_data().segments.empty());
  EXPECT_TRUE(mesh.to_mesh_data().corners.empty());
  MeshExportOptions with_features;
  with_features.feature_edges = true;
  with_features.feature_ref = 7;
  const MeshData d = mesh.to_mesh_data(with_features);
  EXPECT_EQ(d.segments.size(), 4u * (7 + 6 + 5));
  EXPECT_EQ(d.ridges.size(), d.segments.size());
  EXPECT_EQ(d.corners.size(), 8u);
  for (const Segment& s : d.segments) EXPECT_EQ(s.ref, 7);
}

TEST(Features, AngleThresholds) {
  // The box edges turn by 90 degrees: found below that, not above; 180 turns detection off.
  for (const auto& [angle, expected] : {std::pair{89.0, 4u * 18}, std::pair{91.0, 0u}, std::pair{180.0, 0u}}) {
    MeshModel mesh = build_mesh_model(box().grid.data);
    EXPECT_EQ(detect_features(mesh, angle).edges, expected) << angle;
  }
  SimplifyOptions bad;
  bad.feature_angle = 181.0;
  MeshModel mesh = build_mesh_model(box().grid.data);
  EXPECT_EQ(simplify(mesh, bad).status, Status::kInvalidInput);
}

TEST(Features, ListedPolylinesAreNotFeatures) {
  // A box edge listed as a polyline keeps its ref; detection adds the other eleven edges only.
  Shape shape = box();
  testing::add_polyline(shape.grid, testing::grid_line({0, 0, 0}, {7, 0, 0}), 5);
  MeshModel mesh = build_mesh_model(shape.grid.data);
  EXPECT_EQ(detect_features(mesh, 45.0).edges, 4u * 18 - 7);
  const MeshData d = mesh.to_mesh_data();
  EXPECT_EQ(d.segments.size(), 7u);
}

TEST(Features, ParallelOutputIsIdenticalForEveryThreadCount) {
  const Shape shape = multi_material();
  MeshData first;
  for (int threads : {1, 2, 3}) {
    MeshModel mesh = build_mesh_model(shape.grid.data);
    SimplifyOptions options;
    options.num_threads = threads;
    options.target_vertex_ratio = 0.1;
    simplify(mesh, options);
    MeshExportOptions with_features;
    with_features.feature_edges = true;
    const MeshData d = mesh.to_mesh_data(with_features);
    if (threads == 1)
      first = d;
    else
      EXPECT_TRUE(d == first) << threads << " threads";
  }
}

// Features at a scale (issue #23): a block of two materials whose interface is a staircase of
// steps 1 high and 6 deep (a ramp digitized on a grid, like a segmented image). Judged by the
// angle alone, every step is a feature and the ends of the steps are pinned; at a scale H = 2
// (steps lower than H) no step counts, while the block's own edges (8 and more long, 90 degrees)
// and its corners stay.
TEST(Features, StepsLowerThanTheScaleAreNotFeatures) {
  constexpr int kNx = 24, kNy = 8, kNz = 20;
  const testing::Grid grid =
      testing::make_grid(kNx, kNy, kNz, [](int i, int, int k) { return k < 8 + i / 6 ? 2 : 1; }, 0.0);
  const auto inside = [](const std::array<double, 3>& p) {
    return p[0] > 0.5 && p[0] < kNx - 0.5 && p[1] > 0.5 && p[1] < kNy - 0.5;
  };
  const auto step_edges = [&](const MeshData& d) {  // flagged edges off the box's sides
    std::size_t n = 0;
    for (const Segment& e : d.segments) n += inside(d.positions[e.v[0]]) && inside(d.positions[e.v[1]]);
    return n;
  };
  const auto step_corners = [&](const MeshData& d) {  // pinned vertices off the box's ends x = 0, 24
    std::size_t n = 0;
    for (const VertId c : d.corners) n += d.positions[c][0] > 0.5 && d.positions[c][0] < kNx - 0.5;
    return n;
  };
  MeshExportOptions with_features;
  with_features.feature_edges = true;
  {
    MeshModel mesh = build_mesh_model(grid.data);
    detect_features(mesh, 45.0, 0.0);
    const MeshData d = mesh.to_mesh_data(with_features);
    EXPECT_GT(step_edges(d), 0u);
    EXPECT_GT(step_corners(d), 0u);
  }
  MeshModel mesh = build_mesh_model(grid.data);
  const FeatureStats found = detect_features(mesh, 45.0, 2.0);
  EXPECT_GT(found.candidates, found.edges);
  const MeshData d = mesh.to_mesh_data(with_features);
  EXPECT_EQ(step_edges(d), 0u);
  EXPECT_EQ(step_corners(d), 0u);
  for (int x : {0, kNx})
    for (int y : {0, kNy})
      for (int z : {0, kNz}) EXPECT_TRUE(mesh.is_pinned(grid.vid(x, y, z))) << x << " " << y << " " << z;
  // The bottom edges are feature curves from end to end.
  std::set<std::pair<VertId, VertId>> flagged;
  for (const Segment& e : d.segments) flagged.insert(std::minmax(e.v[0], e.v[1]));
  for (int i = 0; i < kNx; ++i) {
    EXPECT_TRUE(flagged.count(std::minmax(grid.vid(i, 0, 0), grid.vid(i + 1, 0, 0)))) << i;
    EXPECT_TRUE(flagged.count(std::minmax(grid.vid(i, kNy, 0), grid.vid(i + 1, kNy, 0)))) << i;
  }
  // Same answer for every thread count.
  for (int threads : {1, 3}) {
    MeshModel again = build_mesh_model(grid.data);
    FeatureStats f;
    run_with_thread_limit(threads, [&] { f = detect_features(again, 45.0, 2.0); });
    EXPECT_EQ(f.edges, found.edges);
    EXPECT_TRUE(again.to_mesh_data(with_features) == d) << threads;
  }
}

// The default run judges features at its tolerance H (Report::feature_scale).
TEST(Features, SimplifyJudgesFeaturesAtTheTolerance) {
  MeshModel mesh = build_mesh_model(box().grid.data);
  SimplifyOptions options;
  options.target_vertex_ratio = 0.5;
  const Report report = simplify(mesh, options);
  EXPECT_EQ(report.feature_scale, report.tolerance);
  EXPECT_EQ(report.feature_edges, 4u * 18);
  EXPECT_EQ(report.feature_corners, 8u);
  options.tolerance_rel = 0.0;  // off: the default relative tolerance still sets the scale
  MeshModel again = build_mesh_model(box().grid.data);
  const Report off = simplify(again, options);
  EXPECT_EQ(off.tolerance, 0.0);
  EXPECT_DOUBLE_EQ(off.feature_scale, report.tolerance);
}

// The default tolerance (issue #12): on without any option, 0 turns it off, and a run it stops
// before the target says so.
TEST(Defaults, ToleranceIsOnAndARunItStopsSaysSo) {
  const MeshData input = generate_mesh({"cube-sphere", 8000, 1});
  {
    MeshModel mesh = build_mesh_model(input);
    SimplifyOptions options;
    EXPECT_EQ(options.tolerance_rel, kDefaultToleranceRel);
    EXPECT_GT(kDefaultToleranceRel, 0.0);
    EXPECT_LE(kDefaultToleranceRel, 0.005);  // the bound: at most 0.5% of the diagonal
    const Report report = simplify(mesh, options);
    EXPECT_GT(report.tolerance, 0.0);
  }
  {
    MeshModel mesh = build_mesh_model(input);
    SimplifyOptions options;
    options.tolerance_rel = 1e-5;  // far below the surfaces' own jitter: hardly anything on them moves
    options.relax_tolerance = false;  // held as given (relaxed runs: unit_relax_limits.cpp)
    options.target_vertex_ratio = 0.02;
    const Report report = simplify(mesh, options);
    EXPECT_EQ(report.status, Status::kStoppedEarly);
    EXPECT_TRUE(report.tolerance_limited);
    EXPECT_NE(report.message.find("tolerance"), std::string::npos) << report.message;
  }
  {
    MeshModel mesh = build_mesh_model(input);
    SimplifyOptions options;
    options.tolerance_rel = 0.0;
    options.target_vertex_ratio = 0.02;
    const Report report = simplify(mesh, options);
    EXPECT_EQ(report.tolerance, 0.0);
    EXPECT_FALSE(report.tolerance_limited);
  }
}

}  // namespace
}  // namespace topotet
