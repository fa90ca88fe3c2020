// End-to-end simplification: both engines keep every Betti number, reach their target, and the
// parallel engine gives the same mesh for every thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <thread>

#include "entry_points.h"
#include "mesh/mesh_model.h"
#include "region_manifold.h"
#include "test_meshes.h"
#include "topotet/generate.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

struct Case {
  const char* planted;
  Engine engine;
};

class SimplifyPlanted : public ::testing::TestWithParam<std::tuple<std::size_t, Engine>> {};

TEST_P(SimplifyPlanted, KeepsTopologyAndReducesTheMesh) {
  const auto meshes = testing::planted_meshes();
  const auto& planted = meshes[std::get<0>(GetParam())];
  const testing::Grid g = planted.make();
  MeshModel mesh = build_mesh_model(g.data);
  const auto before = topotet::compute_topology(mesh.to_mesh_data());
  SimplifyOptions options;
  options.engine = std::get<1>(GetParam());
  options.target_vertex_ratio = 0.2;
  const Report report = simplify(mesh, options);
  ASSERT_NE(report.status, Status::kInvalidInput) << report.message;
  ASSERT_NE(report.status, Status::kOutOfMemory);
  std::string differences;
  EXPECT_TRUE(topotet::same_topology(before, topotet::compute_topology(mesh.to_mesh_data()), &differences))
      << differences;
  EXPECT_LT(report.vertices_after, report.vertices_before * 6 / 10) << planted.name;
  EXPECT_EQ(report.vertices_after, mesh.live_vertex_count());
  EXPECT_EQ(report.vertices_before - report.vertices_after, report.collapses);
  std::printf("[ simplify ] %-45s %s: %llu -> %llu vertices, %llu -> %llu tets, status %s\n", planted.name,
              options.engine == Engine::kSequential ? "sequential" : "parallel  ",
              (unsigned long long)report.vertices_before, (unsigned long long)report.vertices_after,
              (unsigned long long)report.tets_before, (unsigned long long)report.tets_after, to_string(report.status));
}

INSTANTIATE_TEST_SUITE_P(Planted, SimplifyPlanted,
                         ::testing::Combine(::testing::Range<std::size_t>(0, testing::planted_meshes().size()),
                                            ::testing::Values(Engine::kSequential, Engine::kParallel)),
                         [](const ::testing::TestParamInfo<std::tuple<std::size_t, Engine>>& param) {
                           return std::string(testing::planted_meshes()[std::get<0>(param.param)].name) +
                                  (std::get<1>(param.param) == Engine::kSequential ? "_sequential" : "_parallel");
                         });

TEST(Simplify, ParallelOutputIsIdenticalForEveryThreadCount) {
  testing::Grid g = testing::make_grid(14, 12, 10, [](int i, int j, int k) {
    const double dx = i - 7, dy = j - 6, dz = k - 5;
    return dx * dx + dy * dy + dz * dz < 12 ? 2 : 1;
  });
  testing::add_polyline(g, testing::grid_line({1, 6, 5}, {13, 6, 5}), 3);
  testing::add_linear_field(g);
  const MeshModel input = build_mesh_model(g.data);
  MeshData reference;
  for (int threads : {1, 2, 3, 4, 8}) {
    MeshModel mesh = input;
    SimplifyOptions options;
    options.num_threads = threads;
    options.target_vertex_ratio = 0.15;
    const Report report = simplify(mesh, options);
    ASSERT_TRUE(report.status == Status::kOk || report.status == Status::kStoppedEarly) << report.message;
    const MeshData out = mesh.to_mesh_data();
    if (threads == 1)
      reference = out;
    else
      EXPECT_TRUE(out == reference) << "threads = " << threads << " differs from threads = 1";
  }
}

// The same mesh numbered another way (vertices and tets shuffled): simplify() renumbers along a
// space-filling curve first, so the simplified meshes are the same up to numbering.
TEST(Simplify, OutputDoesNotDependOnTheInputNumbering) {
  testing::Grid g = testing::make_grid(10, 9, 8, [](int i, int j, int k) {
    const double dx = i - 5, dy = j - 4.5, dz = k - 4;
    return dx * dx + dy * dy + dz * dz < 9 ? 2 : 1;
  });
  testing::add_polyline(g, testing::grid_line({1, 4, 4}, {9, 4, 4}), 3);
  testing::add_box_boundary(g, 10);
  testing::add_linear_field(g);
  MeshData shuffled = g.data;
  std::vector<VertId> perm(shuffled.positions.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::mt19937 rng(5);
  std::shuffle(perm.begin(), perm.end(), rng);  // old id -> new id
  for (VertId v = 0; v < perm.size(); ++v) shuffled.positions[perm[v]] = g.data.positions[v];
  for (auto& f : shuffled.fields)
    for (VertId v = 0; v < perm.size(); ++v) f.values[perm[v]] = g.data.fields[0].values[v];
  for (auto& t : shuffled.tets)
    for (VertId& x : t) x = perm[x];
  for (auto& tri : shuffled.triangles)
    for (VertId& x : tri.v) x = perm[x];
  for (auto& seg : shuffled.segments)
    for (VertId& x : seg.v) x = perm[x];
  std::vector<std::size_t> order(shuffled.tets.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  MeshData reordered = shuffled;
  for (std::size_t i = 0; i < order.size(); ++i) {
    reordered.tets[i] = shuffled.tets[order[i]];
    reordered.tet_material[i] = shuffled.tet_material[order[i]];
  }
  std::vector<MeshData> outputs;
  for (const MeshData* input : {&g.data, &reordered}) {
    MeshModel mesh = build_mesh_model(*input);
    SimplifyOptions options;
    options.target_vertex_ratio = 0.2;
    ASSERT_EQ(simplify(mesh, options).status, Status::kOk);
    outputs.push_back(mesh.to_mesh_data());
  }
  ASSERT_EQ(outputs[0].positions.size(), outputs[1].positions.size());
  // Same numbering after simplification: the renumbering depends on positions only.
  EXPECT_TRUE(outputs[0] == outputs[1]);
}

// The slab family's box and its layer interfaces are flat: the optimum placement, which curved
// surfaces may take, would move their vertices off the plane by ~1e-5 (its tet and field terms), so
// a flat face must keep every vertex exactly on its plane through the whole run (cost.h, the
// placement rules). Checked on the box: every vertex of a boundary face of the output has a
// coordinate exactly equal to the box's bound on that side.
TEST(Simplify, FlatFacesKeepTheirVerticesExactlyOnTheirPlane) {
  MeshModel mesh = build_mesh_model(generate_mesh({"slab", 20000, 3}));
  std::array<double, 3> lo{}, hi{};
  for (int c = 0; c < 3; ++c) {
    lo[c] = hi[c] = mesh.positions[0][c];
    for (const auto& p : mesh.positions) lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
  }
  SimplifyOptions options;  // the defaults: tolerance, features
  options.target_vertex_ratio = 0.1;
  const Report report = simplify(mesh, options);
  ASSERT_EQ(report.status, Status::kOk) << report.message;
  const MeshData out = mesh.to_mesh_data();
  std::map<std::array<VertId, 3>, int> faces;
  for (const auto& t : out.tets)
    for (int f = 0; f < 4; ++f) {
      std::array<VertId, 3> face{t[(f + 1) % 4], t[(f + 2) % 4], t[(f + 3) % 4]};
      std::sort(face.begin(), face.end());
      ++faces[face];
    }
  std::size_t boundary_vertices = 0, off_plane = 0;
  std::vector<std::uint8_t> seen(out.positions.size(), 0);
  for (const auto& [face, count] : faces) {
    if (count != 1) continue;
    for (VertId v : face) {
      if (seen[v]++) continue;
      ++boundary_vertices;
      const auto& p = out.positions[v];
      bool on_a_plane = false;
      for (int c = 0; c < 3; ++c) on_a_plane = on_a_plane || p[c] == lo[c] || p[c] == hi[c];
      off_plane += on_a_plane ? 0 : 1;
    }
  }
  EXPECT_GT(boundary_vertices, 100u);
  EXPECT_EQ(off_plane, 0u) << "of " << boundary_vertices << " boundary vertices";
}

// The end game: with very few proposals left the round threshold becomes infinite (everything
// competes); vertices without a proposal must still stay out. Many small materials stop the run
// early with few proposals left (a crash here once).
TEST(Simplify, EndGameWithFewProposalsLeft) {
  testing::Grid g = testing::make_grid(9, 9, 9, [](int i, int j, int k) { return 1 + i / 3 + 3 * (j / 3) + 9 * (k / 3); });
  testing::add_linear_field(g);
  for (Engine engine : {Engine::kSequential, Engine::kParallel}) {
    MeshModel mesh = build_mesh_model(g.data);
    const auto before = topotet::compute_topology(mesh.to_mesh_data());
    SimplifyOptions options;
    options.engine = engine;
    options.target_vertices = 4;  // unreachable: the run goes until no legal collapse is left
    const Report report = simplify(mesh, options);
    EXPECT_EQ(report.status, Status::kStoppedEarly) << report.message;
    std::string differences;
    EXPECT_TRUE(topotet::same_topology(before, topotet::compute_topology(mesh.to_mesh_data()), &differences))
        << differences;
    EXPECT_LT(report.vertices_after, report.vertices_before / 2);
  }
}

TEST(Simplify, InvalidOptionsAreReportedNotThrown) {
  testing::Grid g = testing::make_grid(3, 3, 3, [](int, int, int) { return 1; });
  MeshModel mesh = build_mesh_model(g.data);
  const std::size_t tets = mesh.live_tet_count();
  SimplifyOptions options;
  options.target_vertex_ratio = 1.5;
  const Report report = simplify(mesh, options);
  EXPECT_EQ(report.status, Status::kInvalidInput);
  EXPECT_NE(report.message.find("target_vertex_ratio"), std::string::npos);
  EXPECT_EQ(mesh.live_tet_count(), tets);
}

// Many materials: a polycrystal (topotet/generate.h) of 20 cells meeting along triple junction
// curves and at quadruple points, with listed interfaces, junction polylines and pinned junction
// ends. Both engines keep every complex, and every cell stays a 3-manifold region (Betti numbers
// alone would miss a pinch; region_manifold.h).
TEST(Simplify, PolycrystalKeepsEveryCellAndJunction) {
  const MeshData input = generate_mesh({"polycrystal", 30000, 1, 20});
  const topotet::TopologyReport before = topotet::compute_topology(input);
  for (Engine engine : {Engine::kSequential, Engine::kParallel}) {
    MeshModel mesh = build_mesh_model(input);
    SimplifyOptions options;
    options.engine = engine;
    options.target_vertex_ratio = 0.2;
    // The cells are unions of grid tets: their faces are staircases whose every step is a sharp
    // edge at the default feature angle, and whose steps are larger than the default tolerance.
    // This test is about the topology of cells and junctions under heavy simplification.
    options.feature_angle = 180.0;
    options.tolerance_rel = 0.0;
    const Report report = simplify(mesh, options);
    ASSERT_TRUE(report.status == Status::kOk || report.status == Status::kStoppedEarly) << report.message;
    const MeshData output = mesh.to_mesh_data();
    std::string differences;
    EXPECT_TRUE(topotet::same_topology(before, topotet::compute_topology(output), &differences)) << differences;
    EXPECT_EQ(testing::count_nonmanifold_region_vertices(output), 0u);
    EXPECT_LE(report.vertices_after, report.vertices_before / 5 + 1);
    std::printf("[ simplify ] polycrystal 30k, 20 cells %s: %llu -> %llu vertices, status %s\n",
                engine == Engine::kSequential ? "sequential" : "parallel  ",
                (unsigned long long)report.vertices_before, (unsigned long long)report.vertices_after,
                to_string(report.status));
  }
}

// The size term (SimplifyOptions::size_weight; engine/cost/cost.h): a flat boundary layer of thin
// tets (4 layers of 1/4, under 8 layers of 1) whose field, a boundary layer exp(-z / 0.5), is
// steep there. Ranked by the error alone the thin layer is where collapses cost most, so it stays
// dense over a coarse interior; with the size term its short edges go first and the sizes even
// out. Both runs keep the topology, and the run with the term is the same for 1 and 2 threads.
TEST(SizeTerm, CoarsensAFineLayerTheErrorAloneKeeps) {
  testing::Grid g = testing::make_grid(10, 10, 12, [](int, int, int) { return 1; });
  const auto layer_z = [](double z) { return z <= 4.0 ? 0.25 * z : z - 3.0; };  // monotone
  VertexField f{"f", 1, {}};
  for (auto& p : g.data.positions) {
    p[2] = layer_z(p[2]);
    f.values.push_back(std::exp(-p[2] / 0.5));
  }
  g.data.fields.push_back(std::move(f));
  const auto before = topotet::compute_topology(g.data);
  const auto run = [&](double size_weight, int threads) {
    MeshModel mesh = build_mesh_model(g.data);
    SimplifyOptions options;
    options.target_vertex_ratio = 0.3;
    options.size_weight = size_weight;
    options.num_threads = threads;
    const Report report = simplify(mesh, options);
    EXPECT_EQ(report.status, Status::kOk) << report.message;
    return mesh.to_mesh_data();
  };
  // Vertices left inside the thin layer (below z = 1, the boundary plane z = 0 included).
  const auto in_layer = [](const MeshData& m) {
    return std::count_if(m.positions.begin(), m.positions.end(), [](const auto& p) { return p[2] < 0.999; });
  };
  const MeshData error_only = run(0.0, 2), even = run(1e-3, 2), even_1 = run(1e-3, 1);
  const auto layer_error_only = in_layer(error_only), layer_even = in_layer(even);
  std::printf("[ size term ] vertices below z = 1: input %td, error only %td, size weight 1e-3 %td (of %zu / %zu left)\n",
              in_layer(g.data), layer_error_only, layer_even, error_only.positions.size(), even.positions.size());
  EXPECT_LT(layer_even * 10, layer_error_only * 7) << "the thin layer kept its vertices with the size term";
  EXPECT_TRUE(even == even_1) << "the size term's output differs between 1 and 2 threads";
  for (const MeshData* out : {&error_only, &even}) {
    std::string differences;
    EXPECT_TRUE(topotet::same_topology(before, topotet::compute_topology(*out), &differences)) << differences;
  }
}

// size_weight's default, auto: the size term where only the geometry steers the cost, the error
// alone where a field does (SimplifyOptions::size_weight says why).
TEST(SizeTerm, AutoIsOnWithoutFieldsAndOffWithThem) {
  testing::Grid g = testing::make_grid(8, 8, 8, [](int i, int j, int k) {
    const double dx = i - 4, dy = j - 4, dz = k - 4;
    return dx * dx + dy * dy + dz * dz < 7 ? 2 : 1;
  }, 0.12, 7);  // jittered: on a regular grid the interior's costs are the length term alone, ranked alike by any weight
  const auto run = [](const MeshData& input, double size_weight) {
    MeshModel mesh = build_mesh_model(input);
    SimplifyOptions options;
    options.target_vertex_ratio = 0.2;
    options.size_weight = size_weight;
    const Report report = simplify(mesh, options);
    EXPECT_TRUE(report.status == Status::kOk || report.status == Status::kStoppedEarly) << to_string(report.status);
    return mesh.to_mesh_data();
  };
  ASSERT_LT(SimplifyOptions{}.size_weight, 0.0);
  EXPECT_TRUE(run(g.data, kSizeWeightAuto) == run(g.data, kAutoSizeWeight));
  EXPECT_FALSE(run(g.data, kSizeWeightAuto) == run(g.data, 0.0)) << "the size term changed nothing here";
  testing::add_linear_field(g);
  for (auto& p : g.data.fields[0].values) p = p * p;  // a curved field: the error steers
  EXPECT_TRUE(run(g.data, kSizeWeightAuto) == run(g.data, 0.0));
}

TEST(Simplify, ProgressCanCancel) {
  testing::Grid g = testing::make_grid(12, 12, 12, [](int, int, int) { return 1; });
  for (Engine engine : {Engine::kSequential, Engine::kParallel}) {
    MeshModel mesh = build_mesh_model(g.data);
    SimplifyOptions options;
    options.engine = engine;
    options.target_vertex_ratio = 0.05;
    int calls = 0;
    options.on_progress = [&](double) { return ++calls < 2; };
    const Report report = simplify(mesh, options);
    EXPECT_EQ(report.status, Status::kCancelled);
    EXPECT_GT(report.collapses, 0u);
    EXPECT_EQ(mesh.live_vertex_count(), report.vertices_after);
  }
}

}  // namespace
}  // namespace topotet
