// Listed triangles and segments as meshers write them: a face on several surfaces (each with its
// own ref), the same face listed twice with the same ref, and listed elements that are no tet's
// face or edge (Gmsh -save_all writes all three).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>

#include "entry_points.h"
#include "mesh/mesh_model.h"
#include "test_meshes.h"
#include "topotet/error.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

using testing::Grid;
using testing::make_grid;

std::map<std::int32_t, std::size_t> count_by_ref(const std::vector<Triangle>& triangles) {
  std::map<std::int32_t, std::size_t> out;
  for (const Triangle& t : triangles) ++out[t.ref];
  return out;
}

// A 6x6x6 box whose middle plane x = 3 is surface 3 (the whole plane) and whose central 2x2
// squares of that plane are also surface 4: 8 faces carry both refs. Surface 4 is a disc inside
// the disc of surface 3; their seam is a closed curve.
Grid nested_surfaces() {
  Grid g = make_grid(6, 6, 6, [](int, int, int) { return 1; });
  testing::add_patch(g, 0, 3, [](int, int) { return true; }, 3);
  testing::add_patch(g, 0, 3, [](int a, int b) { return a >= 2 && a < 4 && b >= 2 && b < 4; }, 4);
  return g;
}

TEST(ListedSubstructures, FaceOnTwoSurfacesKeepsBothRefs) {
  const Grid g = nested_surfaces();
  BuildNotes notes;
  const MeshModel m = build_mesh_model(g.data, {}, &notes);
  EXPECT_TRUE(notes.empty());
  ASSERT_EQ(m.shared_face_refs.size(), 1u);
  EXPECT_EQ(m.shared_face_refs[0].refs, (std::vector<std::int32_t>{3, 4}));
  EXPECT_GE(m.shared_face_refs[0].stand_in, kFirstStandInRef);
  const MeshData out = m.to_mesh_data();
  const auto counts = count_by_ref(out.triangles);
  EXPECT_EQ(counts.at(3), 6u * 6 * 2);
  EXPECT_EQ(counts.at(4), 2u * 2 * 2);
  EXPECT_EQ(counts.size(), 2u) << "the stand-in ref must never reach the output";
  // Rebuilding the output gives the same model (same stand-in, same flags).
  const MeshModel again = build_mesh_model(out);
  EXPECT_EQ(again.shared_face_refs, m.shared_face_refs);
  EXPECT_EQ(again.flags, m.flags);
}

TEST(ListedSubstructures, StandInAvoidsEveryListedRef) {
  Grid g = make_grid(2, 2, 2, [](int, int, int) { return 1; });
  testing::add_square(g, 0, 1, 0, 0, kFirstStandInRef);  // a file may use any int
  testing::add_square(g, 0, 1, 0, 0, kFirstStandInRef + 1);
  testing::add_square(g, 0, 1, 1, 1, kFirstStandInRef + 2);
  const MeshModel m = build_mesh_model(g.data);
  ASSERT_EQ(m.shared_face_refs.size(), 1u);
  EXPECT_EQ(m.shared_face_refs[0].stand_in, kFirstStandInRef + 3);
}

TEST(ListedSubstructures, EdgeOnTwoPolylinesKeepsBothRefs) {
  Grid g = make_grid(3, 3, 3, [](int, int, int) { return 1; });
  testing::add_polyline(g, testing::grid_line({0, 1, 1}, {3, 1, 1}), 7);
  testing::add_polyline(g, testing::grid_line({1, 1, 1}, {2, 1, 1}), 8);
  g.data.ridges.push_back(static_cast<std::uint32_t>(g.data.segments.size() - 1));  // the shared edge, as a ridge
  const MeshModel m = build_mesh_model(g.data);
  ASSERT_EQ(m.shared_edge_refs.size(), 1u);
  const MeshData out = m.to_mesh_data();
  EXPECT_EQ(out.segments.size(), 4u);
  EXPECT_EQ(out.ridges.size(), 2u) << "both listings of the ridge edge are ridges";
}

TEST(ListedSubstructures, RepeatedFaceWithSameRefIsKeptOnceAndNoted) {
  Grid g = make_grid(2, 2, 2, [](int, int, int) { return 1; });
  testing::add_square(g, 2, 1, 0, 0, 3);
  testing::add_square(g, 2, 1, 0, 0, 3);
  BuildNotes notes;
  const MeshModel m = build_mesh_model(g.data, {}, &notes);
  EXPECT_EQ(notes.repeated_triangles, (std::vector<std::uint32_t>{2, 3}));
  EXPECT_TRUE(m.shared_face_refs.empty());
  EXPECT_EQ(m.to_mesh_data().triangles.size(), 2u);
  MeshData cleaned = g.data;
  drop_noted_substructures(cleaned, notes);
  EXPECT_EQ(cleaned.triangles.size(), 2u);
}

TEST(ListedSubstructures, DetachedTriangleIsAnErrorByDefault) {
  Grid g = make_grid(2, 2, 2, [](int, int, int) { return 1; });
  testing::add_square(g, 2, 1, 0, 0, 3);
  g.data.triangles.push_back({{g.vid(0, 0, 0), g.vid(2, 0, 0), g.vid(0, 2, 0)}, 4});
  try {
    build_mesh_model(g.data);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("triangle 3 (vertices"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is not a face of any tet"), std::string::npos) << e.what();
  }
}

TEST(ListedSubstructures, DetachedElementsAreLeftOutWhenAsked) {
  Grid g = make_grid(2, 2, 2, [](int, int, int) { return 1; });
  g.data.triangles.push_back({{g.vid(0, 0, 0), g.vid(2, 0, 0), g.vid(0, 2, 0)}, 4});  // not a face
  testing::add_square(g, 2, 1, 0, 0, 3);
  g.data.segments.push_back({{g.vid(0, 0, 0), g.vid(2, 2, 2)}, 1});  // not an edge
  g.data.segments.push_back({{g.vid(0, 0, 0), g.vid(1, 0, 0)}, 2});
  g.data.ridges = {0, 1};
  BuildOptions options;
  options.skip_detached_substructures = true;
  BuildNotes notes;
  const MeshModel m = build_mesh_model(g.data, options, &notes);
  EXPECT_EQ(notes.detached_triangles, (std::vector<std::uint32_t>{0}));
  EXPECT_EQ(notes.detached_segments, (std::vector<std::uint32_t>{0}));
  const MeshData out = m.to_mesh_data();
  EXPECT_EQ(out.triangles.size(), 2u);
  EXPECT_EQ(out.segments.size(), 1u);
  MeshData cleaned = g.data;
  drop_noted_substructures(cleaned, notes);
  EXPECT_EQ(cleaned.triangles.size(), 2u);
  ASSERT_EQ(cleaned.segments.size(), 1u);
  EXPECT_EQ(cleaned.segments[0].ref, 2);
  EXPECT_EQ(cleaned.ridges, (std::vector<std::uint32_t>{0}));
}

// The checker sees each surface on its own (a face listed under two refs counts for both), so a
// change to either surface's topology would show.
TEST(ListedSubstructures, CheckerCountsASharedFaceForEachSurface) {
  const Grid g = nested_surfaces();
  const topotet::TopologyReport report = topotet::compute_topology(g.data);
  ASSERT_EQ(report.surfaces.size(), 2u);
  EXPECT_EQ(report.surfaces.at(3).simplex_count[2], 6 * 6 * 2);
  EXPECT_EQ(report.surfaces.at(4).simplex_count[2], 2 * 2 * 2);
  EXPECT_EQ(report.surfaces.at(4).betti[0], 1);
  EXPECT_EQ(report.surfaces.at(4).betti[1], 0);
}

class SharedSurfaces : public ::testing::TestWithParam<Engine> {};

// Both surfaces, each checked on its own by the independent checker, keep their Betti numbers
// and Euler characteristic through a strong simplification, and both refs come out.
TEST_P(SharedSurfaces, EachSurfaceKeepsItsTopology) {
  Grid g = nested_surfaces();
  // A third surface: a strip of surface 3 that reaches the box boundary.
  testing::add_patch(g, 0, 3, [](int a, int b) { return a == 4 && b >= 1; }, 5);
  MeshModel mesh = build_mesh_model(g.data);
  const topotet::TopologyReport before = topotet::compute_topology(g.data);
  SimplifyOptions options;
  options.engine = GetParam();
  options.target_vertex_ratio = 0.1;
  const Report report = simplify(mesh, options);
  ASSERT_NE(report.status, Status::kInvalidInput) << report.message;
  EXPECT_LT(report.vertices_after, report.vertices_before / 2);
  const MeshData out = mesh.to_mesh_data();
  const topotet::TopologyReport after = topotet::compute_topology(out);
  std::string differences;
  EXPECT_TRUE(topotet::same_topology(before, after, &differences)) << differences;
  ASSERT_EQ(after.surfaces.size(), 3u);
  for (std::int32_t ref : {3, 4, 5}) {
    EXPECT_EQ(after.surfaces.at(ref).betti, before.surfaces.at(ref).betti) << "surface " << ref;
    EXPECT_EQ(after.surfaces.at(ref).euler_characteristic, before.surfaces.at(ref).euler_characteristic);
  }
  // Every face of surfaces 4 and 5 is still a face of surface 3.
  std::map<std::int32_t, std::vector<std::array<VertId, 3>>> faces;
  for (const Triangle& t : out.triangles) {
    std::array<VertId, 3> v = t.v;
    std::sort(v.begin(), v.end());
    faces[t.ref].push_back(v);
  }
  std::sort(faces[3].begin(), faces[3].end());
  for (std::int32_t ref : {4, 5})
    for (const auto& v : faces[ref]) EXPECT_TRUE(std::binary_search(faces[3].begin(), faces[3].end(), v)) << ref;
}

INSTANTIATE_TEST_SUITE_P(Engines, SharedSurfaces, ::testing::Values(Engine::kSequential, Engine::kParallel),
                         [](const ::testing::TestParamInfo<Engine>& p) {
                           return std::string(p.param == Engine::kSequential ? "sequential" : "parallel");
                         });

}  // namespace
}  // namespace topotet
