// Small hand-built meshes with planted substructures, for the kernel's unit and property tests.
//
// A Freudenthal grid of nx*ny*nz cubes of size 1, each split into 6 tets around its diagonal from
// its min corner to its max corner. Every axis-aligned square of the grid is then split along its
// diagonal from min to max corner, so a planar patch of squares is a set of mesh faces, and a
// grid line is a chain of mesh edges. Vertices are jittered (interior ones in 3D, boundary ones
// tangentially) so that collapses are not all degenerate.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "mesh/glm_convert.h"
#include "topotet/mesh_data.h"

namespace topotet::testing {

struct Grid {
  MeshData data;
  int nx = 0, ny = 0, nz = 0;
  VertId vid(int i, int j, int k) const {
    return static_cast<VertId>(i + (nx + 1) * (j + (ny + 1) * k));
  }
};

inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// material(i, j, k) of cube (i, j, k); return a negative value to leave the cube out (a hole).
inline Grid make_grid(int nx, int ny, int nz, const std::function<int(int, int, int)>& material,
                      double jitter = 0.12, std::uint64_t seed = 1) {
  Grid g;
  g.nx = nx;
  g.ny = ny;
  g.nz = nz;
  auto rnd = [&](std::uint64_t key) {
    return (static_cast<double>(splitmix64(seed * 0x100000001B3ull ^ key) >> 11) * 0x1.0p-53 - 0.5) * 2.0 * jitter;
  };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const VertId v = g.vid(i, j, k);
        glm::dvec3 p(i, j, k);
        if (i > 0 && i < nx) p.x += rnd(3 * v + 0);
        if (j > 0 && j < ny) p.y += rnd(3 * v + 1);
        if (k > 0 && k < nz) p.z += rnd(3 * v + 2);
        g.data.positions.push_back(from_glm(p));
      }
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int m = material(i, j, k);
        if (m < 0) continue;
        for (const auto& perm : perms) {
          int c[3] = {i, j, k};
          std::array<VertId, 4> t{};
          t[0] = g.vid(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[perm[s]];
            t[s + 1] = g.vid(c[0], c[1], c[2]);
          }
          // Odd permutations give negatively oriented Kuhn simplices on the unit cube.
          const bool odd = (perm[0] == 0 && perm[1] == 2) || (perm[0] == 1 && perm[1] == 0) ||
                           (perm[0] == 2 && perm[1] == 1);
          if (odd) std::swap(t[2], t[3]);
          g.data.tets.push_back(t);
          g.data.tet_material.push_back(m);
        }
      }
  return g;
}

// The unit square of the grid plane `axis` = level with lower corner (a, b) in the other two axes
// (in increasing axis order), as two triangles split along its min-max diagonal.
inline void add_square(Grid& g, int axis, int level, int a, int b, std::int32_t ref) {
  const int ax_a = axis == 0 ? 1 : 0;  // the other two axes, in increasing order
  const int ax_b = axis == 2 ? 1 : 2;
  auto at = [&](int da, int db) {
    int c[3];
    c[axis] = level;
    c[ax_a] = a + da;
    c[ax_b] = b + db;
    return g.vid(c[0], c[1], c[2]);
  };
  g.data.triangles.push_back({{at(0, 0), at(1, 0), at(1, 1)}, ref});
  g.data.triangles.push_back({{at(0, 0), at(0, 1), at(1, 1)}, ref});
}

// A planar patch: every square (a, b) of plane axis = level for which in_patch(a, b).
inline void add_patch(Grid& g, int axis, int level, const std::function<bool(int, int)>& in_patch, std::int32_t ref) {
  const int n[3] = {g.nx, g.ny, g.nz};
  const int ax_a = axis == 0 ? 1 : 0;
  const int ax_b = axis == 2 ? 1 : 2;
  for (int a = 0; a < n[ax_a]; ++a)
    for (int b = 0; b < n[ax_b]; ++b)
      if (in_patch(a, b)) add_square(g, axis, level, a, b, ref);
}

// A polyline through grid points, consecutive points one grid step apart along an axis.
inline void add_polyline(Grid& g, const std::vector<std::array<int, 3>>& points, std::int32_t ref) {
  for (std::size_t s = 0; s + 1 < points.size(); ++s) {
    const auto& p = points[s];
    const auto& q = points[s + 1];
    g.data.segments.push_back({{g.vid(p[0], p[1], p[2]), g.vid(q[0], q[1], q[2])}, ref});
  }
}

// Grid points from `from` to `to` along one axis (inclusive).
inline std::vector<std::array<int, 3>> grid_line(std::array<int, 3> from, std::array<int, 3> to) {
  std::vector<std::array<int, 3>> pts;
  std::array<int, 3> p = from;
  pts.push_back(p);
  while (p != to) {
    for (int a = 0; a < 3; ++a)
      if (p[a] != to[a]) {
        p[a] += to[a] > p[a] ? 1 : -1;
        break;
      }
    pts.push_back(p);
  }
  return pts;
}

// Every boundary face of the grid box listed with `ref` (a surface substructure on the boundary).
inline void add_box_boundary(Grid& g, std::int32_t ref) {
  add_patch(g, 0, 0, [](int, int) { return true; }, ref);
  add_patch(g, 0, g.nx, [](int, int) { return true; }, ref);
  add_patch(g, 1, 0, [](int, int) { return true; }, ref);
  add_patch(g, 1, g.ny, [](int, int) { return true; }, ref);
  add_patch(g, 2, 0, [](int, int) { return true; }, ref);
  add_patch(g, 2, g.nz, [](int, int) { return true; }, ref);
}

inline void add_linear_field(Grid& g) {
  VertexField f{"f", 1, {}};
  for (const auto& p : g.data.positions) f.values.push_back(p[0] + 2.0 * p[1] - 0.5 * p[2]);
  g.data.fields.push_back(std::move(f));
}

// --- the planted meshes of the property tests (each a few thousand tets at most) ---

struct PlantedMesh {
  const char* name;
  std::function<Grid()> make;
};

inline std::vector<PlantedMesh> planted_meshes() {
  std::vector<PlantedMesh> out;
  out.push_back({"ball_in_box_with_listed_boundary", [] {
                   Grid g = make_grid(6, 6, 6, [](int i, int j, int k) {
                     return (i >= 2 && i < 4 && j >= 2 && j < 4 && k >= 2 && k < 4) ? 2 : 1;
                   });
                   add_box_boundary(g, 10);
                   add_linear_field(g);
                   return g;
                 }});
  out.push_back({"surface_with_hole_and_crossing_polyline", [] {
                   Grid g = make_grid(7, 7, 6, [](int, int, int) { return 1; });
                   add_patch(g, 2, 3, [](int a, int b) { return a >= 1 && a < 6 && b >= 1 && b < 6 && !(a == 3 && b == 3); }, 5);
                   add_polyline(g, grid_line({2, 2, 1}, {2, 2, 5}), 7);  // pierces the patch at (2,2,3)
                   add_linear_field(g);
                   return g;
                 }});
  out.push_back({"three_materials_meeting_along_an_edge", [] {
                   Grid g = make_grid(6, 6, 4, [](int i, int j, int) { return i >= 3 ? 3 : (j >= 3 ? 2 : 1); });
                   add_linear_field(g);
                   return g;
                 }});
  out.push_back({"layer_one_tet_thick", [] {
                   Grid g = make_grid(6, 6, 5, [](int, int, int k) { return k == 2 ? 2 : 1; });
                   add_linear_field(g);
                   return g;
                 }});
  out.push_back({"polyline_junction_of_three_branches", [] {
                   Grid g = make_grid(7, 7, 4, [](int, int, int) { return 1; });
                   add_polyline(g, grid_line({1, 3, 2}, {3, 3, 2}), 1);
                   add_polyline(g, grid_line({3, 3, 2}, {6, 3, 2}), 2);
                   add_polyline(g, grid_line({3, 3, 2}, {3, 6, 2}), 3);
                   g.data.corners.push_back(g.vid(0, 0, 0));
                   add_linear_field(g);
                   return g;
                 }});
  out.push_back({"ring_material_with_polyline_through_hole", [] {
                   // A square ring (solid torus) of material 2 around a hole of material 1,
                   // threaded by a polyline through the hole.
                   Grid g = make_grid(7, 7, 5, [](int i, int j, int k) {
                     const bool in_square = i >= 1 && i < 6 && j >= 1 && j < 6 && k >= 1 && k < 4;
                     const bool in_hole = i >= 2 && i < 5 && j >= 2 && j < 5;
                     return in_square && !in_hole ? 2 : 1;
                   });
                   add_polyline(g, grid_line({3, 3, 0}, {3, 3, 5}), 4);
                   add_linear_field(g);
                   return g;
                 }});
  out.push_back({"surface_on_part_of_boundary_and_tunnel", [] {
                   // K itself has a tunnel (a hole through the box); a listed patch covers part of
                   // the bottom boundary (a substructure that touches and lies on the boundary).
                   Grid g = make_grid(6, 6, 4, [](int i, int j, int) { return (i >= 2 && i < 4 && j >= 2 && j < 4) ? -1 : 1; });
                   add_patch(g, 2, 0, [](int a, int b) { return a < 3 && b < 2; }, 3);
                   add_linear_field(g);
                   return g;
                 }});
  return out;
}

}  // namespace topotet::testing
