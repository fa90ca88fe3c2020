// The collapse kernel on tiny hand-built meshes, one behaviour per test.
#include <gtest/gtest.h>

#include "kernel/collapse.h"
#include "kernel/link_condition.h"
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
