// cube-sphere: a ball (material 2) in a cube (material 1).
//
// Substructures, all on the lattice so their topology depends on the grid size only:
//  - ref 1 triangles: the ball's surface (faces between materials 1 and 2), a closed sphere;
//  - ref 2 triangles: a square patch of the grid plane z = level, above the ball, in material 1,
//    touching neither the ball nor the box boundary (an open disc);
//  - ref 10 triangles: the box boundary (a sphere), so the boundary carries a surface too;
//  - ref 1 segments: a chain of grid edges along x from one cell inside the box face x = 0 to the
//    ball's centre; it pierces the ball's surface at one vertex, nearly perpendicular to it;
//  - corners: the 8 box corners.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "generate/freudenthal_grid.h"

namespace topotet::gen {

namespace {

// Grid, ball and polyline line: shared by the in-memory and the streamed generator.
struct Layout {
  FreudenthalGrid grid;
  glm::dvec3 center;
  double radius;
  std::array<std::uint32_t, 3> line;
  bool in_ball(const glm::dvec3& c) const {
    const glm::dvec3 d = c - center;
    return d.x * d.x + d.y * d.y + d.z * d.z < radius * radius;
  }
};

Layout make_layout(std::uint64_t target_tets) {
  // Below ~8 cells a side the ball and the patch above it no longer fit apart.
  check_target("cube-sphere", target_tets, 3000);
  const FreudenthalGrid grid(choose_cells(target_tets, {1.0, 1.0, 1.0}));
  const Cells& n = grid.cells();
  const double n_min = std::min({n[0], n[1], n[2]});

  // The ball sits low in the box to leave room for the patch above it; the small offsets keep it
  // off the lattice's symmetry planes (x is set below).
  glm::dvec3 center(0.5 * n[0], 0.5 * n[1] - 0.09, 0.42 * n[2] + 0.05);
  const double radius = 0.27 * n_min;
  // The polyline runs along x on the grid line nearest the centre. The 6 tets around an x edge
  // have centroids 1/4, 1/2 and 3/4 of the way along it, so a surface crossing the line within
  // 1/4 cell of an edge's middle cuts through its tets and the edge lies on the interface. Shift
  // the ball along x so that the line meets the sphere exactly at a lattice point: the crossing
  // is then a single vertex, with every tet around the edges on either side on one side of it.
  const std::array<std::uint32_t, 3> line = {1, static_cast<std::uint32_t>(std::lround(center.y)),
                                             static_cast<std::uint32_t>(std::lround(center.z))};
  const double dy = line[1] - center.y, dz = line[2] - center.z;
  const double half_chord = std::sqrt(radius * radius - dy * dy - dz * dz);
  center.x = std::round(center.x - half_chord) + half_chord;
  return {grid, center, radius, line};
}

// The patch goes at least a cell above the highest ball vertex (`top`: one past the highest
// layer of ball tets).
std::uint32_t patch_level(const Cells& n, std::uint32_t top) {
  const std::uint32_t level = std::max(top + 1, static_cast<std::uint32_t>(std::lround(0.85 * n[2])));
  if (level + 1 > n[2]) throw std::logic_error("cube-sphere: no room for the patch above the ball");
  return level;
}

std::uint32_t at(std::uint32_t cells, double fraction) { return static_cast<std::uint32_t>(std::lround(fraction * cells)); }

void add_patch(const FreudenthalGrid& grid, std::uint32_t level, MeshData& mesh) {
  const Cells& n = grid.cells();
  add_plane_patch(grid, 2, level, {at(n[0], 0.25), at(n[1], 0.25)}, {at(n[0], 0.75), at(n[1], 0.75)}, 2, mesh);
}

void add_polyline(const Layout& l, MeshData& mesh) {
  add_chain(l.grid, l.line, {1, 0, 0}, static_cast<std::uint32_t>(std::lround(l.center.x)) - l.line[0], 1, mesh);
}

}  // namespace

MeshData generate_cube_sphere(std::uint64_t target_tets, std::uint64_t seed) {
  const Layout l = make_layout(target_tets);
  const FreudenthalGrid& grid = l.grid;
  const Cells& n = grid.cells();
  MeshData mesh;
  build_tets(grid, [&](const glm::dvec3& c) { return l.in_ball(c) ? 2 : 1; }, mesh);
  repair_pinches(grid, 2, 1, mesh);
  set_jittered_positions(grid, seed, mesh);

  add_interface_triangles(grid, [](std::int32_t, std::int32_t) { return 1; }, mesh);

  std::uint32_t top = 0;
  const std::uint64_t tets_per_layer = 6ull * n[0] * n[1];
  for (std::size_t t = 0; t < mesh.tet_count(); ++t) {
    if (mesh.tet_material[t] == 2) top = std::max(top, static_cast<std::uint32_t>(t / tets_per_layer) + 1);
  }
  add_patch(grid, patch_level(n, top), mesh);
  add_boundary_triangles(grid, 10, mesh);
  add_polyline(l, mesh);
  add_box_corners(grid, mesh);
  add_feature_field(grid, mesh);
  return mesh;
}

// Streaming: the materials differ from 1 only in and near the ball, so only the box of cells
// around it (plus kMargin cells, which the pinch repair never reaches: checked) is built in
// memory, as a grid of its own. The Kuhn split is the same in every cube and repair_pinches
// visits vertices in lattice order, doing nothing where no ball tet is near, so repairing the
// sub-grid gives the full grid's materials. Everything else is computed in closed form, layer by
// layer, in the in-memory generator's order.
void stream_cube_sphere(std::uint64_t target_tets, std::uint64_t seed, GenerateSink& sink) {
  constexpr std::uint32_t kMargin = 4;
  const Layout l = make_layout(target_tets);
  const FreudenthalGrid& grid = l.grid;
  const Cells& n = grid.cells();
  Cells lo{}, hi{};
  for (int a = 0; a < 3; ++a) {
    const double from = std::floor(l.center[a] - l.radius) - kMargin, to = std::ceil(l.center[a] + l.radius) + kMargin;
    lo[a] = static_cast<std::uint32_t>(std::clamp(from, 0.0, double(n[a])));
    hi[a] = static_cast<std::uint32_t>(std::clamp(to, 0.0, double(n[a])));
  }
  const FreudenthalGrid box({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const glm::dvec3 offset(lo[0], lo[1], lo[2]);
  MeshData ball;
  build_tets(box, [&](const glm::dvec3& c) { return l.in_ball(c + offset) ? 2 : 1; }, ball);
  repair_pinches(box, 2, 1, ball);
  std::uint32_t top = 0;
  {
    const Cells& b = box.cells();
    std::size_t t = 0;
    for (std::uint32_t k = 0; k < b[2]; ++k)
      for (std::uint32_t j = 0; j < b[1]; ++j)
        for (std::uint32_t i = 0; i < b[0]; ++i)
          for (int p = 0; p < 6; ++p, ++t) {
            if (ball.tet_material[t] != 2) continue;
            top = std::max(top, lo[2] + k + 1);
            // A ball tet near a side of the box that is inside the grid: the repair may have
            // been cut short there.
            const std::uint32_t c[3] = {i, j, k};
            for (int a = 0; a < 3; ++a) {
              if ((lo[a] > 0 && c[a] < 2) || (hi[a] < n[a] && c[a] + 2 >= b[a]))
                throw std::logic_error("cube-sphere: the ball reaches the streaming margin");
            }
          }
  }
  const auto material = [&](TetId t) -> std::int32_t {
    const std::uint64_t cube = t / 6;
    const std::uint64_t i = cube % n[0], j = cube / n[0] % n[1], k = cube / n[0] / n[1];
    if (i < lo[0] || j < lo[1] || k < lo[2] || i >= hi[0] || j >= hi[1] || k >= hi[2]) return 1;
    return ball.tet_material[box.tet(static_cast<std::uint32_t>(i - lo[0]), static_cast<std::uint32_t>(j - lo[1]),
                                     static_cast<std::uint32_t>(k - lo[2]), static_cast<int>(t % 6))];
  };

  sink.begin_vertices(grid.vertex_count());
  const std::uint64_t key = splitmix64(seed);
  for (std::uint32_t k = 0; k <= n[2]; ++k) {
    const bool keep_z = k == 0 || k == n[2];
    for (std::uint32_t j = 0; j <= n[1]; ++j)
      for (std::uint32_t i = 0; i <= n[0]; ++i) {
        const std::array<double, 3> p = jittered_position(grid, key, i, j, k, keep_z);
        sink.vertex(p, feature_value(grid, p));
      }
  }
  sink.begin_tets(grid.tet_count());
  {
    TetId t = 0;
    for (std::uint32_t k = 0; k < n[2]; ++k)
      for (std::uint32_t j = 0; j < n[1]; ++j)
        for (std::uint32_t i = 0; i < n[0]; ++i)
          for (int p = 0; p < 6; ++p, ++t) sink.tet(kuhn_tet(grid, i, j, k, p), material(t));
  }
  // Triangles: interfaces and boundary in for_each_face order (one pass to count them), the patch
  // between them.
  const auto face = [&](TetId t, int local_face, bool inward, std::int32_t ref) {
    const std::array<VertId, 4> v = kuhn_tet(grid, t);
    const auto& f = kOutwardFace[local_face];
    Triangle tri{{v[f[0]], v[f[1]], v[f[2]]}, ref};
    if (inward) std::swap(tri.v[1], tri.v[2]);
    return tri;
  };
  std::uint64_t interface_count = 0, boundary_count = 0;
  for_each_face(grid, [&](TetId t, int, TetId nb) {
    if (nb == kInvalid) ++boundary_count;
    else if (material(t) != material(nb)) ++interface_count;
  });
  MeshData small;  // the patch, the polyline and the corners: at most one layer's worth
  add_patch(grid, patch_level(n, top), small);
  add_polyline(l, small);
  add_box_corners(grid, small);
  sink.begin_triangles(interface_count + small.triangles.size() + boundary_count);
  for_each_face(grid, [&](TetId t, int f, TetId nb) {
    if (nb == kInvalid) return;
    const std::int32_t mt = material(t), mn = material(nb);
    if (mt != mn) sink.triangle(face(t, f, mt < mn, 1));
  });
  for (const Triangle& tri : small.triangles) sink.triangle(tri);
  for_each_face(grid, [&](TetId t, int f, TetId nb) {
    if (nb == kInvalid) sink.triangle(face(t, f, false, 10));
  });
  sink.begin_segments(small.segments.size());
  for (const Segment& s : small.segments) sink.segment(s);
  sink.begin_corners(small.corners.size());
  for (VertId v : small.corners) sink.corner(v);
}

}  // namespace topotet::gen
