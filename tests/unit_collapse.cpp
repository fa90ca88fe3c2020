// The collapse kernel on tiny hand-built meshes, one behaviour per test.
#include <gtest/gtest.h>

#include "kernel/collapse.h"
#include "kernel/link_condition.h"
#include "mesh/dihedral.h"
#include "mesh/moved_corner.h"
#include "mesh/mesh_model.h"
#include "test_meshes.h"

namespace topotet {
namespace {

using testing::Grid;
using testing::make_grid;

CollapseReason try_collapse(const MeshModel& m, VertId u, VertId v) {
  CollapseScratch s;
  return may_collapse(m, u, v, m.positions[u], CollapseOptions{}, s);
}

// The topological verdict alone (may_collapse reports an inversion first when both apply).
LinkResult link_result(const MeshModel& m, VertId u, VertId v) {
  CollapseScratch s;
  if (!gather_stars(m, u, v, s)) return LinkResult::kLinkK;
  return check_link_conditions(m, u, v, s.star_uv, s.link);
}

VertexOrders orders(const MeshModel& m, VertId v) {
  LinkScratch s;
  return vertex_orders(m, v, s);
}

Grid uniform(int n) { return make_grid(n, n, n, [](int, int, int) { return 1; }); }

TEST(Collapse, InteriorEdgeOfPlainMaterialIsAllowed) {
  Grid g = uniform(4);
  const MeshModel m = build_mesh_model(g.data);
  EXPECT_EQ(try_collapse(m, g.vid(2, 2, 2), g.vid(2, 2, 1)), CollapseReason::kOk);
}

TEST(Collapse, SingleTetCannotBeSimplified) {
  MeshData d;
  d.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  d.tets = {{0, 1, 2, 3}};
  d.tet_material = {1};
  const MeshModel m = build_mesh_model(d);
  for (VertId a = 0; a < 4; ++a)
    for (VertId b = 0; b < 4; ++b) {
      if (a != b) {
        EXPECT_EQ(try_collapse(m, a, b), CollapseReason::kLinkK) << a << " " << b;
      }
    }
}

TEST(Collapse, ClosingATunnelOfTheMeshIsLinkK) {
  // A ring of cubes one cube thick: the diagonal of a cube is an interior edge joining two
  // boundary vertices; collapsing it would pinch the ring.
  Grid g = make_grid(3, 3, 1, [](int i, int j, int) { return i == 1 && j == 1 ? -1 : 1; });
  const MeshModel m = build_mesh_model(g.data);
  EXPECT_EQ(try_collapse(m, g.vid(0, 0, 0), g.vid(1, 1, 1)), CollapseReason::kLinkK);
}

TEST(Collapse, LockedVertexNeverMoves) {
  Grid g = uniform(4);
  g.data.corners.push_back(g.vid(2, 2, 2));
  const MeshModel m = build_mesh_model(g.data);
  EXPECT_EQ(try_collapse(m, g.vid(2, 2, 1), g.vid(2, 2, 2)), CollapseReason::kPinned);  // pinned would vanish
  CollapseScratch s;
  EXPECT_EQ(may_collapse(m, g.vid(2, 2, 2), g.vid(2, 2, 1), m.positions[g.vid(2, 2, 1)], {}, s),
            CollapseReason::kPinned);  // pinned would move
  EXPECT_EQ(try_collapse(m, g.vid(2, 2, 2), g.vid(2, 2, 1)), CollapseReason::kOk);  // stays put
}

TEST(Collapse, CollapsingALayerOneTetThickIsRejected) {
  Grid g = make_grid(4, 4, 4, [](int, int, int k) { return k == 2 ? 2 : 1; });
  const MeshModel m = build_mesh_model(g.data);
  // (1,1,2)-(1,1,3) crosses the layer from its lower to its upper interface.
  EXPECT_EQ(try_collapse(m, g.vid(1, 1, 2), g.vid(1, 1, 3)), CollapseReason::kLinkKtilde);
  // Along the interface itself it is fine.
  EXPECT_EQ(try_collapse(m, g.vid(2, 2, 2), g.vid(1, 2, 2)), CollapseReason::kOk);
}

TEST(Collapse, EdgeBetweenTwoDifferentSurfacesIsRejected) {
  Grid g = uniform(5);
  testing::add_patch(g, 2, 2, [](int a, int b) { return a >= 1 && a < 4 && b >= 1 && b < 4; }, 1);
  testing::add_patch(g, 2, 3, [](int a, int b) { return a >= 1 && a < 4 && b >= 1 && b < 4; }, 2);
  const MeshModel m = build_mesh_model(g.data);
  EXPECT_EQ(try_collapse(m, g.vid(2, 2, 2), g.vid(2, 2, 3)), CollapseReason::kLinkKtilde);
}

TEST(Collapse, PinchingAPolylineIntoALoopIsRejected) {
  // Path (1,1)-(2,1)-(2,2) on z=2; (1,1)-(2,2) is a mesh edge (a square diagonal) not on the path.
  Grid g = uniform(4);
  testing::add_polyline(g, {{0, 1, 2}, {1, 1, 2}, {2, 1, 2}, {2, 2, 2}, {2, 3, 2}}, 1);
  const MeshModel m = build_mesh_model(g.data);
  EXPECT_EQ(orders(m, g.vid(1, 1, 2)).ktilde, 2);
  EXPECT_EQ(link_result(m, g.vid(1, 1, 2), g.vid(2, 2, 2)), LinkResult::kLinkKtilde);
  EXPECT_EQ(link_result(m, g.vid(2, 2, 2), g.vid(1, 1, 2)), LinkResult::kLinkKtilde);
  // Sliding along the polyline is fine.
  EXPECT_EQ(try_collapse(m, g.vid(1, 1, 2), g.vid(2, 1, 2)), CollapseReason::kOk);
}

TEST(Collapse, MergingTwoPolylinesIsRejected) {
  Grid g = uniform(4);
  testing::add_polyline(g, testing::grid_line({0, 1, 2}, {4, 1, 2}), 1);
  testing::add_polyline(g, testing::grid_line({0, 2, 2}, {4, 2, 2}), 2);
  const MeshModel m = build_mesh_model(g.data);
  EXPECT_EQ(try_collapse(m, g.vid(2, 1, 2), g.vid(2, 2, 2)), CollapseReason::kLinkKtilde);
}

TEST(Collapse, PolylineEndpointsAndJunctionsAreOrderThree) {
  Grid g = uniform(6);
  testing::add_polyline(g, testing::grid_line({1, 3, 3}, {3, 3, 3}), 1);
  testing::add_polyline(g, testing::grid_line({3, 3, 3}, {5, 3, 3}), 1);
  testing::add_polyline(g, testing::grid_line({3, 3, 3}, {3, 5, 3}), 2);
  const MeshModel m = build_mesh_model(g.data);
  EXPECT_EQ(orders(m, g.vid(1, 3, 3)).ktilde, 3);  // endpoint
  EXPECT_EQ(orders(m, g.vid(3, 3, 3)).ktilde, 3);  // junction of three branches
  EXPECT_EQ(orders(m, g.vid(2, 3, 3)).ktilde, 2);  // plain curve point
  EXPECT_EQ(orders(m, g.vid(2, 2, 2)).ktilde, 0);
}

TEST(Collapse, PolylineCrossingASurfaceMakesAnOrderThreeVertex) {
  Grid g = uniform(6);
  testing::add_patch(g, 2, 3, [](int a, int b) { return a >= 1 && a < 5 && b >= 1 && b < 5; }, 1);
  testing::add_polyline(g, testing::grid_line({3, 3, 1}, {3, 3, 5}), 2);
  const MeshModel m = build_mesh_model(g.data);
  EXPECT_EQ(orders(m, g.vid(3, 3, 3)).ktilde, 3);
  EXPECT_EQ(orders(m, g.vid(2, 2, 3)).ktilde, 1);  // surface interior
  EXPECT_EQ(orders(m, g.vid(1, 2, 3)).ktilde, 2);  // surface rim
}

TEST(Collapse, RegionInterfaceIsPreserved) {
  // Material 2 is a single cube: its interface is a small closed surface; an edge crossing the
  // cube joins two interface vertices through the inside and may not collapse.
  Grid g = make_grid(3, 3, 3, [](int i, int j, int k) { return i == 1 && j == 1 && k == 1 ? 2 : 1; });
  const MeshModel m = build_mesh_model(g.data);
  EXPECT_EQ(try_collapse(m, g.vid(1, 1, 1), g.vid(2, 2, 2)), CollapseReason::kLinkKtilde);
}

TEST(Collapse, BoundaryOrdersFollowTheBoxGeometry) {
  Grid g = uniform(4);
  const MeshModel m = build_mesh_model(g.data);
  EXPECT_EQ(orders(m, g.vid(2, 2, 0)).k, 1);  // face of the box
  EXPECT_EQ(orders(m, g.vid(2, 2, 2)).k, 0);
  testing::add_box_boundary(g, 9);
  const MeshModel listed = build_mesh_model(g.data);
  EXPECT_EQ(orders(listed, g.vid(2, 2, 0)).ktilde, 1);
}

TEST(Collapse, InversionIsDetected) {
  Grid g = uniform(4);
  const MeshModel m = build_mesh_model(g.data);
  CollapseScratch s;
  // Move the merged vertex far outside its star: some tet must flip.
  const glm::dvec3 far = m.positions[g.vid(2, 2, 2)] + glm::dvec3(0, 0, 5);
  EXPECT_EQ(may_collapse(m, g.vid(2, 2, 2), g.vid(2, 2, 1), far, {}, s), CollapseReason::kInversion);
}

// The dihedral floor's sine: the regular tet's angle is acos(1/3) (sin^2 = 8/9); the screen
// (mesh/dihedral.h): no tet with an angle under 5 degrees (or over 175) has a mean ratio of 0.25.
TEST(DihedralFloor, SineOfTheSmallestAngleAndTheScreen) {
  const glm::dvec3 a(1, 0, -1 / std::sqrt(2.0)), b(-1, 0, -1 / std::sqrt(2.0)), c(0, 1, 1 / std::sqrt(2.0)),
      d(0, -1, 1 / std::sqrt(2.0));
  EXPECT_NEAR(min_dihedral_sine_sq(a, b, c, d), 8.0 / 9.0, 1e-12);
  EXPECT_NEAR(min_dihedral_sine_sq(a, c, b, d), 8.0 / 9.0, 1e-12);  // either orientation
  // A sliver: a unit square's corners, two of them lifted by h: angles near 0 and 180.
  const double h = 0.01;
  const double s = min_dihedral_sine_sq({0, 0, 0}, {1, 1, 0}, {1, 0, h}, {0, 1, h});
  EXPECT_LT(s, 4.0 * h * h);
  EXPECT_GT(s, 0.0);
  EXPECT_EQ(min_dihedral_sine_sq({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}), 0.0);  // flat
  const DihedralFloor floor = DihedralFloor::degrees(5.0);
  std::uint64_t state = 12345;
  const auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / static_cast<double>(1ull << 53);
  };
  int under = 0;
  for (int i = 0; i < 200000; ++i) {
    glm::dvec3 p[4];
    for (auto& x : p) x = {next(), next() * (0.05 + next()), next() * (0.05 + next())};
    const double q3 = std::fabs(mean_ratio_cubed(p[0], p[1], p[2], p[3]));
    if (min_dihedral_sine_sq(p[0], p[1], p[2], p[3]) < floor.sine_sq) {
      ++under;
      EXPECT_LT(q3, floor.screen_q3) << "a tet under the floor passes the screen";
    }
  }
  EXPECT_GT(under, 1000);
  EXPECT_EQ(DihedralFloor::degrees(20.0).screen_q3, 2.0);  // above 5 degrees: every tet is tested
  EXPECT_FALSE(DihedralFloor::degrees(0.0).active());
}

// The kernel refuses a placement whose new star has an angle under min(floor, the old star's),
// as the quality floor does (the same reason).
TEST(DihedralFloor, TheKernelRefusesAPlacementUnderIt) {
  Grid g = uniform(4);
  const MeshModel m = build_mesh_model(g.data);
  CollapseScratch s;
  const VertId u = g.vid(2, 2, 2), v = g.vid(2, 2, 1);
  CollapseOptions none;
  none.quality_floor = 0.0;
  ASSERT_EQ(may_collapse(m, u, v, m.positions[u], none, s), CollapseReason::kOk);
  CollapseOptions with = none;
  with.dihedral_floor = DihedralFloor::degrees(44.0);  // the grid's tets have 45, 60 and 90 degrees
  EXPECT_EQ(may_collapse(m, u, v, m.positions[u], with, s), CollapseReason::kQuality);
  with.dihedral_floor = DihedralFloor::degrees(1.0);
  EXPECT_EQ(may_collapse(m, u, v, m.positions[u], with, s), CollapseReason::kOk);
}

TEST(Collapse, ApplyKeepsIncidenceAndFlagsConsistent) {
  Grid g = make_grid(5, 5, 5, [](int i, int, int) { return i < 2 ? 1 : 2; });
  testing::add_polyline(g, testing::grid_line({0, 2, 2}, {5, 2, 2}), 1);
  const MeshModel before = build_mesh_model(g.data);
  MeshModel m = before;
  CollapseScratch s;
  const VertId u = g.vid(3, 2, 2), v = g.vid(4, 2, 2);
  ASSERT_EQ(may_collapse(m, u, v, m.positions[u], {}, s), CollapseReason::kOk);
  std::uint32_t used = static_cast<std::uint32_t>(m.refs_table.size());
  reserve_refs_headroom(m, used, s.star_u.size() + s.star_v.size());
  collapse(m, u, v, m.positions[u], nullptr, s, used);
  EXPECT_TRUE(m.is_dead_vertex(v));
  EXPECT_EQ(m.live_tet_count(), before.live_tet_count() - s.star_uv.size());
  // The exported mesh rebuilds into the same model: incidence and flags are consistent.
  const MeshData out = m.to_mesh_data();
  const MeshModel rebuilt = build_mesh_model(out);
  EXPECT_EQ(rebuilt.to_mesh_data(), out);
  EXPECT_EQ(out.segments.size(), g.data.segments.size() - 1);  // one polyline edge merged away
}

}  // namespace
}  // namespace topotet
