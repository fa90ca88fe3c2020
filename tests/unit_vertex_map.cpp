// The input -> output vertex map of simplify(): total, onto the live output vertices, the same for
// every thread count, and each entry is the vertex the input vertex really merged into.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "mesh/glm_convert.h"
#include "entry_points.h"
#include "mesh/mesh_model.h"
#include "test_meshes.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

MeshData ball_in_box() {
  testing::Grid g = testing::make_grid(12, 10, 9, [](int i, int j, int k) {
    const double dx = i - 6, dy = j - 5, dz = k - 4.5;
    return dx * dx + dy * dy + dz * dz < 10 ? 2 : 1;
  });
  testing::add_polyline(g, testing::grid_line({1, 5, 4}, {11, 5, 4}), 3);
  testing::add_linear_field(g);
  g.data.corners = {0};  // a pinned vertex: it never moves, so it maps to itself exactly
  return g.data;
}

struct Mapped {
  MeshData output;
  std::vector<VertId> map;
  Report report;
};

Mapped simplify_with_map(const MeshData& input, Engine engine, int threads, double ratio,
                         Optimize optimize = SimplifyOptions{}.optimize) {
  MeshModel mesh = build_mesh_model(input);
  SimplifyOptions options;
  options.optimize = optimize;
  options.engine = engine;
  options.num_threads = threads;
  options.target_vertex_ratio = ratio;
  Mapped m;
  m.report = simplify(mesh, options, m.map);
  m.output = mesh.to_mesh_data();
  return m;
}

class VertexMap : public ::testing::TestWithParam<Engine> {};

TEST_P(VertexMap, IsTotalAndOnto) {
  const MeshData input = ball_in_box();
  const Mapped m = simplify_with_map(input, GetParam(), 2, 0.2);
  ASSERT_TRUE(m.report.status == Status::kOk || m.report.status == Status::kStoppedEarly) << m.report.message;
  ASSERT_LT(m.output.vertex_count(), input.vertex_count() / 2);
  ASSERT_EQ(m.map.size(), input.vertex_count());
  std::vector<int> preimages(m.output.vertex_count(), 0);
  for (std::size_t i = 0; i < m.map.size(); ++i) {
    ASSERT_LT(m.map[i], m.output.vertex_count()) << "input vertex " << i;
    ++preimages[m.map[i]];
  }
  // Every output vertex is an input vertex that survived: it is its own image at least.
  for (std::size_t o = 0; o < preimages.size(); ++o) EXPECT_GE(preimages[o], 1) << "output vertex " << o;
  // The number of merged vertices is the number of collapses.
  EXPECT_EQ(input.vertex_count() - m.output.vertex_count(), m.report.collapses);
  // The pinned corner keeps its position: its image is where it was.
  EXPECT_EQ(m.output.positions[m.map[0]], input.positions[0]);
}

// Collapses only rename vertices: a tet survives iff its four vertices keep four distinct images,
// and then it is that tet renamed. So the output tets are exactly the input tets mapped through
// the vertex map, less those whose images repeat a vertex (with their materials): a wrong entry
// anywhere in a chain of merges would show up here.
// Without the optimisation: its flips make tets that are no input tet renamed (it moves no vertex
// from one id to another, so the map is the same with it: checked here too).
TEST_P(VertexMap, OutputTetsAreTheInputTetsRenamedThroughTheMap) {
  const MeshData input = ball_in_box();
  const Mapped m = simplify_with_map(input, GetParam(), 2, 0.2, Optimize::kNone);
  EXPECT_EQ(simplify_with_map(input, GetParam(), 2, 0.2).map, m.map);
  ASSERT_TRUE(m.report.status == Status::kOk || m.report.status == Status::kStoppedEarly) << m.report.message;
  using Key = std::pair<std::array<VertId, 4>, std::int32_t>;
  std::vector<Key> renamed, output;
  for (std::size_t t = 0; t < input.tet_count(); ++t) {
    std::array<VertId, 4> v;
    for (int k = 0; k < 4; ++k) v[k] = m.map[input.tets[t][k]];
    std::sort(v.begin(), v.end());
    if (std::adjacent_find(v.begin(), v.end()) == v.end()) renamed.push_back({v, input.tet_material[t]});
  }
  for (std::size_t t = 0; t < m.output.tet_count(); ++t) {
    std::array<VertId, 4> v = m.output.tets[t];
    std::sort(v.begin(), v.end());
    output.push_back({v, m.output.tet_material[t]});
  }
  std::sort(renamed.begin(), renamed.end());
  std::sort(output.begin(), output.end());
  EXPECT_EQ(renamed.size(), output.size());
  EXPECT_TRUE(renamed == output);
}

TEST_P(VertexMap, IsTheSameForEveryThreadCount) {
  const MeshData input = ball_in_box();
  const Mapped one = simplify_with_map(input, GetParam(), 1, 0.2);
  for (int threads : {2, 4}) {
    const Mapped other = simplify_with_map(input, GetParam(), threads, 0.2);
    EXPECT_TRUE(other.map == one.map) << "threads = " << threads;
  }
}

// One collapse: exactly two adjacent input vertices share an image, every other input vertex maps
// to an output vertex at its own position, and the merged pair's image is one of the two (the one
// kept, at its new place): the map names the vertex the collapse merged into.
TEST_P(VertexMap, OneCollapseMergesExactlyOneEdge) {
  const MeshData input = ball_in_box();
  MeshModel mesh = build_mesh_model(input);
  SimplifyOptions options;
  options.engine = GetParam();
  options.target_vertices = input.vertex_count() - 1;
  std::vector<VertId> map;
  const Report report = simplify(mesh, options, map);
  ASSERT_EQ(report.collapses, 1u) << report.message;
  const MeshData out = mesh.to_mesh_data();
  ASSERT_EQ(out.vertex_count(), input.vertex_count() - 1);
  std::vector<std::vector<VertId>> preimages(out.vertex_count());
  for (VertId i = 0; i < map.size(); ++i) preimages[map[i]].push_back(i);
  int merged = 0;
  for (std::size_t o = 0; o < preimages.size(); ++o) {
    ASSERT_FALSE(preimages[o].empty());
    if (preimages[o].size() == 1) {
      EXPECT_EQ(out.positions[o], input.positions[preimages[o][0]]) << "output vertex " << o;
      continue;
    }
    ASSERT_EQ(preimages[o].size(), 2u);
    ++merged;
    const VertId a = preimages[o][0], b = preimages[o][1];
    EXPECT_TRUE(std::any_of(input.tets.begin(), input.tets.end(), [&](const std::array<VertId, 4>& t) {
      return std::count(t.begin(), t.end(), a) == 1 && std::count(t.begin(), t.end(), b) == 1;
    })) << "merged vertices " << a << " and " << b << " share no tet";
  }
  EXPECT_EQ(merged, 1);
}

// Frozen vertices (vertex_state::kFrozen, what mpi/ gives the vertices a rank shares): no collapse
// touches them, neither as the removed end nor as the end that stays. So each is alone in its
// preimage and keeps its position, while the rest of the mesh is still simplified.
TEST_P(VertexMap, FrozenVerticesAreNeitherRemovedNorKept) {
  const MeshData input = ball_in_box();
  MeshModel mesh = build_mesh_model(input);
  std::vector<bool> frozen(input.vertex_count());
  for (VertId v = 0; v < input.vertex_count(); ++v) {
    frozen[v] = input.positions[v][0] < 0.45 * input.positions[input.vertex_count() - 1][0];
    if (frozen[v]) mesh.vertex_states[v] |= vertex_state::kFrozen | vertex_state::kPinned;
  }
  SimplifyOptions options;
  options.engine = GetParam();
  options.num_threads = 2;
  options.target_vertex_ratio = 0.2;
  std::vector<VertId> map;
  const Report report = simplify(mesh, options, map);
  ASSERT_TRUE(report.status == Status::kOk || report.status == Status::kStoppedEarly) << report.message;
  EXPECT_GT(report.collapses, input.vertex_count() / 4);
  const MeshData out = mesh.to_mesh_data();
  std::vector<int> preimages(out.vertex_count(), 0);
  for (VertId i = 0; i < map.size(); ++i) ++preimages[map[i]];
  for (VertId v = 0; v < input.vertex_count(); ++v) {
    if (!frozen[v]) continue;
    EXPECT_EQ(preimages[map[v]], 1) << "frozen vertex " << v << " took part in a collapse";
    EXPECT_EQ(out.positions[map[v]], input.positions[v]) << "frozen vertex " << v << " moved";
  }
}

INSTANTIATE_TEST_SUITE_P(Engines, VertexMap, ::testing::Values(Engine::kSequential, Engine::kParallel),
                         [](const ::testing::TestParamInfo<Engine>& p) {
                           return p.param == Engine::kSequential ? "sequential" : "parallel";
                         });

TEST(VertexMapInvalidOptions, IsTheIdentity) {
  const MeshData input = ball_in_box();
  MeshModel mesh = build_mesh_model(input);
  SimplifyOptions options;
  options.target_vertex_ratio = 2.0;
  std::vector<VertId> map;
  ASSERT_EQ(simplify(mesh, options, map).status, Status::kInvalidInput);
  ASSERT_EQ(map.size(), input.vertex_count());
  for (VertId i = 0; i < map.size(); ++i) EXPECT_EQ(map[i], i);
}

}  // namespace
}  // namespace topotet
