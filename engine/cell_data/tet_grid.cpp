#include "cell_data/tet_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "mesh/glm_convert.h"

namespace topotet::cell_data {

Box tet_box(const MeshData& m, std::size_t t) {
  Box b{to_glm(m.positions[m.tets[t][0]]), to_glm(m.positions[m.tets[t][0]])};
  for (int k = 1; k < 4; ++k) {
    const glm::dvec3 p = to_glm(m.positions[m.tets[t][static_cast<std::size_t>(k)]]);
    b.lo = glm::min(b.lo, p);
    b.hi = glm::max(b.hi, p);
  }
  return b;
}

glm::dvec3 tet_centroid(const MeshData& m, std::size_t t) {
  glm::dvec3 c(0.0);
  for (VertId v : m.tets[t]) c += to_glm(m.positions[v]);
  return c * 0.25;
}

namespace {
constexpr double kTetsPerCell = 8.0;
constexpr int kMaxDim = 1024;  // per axis: bounds the grid of a very flat or very long mesh
}  // namespace

TetGrid::TetGrid(const MeshData& mesh) : mesh_(mesh) {
  const std::size_t n = mesh.tets.size();
  if (n == 0) {
    offsets_.assign(2, 0);
    return;
  }
  Box all = tet_box(mesh, 0);
  for (std::size_t t = 1; t < n; ++t) {
    const Box b = tet_box(mesh, t);
    all.lo = glm::min(all.lo, b.lo);
    all.hi = glm::max(all.hi, b.hi);
  }
  const glm::dvec3 extent = glm::max(all.hi - all.lo, glm::dvec3(1e-300));
  // A cube cell holding kTetsPerCell tets on average, at least 1/kMaxDim of each axis.
  const double side = std::cbrt(extent.x * extent.y * extent.z * kTetsPerCell / static_cast<double>(n));
  for (int a = 0; a < 3; ++a) {
    const double cells = std::ceil(extent[a] / std::max(side, extent[a] / kMaxDim));
    dims_[static_cast<std::size_t>(a)] = static_cast<int>(std::clamp(cells, 1.0, double{kMaxDim}));
    cell_size_[a] = extent[a] / dims_[static_cast<std::size_t>(a)];
  }
  lo_ = all.lo;

  // Two passes (count, then fill) in tet order, so that each cell lists its tets by increasing id.
  offsets_.assign(index(0, 0, dims_[2]) + 1, 0);
  const auto for_cells = [&](std::size_t t, auto&& f) {
    const Box b = tet_box(mesh, t);
    const std::array<int, 3> c0 = cell_of(b.lo), c1 = cell_of(b.hi);
    for (int z = c0[2]; z <= c1[2]; ++z)
      for (int y = c0[1]; y <= c1[1]; ++y)
        for (int x = c0[0]; x <= c1[0]; ++x)
          f(index(x, y, z), static_cast<std::uint8_t>((x == c0[0] ? 1 : 0) | (y == c0[1] ? 2 : 0) | (z == c0[2] ? 4 : 0)));
  };
  for (std::size_t t = 0; t < n; ++t) for_cells(t, [&](std::size_t c, std::uint8_t) { ++offsets_[c + 1]; });
  for (std::size_t c = 1; c < offsets_.size(); ++c) offsets_[c] += offsets_[c - 1];
  ids_.resize(offsets_.back());
  firsts_.resize(offsets_.back());
  std::vector<std::size_t> fill(offsets_.begin(), offsets_.end() - 1);
  for (std::size_t t = 0; t < n; ++t)
    for_cells(t, [&](std::size_t c, std::uint8_t firsts) {
      firsts_[fill[c]] = firsts;
      ids_[fill[c]++] = static_cast<TetId>(t);
    });
}

std::array<int, 3> TetGrid::cell_of(const glm::dvec3& p) const {
  std::array<int, 3> c{};
  for (int a = 0; a < 3; ++a) {
    const double x = std::floor((p[a] - lo_[a]) / cell_size_[a]);
    c[static_cast<std::size_t>(a)] = static_cast<int>(std::clamp(x, 0.0, double(dims_[static_cast<std::size_t>(a)] - 1)));
  }
  return c;
}

void TetGrid::gather(const Box& box, std::int32_t material, std::vector<TetId>& out) const {
  if (ids_.empty()) return;
  const std::array<int, 3> c0 = cell_of(box.lo), c1 = cell_of(box.hi);
  for (int z = c0[2]; z <= c1[2]; ++z)
    for (int y = c0[1]; y <= c1[1]; ++y)
      for (int x = c0[0]; x <= c1[0]; ++x) {
        // An entry counts here if, along each axis, its cell is the tet's first or the query's.
        const std::uint8_t needed = static_cast<std::uint8_t>((x == c0[0] ? 0 : 1) | (y == c0[1] ? 0 : 2) | (z == c0[2] ? 0 : 4));
        const std::size_t c = index(x, y, z);
        for (std::size_t k = offsets_[c]; k < offsets_[c + 1]; ++k) {
          if ((firsts_[k] & needed) != needed) continue;
          const TetId t = ids_[k];
          if ((mesh_.tet_material.empty() ? 0 : mesh_.tet_material[t]) != material) continue;
          if (tet_box(mesh_, t).meets(box)) out.push_back(t);
        }
      }
}

// Rings of cells around the point's cell, outwards. After ring r, a tet not yet seen has its
// centroid in a cell of ring r + 1 or beyond, at least r cells away along some axis: once the best
// distance is within r * (smallest cell side) no later ring can beat it. A point outside the grid
// starts from the nearest cell; the bound still holds (it is only farther from the other cells).
TetId TetGrid::nearest(const glm::dvec3& point, std::int32_t material, bool any_material) const {
  if (ids_.empty()) return kInvalid;
  const std::array<int, 3> c = cell_of(point);
  const double min_side = std::min({cell_size_.x, cell_size_.y, cell_size_.z});
  const int max_ring = std::max({dims_[0], dims_[1], dims_[2]});
  TetId best = kInvalid;
  double best_d2 = std::numeric_limits<double>::infinity();
  const auto visit = [&](int x, int y, int z) {
    const std::size_t cell = index(x, y, z);
    for (std::size_t k = offsets_[cell]; k < offsets_[cell + 1]; ++k) {
      const TetId t = ids_[k];
      if (!any_material && (mesh_.tet_material.empty() ? 0 : mesh_.tet_material[t]) != material) continue;
      const glm::dvec3 d = tet_centroid(mesh_, t) - point;
      const double d2 = glm::dot(d, d);
      if (d2 < best_d2 || (d2 == best_d2 && t < best)) {
        best_d2 = d2;
        best = t;
      }
    }
  };
  for (int r = 0; r <= max_ring; ++r) {
    // The shell of ring r only (every cell of it once): whole rows where y or z is on the shell,
    // else the two ends of the row. Each ring costs its own cells, so a search over the whole
    // grid (a material that is nowhere) costs one pass over the cells.
    for (int z = std::max(0, c[2] - r); z <= std::min(dims_[2] - 1, c[2] + r); ++z) {
      for (int y = std::max(0, c[1] - r); y <= std::min(dims_[1] - 1, c[1] + r); ++y) {
        const bool whole_row = std::abs(z - c[2]) == r || std::abs(y - c[1]) == r;
        if (whole_row) {
          for (int x = std::max(0, c[0] - r); x <= std::min(dims_[0] - 1, c[0] + r); ++x) visit(x, y, z);
        } else {
          if (c[0] - r >= 0) visit(c[0] - r, y, z);
          if (r > 0 && c[0] + r < dims_[0]) visit(c[0] + r, y, z);
        }
      }
    }
    if (best != kInvalid && std::sqrt(best_d2) <= r * min_side) break;
  }
  return best;
}

}  // namespace topotet::cell_data
