#include "generate/freudenthal_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "mesh/glm_convert.h"
#include "topotet/error.h"

namespace topotet::gen {
namespace {

// 6 * nx * ny * nz must fit TetId, and every vertex id VertId.
constexpr std::uint64_t kMaxTets = 2'000'000'000;

// Kuhn paths through each corner o of a cube (bit a of o = offset along axis a): a path visits
// 0, e[a], e[a] + e[b], (1,1,1), so it passes o when o's axes are its first |o| steps.
struct StarPerms {
  std::array<std::array<int, 6>, 8> perms{};
  std::array<int, 8> count{};
};
constexpr StarPerms make_star_perms() {
  StarPerms s;
  for (int o = 0; o < 8; ++o) {
    for (int p = 0; p < 6; ++p) {
      const int first = 1 << kPerms[p][0], second = first | (1 << kPerms[p][1]);
      if (o == 0 || o == 7 || o == first || o == second) s.perms[o][s.count[o]++] = p;
    }
  }
  return s;
}
constexpr StarPerms kStarPerms = make_star_perms();

// True when the tets of `material` around vertex v (its star) meet the other tets along one disc
// of the interface, or not at all. The faces opposite v of the star tets triangulate a sphere
// around v (its link); the interface near v is the cone over the link edges that separate a
// `material` face from another one, so it is a disc iff those edges form one simple cycle.
bool interface_is_disc(const MeshData& mesh, VertId v, const std::array<TetId, 24>& star, std::int32_t material) {
  struct LinkEdge {
    VertId a, b;
    int inside;
  };
  std::array<LinkEdge, 36> edges{};  // the link of an interior Kuhn vertex has 36 edges
  int edge_count = 0;
  for (TetId t : star) {
    VertId w[3];
    int n = 0;
    for (VertId x : mesh.tets[t])
      if (x != v) w[n++] = x;
    const int in = mesh.tet_material[t] == material;
    for (int e = 0; e < 3; ++e) {
      VertId a = w[e], b = w[(e + 1) % 3];
      if (a > b) std::swap(a, b);
      int found = 0;
      while (found < edge_count && !(edges[found].a == a && edges[found].b == b)) ++found;
      if (found == edge_count) edges[edge_count++] = {a, b, 0};
      edges[found].inside += in;
    }
  }
  // Degrees of the link vertices in the separating edges, and their neighbours.
  struct LinkVertex {
    VertId id;
    int degree;
    VertId next[2];
  };
  std::array<LinkVertex, 14> verts{};
  int vert_count = 0, cut_count = 0;
  const auto add = [&](VertId x, VertId y) {
    int i = 0;
    while (i < vert_count && verts[i].id != x) ++i;
    if (i == vert_count) verts[vert_count++] = {x, 0, {kInvalid, kInvalid}};
    if (verts[i].degree < 2) verts[i].next[verts[i].degree] = y;
    ++verts[i].degree;
  };
  VertId start = kInvalid, first = kInvalid;
  for (int e = 0; e < edge_count; ++e) {
    if (edges[e].inside != 1) continue;
    ++cut_count;
    add(edges[e].a, edges[e].b);
    add(edges[e].b, edges[e].a);
    start = edges[e].a;
    first = edges[e].b;
  }
  if (cut_count == 0) return true;
  for (int i = 0; i < vert_count; ++i)
    if (verts[i].degree != 2) return false;
  // Walk the cycle through `start`; it must use every separating edge.
  const auto find = [&](VertId x) -> const LinkVertex& {
    int i = 0;
    while (verts[i].id != x) ++i;
    return verts[i];
  };
  int steps = 1;
  VertId prev = start, cur = first;
  while (cur != start) {
    const LinkVertex& lv = find(cur);
    const VertId next = lv.next[0] == prev ? lv.next[1] : lv.next[0];
    prev = cur;
    cur = next;
    ++steps;
  }
  return steps == cut_count;
}

}  // namespace

std::array<TetId, 24> vertex_star(const FreudenthalGrid& grid, std::uint32_t i, std::uint32_t j, std::uint32_t k) {
  std::array<TetId, 24> star{};
  int n = 0;
  for (int o = 0; o < 8; ++o) {
    const std::uint32_t ci = i - (o & 1), cj = j - ((o >> 1) & 1), ck = k - ((o >> 2) & 1);
    for (int q = 0; q < kStarPerms.count[o]; ++q) star[n++] = grid.tet(ci, cj, ck, kStarPerms.perms[o][q]);
  }
  return star;
}

void repair_pinches(const FreudenthalGrid& grid, std::int32_t material, std::int32_t background, MeshData& mesh) {
  const Cells& n = grid.cells();
  // First every interior vertex, then only the neighbours of the stars that grew.
  std::vector<std::array<std::uint32_t, 3>> work, next;
  for (std::uint32_t k = 1; k < n[2]; ++k)
    for (std::uint32_t j = 1; j < n[1]; ++j)
      for (std::uint32_t i = 1; i < n[0]; ++i) work.push_back({i, j, k});
  for (int pass = 0; !work.empty(); ++pass) {
    if (pass == 100) throw std::logic_error("repair_pinches: no convergence");
    next.clear();
    for (const auto& p : work) {
      const std::array<TetId, 24> star = vertex_star(grid, p[0], p[1], p[2]);
      bool in = false, out = false;
      for (TetId t : star) (mesh.tet_material[t] == material ? in : out) = true;
      if (!in || !out || interface_is_disc(mesh, grid.vertex(p), star, material)) continue;
      for (TetId t : star) {
        std::int32_t& m = mesh.tet_material[t];
        if (m != material && m != background) throw std::logic_error("repair_pinches: shapes too close");
        m = material;
      }
      for (std::uint32_t dk = p[2] - 1; dk <= p[2] + 1; ++dk)
        for (std::uint32_t dj = p[1] - 1; dj <= p[1] + 1; ++dj)
          for (std::uint32_t di = p[0] - 1; di <= p[0] + 1; ++di)
            if (di > 0 && dj > 0 && dk > 0 && di < n[0] && dj < n[1] && dk < n[2]) next.push_back({di, dj, dk});
    }
    std::sort(next.begin(), next.end(), [](const auto& a, const auto& b) {
      return std::tie(a[2], a[1], a[0]) < std::tie(b[2], b[1], b[0]);
    });
    next.erase(std::unique(next.begin(), next.end()), next.end());
    work.swap(next);
  }
}

void check_target(std::string_view family, std::uint64_t target_tets, std::uint64_t min_tets) {
  if (target_tets < min_tets) {
    throw InputError(std::string(family) + ": --tets must be at least " + std::to_string(min_tets));
  }
  if (target_tets > kMaxTets) {
    throw InputError(std::string(family) + ": --tets must be at most " + std::to_string(kMaxTets));
  }
}

Cells choose_cells(std::uint64_t target_tets, std::array<double, 3> aspect, std::uint32_t fixed_nz) {
  const double cubes = static_cast<double>(target_tets) / 6.0;
  // Ideal (real) cell counts with the requested shape.
  std::array<double, 3> ideal{};
  if (fixed_nz > 0) {
    const double s = std::sqrt(cubes / fixed_nz / (aspect[0] * aspect[1]));
    ideal = {aspect[0] * s, aspect[1] * s, static_cast<double>(fixed_nz)};
  } else {
    const double s = std::cbrt(cubes / (aspect[0] * aspect[1] * aspect[2]));
    ideal = {aspect[0] * s, aspect[1] * s, aspect[2] * s};
  }
  // Rounding each count alone can miss the target by 3/(2n) (12% at n = 12); search nearby
  // shapes and trade a little shape distortion for count accuracy.
  const auto range = [](double x) {
    const double slack = std::max(2.0, 0.1 * x);
    const auto lo = static_cast<std::uint32_t>(std::max(1.0, std::floor(x - slack)));
    const auto hi = static_cast<std::uint32_t>(std::ceil(x + slack));
    return std::array<std::uint32_t, 2>{lo, hi};
  };
  Cells best{1, 1, 1};
  double best_score = std::numeric_limits<double>::infinity();
  double best_error = std::numeric_limits<double>::infinity();
  const auto rx = range(ideal[0]);
  const auto ry = range(ideal[1]);
  for (std::uint32_t nx = rx[0]; nx <= rx[1]; ++nx) {
    for (std::uint32_t ny = ry[0]; ny <= ry[1]; ++ny) {
      const double nz_real = cubes / (double(nx) * ny);
      std::uint32_t nz_options[2] = {fixed_nz, fixed_nz};
      if (fixed_nz == 0) {
        nz_options[0] = static_cast<std::uint32_t>(std::max(1.0, std::floor(nz_real)));
        nz_options[1] = nz_options[0] + 1;
      }
      for (std::uint32_t nz : nz_options) {
        const double tets = 6.0 * nx * ny * nz;
        const double error = std::abs(tets - double(target_tets)) / double(target_tets);
        const double distortion = std::max({std::abs(std::log(nx / ideal[0])), std::abs(std::log(ny / ideal[1])),
                                            std::abs(std::log(nz / ideal[2]))});
        const double score = error + 0.5 * distortion;
        // Best score among shapes within 10% of the target; the smallest error if none is.
        const bool ok = error <= 0.1, best_ok = best_error <= 0.1;
        const bool better = ok != best_ok ? ok : ok ? score < best_score : error < best_error;
        if (better) {
          best = {nx, ny, nz};
          best_score = score;
          best_error = error;
        }
      }
    }
  }
  return best;
}

FreudenthalGrid::FreudenthalGrid(Cells cells) : cells_(cells) {
  stride_ = {1, cells[0] + 1ull, (cells[0] + 1ull) * (cells[1] + 1ull)};
  if (vertex_count() > std::numeric_limits<VertId>::max() || tet_count() > std::numeric_limits<TetId>::max()) {
    throw std::logic_error("FreudenthalGrid: too many cells for 32-bit ids");
  }
}

double FreudenthalGrid::cell_size() const {
  return 1.0 / static_cast<double>(std::max({cells_[0], cells_[1], cells_[2]}));
}

Triangle tet_face(const MeshData& mesh, TetId tet, int local_face, bool inward, std::int32_t ref) {
  const auto& v = mesh.tets[tet];
  const auto& f = kOutwardFace[local_face];
  Triangle tri{{v[f[0]], v[f[1]], v[f[2]]}, ref};
  if (inward) std::swap(tri.v[1], tri.v[2]);
  return tri;
}

void add_boundary_triangles(const FreudenthalGrid& grid, std::int32_t ref, MeshData& mesh) {
  for_each_face(grid, [&](TetId t, int face, TetId nb) {
    if (nb == kInvalid) mesh.triangles.push_back(tet_face(mesh, t, face, false, ref));
  });
}

void add_plane_patch(const FreudenthalGrid& grid, int axis, std::uint32_t level,
                     std::array<std::uint32_t, 2> lo, std::array<std::uint32_t, 2> hi, std::int32_t ref,
                     MeshData& mesh) {
  const int u = axis == 0 ? 1 : 0;
  const int w = axis == 2 ? 1 : 2;
  for (std::uint32_t t = lo[1]; t < hi[1]; ++t) {
    for (std::uint32_t s = lo[0]; s < hi[0]; ++s) {
      std::array<std::uint32_t, 3> p{};
      p[axis] = level;
      const auto at = [&](std::uint32_t du, std::uint32_t dw) {
        p[u] = s + du;
        p[w] = t + dw;
        return grid.vertex(p);
      };
      const VertId p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
      mesh.triangles.push_back({{p00, p10, p11}, ref});
      mesh.triangles.push_back({{p00, p11, p01}, ref});
    }
  }
}

void add_chain(const FreudenthalGrid& grid, std::array<std::uint32_t, 3> start, std::array<int, 3> step,
               std::uint32_t count, std::int32_t ref, MeshData& mesh) {
  const bool up = std::all_of(step.begin(), step.end(), [](int s) { return s == 0 || s == 1; });
  const bool down = std::all_of(step.begin(), step.end(), [](int s) { return s == 0 || s == -1; });
  if (!(up || down) || step == std::array<int, 3>{0, 0, 0}) {
    throw std::logic_error("add_chain: step is not a Freudenthal grid edge");
  }
  std::array<std::uint32_t, 3> p = start;
  for (std::uint32_t e = 0; e < count; ++e) {
    const VertId from = grid.vertex(p);
    for (int a = 0; a < 3; ++a) {
      p[a] = static_cast<std::uint32_t>(static_cast<std::int64_t>(p[a]) + step[a]);
      if (p[a] > grid.cells()[a]) throw std::logic_error("add_chain: chain leaves the grid");
    }
    mesh.segments.push_back({{from, grid.vertex(p)}, ref});
  }
}

std::array<double, 3> jittered_position(const FreudenthalGrid& grid, std::uint64_t key, std::uint32_t i, std::uint32_t j,
                                        std::uint32_t k, bool keep_z) {
  const Cells& n = grid.cells();
  const std::uint64_t v = grid.vertex(i, j, k);
  // Uniform in the unit ball by rejection: every attempt hashes (seed, vertex, attempt),
  // so the result does not depend on the order vertices are visited in. After 16 misses
  // (about one vertex in 10^5) the vertex stays on the lattice.
  glm::dvec3 d(0.0);
  for (std::uint64_t attempt = 0; attempt < 16; ++attempt) {
    const std::uint64_t base = splitmix64(key ^ (v * 64 + attempt * 4));
    const glm::dvec3 c(to_symmetric_unit(splitmix64(base + 1)), to_symmetric_unit(splitmix64(base + 2)),
                       to_symmetric_unit(splitmix64(base + 3)));
    if (c.x * c.x + c.y * c.y + c.z * c.z <= 1.0) {
      d = c;
      break;
    }
  }
  // Box faces stay flat: no motion along the normal of a face the vertex lies on.
  if (i == 0 || i == n[0]) d.x = 0.0;
  if (j == 0 || j == n[1]) d.y = 0.0;
  if (keep_z) d.z = 0.0;
  return from_glm((glm::dvec3(i, j, k) + kJitter * d) * grid.cell_size());
}

void set_jittered_positions(const FreudenthalGrid& grid, std::uint64_t seed, MeshData& mesh,
                            const std::vector<std::uint32_t>& flat_z) {
  const Cells& n = grid.cells();
  const std::uint64_t key = splitmix64(seed);
  mesh.positions.resize(grid.vertex_count());
  std::size_t v = 0;
  for (std::uint32_t k = 0; k <= n[2]; ++k) {
    const bool keep_z = k == 0 || k == n[2] || std::find(flat_z.begin(), flat_z.end(), k) != flat_z.end();
    for (std::uint32_t j = 0; j <= n[1]; ++j)
      for (std::uint32_t i = 0; i <= n[0]; ++i, ++v) mesh.positions[v] = jittered_position(grid, key, i, j, k, keep_z);
  }
}

double feature_value(const FreudenthalGrid& grid, const std::array<double, 3>& position) {
  const Cells& n = grid.cells();
  const double h = grid.cell_size();
  const glm::dvec3 extent(n[0] * h, n[1] * h, n[2] * h);
  constexpr double kPi = 3.14159265358979323846;
  const glm::dvec3 q = to_glm(position) / extent;  // in [0, 1]^3
  const double smooth =
      0.5 * std::sin(2 * kPi * q.x) * std::cos(3 * kPi * q.y) + 0.25 * std::sin(4 * kPi * q.z + 1.0);
  // A steep front across an oblique plane (width 1% of the box).
  const double front = 0.5 * std::tanh((q.x + 0.6 * q.y - 0.3 * q.z - 0.55) / 0.01);
  // A narrow peak away from the planted substructures.
  const glm::dvec3 r = q - glm::dvec3(0.8, 0.25, 0.7);
  const double peak = 1.5 * std::exp(-(r.x * r.x + r.y * r.y + r.z * r.z) / (2 * 0.03 * 0.03));
  return smooth + front + peak;
}

void add_feature_field(const FreudenthalGrid& grid, MeshData& mesh) {
  VertexField field{"f", 1, {}};
  field.values.resize(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) field.values[v] = feature_value(grid, mesh.positions[v]);
  mesh.fields.push_back(std::move(field));
}

void add_box_corners(const FreudenthalGrid& grid, MeshData& mesh) {
  const Cells& n = grid.cells();
  for (std::uint32_t k : {0u, n[2]})
    for (std::uint32_t j : {0u, n[1]})
      for (std::uint32_t i : {0u, n[0]}) mesh.corners.push_back(grid.vertex(i, j, k));
}

}  // namespace topotet::gen
