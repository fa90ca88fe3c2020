// Tests of the independent topology checker (metrics/topology.h): known complexes, planted faults
// that must be caught, an exact-orientation check against 128-bit integers, a cross-check of the
// reduction-based Betti numbers against dense Gaussian elimination, and timings.
//
// Meshes are built here (Kuhn grids: each unit cube split into 6 tets around its main diagonal),
// not with the engine's generators, so that the referee is tested on its own.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "mesh/glm_convert.h"
#include "test_meshes.h"
#include "topotet/metrics/topology.h"

namespace topotet::metrics {
namespace {

using Betti = std::array<std::int64_t, 4>;   // b0..b3
using Counts = std::array<std::int64_t, 4>;  // vertices, edges, triangles, tets

// ---------------------------------------------------------------------------------------------
// Mesh building helpers.

// A lattice of (nx+1)(ny+1)(nz+1) points; cubes are added one by one, each as 6 positively
// oriented Kuhn tets (conforming across cubes since every cube uses the same diagonal).
class Grid {
 public:
  Grid(int nx, int ny, int nz) : nx_(nx), ny_(ny) {
    for (int k = 0; k <= nz; ++k)
      for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) mesh.positions.push_back({double(i), double(j), double(k)});
  }

  VertId v(int i, int j, int k) const { return static_cast<VertId>((k * (ny_ + 1) + j) * (nx_ + 1) + i); }

  void add_cube(int i, int j, int k, std::int32_t material = 1) {
    static constexpr std::array<std::array<int, 3>, 6> kPermutations = {
        {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
    for (const auto& p : kPermutations) {
      std::array<int, 3> c = {i, j, k};
      std::array<VertId, 4> tet{};
      tet[0] = v(c[0], c[1], c[2]);
      for (int s = 0; s < 3; ++s) {
        ++c[p[s]];
        tet[s + 1] = v(c[0], c[1], c[2]);
      }
      if (signed_volume6(tet) < 0) std::swap(tet[2], tet[3]);
      mesh.tets.push_back(tet);
      mesh.tet_material.push_back(material);
    }
  }

  // Adds every cube for which material(i, j, k) != 0, with that material.
  void fill(int nx, int ny, int nz, const std::function<std::int32_t(int, int, int)>& material) {
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          if (const std::int32_t m = material(i, j, k); m != 0) add_cube(i, j, k, m);
  }

  void add_path(const std::vector<VertId>& path, std::int32_t ref) {
    for (std::size_t s = 0; s + 1 < path.size(); ++s) mesh.segments.push_back({{path[s], path[s + 1]}, ref});
  }

  double signed_volume6(const std::array<VertId, 4>& t) const {
    const glm::dvec3 a = to_glm(mesh.positions[t[1]]) - to_glm(mesh.positions[t[0]]);
    const glm::dvec3 b = to_glm(mesh.positions[t[2]]) - to_glm(mesh.positions[t[0]]);
    const glm::dvec3 c = to_glm(mesh.positions[t[3]]) - to_glm(mesh.positions[t[0]]);
    return a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) + a.z * (b.x * c.y - b.y * c.x);
  }

  MeshData mesh;

 private:
  int nx_, ny_;
};

MeshData full_grid(int nx, int ny, int nz, std::int32_t material = 1) {
  Grid g(nx, ny, nz);
  g.fill(nx, ny, nz, [material](int, int, int) { return material; });
  return std::move(g.mesh);
}

using FacePredicate = std::function<bool(const glm::dvec3&, const glm::dvec3&, const glm::dvec3&)>;

// Distinct faces of the mesh's tets (sorted vertex triples) whose vertices satisfy `keep`.
std::vector<std::array<VertId, 3>> tet_faces_where(const MeshData& mesh, const FacePredicate& keep) {
  std::set<std::array<VertId, 3>> faces;
  for (const auto& t : mesh.tets)
    for (int i = 0; i < 4; ++i) {
      std::array<VertId, 3> f{};
      for (int k = 0, n = 0; k < 4; ++k)
        if (k != i) f[n++] = t[k];
      std::sort(f.begin(), f.end());
      if (keep(to_glm(mesh.positions[f[0]]), to_glm(mesh.positions[f[1]]), to_glm(mesh.positions[f[2]]))) faces.insert(f);
    }
  return {faces.begin(), faces.end()};
}

void add_triangles(MeshData& mesh, const std::vector<std::array<VertId, 3>>& faces, std::int32_t ref) {
  for (const auto& f : faces) mesh.triangles.push_back({f, ref});
}

// Faces lying on the surface of the axis-aligned box [lo, hi]^3.
FacePredicate on_box_surface(double lo, double hi) {
  return [lo, hi](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    auto inside = [&](const glm::dvec3& p) {
      return p.x >= lo && p.x <= hi && p.y >= lo && p.y <= hi && p.z >= lo && p.z <= hi;
    };
    if (!inside(a) || !inside(b) || !inside(c)) return false;
    for (int axis = 0; axis < 3; ++axis)
      for (double side : {lo, hi})
        if (a[axis] == side && b[axis] == side && c[axis] == side) return true;
    return false;
  };
}

std::string diff_of(const TopologyReport& a, const TopologyReport& b) {
  std::string d;
  same_topology(a, b, &d);
  return d;
}

// chi == sum (-1)^k b_k must hold for every fully computed complex.
void expect_consistent(const ComplexTopology& t) {
  const auto& b = t.betti;
  EXPECT_EQ(t.euler_characteristic, b[0] - b[1] + b[2] - b[3]);
  const auto& n = t.simplex_count;
  EXPECT_EQ(t.euler_characteristic, n[0] - n[1] + n[2] - n[3]);
}

// ---------------------------------------------------------------------------------------------
// Known complexes.

TEST(Topology, SingleTetIsBallWithSphereBoundary) {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  m.tet_material = {7};
  const TopologyReport r = compute_topology(m);
  EXPECT_EQ(r.mesh.betti, (Betti{1, 0, 0, 0}));
  EXPECT_EQ(r.mesh.simplex_count, (Counts{4, 6, 4, 1}));
  EXPECT_EQ(r.boundary.betti, (Betti{1, 0, 1, 0}));
  EXPECT_EQ(r.boundary.simplex_count, (Counts{4, 6, 4, 0}));
  ASSERT_EQ(r.materials.size(), 1u);
  EXPECT_EQ(r.materials.at(7).betti, (Betti{1, 0, 0, 0}));
  EXPECT_TRUE(r.interfaces.empty());
  EXPECT_EQ(r.all_surfaces.simplex_count, (Counts{0, 0, 0, 0}));
  EXPECT_EQ(r.embedded.betti, (Betti{0, 0, 0, 0}));
  EXPECT_EQ(r.inverted_tet_count, 0u);
  EXPECT_EQ(r.degenerate_tet_count, 0u);
  EXPECT_EQ(r.nonmanifold_face_count, 0u);
  EXPECT_EQ(r.unreferenced_vertex_count, 0u);
  EXPECT_TRUE(same_topology(r, r));
}

TEST(Topology, CubeOfSixTetsIsBall) {
  const TopologyReport r = compute_topology(full_grid(1, 1, 1));
  EXPECT_EQ(r.mesh.simplex_count, (Counts{8, 19, 18, 6}));
  EXPECT_EQ(r.mesh.betti, (Betti{1, 0, 0, 0}));
  EXPECT_EQ(r.boundary.betti, (Betti{1, 0, 1, 0}));
  EXPECT_EQ(r.boundary.simplex_count[2], 12);
  EXPECT_EQ(r.inverted_tet_count, 0u);
  expect_consistent(r.mesh);
  expect_consistent(r.boundary);
}

TEST(Topology, HollowCubeHasCavity) {
  Grid g(3, 3, 3);
  g.fill(3, 3, 3, [](int i, int j, int k) { return (i == 1 && j == 1 && k == 1) ? 0 : 1; });
  const TopologyReport r = compute_topology(g.mesh);
  EXPECT_EQ(r.mesh.betti, (Betti{1, 0, 1, 0}));
  EXPECT_EQ(r.boundary.betti, (Betti{2, 0, 2, 0}));
  EXPECT_EQ(r.materials.at(1).betti, (Betti{1, 0, 1, 0}));
  expect_consistent(r.mesh);
}

TEST(Topology, SolidTorusHasTorusBoundary) {
  Grid g(3, 3, 1);
  g.fill(3, 3, 1, [](int i, int j, int) { return (i == 1 && j == 1) ? 0 : 1; });
  const TopologyReport r = compute_topology(g.mesh);
  EXPECT_EQ(r.mesh.betti, (Betti{1, 1, 0, 0}));
  EXPECT_EQ(r.boundary.betti, (Betti{1, 2, 1, 0}));
  EXPECT_EQ(r.boundary.euler_characteristic, 0);
}

TEST(Topology, TwoDisjointBlocksHaveTwoComponents) {
  Grid g(3, 1, 1);
  g.add_cube(0, 0, 0);
  g.add_cube(2, 0, 0);
  const TopologyReport r = compute_topology(g.mesh);
  EXPECT_EQ(r.mesh.betti, (Betti{2, 0, 0, 0}));
  EXPECT_EQ(r.boundary.betti, (Betti{2, 0, 2, 0}));
  EXPECT_EQ(r.unreferenced_vertex_count, 0u);
}

TEST(Topology, BlocksTouchingAtAnEdgeAreOneComponentWithPinchedBoundary) {
  Grid g(2, 2, 1);
  g.add_cube(0, 0, 0);
  g.add_cube(1, 1, 0);
  const TopologyReport r = compute_topology(g.mesh);
  EXPECT_EQ(r.mesh.betti, (Betti{1, 0, 0, 0}));
  // Two spheres glued along an edge: connected, b2 = 2.
  EXPECT_EQ(r.boundary.betti, (Betti{1, 0, 2, 0}));
}

TEST(Topology, MaterialInclusionGivesSphereInterface) {
  Grid g(3, 3, 3);
  g.fill(3, 3, 3, [](int i, int j, int k) { return (i == 1 && j == 1 && k == 1) ? 2 : 1; });
  const TopologyReport r = compute_topology(g.mesh);
  EXPECT_EQ(r.mesh.betti, (Betti{1, 0, 0, 0}));
  ASSERT_EQ(r.materials.size(), 2u);
  EXPECT_EQ(r.materials.at(1).betti, (Betti{1, 0, 1, 0}));
  EXPECT_EQ(r.materials.at(2).betti, (Betti{1, 0, 0, 0}));
  ASSERT_EQ(r.interfaces.size(), 1u);
  const ComplexTopology& interface = r.interfaces.at({1, 2});
  EXPECT_EQ(interface.betti, (Betti{1, 0, 1, 0}));
  EXPECT_EQ(interface.simplex_count[2], 12);
  EXPECT_EQ(r.all_surfaces.betti, (Betti{1, 0, 1, 0}));
  EXPECT_EQ(r.embedded.betti, (Betti{1, 0, 1, 0}));
  expect_consistent(r.materials.at(1));
}

TEST(Topology, ListedInterfaceIsNotCountedTwiceInUnion) {
  Grid g(3, 3, 3);
  g.fill(3, 3, 3, [](int i, int j, int k) { return (i == 1 && j == 1 && k == 1) ? 2 : 1; });
  add_triangles(g.mesh, tet_faces_where(g.mesh, on_box_surface(1, 2)), 9);
  const TopologyReport r = compute_topology(g.mesh);
  EXPECT_EQ(r.surfaces.at(9).betti, (Betti{1, 0, 1, 0}));
  EXPECT_EQ(r.all_surfaces.simplex_count, r.interfaces.at({1, 2}).simplex_count);
  EXPECT_EQ(r.all_surfaces.betti, (Betti{1, 0, 1, 0}));
}

TEST(Topology, SurfaceRefWithHoleIsAnnulus) {
  const MeshData base = full_grid(3, 3, 1);
  MeshData m = base;
  add_triangles(m, tet_faces_where(m, [](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
                  const glm::dvec3 centre = (a + b + c) / 3.0;
                  const bool in_hole = centre.x > 1 && centre.x < 2 && centre.y > 1 && centre.y < 2;
                  return a.z == 1 && b.z == 1 && c.z == 1 && !in_hole;
                }),
                2);
  const TopologyReport r = compute_topology(m);
  ASSERT_EQ(r.surfaces.size(), 1u);
  EXPECT_EQ(r.surfaces.at(2).betti, (Betti{1, 1, 0, 0}));
  EXPECT_EQ(r.surfaces.at(2).simplex_count[2], 16);
  EXPECT_EQ(r.all_surfaces.betti, (Betti{1, 1, 0, 0}));
}

// Polylines of a 4x4x4 grid: a path (ref 1), a square loop (ref 2) and a "Y" (ref 3), pairwise
// disjoint; a disk on the top face (surface ref 7); pinned: one vertex on the path and one alone.
struct PolylineScene {
  Grid grid{4, 4, 4};
  PolylineScene() {
    Grid& g = grid;
    g.fill(4, 4, 4, [](int, int, int) { return 1; });
    g.add_path({g.v(0, 0, 0), g.v(1, 0, 0), g.v(2, 0, 0), g.v(3, 0, 0)}, 1);
    g.add_path({g.v(0, 2, 0), g.v(1, 2, 0), g.v(1, 3, 0), g.v(0, 3, 0), g.v(0, 2, 0)}, 2);
    g.add_path({g.v(4, 2, 2), g.v(3, 2, 2), g.v(2, 2, 2), g.v(2, 3, 2)}, 3);
    g.add_path({g.v(2, 2, 2), g.v(2, 2, 3)}, 3);
    add_triangles(g.mesh, tet_faces_where(g.mesh, [](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
                    return a.z == 4 && b.z == 4 && c.z == 4;
                  }),
                  7);
    g.mesh.corners = {g.v(0, 0, 0), g.v(4, 4, 0)};
    g.mesh.required_vertices = {g.v(4, 4, 0)};  // also a corner: counted once
  }
};

TEST(Topology, PolylinesPathLoopAndY) {
  const PolylineScene scene;
  const TopologyReport r = compute_topology(scene.grid.mesh);
  ASSERT_EQ(r.polylines.size(), 3u);
  EXPECT_EQ(r.polylines.at(1).betti, (Betti{1, 0, 0, 0}));
  EXPECT_EQ(r.polylines.at(1).simplex_count, (Counts{4, 3, 0, 0}));
  EXPECT_EQ(r.polylines.at(2).betti, (Betti{1, 1, 0, 0}));
  EXPECT_EQ(r.polylines.at(3).betti, (Betti{1, 0, 0, 0}));
  EXPECT_EQ(r.polylines.at(3).simplex_count, (Counts{5, 4, 0, 0}));
  EXPECT_EQ(r.all_polylines.betti, (Betti{3, 1, 0, 0}));
}

TEST(Topology, EmbeddedStructureUnitesSurfacesPolylinesAndPins) {
  const PolylineScene scene;
  const TopologyReport r = compute_topology(scene.grid.mesh);
  EXPECT_EQ(r.pinned_vertex_count, 2u);
  EXPECT_EQ(r.surfaces.at(7).betti, (Betti{1, 0, 0, 0}));
  // path (holding one pin) + loop + Y + disk + the lone pinned vertex.
  EXPECT_EQ(r.embedded.betti, (Betti{5, 1, 0, 0}));
  expect_consistent(r.embedded);
}

TEST(Topology, FastModeGivesComponentsAndEuler) {
  const PolylineScene scene;
  const TopologyReport full = compute_topology(scene.grid.mesh);
  const TopologyReport fast = compute_topology(scene.grid.mesh, {.fast = true});
  EXPECT_TRUE(fast.is_fast);
  EXPECT_EQ(fast.mesh.betti, (Betti{1, kUnknownBetti, kUnknownBetti, kUnknownBetti}));
  EXPECT_EQ(fast.mesh.euler_characteristic, 1);
  EXPECT_EQ(fast.surfaces.at(7).betti, (Betti{1, kUnknownBetti, kUnknownBetti, 0}));
  EXPECT_EQ(fast.polylines.at(2).betti, (Betti{1, 1, 0, 0}));  // graphs: b1 = b0 - chi
  EXPECT_EQ(fast.all_polylines.betti, full.all_polylines.betti);
  EXPECT_EQ(fast.embedded.euler_characteristic, full.embedded.euler_characteristic);
  EXPECT_EQ(fast.embedded.betti[0], full.embedded.betti[0]);
  std::string d;
  EXPECT_TRUE(same_topology(full, fast, &d)) << d;
  EXPECT_TRUE(same_topology(fast, full, &d)) << d;
}

TEST(Topology, DifferentMeshesWithSameTopologyCompareEqual) {
  // A 2x2x2 block and a single cube: both balls with sphere boundaries, one material.
  std::string d;
  EXPECT_TRUE(same_topology(compute_topology(full_grid(2, 2, 2)), compute_topology(full_grid(1, 1, 1)), &d)) << d;
  EXPECT_TRUE(d.empty());
}

TEST(Topology, HugeVertexIdsUseWideKeysAndGiveTheSameAnswer) {
  // Beyond 2,642,245 vertices face keys no longer fit in 64 bits, and beyond 32,768 vertices the
  // checker renumbers vertices and tets internally: both paths must agree with the plain one.
  Grid g(3, 3, 3);
  g.fill(3, 3, 3, [](int i, int j, int k) { return (i == 1 && j == 1 && k == 1) ? 2 : 1; });
  g.add_path({g.v(0, 0, 0), g.v(1, 0, 0), g.v(1, 1, 0), g.v(0, 0, 0)}, 3);
  add_triangles(g.mesh, tet_faces_where(g.mesh, on_box_surface(0, 3)), 4);
  g.mesh.corners = {g.v(3, 3, 3), g.v(0, 0, 0)};
  g.mesh.required_vertices = {g.v(2, 0, 3)};
  // A copy of the centre cube's first tet with another material: the first copy (material 2)
  // must stay the one kept, or the interface and the regions would change.
  const std::size_t centre_tet = 13 * 6;
  ASSERT_EQ(g.mesh.tet_material[centre_tet], 2);
  g.mesh.tets.push_back(g.mesh.tets[centre_tet]);
  g.mesh.tet_material.push_back(1);
  const TopologyReport small = compute_topology(g.mesh);
  EXPECT_EQ(small.duplicate_tet_count, 1u);
  EXPECT_EQ(small.interfaces.at({1, 2}).betti, (Betti{1, 0, 1, 0}));
  EXPECT_EQ(small.pinned_vertex_count, 3u);
  constexpr VertId kShift = 2'700'000;
  MeshData wide = g.mesh;
  wide.positions.insert(wide.positions.begin(), kShift, {-1.0, -1.0, -1.0});
  for (auto& t : wide.tets)
    for (auto& v : t) v += kShift;
  for (auto& t : wide.triangles)
    for (auto& v : t.v) v += kShift;
  for (auto& s : wide.segments)
    for (auto& v : s.v) v += kShift;
  for (auto& v : wide.corners) v += kShift;
  for (auto& v : wide.required_vertices) v += kShift;
  TopologyReport shifted = compute_topology(wide);
  EXPECT_EQ(shifted.unreferenced_vertex_count, kShift);
  shifted.unreferenced_vertex_count = 0;
  EXPECT_EQ(shifted, small);
  EXPECT_EQ(small.polylines.at(3).betti, (Betti{1, 1, 0, 0}));
  // The same through the renumbering path only (64-bit keys): 40,000 padding vertices spread
  // over space, so the Morton order interleaves them with the grid's.
  MeshData padded = g.mesh;
  constexpr VertId kPad = 40'000;
  std::vector<std::array<double, 3>> padding(kPad);
  for (VertId i = 0; i < kPad; ++i) padding[i] = {(i * 7919 % 1000) * 0.004, (i * 104729 % 1000) * 0.004, (i % 997) * 0.004};
  padded.positions.insert(padded.positions.begin(), padding.begin(), padding.end());
  for (auto& t : padded.tets)
    for (auto& v : t) v += kPad;
  for (auto& t : padded.triangles)
    for (auto& v : t.v) v += kPad;
  for (auto& s : padded.segments)
    for (auto& v : s.v) v += kPad;
  for (auto& v : padded.corners) v += kPad;
  for (auto& v : padded.required_vertices) v += kPad;
  TopologyReport moved = compute_topology(padded);
  moved.unreferenced_vertex_count -= kPad;
  EXPECT_EQ(moved, small);
}

TEST(Topology, EmptyMeshIsEmpty) {
  const TopologyReport r = compute_topology(MeshData{});
  EXPECT_EQ(r.mesh.betti, (Betti{0, 0, 0, 0}));
  EXPECT_EQ(r.mesh.simplex_count, (Counts{0, 0, 0, 0}));
  EXPECT_TRUE(r.materials.empty());
  EXPECT_TRUE(same_topology(r, r));
}

// ---------------------------------------------------------------------------------------------
// Planted faults: same_topology must say no, and name the complex.

TEST(TopologyFaults, OpeningAClosedSurfaceIsCaught) {
  Grid g(3, 3, 3);
  g.fill(3, 3, 3, [](int, int, int) { return 1; });
  add_triangles(g.mesh, tet_faces_where(g.mesh, on_box_surface(1, 2)), 5);
  const TopologyReport before = compute_topology(g.mesh);
  ASSERT_EQ(before.surfaces.at(5).betti, (Betti{1, 0, 1, 0}));
  g.mesh.triangles.pop_back();
  const TopologyReport after = compute_topology(g.mesh);
  const std::string d = diff_of(before, after);
  EXPECT_FALSE(same_topology(before, after));
  EXPECT_NE(d.find("surface ref 5: b2 1 -> 0"), std::string::npos) << d;
  EXPECT_NE(d.find("all surfaces: b2 1 -> 0"), std::string::npos) << d;
}

TEST(TopologyFaults, MergingTwoPolylinesIsCaught) {
  Grid g(4, 2, 1);
  g.fill(4, 2, 1, [](int, int, int) { return 1; });
  g.add_path({g.v(0, 0, 0), g.v(1, 0, 0)}, 1);
  g.add_path({g.v(2, 0, 0), g.v(3, 0, 0), g.v(4, 0, 0)}, 4);
  const TopologyReport before = compute_topology(g.mesh);
  ASSERT_EQ(before.all_polylines.betti, (Betti{2, 0, 0, 0}));
  g.add_path({g.v(1, 0, 0), g.v(2, 0, 0)}, 1);  // ref 1 stays a path, but now touches ref 4
  const TopologyReport after = compute_topology(g.mesh);
  const std::string d = diff_of(before, after);
  EXPECT_FALSE(same_topology(before, after));
  EXPECT_NE(d.find("all polylines: b0 2 -> 1"), std::string::npos) << d;
  EXPECT_NE(d.find("embedded structure: b0 2 -> 1"), std::string::npos) << d;
  EXPECT_EQ(d.find("polyline ref 1:"), std::string::npos) << d;
}

TEST(TopologyFaults, PinchingAPolylineIntoALoopIsCaught) {
  Grid g(2, 2, 1);
  g.fill(2, 2, 1, [](int, int, int) { return 1; });
  g.add_path({g.v(0, 0, 0), g.v(1, 0, 0), g.v(1, 1, 0), g.v(0, 1, 0)}, 1);
  const TopologyReport before = compute_topology(g.mesh);
  g.add_path({g.v(0, 1, 0), g.v(0, 0, 0)}, 1);
  const TopologyReport after = compute_topology(g.mesh);
  const std::string d = diff_of(before, after);
  EXPECT_FALSE(same_topology(before, after));
  EXPECT_NE(d.find("polyline ref 1: b1 0 -> 1"), std::string::npos) << d;
}

TEST(TopologyFaults, InvertedTetIsCaught) {
  MeshData m = full_grid(1, 1, 1);
  const TopologyReport before = compute_topology(m);
  std::swap(m.tets[0][0], m.tets[0][1]);
  const TopologyReport after = compute_topology(m);
  EXPECT_EQ(after.inverted_tet_count, 1u);
  EXPECT_EQ(after.degenerate_tet_count, 0u);
  EXPECT_EQ(after.mesh, before.mesh);  // the complex is the same, only the geometry is wrong
  const std::string d = diff_of(before, after);
  EXPECT_FALSE(same_topology(before, after));
  EXPECT_NE(d.find("inverted tets: 1"), std::string::npos) << d;
}

TEST(TopologyFaults, FlatTetIsCaught) {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  const TopologyReport before = compute_topology(m);
  m.positions[3] = {0.3, 0.3, 0};  // into the plane of the others
  const TopologyReport flat = compute_topology(m);
  EXPECT_EQ(flat.degenerate_tet_count, 1u);
  EXPECT_EQ(flat.inverted_tet_count, 0u);
  EXPECT_NE(diff_of(before, flat).find("degenerate tets: 1"), std::string::npos);
  // A repeated vertex index is flat too, and also invalid (left out of the complexes).
  m.positions[3] = {0, 0, 1};
  m.tets = {{0, 1, 2, 2}};
  const TopologyReport repeated = compute_topology(m);
  EXPECT_EQ(repeated.degenerate_tet_count, 1u);
  EXPECT_EQ(repeated.invalid_element_count, 1u);
  EXPECT_EQ(repeated.mesh.simplex_count, (Counts{0, 0, 0, 0}));
  EXPECT_FALSE(same_topology(before, repeated));
}

TEST(TopologyFaults, FaceOfThreeTetsIsCaught) {
  Grid g(1, 1, 1);
  g.add_cube(0, 0, 0);
  const TopologyReport before = compute_topology(g.mesh);
  // An interior face of the cube (shared by two tets) gets a third tet on a new vertex.
  std::map<std::array<VertId, 3>, int> face_count;
  for (const auto& t : g.mesh.tets)
    for (int i = 0; i < 4; ++i) {
      std::array<VertId, 3> f{};
      for (int k = 0, n = 0; k < 4; ++k)
        if (k != i) f[n++] = t[k];
      std::sort(f.begin(), f.end());
      ++face_count[f];
    }
  const auto interior = std::find_if(face_count.begin(), face_count.end(), [](const auto& e) { return e.second == 2; });
  ASSERT_NE(interior, face_count.end());
  g.mesh.positions.push_back({3, -2, 5});
  std::array<VertId, 4> extra = {interior->first[0], interior->first[1], interior->first[2],
                                 static_cast<VertId>(g.mesh.positions.size() - 1)};
  if (g.signed_volume6(extra) < 0) std::swap(extra[0], extra[1]);
  g.mesh.tets.push_back(extra);
  g.mesh.tet_material.push_back(1);
  const TopologyReport after = compute_topology(g.mesh);
  EXPECT_EQ(after.nonmanifold_face_count, 1u);
  EXPECT_EQ(after.inverted_tet_count, 0u);
  const std::string d = diff_of(before, after);
  EXPECT_NE(d.find("faces with more than two tets: 1"), std::string::npos) << d;
}

TEST(TopologyFaults, DuplicateTetIsCaught) {
  MeshData m = full_grid(1, 1, 1);
  const TopologyReport before = compute_topology(m);
  m.tets.push_back({m.tets[2][1], m.tets[2][0], m.tets[2][3], m.tets[2][2]});  // same set, same orientation
  m.tet_material.push_back(1);
  const TopologyReport after = compute_topology(m);
  EXPECT_EQ(after.duplicate_tet_count, 1u);
  EXPECT_EQ(after.nonmanifold_face_count, 0u);  // the copy is left out of the complexes
  EXPECT_EQ(after.mesh, before.mesh);
  EXPECT_NE(diff_of(before, after).find("duplicate tets: 1"), std::string::npos);
}

TEST(TopologyFaults, LostPinnedVertexAndLostMaterialAreCaught) {
  Grid g(2, 1, 1);
  g.add_cube(0, 0, 0, 1);
  g.add_cube(1, 0, 0, 2);
  g.mesh.corners = {g.v(0, 0, 0), g.v(2, 1, 1)};
  const TopologyReport before = compute_topology(g.mesh);
  g.mesh.corners.pop_back();
  std::fill(g.mesh.tet_material.begin(), g.mesh.tet_material.end(), 1);
  const TopologyReport after = compute_topology(g.mesh);
  const std::string d = diff_of(before, after);
  EXPECT_NE(d.find("pinned vertices: 2 -> 1"), std::string::npos) << d;
  EXPECT_NE(d.find("material 2: missing after"), std::string::npos) << d;
  EXPECT_NE(d.find("interface (1,2): missing after"), std::string::npos) << d;
}

TEST(TopologyFaults, TrianglesAndSegmentsOffTheMeshAreCaught) {
  Grid g(2, 2, 2);
  g.fill(2, 2, 2, [](int, int, int) { return 1; });
  g.add_path({g.v(0, 0, 0), g.v(1, 0, 0)}, 1);
  const TopologyReport before = compute_topology(g.mesh);
  EXPECT_EQ(before.detached_segment_count, 0u);
  // (0,0,0)-(2,0,0) and the triangle (0,0,0),(2,0,0),(0,2,0) span no tet edge or face.
  g.add_path({g.v(0, 0, 0), g.v(2, 0, 0)}, 2);
  g.mesh.triangles.push_back({{g.v(0, 0, 0), g.v(2, 0, 0), g.v(0, 2, 0)}, 5});
  const TopologyReport after = compute_topology(g.mesh);
  EXPECT_EQ(after.detached_segment_count, 1u);
  EXPECT_EQ(after.detached_triangle_count, 1u);
  EXPECT_EQ(after.surfaces.at(5).betti, (Betti{1, 0, 0, 0}));  // still part of its complexes
  const std::string d = diff_of(before, after);
  EXPECT_NE(d.find("triangles on no tet: 0 -> 1"), std::string::npos) << d;
  EXPECT_NE(d.find("segments on no tet: 0 -> 1"), std::string::npos) << d;
  EXPECT_TRUE(same_topology(after, after));  // present in the input: not a fault by itself
}

TEST(TopologyFaults, OutOfRangeIndicesAreCountedNotFatal) {
  MeshData m = full_grid(1, 1, 1);
  m.tets.push_back({0, 1, 2, 99});
  m.triangles.push_back({{0, 1, 77}, 3});
  m.segments.push_back({{5, 5}, 4});
  m.required_vertices.push_back(1000);
  const TopologyReport r = compute_topology(m);
  EXPECT_EQ(r.invalid_element_count, 4u);
  EXPECT_EQ(r.mesh.betti, (Betti{1, 0, 0, 0}));
  EXPECT_TRUE(r.surfaces.empty());
  EXPECT_TRUE(r.polylines.empty());
  EXPECT_FALSE(same_topology(r, r));
}

// ---------------------------------------------------------------------------------------------
// Exact orientation: nearly flat tets with integer coordinates up to 2^31, whose determinant
// terms (~2^90) swamp double precision, checked against a 128-bit integer determinant.

TEST(TopologyOrientation, SignIsExactOnNearlyFlatTets) {
  __extension__ typedef __int128 I128;
  std::mt19937_64 rng(12345);
  std::uniform_int_distribution<std::int64_t> big(-(std::int64_t{1} << 29), std::int64_t{1} << 29);
  std::uniform_int_distribution<std::int64_t> small(-2, 2);
  int counts[3] = {0, 0, 0};  // expected negative, zero, positive
  int mismatches = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const std::array<std::int64_t, 3> p0 = {big(rng) + (1 << 30), big(rng) + (1 << 30), big(rng) + (1 << 30)};
    std::array<std::int64_t, 3> u{}, d{}, e{};
    for (int k = 0; k < 3; ++k) {
      u[k] = big(rng);
      d[k] = trial % 7 == 0 ? 0 : small(rng);
      e[k] = trial % 5 == 0 ? 0 : small(rng);
    }
    // p1 = p0 + u, p2 = p0 + u + d, p3 = p0 + 2u + e: det = det(u, d, e), tiny or zero.
    std::array<std::array<std::int64_t, 3>, 3> rows{};
    for (int k = 0; k < 3; ++k) {
      rows[0][k] = u[k];
      rows[1][k] = u[k] + d[k];
      rows[2][k] = 2 * u[k] + e[k];
    }
    const auto& a = rows[0];
    const auto& b = rows[1];
    const auto& c = rows[2];
    const I128 det = I128{a[0]} * (I128{b[1]} * c[2] - I128{b[2]} * c[1]) -
                     I128{a[1]} * (I128{b[0]} * c[2] - I128{b[2]} * c[0]) +
                     I128{a[2]} * (I128{b[0]} * c[1] - I128{b[1]} * c[0]);
    const int expected = det > 0 ? 1 : det < 0 ? -1 : 0;
    ++counts[expected + 1];
    MeshData m;
    m.positions.push_back({double(p0[0]), double(p0[1]), double(p0[2])});
    for (const auto& r : rows)
      m.positions.push_back({double(p0[0] + r[0]), double(p0[1] + r[1]), double(p0[2] + r[2])});
    m.tets = {{0, 1, 2, 3}};
    const TopologyReport rep = compute_topology(m);
    const int got = rep.inverted_tet_count ? -1 : rep.degenerate_tet_count ? 0 : 1;
    mismatches += got != expected;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(counts[0], 100);  // every sign is exercised
  EXPECT_GT(counts[1], 100);
  EXPECT_GT(counts[2], 100);
}

// ---------------------------------------------------------------------------------------------
// Cross-check against a dense brute-force implementation written independently of the library:
// std::set closures and Gaussian elimination on dense Z2 bit matrices.

using Simplex = std::vector<VertId>;  // sorted

struct DenseResult {
  Betti betti{};
  Counts counts{};
};

// Rank over Z2 of the given columns (bitsets over the rows), by Gaussian elimination: each column
// is reduced by the basis vectors indexed by their leading row.
std::int64_t dense_rank(std::vector<std::vector<std::uint64_t>> columns, std::size_t row_count) {
  std::vector<std::vector<std::uint64_t>> basis(row_count);
  std::int64_t rank = 0;
  for (auto& col : columns) {
    for (;;) {
      std::size_t lead = row_count;
      for (std::size_t w = col.size(); w-- > 0;)
        if (col[w] != 0) {
          lead = w * 64 + 63 - static_cast<std::size_t>(__builtin_clzll(col[w]));
          break;
        }
      if (lead == row_count) break;
      if (basis[lead].empty()) {
        basis[lead] = col;
        ++rank;
        break;
      }
      for (std::size_t w = 0; w < col.size(); ++w) col[w] ^= basis[lead][w];
    }
  }
  return rank;
}

DenseResult dense_betti(const std::vector<Simplex>& tops) {
  std::array<std::set<Simplex>, 4> cells;
  for (const Simplex& s : tops)
    for (unsigned mask = 1; mask < (1u << s.size()); ++mask) {
      Simplex face;
      for (std::size_t k = 0; k < s.size(); ++k)
        if (mask & (1u << k)) face.push_back(s[k]);
      cells[face.size() - 1].insert(face);
    }
  std::array<std::map<Simplex, std::size_t>, 4> id;
  DenseResult result;
  for (int d = 0; d < 4; ++d) {
    for (const Simplex& s : cells[d]) id[d].emplace(s, id[d].size());
    result.counts[d] = static_cast<std::int64_t>(cells[d].size());
  }
  std::array<std::int64_t, 5> rank{};
  for (int d = 1; d < 4; ++d) {
    const std::size_t rows = cells[d - 1].size();
    std::vector<std::vector<std::uint64_t>> columns;
    for (const Simplex& s : cells[d]) {
      std::vector<std::uint64_t> col((rows + 63) / 64, 0);
      for (std::size_t drop = 0; drop < s.size(); ++drop) {
        Simplex face;
        for (std::size_t k = 0; k < s.size(); ++k)
          if (k != drop) face.push_back(s[k]);
        const std::size_t r = id[d - 1].at(face);
        col[r / 64] ^= std::uint64_t{1} << (r % 64);
      }
      columns.push_back(std::move(col));
    }
    rank[d] = dense_rank(std::move(columns), rows);
  }
  for (int d = 0; d < 4; ++d) result.betti[d] = result.counts[d] - rank[d] - rank[d + 1];
  return result;
}

Simplex sorted(std::vector<VertId> s) {
  std::sort(s.begin(), s.end());
  return s;
}

// The complexes of the report, defined again from scratch with std::map.
std::map<std::string, std::vector<Simplex>> brute_force_tops(const MeshData& m) {
  std::map<std::string, std::vector<Simplex>> tops;
  tops["mesh"];
  tops["boundary"];
  tops["all surfaces"];
  tops["all polylines"];
  tops["embedded"];
  std::map<Simplex, std::vector<std::size_t>> face_tets;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const auto& v = m.tets[t];
    const Simplex s = sorted({v[0], v[1], v[2], v[3]});
    tops["mesh"].push_back(s);
    tops["material " + std::to_string(m.tet_material[t])].push_back(s);
    for (int drop = 0; drop < 4; ++drop) {
      Simplex f = s;
      f.erase(f.begin() + drop);
      face_tets[f].push_back(t);
    }
  }
  for (const auto& [f, tets] : face_tets) {
    if (tets.size() == 1) tops["boundary"].push_back(f);
    if (tets.size() == 2 && m.tet_material[tets[0]] != m.tet_material[tets[1]]) {
      const auto a = std::min(m.tet_material[tets[0]], m.tet_material[tets[1]]);
      const auto b = std::max(m.tet_material[tets[0]], m.tet_material[tets[1]]);
      tops["interface " + std::to_string(a) + "," + std::to_string(b)].push_back(f);
      tops["all surfaces"].push_back(f);
      tops["embedded"].push_back(f);
    }
  }
  for (const auto& tri : m.triangles) {
    const Simplex s = sorted({tri.v[0], tri.v[1], tri.v[2]});
    tops["surface " + std::to_string(tri.ref)].push_back(s);
    tops["all surfaces"].push_back(s);
    tops["embedded"].push_back(s);
  }
  for (const auto& seg : m.segments) {
    const Simplex s = sorted({seg.v[0], seg.v[1]});
    tops["polyline " + std::to_string(seg.ref)].push_back(s);
    tops["all polylines"].push_back(s);
    tops["embedded"].push_back(s);
  }
  for (VertId v : m.corners) tops["embedded"].push_back({v});
  for (VertId v : m.required_vertices) tops["embedded"].push_back({v});
  return tops;
}

std::map<std::string, ComplexTopology> report_by_name(const TopologyReport& r) {
  std::map<std::string, ComplexTopology> out = {{"mesh", r.mesh},
                                                {"boundary", r.boundary},
                                                {"all surfaces", r.all_surfaces},
                                                {"all polylines", r.all_polylines},
                                                {"embedded", r.embedded}};
  for (const auto& [k, t] : r.materials) out["material " + std::to_string(k)] = t;
  for (const auto& [k, t] : r.surfaces) out["surface " + std::to_string(k)] = t;
  for (const auto& [k, t] : r.interfaces) out["interface " + std::to_string(k.first) + "," + std::to_string(k.second)] = t;
  for (const auto& [k, t] : r.polylines) out["polyline " + std::to_string(k)] = t;
  return out;
}

TEST(TopologyCrossCheck, RandomSubcomplexesMatchDenseElimination) {
  const MeshData grid = full_grid(4, 4, 4);
  // Candidate substructures: every tet face and tet edge of the full grid.
  std::set<Simplex> all_faces, all_edges;
  for (const auto& t : grid.tets) {
    const Simplex s = sorted({t[0], t[1], t[2], t[3]});
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        all_edges.insert({s[a], s[b]});
        for (int c = b + 1; c < 4; ++c) all_faces.insert({s[a], s[b], s[c]});
      }
  }
  const std::vector<Simplex> faces(all_faces.begin(), all_faces.end()), edges(all_edges.begin(), all_edges.end());
  std::int64_t complexes_checked = 0, nontrivial_b1 = 0, nontrivial_b2 = 0;
  for (std::uint32_t seed = 1; seed <= 100; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    const double keep_tet = 0.3 + 0.65 * unit(rng);
    const double keep_face = 0.02 + 0.3 * unit(rng);
    const double keep_edge = 0.02 + 0.1 * unit(rng);
    MeshData m;
    m.positions = grid.positions;
    for (std::size_t t = 0; t < grid.tets.size(); ++t)
      if (unit(rng) < keep_tet) {
        m.tets.push_back(grid.tets[t]);
        m.tet_material.push_back(1 + static_cast<std::int32_t>(rng() % 3));
      }
    for (const Simplex& f : faces)
      if (unit(rng) < keep_face) m.triangles.push_back({{f[0], f[1], f[2]}, static_cast<std::int32_t>(rng() % 2)});
    for (const Simplex& e : edges)
      if (unit(rng) < keep_edge) m.segments.push_back({{e[0], e[1]}, 1 + static_cast<std::int32_t>(rng() % 3)});
    for (int k = 0; k < 3; ++k) m.corners.push_back(static_cast<VertId>(rng() % m.positions.size()));

    const TopologyReport full = compute_topology(m);
    const TopologyReport fast = compute_topology(m, {.fast = true});
    {
      std::set<Simplex> tet_faces, tet_edges;
      for (const auto& t : m.tets) {
        const Simplex s = sorted({t[0], t[1], t[2], t[3]});
        for (int a = 0; a < 4; ++a)
          for (int b = a + 1; b < 4; ++b) {
            tet_edges.insert({s[a], s[b]});
            for (int c = b + 1; c < 4; ++c) tet_faces.insert({s[a], s[b], s[c]});
          }
      }
      const auto detached_triangles = std::count_if(m.triangles.begin(), m.triangles.end(), [&](const Triangle& t) {
        return !tet_faces.count(sorted({t.v[0], t.v[1], t.v[2]}));
      });
      const auto detached_segments = std::count_if(m.segments.begin(), m.segments.end(), [&](const Segment& e) {
        return !tet_edges.count(sorted({e.v[0], e.v[1]}));
      });
      EXPECT_EQ(full.detached_triangle_count, static_cast<std::uint64_t>(detached_triangles));
      EXPECT_EQ(full.detached_segment_count, static_cast<std::uint64_t>(detached_segments));
    }
    const auto got = report_by_name(full), got_fast = report_by_name(fast);
    const auto tops = brute_force_tops(m);
    ASSERT_EQ(got.size(), tops.size()) << "seed " << seed;
    for (const auto& [name, simplices] : tops) {
      SCOPED_TRACE("seed " + std::to_string(seed) + ", " + name);
      ASSERT_TRUE(got.count(name));
      const DenseResult expected = dense_betti(simplices);
      EXPECT_EQ(got.at(name).betti, expected.betti);
      EXPECT_EQ(got.at(name).simplex_count, expected.counts);
      EXPECT_EQ(got_fast.at(name).betti[0], expected.betti[0]);
      EXPECT_EQ(got_fast.at(name).euler_characteristic, got.at(name).euler_characteristic);
      ++complexes_checked;
      nontrivial_b1 += expected.betti[1] > 0;
      nontrivial_b2 += expected.betti[2] > 0;
    }
    std::string d;
    EXPECT_TRUE(same_topology(full, fast, &d)) << d;
  }
  // The random cases must actually exercise loops and cavities.
  EXPECT_GT(nontrivial_b1, 50);
  EXPECT_GT(nontrivial_b2, 20);
  std::cout << "[ cross-check ] " << complexes_checked << " complexes, " << nontrivial_b1 << " with b1 > 0, "
            << nontrivial_b2 << " with b2 > 0\n";
}

// ---------------------------------------------------------------------------------------------
// The manifold fast path (metrics/manifold_betti.h) against the reference reduction.

// Everything but the informative certified-complex count.
void expect_same_reports(TopologyReport fast, const TopologyReport& reference, const std::string& what) {
  fast.certified_manifold_count = reference.certified_manifold_count;
  EXPECT_TRUE(fast == reference) << what << ": " << diff_of(reference, fast);
}

TEST(TopologyManifoldFastPath, PlantedMeshesMatchTheReduction) {
  std::uint64_t certified = 0;
  for (const testing::PlantedMesh& planted : testing::planted_meshes()) {
    const MeshData m = planted.make().data;
    const TopologyReport fast = compute_topology(m);
    const TopologyReport reference = compute_topology(m, {.manifold_fast_path = false});
    EXPECT_EQ(reference.certified_manifold_count, 0u);
    certified += fast.certified_manifold_count;
    expect_same_reports(fast, reference, planted.name);
  }
  // The planted meshes are manifolds almost everywhere: the fast path must carry most complexes.
  EXPECT_GT(certified, 4 * testing::planted_meshes().size());
}

// Random solids and surfaces: jittered grids with random holes (whole cubes: tunnels, cavities,
// several components, and pinched edges and vertices where holes meet diagonally), materials split
// at random planes (interfaces with boundaries and corners), and listed patches of a grid plane
// with random tets' faces (surfaces with holes, non-manifold fans). Every certified complex must
// give the reduction's Betti numbers, and both certificates must be accepted and refused often.
TEST(TopologyManifoldFastPath, RandomSubsetsMatchTheReduction) {
  std::uint64_t certified = 0, refused = 0, with_loops = 0, with_cavities = 0;
  constexpr int kN = 5;
  for (std::uint32_t seed = 1; seed <= 80; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    const double hole = 0.35 * unit(rng);
    const int cut_i = static_cast<int>(rng() % kN), cut_j = static_cast<int>(rng() % kN);
    std::vector<int> cube_material(kN * kN * kN);
    for (int& c : cube_material) c = unit(rng) < hole ? -1 : 0;
    testing::Grid grid = testing::make_grid(
        kN, kN, kN,
        [&](int i, int j, int k) {
          return cube_material[static_cast<std::size_t>(i + kN * (j + kN * k))] < 0 ? -1
                                                                                   : 1 + (i >= cut_i) + 2 * (j >= cut_j);
        },
        0.12, seed);
    MeshData& m = grid.data;
    const int plane = 1 + static_cast<int>(rng() % (kN - 1));
    const auto level = [&](VertId v) { return static_cast<int>(v / ((kN + 1) * (kN + 1))); };
    for (const auto& t : m.tets)
      for (int f = 0; f < 4; ++f) {
        const VertId a = t[(f + 1) % 4], b = t[(f + 2) % 4], c = t[(f + 3) % 4];
        const bool on_plane = level(a) == plane && level(b) == plane && level(c) == plane;
        if ((on_plane && unit(rng) < 0.85) || unit(rng) < 0.002)
          m.triangles.push_back({{a, b, c}, on_plane ? 7 : 8});
      }
    const TopologyReport fast = compute_topology(m);
    const TopologyReport reference = compute_topology(m, {.manifold_fast_path = false});
    const std::size_t complexes = 6 + reference.materials.size() + reference.surfaces.size() +
                                  reference.interfaces.size() + reference.polylines.size();
    certified += fast.certified_manifold_count;
    refused += complexes - fast.certified_manifold_count;
    expect_same_reports(fast, reference, "seed " + std::to_string(seed));
    for (const ComplexTopology* t : {&reference.mesh, &reference.boundary}) {
      with_loops += t->betti[1] > 0;
      with_cavities += t->betti[2] > 0;
    }
  }
  EXPECT_GT(certified, 300u);
  EXPECT_GT(refused, 100u);
  EXPECT_GT(with_loops, 40u);    // tunnels through the solid, handles on its boundary
  EXPECT_GT(with_cavities, 40u);  // cavities, several boundary components
  std::cout << "[ fast path ] " << certified << " complexes certified, " << refused << " by the reduction; "
            << with_loops << " with b1 > 0, " << with_cavities << " with b2 > 0\n";
}

// A solid whose coordinates put tets on top of each other is no embedding: the solid certificate
// is not tried when a tet is inverted, and the answers stay the reduction's.
TEST(TopologyManifoldFastPath, InvertedTetsKeepSolidsOnTheReduction) {
  MeshData m = full_grid(3, 3, 2);
  std::swap(m.tets[5][0], m.tets[5][1]);  // inverted, still the same combinatorial ball
  const TopologyReport fast = compute_topology(m);
  const TopologyReport reference = compute_topology(m, {.manifold_fast_path = false});
  expect_same_reports(fast, reference, "inverted tet");
  EXPECT_EQ(fast.inverted_tet_count, 1u);
  // Only surfaces (boundary, all surfaces, features...) may be certified, never the mesh.
  MeshData valid = full_grid(3, 3, 2);
  EXPECT_GT(compute_topology(valid).certified_manifold_count, fast.certified_manifold_count);
}

// ---------------------------------------------------------------------------------------------
// Output formats.

TEST(TopologyReportFormat, TableAndJsonNameEveryComplex) {
  Grid g(3, 3, 3);
  g.fill(3, 3, 3, [](int i, int j, int k) { return (i == 1 && j == 1 && k == 1) ? 2 : 1; });
  g.add_path({g.v(0, 0, 0), g.v(1, 0, 0)}, 4);
  add_triangles(g.mesh, tet_faces_where(g.mesh, on_box_surface(0, 3)), 6);
  const TopologyReport r = compute_topology(g.mesh);
  const std::string table = format_topology_table(r);
  for (const char* name : {"mesh", "boundary", "material 1", "material 2", "surface ref 6", "interface (1,2)",
                           "all surfaces", "polyline ref 4", "all polylines", "embedded structure", "inverted tets: 0"})
    EXPECT_NE(table.find(name), std::string::npos) << name << "\n" << table;
  const std::string json = topology_to_json(r);
  EXPECT_EQ(json.front(), '{');
  EXPECT_EQ(json.back(), '}');
  EXPECT_NE(json.find("\"interfaces\":{\"1,2\":{\"simplices\":[8,18,12,0],\"betti\":[1,0,1,0],\"euler\":2}}"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find("\"polylines\":{\"4\":"), std::string::npos) << json;
  const std::string fast_json = topology_to_json(compute_topology(g.mesh, {.fast = true}));
  EXPECT_NE(fast_json.find("\"betti\":[1,null,null,null]"), std::string::npos) << fast_json;
  EXPECT_NE(format_topology_table(compute_topology(g.mesh, {.fast = true})).find("?"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// Timings (printed; the only bounds asserted are loose, to catch accidental quadratic behaviour).

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST(TopologyPerf, ThreeThousandTetsPerCall) {
  Grid g(10, 10, 5);
  g.fill(10, 10, 5, [](int i, int j, int k) { return (i >= 3 && i < 7 && j >= 3 && j < 7 && k >= 1 && k < 4) ? 2 : 1; });
  add_triangles(g.mesh, tet_faces_where(g.mesh, [](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
                  return a.z == 0 && b.z == 0 && c.z == 0;
                }),
                1);
  g.add_path({g.v(0, 0, 5), g.v(1, 0, 5), g.v(2, 0, 5), g.v(3, 0, 5)}, 1);
  ASSERT_EQ(g.mesh.tets.size(), 3000u);
  const TopologyReport reference = compute_topology(g.mesh);
  EXPECT_EQ(reference.interfaces.at({1, 2}).betti, (Betti{1, 0, 1, 0}));
#ifdef NDEBUG
  constexpr int kCalls = 100;
#else
  constexpr int kCalls = 10;  // unoptimised builds are ~20x slower; the loop only measures
#endif
  auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kCalls; ++i) EXPECT_EQ(compute_topology(g.mesh), reference);
  const double full_ms = 1e3 * seconds_since(start) / kCalls;
  start = std::chrono::steady_clock::now();
  for (int i = 0; i < kCalls; ++i) compute_topology(g.mesh, {.fast = true});
  const double fast_ms = 1e3 * seconds_since(start) / kCalls;
  std::cout << "[ timing ] 3000 tets: full " << full_ms << " ms/call, fast " << fast_ms << " ms/call\n";
  RecordProperty("full_ms_per_call", std::to_string(full_ms));
#ifdef NDEBUG
  EXPECT_LT(full_ms, 200.0);  // ~1-2 ms expected; only a blow-up should fail here
#endif
}

TEST(SlowTopology, MillionTets) {
  auto start = std::chrono::steady_clock::now();
  Grid g(55, 55, 55);
  // Two materials (an inclusion) and a listed boundary patch, so every kind of complex is big.
  g.fill(55, 55, 55, [](int i, int j, int k) {
    return (i >= 10 && i < 40 && j >= 10 && j < 40 && k >= 10 && k < 40) ? 2 : 1;
  });
  for (int j = 0; j < 55; ++j)
    for (int i = 0; i < 55; ++i) {
      g.mesh.triangles.push_back({{g.v(i, j, 0), g.v(i + 1, j, 0), g.v(i + 1, j + 1, 0)}, 3});
      g.mesh.triangles.push_back({{g.v(i, j, 0), g.v(i, j + 1, 0), g.v(i + 1, j + 1, 0)}, 3});
    }
  std::vector<VertId> path;
  for (int i = 0; i <= 55; ++i) path.push_back(g.v(i, 0, 55));
  g.add_path(path, 1);
  const double build_s = seconds_since(start);
  ASSERT_EQ(g.mesh.tets.size(), 998'250u);

  start = std::chrono::steady_clock::now();
  const TopologyReport fast = compute_topology(g.mesh, {.fast = true});
  const double fast_s = seconds_since(start);
  start = std::chrono::steady_clock::now();
  const TopologyReport full = compute_topology(g.mesh);
  const double full_s = seconds_since(start);
  std::cout << "[ timing ] 998,250 tets: full " << full_s << " s, fast " << fast_s << " s (grid built in " << build_s
            << " s)\n";

  EXPECT_EQ(full.mesh.betti, (Betti{1, 0, 0, 0}));
  EXPECT_EQ(full.boundary.betti, (Betti{1, 0, 1, 0}));
  EXPECT_EQ(full.materials.at(1).betti, (Betti{1, 0, 1, 0}));
  EXPECT_EQ(full.materials.at(2).betti, (Betti{1, 0, 0, 0}));
  EXPECT_EQ(full.interfaces.at({1, 2}).betti, (Betti{1, 0, 1, 0}));
  EXPECT_EQ(full.surfaces.at(3).betti, (Betti{1, 0, 0, 0}));
  EXPECT_EQ(full.polylines.at(1).betti, (Betti{1, 0, 0, 0}));
  EXPECT_EQ(full.inverted_tet_count, 0u);
  std::string d;
  EXPECT_TRUE(same_topology(full, fast, &d)) << d;
}

}  // namespace
}  // namespace topotet::metrics
