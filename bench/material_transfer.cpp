#include "material_transfer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "mesh/glm_convert.h"

namespace topotet::bench {
namespace {

double volume6(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  return glm::dot(b - a, glm::cross(c - a, d - a));
}

// Smallest barycentric coordinate of p in tet t: >= 0 inside, and the more negative the farther
// outside. Ratios of signed volumes, so the tet's orientation does not matter.
double min_barycentric(const MeshData& mesh, TetId t, const glm::dvec3& p) {
  std::array<glm::dvec3, 4> v;
  for (int k = 0; k < 4; ++k) v[k] = to_glm(mesh.positions[mesh.tets[t][k]]);
  const double whole = volume6(v[0], v[1], v[2], v[3]);
  if (whole == 0.0) return -std::numeric_limits<double>::infinity();
  double smallest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k) {
    std::array<glm::dvec3, 4> w = v;
    w[k] = p;
    smallest = std::min(smallest, volume6(w[0], w[1], w[2], w[3]) / whole);
  }
  return smallest;
}

// Tets binned by bounding box on a uniform grid of about one cell per tet (CSR layout).
struct TetGrid {
  glm::dvec3 lo{0.0};
  double cell = 1.0;
  std::array<int, 3> n{1, 1, 1};
  std::vector<std::uint32_t> start, items;

  std::array<int, 3> cell_of(const glm::dvec3& p) const {
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor((p[a] - lo[a]) / cell)), 0, n[a] - 1);
    return c;
  }
  std::size_t flat(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(n[1]) + static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(n[0]) + static_cast<std::size_t>(x);
  }
};

template <typename Visit>
void for_each_cell_of_tet(const TetGrid& grid, const MeshData& mesh, TetId t, Visit visit) {
  glm::dvec3 lo = to_glm(mesh.positions[mesh.tets[t][0]]), hi = lo;
  for (int k = 1; k < 4; ++k) {
    lo = glm::min(lo, to_glm(mesh.positions[mesh.tets[t][k]]));
    hi = glm::max(hi, to_glm(mesh.positions[mesh.tets[t][k]]));
  }
  const auto a = grid.cell_of(lo), b = grid.cell_of(hi);
  for (int z = a[2]; z <= b[2]; ++z)
    for (int y = a[1]; y <= b[1]; ++y)
      for (int x = a[0]; x <= b[0]; ++x) visit(grid.flat(x, y, z));
}

TetGrid build_grid(const MeshData& mesh) {
  TetGrid grid;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const auto& p : mesh.positions) lo = glm::min(lo, to_glm(p)), hi = glm::max(hi, to_glm(p));
  const glm::dvec3 extent = glm::max(hi - lo, glm::dvec3(1e-300));
  const double tets = std::max<double>(1.0, static_cast<double>(mesh.tet_count()));
  grid.lo = lo;
  grid.cell = std::cbrt(extent.x * extent.y * extent.z / tets) * 2.0;  // ~ a few tets per cell
  for (int a = 0; a < 3; ++a) grid.n[a] = std::clamp(static_cast<int>(std::ceil(extent[a] / grid.cell)), 1, 4096);

  const std::size_t cells = static_cast<std::size_t>(grid.n[0]) * grid.n[1] * grid.n[2];
  grid.start.assign(cells + 1, 0);
  for (TetId t = 0; t < mesh.tet_count(); ++t) for_each_cell_of_tet(grid, mesh, t, [&](std::size_t c) { ++grid.start[c + 1]; });
  for (std::size_t c = 0; c < cells; ++c) grid.start[c + 1] += grid.start[c];
  grid.items.resize(grid.start[cells]);
  std::vector<std::uint32_t> fill(grid.start.begin(), grid.start.end() - 1);
  for (TetId t = 0; t < mesh.tet_count(); ++t) for_each_cell_of_tet(grid, mesh, t, [&](std::size_t c) { grid.items[fill[c]++] = t; });
  return grid;
}

}  // namespace

MaterialTransfer transfer_materials(const MeshData& source, const MeshData& target) {
  MaterialTransfer result;
  result.tet_material.assign(target.tet_count(), 0);
  if (source.tet_count() == 0) return result;
  const TetGrid grid = build_grid(source);
  auto material_of = [&](TetId t) { return source.tet_material.empty() ? 0 : source.tet_material[t]; };

  // The material at p, and whether p lies inside some source tet.
  auto locate = [&](const glm::dvec3& p, bool& inside) {
    const auto home = grid.cell_of(p);
    double best = -std::numeric_limits<double>::infinity();
    TetId best_tet = kInvalid;
    auto scan = [&](std::size_t c) {
      for (std::uint32_t i = grid.start[c]; i < grid.start[c + 1]; ++i) {
        const double b = min_barycentric(source, grid.items[i], p);
        if (b > best) best = b, best_tet = grid.items[i];
      }
    };
    scan(grid.flat(home[0], home[1], home[2]));
    // Not inside any tet of its own cell: the boundary moved, so look around before giving up.
    if (best < 0.0)
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int x = home[0] + dx, y = home[1] + dy, z = home[2] + dz;
            if ((dx || dy || dz) && x >= 0 && y >= 0 && z >= 0 && x < grid.n[0] && y < grid.n[1] && z < grid.n[2])
              scan(grid.flat(x, y, z));
          }
    inside = best >= 0.0;
    return best_tet == kInvalid ? 0 : material_of(best_tet);
  };

  for (std::size_t t = 0; t < target.tet_count(); ++t) {
    std::array<glm::dvec3, 4> v;
    for (int k = 0; k < 4; ++k) v[k] = to_glm(target.positions[target.tets[t][k]]);
    const glm::dvec3 centroid = (v[0] + v[1] + v[2] + v[3]) / 4.0;
    bool inside = true;
    const std::int32_t material = locate(centroid, inside);
    result.tet_material[t] = material;
    result.outside += !inside;
    // Points well inside the tet near each corner (barycentric 0.7, 0.1, 0.1, 0.1): a tet whose
    // samples fall in different input materials has an input interface running through it.
    bool straddles = false;
    for (int k = 0; k < 4 && !straddles; ++k) {
      bool corner_inside = true;
      const glm::dvec3 p = 0.6 * v[k] + 0.4 * centroid;
      straddles = locate(p, corner_inside) != material && corner_inside;
    }
    result.straddling += straddles;
  }
  return result;
}

}  // namespace topotet::bench
