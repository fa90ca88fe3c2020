// The mesh model: building from MeshData, flags, incidence, export, and input validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "mesh/glm_convert.h"
#include "mesh/mesh_model.h"
#include "mesh/reorder.h"
#include "test_meshes.h"
#include "topotet/error.h"

namespace topotet {
namespace {

using testing::Grid;
using testing::make_grid;

std::string build_error(const MeshData& d) {
  try {
    build_mesh_model(d);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

MeshData one_tet() {
  MeshData d;
  d.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  d.tets = {{0, 1, 2, 3}};
  d.tet_material = {1};
  return d;
}

TEST(MeshModel, BuildsIncidenceAndCounts) {
  Grid g = make_grid(3, 2, 2, [](int, int, int) { return 1; });
  const MeshModel m = build_mesh_model(g.data);
  EXPECT_EQ(m.live_tet_count(), 3u * 2 * 2 * 6);
  EXPECT_EQ(m.live_vertex_count(), 4u * 3 * 3);
  for (VertId v = 0; v < m.positions.size(); ++v) {
    std::set<TetId> expected, got;
    for (TetId t = 0; t < m.tets.size(); ++t)
      if (std::count(m.tets[t].begin(), m.tets[t].end(), v)) expected.insert(t);
    m.for_each_tet_of(v, [&](TetId t) { got.insert(t); });
    EXPECT_EQ(got, expected) << "vertex " << v;
  }
}

TEST(MeshModel, MaterialInterfacesAreFlaggedButNotExported) {
  Grid g = make_grid(3, 3, 3, [](int i, int j, int k) { return i == 1 && j == 1 && k == 1 ? 2 : 1; });
  const MeshModel m = build_mesh_model(g.data);
  int flagged_faces = 0;
  for (TetId t = 0; t < m.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) flagged_faces += is_surface_face(m.flags[t], f);
  EXPECT_EQ(flagged_faces, 2 * 6 * 2);  // 6 squares x 2 triangles, each seen from both sides
  EXPECT_TRUE(m.to_mesh_data().triangles.empty());
}

TEST(MeshModel, ListedSubstructuresRoundTripThroughTheFlags) {
  Grid g = make_grid(4, 4, 4, [](int i, int, int) { return i < 2 ? 1 : 2; });
  testing::add_patch(g, 2, 2, [](int a, int b) { return a < 2 && b < 3; }, 7);
  testing::add_polyline(g, testing::grid_line({1, 1, 0}, {1, 1, 4}), 3);
  g.data.ridges = {0, 2};
  g.data.corners = {0};
  g.data.required_vertices = {5};
  testing::add_linear_field(g);
  const MeshModel m = build_mesh_model(g.data);
  const MeshData out = m.to_mesh_data();
  auto tri_set = [](const MeshData& d) {
    std::set<std::pair<std::array<VertId, 3>, int>> s;
    for (const Triangle& t : d.triangles) {
      auto k = t.v;
      std::sort(k.begin(), k.end());
      s.insert({k, t.ref});
    }
    return s;
  };
  auto seg_set = [](const MeshData& d) {
    std::set<std::tuple<VertId, VertId, int, bool>> s;
    for (std::size_t i = 0; i < d.segments.size(); ++i) {
      const Segment& e = d.segments[i];
      const bool ridge = std::count(d.ridges.begin(), d.ridges.end(), i) > 0;
      s.insert({std::min(e.v[0], e.v[1]), std::max(e.v[0], e.v[1]), e.ref, ridge});
    }
    return s;
  };
  EXPECT_EQ(tri_set(out), tri_set(g.data));
  EXPECT_EQ(seg_set(out), seg_set(g.data));
  EXPECT_EQ(out.corners, g.data.corners);
  EXPECT_EQ(out.required_vertices, g.data.required_vertices);
  EXPECT_EQ(out.fields, g.data.fields);
  EXPECT_EQ(out.positions, g.data.positions);
  EXPECT_EQ(out.tets, g.data.tets);
}

TEST(MeshModel, ModelStaysUnder64BytesPerTet) {
  Grid g = make_grid(20, 20, 20, [](int, int, int) { return 1; });
  testing::add_linear_field(g);
  const MeshModel m = build_mesh_model(g.data);
  const double bytes_per_tet = static_cast<double>(m.memory_bytes()) / m.tets.size();
  EXPECT_LT(bytes_per_tet, 64.0);
  RecordProperty("bytes_per_tet", std::to_string(bytes_per_tet));
}

TEST(MeshModel, ReorientsConsistentlyInvertedInput) {
  MeshData d = one_tet();
  std::swap(d.tets[0][0], d.tets[0][1]);
  const MeshModel m = build_mesh_model(d);
  EXPECT_EQ(m.live_tet_count(), 1u);
  BuildOptions strict;
  strict.reorient_inverted = false;
  EXPECT_THROW(build_mesh_model(d, strict), InputError);
}

TEST(TetMeshShouldFail, NaNCoordinate) {
  MeshData d = one_tet();
  d.positions[2][1] = std::nan("");
  EXPECT_NE(build_error(d).find("vertex 3: coordinate is not finite"), std::string::npos);
}

TEST(TetMeshShouldFail, IndexOutOfRange) {
  MeshData d = one_tet();
  d.tets[0][3] = 9;
  EXPECT_NE(build_error(d).find("tet 1: vertex index 10 out of range [1, 4]"), std::string::npos);
}

TEST(TetMeshShouldFail, RepeatedVertex) {
  MeshData d = one_tet();
  d.tets[0][3] = 0;
  EXPECT_NE(build_error(d).find("repeated vertex"), std::string::npos);
}

TEST(TetMeshShouldFail, ZeroVolume) {
  MeshData d = one_tet();
  d.positions[3] = {0.5, 0.5, 0};
  EXPECT_NE(build_error(d).find("zero or near-zero volume"), std::string::npos);
}

TEST(TetMeshShouldFail, MixedOrientation) {
  Grid g = make_grid(2, 1, 1, [](int, int, int) { return 1; });
  std::swap(g.data.tets[3][0], g.data.tets[3][1]);
  EXPECT_NE(build_error(g.data).find("tet 4: inverted"), std::string::npos);
}

TEST(TetMeshShouldFail, FaceSharedByThreeTets) {
  MeshData d = one_tet();
  d.positions.push_back({0.2, 0.2, -1});
  d.positions.push_back({0.3, 0.2, -2});
  d.tets.push_back({0, 2, 1, 4});
  d.tets.push_back({0, 2, 1, 5});
  d.tet_material = {1, 1, 1};
  EXPECT_NE(build_error(d).find("shared by 3 tets"), std::string::npos) << build_error(d);
}

TEST(TetMeshShouldFail, DuplicateTet) {
  MeshData d = one_tet();
  d.tets.push_back(d.tets[0]);
  d.tet_material.push_back(1);
  EXPECT_NE(build_error(d).find("tet 2 duplicates tet 1"), std::string::npos) << build_error(d);
}

TEST(TetMeshShouldFail, TriangleThatIsNotAFace) {
  Grid g = make_grid(2, 2, 2, [](int, int, int) { return 1; });
  g.data.triangles.push_back({{g.vid(0, 0, 0), g.vid(2, 0, 0), g.vid(0, 2, 0)}, 4});
  EXPECT_NE(build_error(g.data).find("triangle 1 (vertices"), std::string::npos);
  EXPECT_NE(build_error(g.data).find("is not a face of any tet"), std::string::npos);
}

TEST(TetMeshShouldFail, SegmentThatIsNotAnEdge) {
  Grid g = make_grid(2, 2, 2, [](int, int, int) { return 1; });
  g.data.segments.push_back({{g.vid(0, 0, 0), g.vid(2, 2, 2)}, 1});
  EXPECT_NE(build_error(g.data).find("is not an edge of any tet"), std::string::npos);
}

TEST(MeshModel, TriangleListedWithTwoRefsIsOnBothSurfaces) {
  Grid g = make_grid(2, 2, 2, [](int, int, int) { return 1; });
  testing::add_square(g, 2, 1, 0, 0, 3);
  testing::add_square(g, 2, 1, 0, 0, 4);
  const MeshData out = build_mesh_model(g.data).to_mesh_data();
  EXPECT_EQ(out.triangles.size(), 4u);
}

TEST(TetMeshShouldFail, FieldOfWrongSize) {
  MeshData d = one_tet();
  d.fields.push_back({"f", 1, {1.0, 2.0}});
  EXPECT_NE(build_error(d).find("field 'f' has 2 values for 4 vertices"), std::string::npos);
}

TEST(MeshModel, CompactDropsDeadElementsAndKeepsOrder) {
  Grid g = make_grid(2, 2, 2, [](int, int, int) { return 1; });
  MeshModel m = build_mesh_model(g.data);
  m.flags[0] |= tet_flag::kDead;
  m.flags[5] |= tet_flag::kDead;
  const auto t1 = m.tets[1];
  compact(m);
  EXPECT_EQ(m.tets.size(), g.data.tets.size() - 2);
  EXPECT_EQ(m.tets[0], t1);
}

// The mesh as sets of positions: tets (with material and orientation), listed triangles and
// segments (with refs), corners, and each vertex's field value. Independent of the numbering.
struct GeometricView {
  std::multiset<std::tuple<std::array<double, 12>, std::int32_t>> tets;
  std::multiset<std::tuple<std::array<double, 9>, std::int32_t>> triangles;
  std::multiset<std::tuple<std::array<double, 6>, std::int32_t>> segments;
  std::multiset<std::array<double, 3>> corners;
  std::multiset<std::array<double, 4>> field;
  bool operator==(const GeometricView&) const = default;
};

std::array<double, 3> at(const MeshData& d, VertId v) { return d.positions[v]; }

GeometricView view(const MeshData& d) {
  GeometricView g;
  for (std::size_t t = 0; t < d.tets.size(); ++t) {
    // Rotate the orientation-preserving way so the smallest position comes first.
    auto v = d.tets[t];
    const std::array<std::array<int, 4>, 4> even = {{{0, 1, 2, 3}, {1, 0, 3, 2}, {2, 3, 0, 1}, {3, 2, 1, 0}}};
    int first = 0;
    for (int k = 1; k < 4; ++k)
      if (at(d, v[k]) < at(d, v[first])) first = k;
    std::array<double, 12> key{};
    for (int k = 0; k < 4; ++k) {
      const auto p = at(d, v[even[first][k]]);
      std::copy(p.begin(), p.end(), key.begin() + 3 * k);
    }
    // The last three corners may still be cyclically rotated: take the smallest rotation.
    std::array<double, 12> best = key;
    for (int r = 1; r < 3; ++r) {
      std::array<double, 12> k2 = key;
      for (int c = 0; c < 3; ++c)
        for (int d3 = 0; d3 < 3; ++d3) k2[3 + 3 * c + d3] = key[3 + 3 * ((c + r) % 3) + d3];
      best = std::min(best, k2);
    }
    g.tets.insert({best, d.tet_material[t]});
  }
  for (const Triangle& tri : d.triangles) {
    std::array<std::array<double, 3>, 3> p = {at(d, tri.v[0]), at(d, tri.v[1]), at(d, tri.v[2])};
    std::sort(p.begin(), p.end());
    std::array<double, 9> key{};
    for (int k = 0; k < 3; ++k) std::copy(p[k].begin(), p[k].end(), key.begin() + 3 * k);
    g.triangles.insert({key, tri.ref});
  }
  for (const Segment& seg : d.segments) {
    std::array<std::array<double, 3>, 2> p = {at(d, seg.v[0]), at(d, seg.v[1])};
    std::sort(p.begin(), p.end());
    g.segments.insert({{p[0][0], p[0][1], p[0][2], p[1][0], p[1][1], p[1][2]}, seg.ref});
  }
  for (VertId c : d.corners) g.corners.insert(at(d, c));
  if (!d.fields.empty())
    for (VertId v = 0; v < d.positions.size(); ++v) {
      const auto p = at(d, v);
      g.field.insert({p[0], p[1], p[2], d.fields[0].values[v * d.fields[0].components]});
    }
  return g;
}

TEST(Reorder, KeepsEveryElementAndRenumbersAlongTheCurve) {
  const auto meshes = testing::planted_meshes();
  for (const auto& planted : meshes) {
    SCOPED_TRACE(planted.name);
    const testing::Grid g = planted.make();
    MeshModel m = build_mesh_model(g.data);
    const MeshData before = m.to_mesh_data();
    reorder_for_locality(m);
    EXPECT_TRUE(view(m.to_mesh_data()) == view(before));
    // Reordering is a pure function of the mesh: doing it again changes nothing.
    MeshModel again = m;
    reorder_for_locality(again);
    EXPECT_TRUE(again.to_mesh_data() == m.to_mesh_data());
  }
}

TEST(Reorder, DropsDeadElements) {
  const testing::Grid g = testing::make_grid(3, 3, 3, [](int, int, int) { return 1; });
  MeshModel m = build_mesh_model(g.data);
  const std::size_t tets = m.live_tet_count();
  // Kill one tet by hand (as a collapse would, with its vertices still used elsewhere).
  m.flags[0] = tet_flag::kDead;
  rebuild_incidence(m);
  reorder_for_locality(m);
  EXPECT_EQ(m.tets.size(), tets - 1);
  EXPECT_EQ(m.live_tet_count(), tets - 1);
}

}  // namespace
}  // namespace topotet
