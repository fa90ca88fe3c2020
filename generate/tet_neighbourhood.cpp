#include "generate/tet_neighbourhood.h"

#include <algorithm>
#include <bit>

namespace topotet::gen {
namespace {

using LatticePoint = std::array<int, 3>;

// The 4 lattice points of the Kuhn path `perm` starting at `origin`, in path order.
std::array<LatticePoint, 4> path_points(LatticePoint origin, int perm) {
  std::array<LatticePoint, 4> points{origin, origin, origin, origin};
  for (int q = 0; q < 3; ++q) {
    points[q + 1] = points[q];
    ++points[q + 1][kPerms[perm][q]];
  }
  return points;
}

// A subset of the centre tet's 4 vertices is a 4-bit mask (bit q = q-th path vertex); the part of
// the tet's boundary a region touches is a 16-bit set of such masks (bit s = the simplex spanned by
// subset s). kFaceMasks are the triangles; kClosure[f] is every nonempty subset of triangle f.
constexpr std::array<int, 4> kFaceMasks = {0b0111, 0b1011, 0b1101, 0b1110};
constexpr std::array<std::uint16_t, 16> make_closures() {
  std::array<std::uint16_t, 16> closure{};
  for (int f = 0; f < 16; ++f)
    for (int s = 1; s < 16; ++s)
      if ((s & ~f) == 0) closure[f] = static_cast<std::uint16_t>(closure[f] | (1u << s));
  return closure;
}
constexpr std::array<std::uint16_t, 16> kClosure = make_closures();

// True when the simplices of a tet's boundary in `contact` make a disc: one to three triangles
// (four would be the whole sphere) and nothing outside their closure (that would pinch).
bool is_disc_in_boundary(std::uint32_t contact) {
  std::uint32_t closure = 0;
  int faces = 0;
  for (int f : kFaceMasks) {
    if ((contact >> f) & 1u) {
      closure |= kClosure[f];
      ++faces;
    }
  }
  return faces >= 1 && faces <= 3 && (contact & ~closure) == 0;
}

}  // namespace

TetNeighbourhood::TetNeighbourhood(const FreudenthalGrid& grid) : cells_(grid.cells()) {
  const std::int64_t nx = cells_[0], ny = cells_[1];
  for (int p = 0; p < 6; ++p) {
    const auto centre = path_points({0, 0, 0}, p);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          for (int q = 0; q < 6; ++q) {
            if (dx == 0 && dy == 0 && dz == 0 && q == p) continue;
            const auto other = path_points({dx, dy, dz}, q);
            std::uint8_t shared = 0;
            for (int v = 0; v < 4; ++v)
              if (std::find(other.begin(), other.end(), centre[v]) != other.end()) shared = static_cast<std::uint8_t>(shared | (1u << v));
            if (shared == 0) continue;
            const Entry entry = {static_cast<std::int32_t>(6 * (dx + nx * (dy + ny * dz)) + (q - p)), shared,
                                 {static_cast<std::int8_t>(dx), static_cast<std::int8_t>(dy), static_cast<std::int8_t>(dz)}};
            entries_[p].push_back(entry);
            if (std::popcount(unsigned{shared}) == 3) faces_[p].push_back(entry);
          }
  }
}

TetNeighbourhood::Place TetNeighbourhood::place(TetId t) const {
  // 32-bit divisions: tet ids fit 32 bits (FreudenthalGrid checks), and these run per test.
  const std::uint32_t cube = t / 6, row = cube / cells_[0];
  Place at;
  at.perm = static_cast<int>(t - 6 * cube);
  at.cube = {cube - row * cells_[0], row % cells_[1], row / cells_[1]};
  at.is_interior = true;
  for (int a = 0; a < 3; ++a) at.is_interior &= at.cube[a] > 0 && at.cube[a] + 1 < cells_[a];
  return at;
}

std::uint32_t TetNeighbourhood::boundary_contact(const Place& at) const {
  if (at.is_interior) return 0;
  // Bit 2a / 2a + 1 of planes[q]: path vertex q lies on the box face x[a] = 0 / x[a] = n[a].
  std::array<std::uint32_t, 4> planes{};
  std::array<std::uint32_t, 3> p = at.cube;
  for (int q = 0; q < 4; ++q) {
    if (q > 0) ++p[kPerms[at.perm][q - 1]];
    for (int a = 0; a < 3; ++a) {
      if (p[a] == 0) planes[q] |= 1u << (2 * a);
      if (p[a] == cells_[a]) planes[q] |= 1u << (2 * a + 1);
    }
  }
  // A simplex of t lies on the boundary when its vertices share a box face.
  std::uint32_t contact = 0;
  for (int s = 1; s < 16; ++s) {
    std::uint32_t common = 0x3F;
    for (int q = 0; q < 4; ++q)
      if ((s >> q) & 1) common &= planes[q];
    if (common != 0) contact |= 1u << s;
  }
  return contact;
}

bool TetNeighbourhood::joins_as_ball(TetId t, std::int32_t m, const std::vector<std::int32_t>& material) const {
  return is_disc_in_boundary(contact(t, place(t), material, [m](std::int32_t x) { return x == m; }));
}

bool TetNeighbourhood::leaves_as_ball(TetId t, const std::vector<std::int32_t>& material) const {
  const Place at = place(t);
  const std::int32_t own = material[t];
  return is_disc_in_boundary(boundary_contact(at) | contact(t, at, material, [own](std::int32_t x) { return x != own; }));
}

glm::dvec3 tet_centroid(const FreudenthalGrid& grid, TetId t) {
  const Cells& n = grid.cells();
  const std::uint64_t cube = t / 6;
  const auto [a, b, d] = kPerms[t % 6];
  glm::dvec3 c(static_cast<double>(cube % n[0]), static_cast<double>(cube / n[0] % n[1]),
               static_cast<double>(cube / n[0] / n[1]));
  c[a] += 0.75;
  c[b] += 0.5;
  c[d] += 0.25;
  return c;
}

std::array<VertId, 4> tet_vertices(const FreudenthalGrid& grid, TetId t) {
  const Cells& n = grid.cells();
  const std::uint64_t cube = t / 6;
  const auto origin = grid.vertex(static_cast<std::uint32_t>(cube % n[0]), static_cast<std::uint32_t>(cube / n[0] % n[1]),
                                  static_cast<std::uint32_t>(cube / n[0] / n[1]));
  std::array<VertId, 4> v{origin, 0, 0, 0};
  for (int q = 0; q < 3; ++q) v[q + 1] = static_cast<VertId>(v[q] + grid.stride(kPerms[t % 6][q]));
  return v;
}

}  // namespace topotet::gen
