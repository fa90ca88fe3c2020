// compare_fields: locate each mesh's vertices in the other mesh, interpolate, accumulate errors.
//
// Point location is a uniform grid of cubic cells; every tet is listed in each cell its bounding
// box overlaps (CSR arrays, cell lists sorted by tet id so that the grid, and every answer, is the
// same whatever the thread interleaving while building it). A query tests the tets of its cell in
// increasing id order: the first whose barycentric coordinates all exceed kInsideTolerance wins
// (in a valid mesh no other tet contains the point); otherwise the one with the largest minimum
// barycentric coordinate (ties to the smaller tet id), which contains the point if that
// coordinate is >= -kInsideTolerance. Otherwise the point is outside
// the mesh and a ring search over the cells around it finds the closest tet exactly.
//
// Determinism: queries are independent; sums over samples run in fixed-size blocks whose partial
// sums are combined in block order, so results do not depend on the thread count.
#include "topotet/metrics/field_error.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "parallel/for_range.h"
#include "topotet/error.h"

namespace topotet {
namespace {

// Barycentric slack accepted as "inside": points on shared faces or on a boundary that coincides
// up to rounding. Barycentric coordinates are scale-free, so one constant serves every mesh.
constexpr double kInsideTolerance = 1e-9;
constexpr std::size_t kBlock = 4096;

using Bary = std::array<double, 4>;

struct Location {
  TetId tet = kInvalid;
  Bary bary{};                  // in [0, 1], summing to 1
  bool outside = false;         // found by the closest-tet search
  double outside_distance = 0.0;
};

double det3(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return glm::dot(a, glm::cross(b, c));
}

// Barycentric coordinates of q in tet p: l_i = V_i / sum V_j, V_i the signed volume of the tet
// with vertex i replaced by q, each evaluated from the vectors p_j - q. At a vertex p_k of the
// tet one of those vectors is exactly zero in every V_i with i != k, so the answer is exactly the
// unit vector e_k and identical meshes compare with no rounding error at all. False for a tet of
// zero volume.
bool barycentric(const std::array<glm::dvec3, 4>& p, const glm::dvec3& q, Bary& l) {
  const double d = det3(p[1] - p[0], p[2] - p[0], p[3] - p[0]);
  if (d == 0.0 || !std::isfinite(d)) return false;
  const glm::dvec3 a = p[0] - q, b = p[1] - q, c = p[2] - q, e = p[3] - q;
  // Moving q to the front of (p0, .., q, .., p3) takes i transpositions: sign (-1)^i.
  l[0] = det3(b, c, e);
  l[1] = -det3(a, c, e);
  l[2] = det3(a, b, e);
  l[3] = -det3(a, b, c);
  const double sum = l[0] + l[1] + l[2] + l[3];  // = d up to rounding
  if (sum == 0.0 || !std::isfinite(sum)) return false;
  for (double& x : l) x /= sum;
  return true;
}

// False when q is clearly outside the bounding box of tet p: farther than 1e-6 times the box's
// extent. A point whose barycentric coordinates are all >= -kInsideTolerance lies within
// 4 kInsideTolerance times the tet's diameter of it, so such a tet could never have been chosen
// (it is not inside, and a point inside no tet is located by the closest-tet search instead):
// the test only saves the barycentric coordinates of most tets listed in a query's cell.
bool near_box(const std::array<glm::dvec3, 4>& p, const glm::dvec3& q) {
  for (int k = 0; k < 3; ++k) {
    const double lo = std::min({p[0][k], p[1][k], p[2][k], p[3][k]});
    const double hi = std::max({p[0][k], p[1][k], p[2][k], p[3][k]});
    const double slack = 1e-6 * (hi - lo);
    if (q[k] < lo - slack || q[k] > hi + slack) return false;
  }
  return true;
}

// Parameter of the point of segment [a, b] closest to p, in [0, 1].
double closest_on_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  if (!(len2 > 0.0)) return 0.0;
  return std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0);
}

// Barycentric coordinates (of a, b, c) of the point of triangle abc closest to p, by Voronoi
// regions (Ericson, Real-Time Collision Detection, 5.1.5). Degenerate triangles fall back to
// the closest point of their three edges.
std::array<double, 3> closest_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                          const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {1.0, 0.0, 0.0};
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return {0.0, 1.0, 0.0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) {
    const double v = d1 / (d1 - d3);
    return {1.0 - v, v, 0.0};
  }
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 0.0, 1.0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) {
    const double w = d2 / (d2 - d6);
    return {1.0 - w, 0.0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0.0, 1.0 - w, w};
  }
  const double sum = va + vb + vc;
  if (sum > 0.0 && std::isfinite(sum)) {
    const double v = vb / sum, w = vc / sum;
    return {1.0 - v - w, v, w};
  }
  // Degenerate (collinear or coincident corners): best of the three edges.
  const double s_ab = closest_on_segment(p, a, b), s_bc = closest_on_segment(p, b, c),
               s_ca = closest_on_segment(p, c, a);
  const std::array<std::array<double, 3>, 3> cand = {{{1.0 - s_ab, s_ab, 0.0},
                                                      {0.0, 1.0 - s_bc, s_bc},
                                                      {s_ca, 0.0, 1.0 - s_ca}}};
  std::array<double, 3> best = cand[0];
  double best_d2 = std::numeric_limits<double>::infinity();
  for (const auto& w : cand) {
    const glm::dvec3 x = w[0] * a + w[1] * b + w[2] * c;
    const double dist2 = glm::dot(x - p, x - p);
    if (dist2 < best_d2) best_d2 = dist2, best = w;
  }
  return best;
}

// Squared distance from q to tet p and the barycentric coordinates of the closest point.
double closest_in_tet(const std::array<glm::dvec3, 4>& p, const glm::dvec3& q, Bary& out) {
  Bary l;
  if (barycentric(p, q, l) && std::min({l[0], l[1], l[2], l[3]}) >= 0.0) {
    out = l;
    return 0.0;
  }
  // Outside (or flat): the closest point lies on a face. Face i is the one opposite vertex i.
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {
    const int a = (i + 1) % 4, b = (i + 2) % 4, c = (i + 3) % 4;
    const auto w = closest_on_triangle(q, p[a], p[b], p[c]);
    const glm::dvec3 x = w[0] * p[a] + w[1] * p[b] + w[2] * p[c];
    const double d2 = glm::dot(x - q, x - q);
    if (d2 < best) {
      best = d2;
      out = {};
      out[a] = w[0];
      out[b] = w[1];
      out[c] = w[2];
    }
  }
  return best;
}

// Uniform grid over the tets of one mesh, for point location.
class TetGrid {
 public:
  // `queries` (how many points will be located) tunes the cell size: larger cells cost less to
  // build, smaller ones less per query.
  TetGrid(const MeshData& mesh, std::size_t queries) : mesh_(mesh) { build(queries); }

  Location locate(const glm::dvec3& q) const {
    Location loc;
    const auto c = cell_of(q);
    const std::size_t cell = index(c[0], c[1], c[2]);
    double best_min = -std::numeric_limits<double>::infinity();
    for (std::uint64_t s = start_[cell]; s < start_[cell + 1]; ++s) {
      const TetId t = items_[s];  // increasing ids: strict > keeps the smallest on ties
      const auto p = points(t);
      if (!near_box(p, q)) continue;  // min barycentric coordinate far below -kInsideTolerance
      Bary l;
      if (!barycentric(p, q, l)) continue;
      const double m = std::min({l[0], l[1], l[2], l[3]});
      if (m > best_min) best_min = m, loc.tet = t, loc.bary = l;
      if (m > kInsideTolerance) break;  // inside with a margin: in a valid mesh no other tet can be
    }
    if (loc.tet != kInvalid && best_min >= -kInsideTolerance) {
      if (best_min < 0.0) {  // on a face up to rounding: snap onto it
        double sum = 0.0;
        for (double& x : loc.bary) sum += (x = std::max(x, 0.0));
        for (double& x : loc.bary) x /= sum;
      }
      return loc;
    }
    return closest(q, c);
  }

 private:
  std::array<glm::dvec3, 4> points(TetId t) const {
    const auto& tv = mesh_.tets[t];
    const auto& P = mesh_.positions;
    return {P[tv[0]], P[tv[1]], P[tv[2]], P[tv[3]]};
  }

  int axis_cell(double x, int axis) const {
    const double f = (x - lo_[axis]) / h_;
    if (!(f >= 0.0)) return 0;  // also NaN
    return f < static_cast<double>(dims_[axis]) ? static_cast<int>(f) : dims_[axis] - 1;
  }
  std::array<int, 3> cell_of(const glm::dvec3& p) const {
    return {axis_cell(p.x, 0), axis_cell(p.y, 1), axis_cell(p.z, 2)};
  }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(dims_[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims_[1]) * k);
  }
  // Inclusive cell ranges overlapped by tet t's bounding box.
  std::array<std::array<int, 3>, 2> cell_range(TetId t) const {
    const auto p = points(t);
    glm::dvec3 lo = p[0], hi = p[0];
    for (int i = 1; i < 4; ++i) lo = glm::min(lo, p[i]), hi = glm::max(hi, p[i]);
    return {cell_of(lo), cell_of(hi)};
  }

  void build(std::size_t queries);
  Location closest(const glm::dvec3& q, const std::array<int, 3>& c) const;

  const MeshData& mesh_;
  glm::dvec3 lo_{0.0};
  double h_ = 1.0;
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<std::uint64_t> start_;  // [cell count + 1]: CSR offsets into items_
  std::vector<TetId> items_;
};

void TetGrid::build(std::size_t queries) {
  const std::size_t nt = mesh_.tets.size();
  const std::size_t blocks = (nt + kBlock - 1) / kBlock;

  // Bounding box of the mesh and mean bounding-box size of a tet (summed per block, in order).
  struct Extent {
    glm::dvec3 lo{std::numeric_limits<double>::infinity()};
    glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
    double size_sum = 0.0;
  };
  std::vector<Extent> part(blocks);
  parallel::for_range<std::size_t>(0, blocks, 1, "grid_extent", [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) {
      Extent e;
      for (std::size_t t = b * kBlock; t < std::min(nt, (b + 1) * kBlock); ++t) {
        const auto p = points(static_cast<TetId>(t));
        glm::dvec3 lo = p[0], hi = p[0];
        for (int i = 1; i < 4; ++i) lo = glm::min(lo, p[i]), hi = glm::max(hi, p[i]);
        e.lo = glm::min(e.lo, lo);
        e.hi = glm::max(e.hi, hi);
        const glm::dvec3 d = hi - lo;
        e.size_sum += std::max({d.x, d.y, d.z});
      }
      part[b] = e;
    }
  });
  Extent all;
  for (const Extent& e : part) {
    all.lo = glm::min(all.lo, e.lo);
    all.hi = glm::max(all.hi, e.hi);
    all.size_sum += e.size_sum;
  }
  lo_ = all.lo;
  const glm::dvec3 ext = all.hi - all.lo;
  if (!std::isfinite(ext.x) || !std::isfinite(ext.y) || !std::isfinite(ext.z))
    throw InputError("compare_fields: a tet has a non-finite vertex coordinate");
  const double max_ext = std::max({ext.x, ext.y, ext.z});
  const double mean_size = all.size_sum / static_cast<double>(nt);

  // Cell edge = mean tet size times x. Per query we test about (1 + x)^3 cells' worth of tets, per
  // tet we list about (1 + 1/x)^3 cells; with unit costs and ~6 tets per cell volume, the total
  // N (1 + 1/x)^3 + 6 Q (1 + x)^3 is smallest at x = (N / 6Q)^(1/4).
  const double x = std::clamp(std::pow(static_cast<double>(nt) / (6.0 * static_cast<double>(std::max<std::size_t>(queries, 1))), 0.25), 0.5, 4.0);
  h_ = mean_size * x;
  if (!(h_ > 0.0) || !std::isfinite(h_)) h_ = max_ext > 0.0 && std::isfinite(max_ext) ? max_ext : 1.0;

  // Bound memory: at most ~4 cells per tet, and at most ~64 listed cells per tet (graded meshes
  // whose few big tets would otherwise span very many small cells).
  const double max_cells = 4.0 * static_cast<double>(nt) + 4096.0;
  const std::uint64_t max_items = 64 * static_cast<std::uint64_t>(nt) + 4096;
  std::uint64_t total = 0;
  for (;;) {
    double cells = 1.0;
    for (int a = 0; a < 3; ++a) cells *= std::max(1.0, std::ceil(ext[a] / h_));
    if (cells > max_cells) {
      h_ *= 1.25;
      continue;
    }
    for (int a = 0; a < 3; ++a) dims_[a] = static_cast<int>(std::max(1.0, std::ceil(ext[a] / h_)));
    std::vector<std::uint64_t> count(blocks, 0);
    parallel::for_range<std::size_t>(0, blocks, 1, "grid_size", [&](std::size_t b0, std::size_t b1) {
      for (std::size_t b = b0; b < b1; ++b)
        for (std::size_t t = b * kBlock; t < std::min(nt, (b + 1) * kBlock); ++t) {
          const auto r = cell_range(static_cast<TetId>(t));
          count[b] += std::uint64_t(r[1][0] - r[0][0] + 1) * (r[1][1] - r[0][1] + 1) * (r[1][2] - r[0][2] + 1);
        }
    });
    total = 0;
    for (const std::uint64_t c : count) total += c;
    if (total <= max_items) break;
    h_ *= 1.5;
  }

  // Counting sort of (cell, tet) pairs: atomic counts, prefix sum, atomic fill, then each cell's
  // list sorted, which removes the fill's dependence on thread interleaving.
  const std::size_t ncells = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
  start_.assign(ncells + 1, 0);
  auto for_each_cell_of = [&](std::size_t t, auto&& fn) {
    const auto r = cell_range(static_cast<TetId>(t));
    for (int k = r[0][2]; k <= r[1][2]; ++k)
      for (int j = r[0][1]; j <= r[1][1]; ++j)
        for (int i = r[0][0]; i <= r[1][0]; ++i) fn(index(i, j, k));
  };
  parallel::for_range<std::size_t>(0, nt, 4096, "grid_count", [&](std::size_t t0, std::size_t t1) {
    for (std::size_t t = t0; t < t1; ++t)
      for_each_cell_of(t, [&](std::size_t c) { std::atomic_ref(start_[c + 1]).fetch_add(1, std::memory_order_relaxed); });
  });
  for (std::size_t c = 0; c < ncells; ++c) start_[c + 1] += start_[c];
  items_.resize(total);
  std::vector<std::uint64_t> cursor(start_.begin(), start_.end() - 1);
  parallel::for_range<std::size_t>(0, nt, 4096, "grid_fill", [&](std::size_t t0, std::size_t t1) {
    for (std::size_t t = t0; t < t1; ++t)
      for_each_cell_of(t, [&](std::size_t c) {
        items_[std::atomic_ref(cursor[c]).fetch_add(1, std::memory_order_relaxed)] = static_cast<TetId>(t);
      });
  });
  parallel::for_range<std::size_t>(0, ncells, 4096, "grid_sort", [&](std::size_t c0, std::size_t c1) {
    for (std::size_t c = c0; c < c1; ++c) std::sort(items_.begin() + start_[c], items_.begin() + start_[c + 1]);
  });
}

// Closest tet to q by exact point-tet distance, searching rings of cells around q's (clamped)
// cell c: ring r holds the cells at Chebyshev index distance r. A tet not seen after rings 0..r
// has no listed cell within them, so its closest point to q (which lies in its bounding box, hence
// in one of its listed cells) lies in the part of the grid box beyond the index cube [c-r, c+r]:
// one of at most six boxes (one per axis and side). Their distance to q bounds every unseen tet,
// so the search stops once the best distance found is within it; this stays quick also for points
// far outside the grid, where the plain bound r h would need many rings.
Location TetGrid::closest(const glm::dvec3& q, const std::array<int, 3>& c) const {
  Location loc;
  loc.outside = true;
  double best = std::numeric_limits<double>::infinity();
  auto visit = [&](int i, int j, int k) {
    const std::size_t cell = index(i, j, k);
    for (std::uint64_t s = start_[cell]; s < start_[cell + 1]; ++s) {
      const TetId t = items_[s];
      Bary l;
      const double d2 = closest_in_tet(points(t), q, l);
      if (d2 < best || (d2 == best && t < loc.tet)) best = d2, loc.tet = t, loc.bary = l;
    }
  };
  // Squared distance from q to the grid box with axis `a` restricted to [from, to].
  auto box_dist2 = [&](int a, double from, double to) {
    double d2 = 0.0;
    for (int b = 0; b < 3; ++b) {
      const double lo = b == a ? from : lo_[b];
      const double hi = b == a ? to : lo_[b] + dims_[b] * h_;
      const double g = q[b] < lo ? lo - q[b] : (q[b] > hi ? q[b] - hi : 0.0);
      d2 += g * g;
    }
    return d2;
  };
  for (int r = 0;; ++r) {
    for (int i = std::max(0, c[0] - r); i <= std::min(dims_[0] - 1, c[0] + r); ++i)
      for (int j = std::max(0, c[1] - r); j <= std::min(dims_[1] - 1, c[1] + r); ++j) {
        if (std::abs(i - c[0]) == r || std::abs(j - c[1]) == r) {
          for (int k = std::max(0, c[2] - r); k <= std::min(dims_[2] - 1, c[2] + r); ++k) visit(i, j, k);
        } else {
          if (c[2] - r >= 0) visit(i, j, c[2] - r);
          if (r > 0 && c[2] + r < dims_[2]) visit(i, j, c[2] + r);
        }
      }
    double bound2 = std::numeric_limits<double>::infinity();  // stays infinite once all is seen
    for (int a = 0; a < 3; ++a) {
      if (c[a] - r - 1 >= 0) bound2 = std::min(bound2, box_dist2(a, lo_[a], lo_[a] + (c[a] - r) * h_));
      if (c[a] + r + 1 < dims_[a])
        bound2 = std::min(bound2, box_dist2(a, lo_[a] + (c[a] + r + 1) * h_, lo_[a] + dims_[a] * h_));
    }
    if (bound2 == std::numeric_limits<double>::infinity() || (loc.tet != kInvalid && best <= bound2)) break;
  }
  loc.outside_distance = std::sqrt(best);
  return loc;
}

void check_tets(const MeshData& m, const char* which) {
  const std::size_t nv = m.positions.size();
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (const VertId v : m.tets[t])
      if (v >= nv)
        throw InputError(std::string(which) + " tet " + std::to_string(t) + ": vertex index " +
                         std::to_string(v) + " out of range [0, " + std::to_string(nv) + ")");
}

void check_field(const MeshData& m, const VertexField& f, const char* which) {
  if (f.components < 1 || f.values.size() != m.positions.size() * static_cast<std::size_t>(f.components))
    throw InputError(std::string(which) + " field '" + f.name + "': " + std::to_string(f.values.size()) +
                     " values for " + std::to_string(m.positions.size()) + " vertices of " +
                     std::to_string(f.components) + " components");
}

// Vertices used by at least one tet, in increasing order.
std::vector<VertId> used_vertices(const MeshData& m) {
  std::vector<std::uint8_t> used(m.positions.size(), 0);
  for (const auto& tv : m.tets)
    for (const VertId v : tv) used[v] = 1;
  std::vector<VertId> out;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) out.push_back(static_cast<VertId>(v));
  return out;
}

// Locates `queries` (vertices of `from`) in `in`.
std::vector<Location> locate_all(const MeshData& from, const std::vector<VertId>& queries, const MeshData& in) {
  std::vector<Location> loc(queries.size());
  const TetGrid grid(in, queries.size());
  parallel::for_range<std::size_t>(0, queries.size(), 512, "locate", [&](std::size_t q0, std::size_t q1) {
    for (std::size_t q = q0; q < q1; ++q) loc[q] = grid.locate(from.positions[queries[q]]);
  });
  return loc;
}

LocationStats location_stats(const std::vector<Location>& loc) {
  LocationStats s;
  s.points = loc.size();
  for (const Location& l : loc)
    if (l.outside) ++s.outside, s.max_outside_distance = std::max(s.max_outside_distance, l.outside_distance);
  return s;
}

// Sum of squared and max absolute differences, at the query vertices (of some mesh), between
// their own value of component c (from_field) and `in`'s field interpolated at their location.
struct ErrorSums {
  double sum_sq = 0.0;
  double max_abs = 0.0;
};

ErrorSums direction_error(const VertexField& from_field, const std::vector<VertId>& queries,
                          const std::vector<Location>& loc, const MeshData& in, const VertexField& in_field, int c) {
  const std::size_t n = queries.size();
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  const std::size_t fk = static_cast<std::size_t>(from_field.components);
  const std::size_t ik = static_cast<std::size_t>(in_field.components);
  std::vector<ErrorSums> part(blocks);
  parallel::for_range<std::size_t>(0, blocks, 1, "field_error", [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) {
      ErrorSums s;
      for (std::size_t q = b * kBlock; q < std::min(n, (b + 1) * kBlock); ++q) {
        const auto& tv = in.tets[loc[q].tet];
        double interp = 0.0;
        for (int i = 0; i < 4; ++i) interp += loc[q].bary[i] * in_field.values[tv[i] * ik + c];
        const double d = from_field.values[queries[q] * fk + c] - interp;
        s.sum_sq += d * d;
        s.max_abs = std::max(s.max_abs, std::abs(d));
      }
      part[b] = s;
    }
  });
  // Neumaier-compensated sum of the block sums, in block order.
  ErrorSums total;
  double comp = 0.0;
  for (const ErrorSums& s : part) {
    const double t = total.sum_sq + s.sum_sq;
    comp += std::abs(total.sum_sq) >= std::abs(s.sum_sq) ? (total.sum_sq - t) + s.sum_sq : (s.sum_sq - t) + total.sum_sq;
    total.sum_sq = t;
    total.max_abs = std::max(total.max_abs, s.max_abs);
  }
  total.sum_sq += comp;
  return total;
}

DirectionalError finish(const ErrorSums& s, std::size_t n, double scale) {
  DirectionalError e;
  e.samples = n;
  if (n == 0) return e;
  e.rms = std::sqrt(s.sum_sq / static_cast<double>(n));
  e.max_abs = s.max_abs;
  e.rms_rel = e.rms / scale;
  e.max_rel = e.max_abs / scale;
  return e;
}

}  // namespace

FieldError compare_fields(const MeshData& original, const MeshData& simplified) {
  check_tets(original, "original");
  check_tets(simplified, "simplified");

  FieldError out;
  // Match by name: the first field of each name in each mesh.
  auto find = [](const MeshData& m, const std::string& name) -> const VertexField* {
    for (const auto& f : m.fields)
      if (f.name == name) return &f;
    return nullptr;
  };
  std::vector<std::pair<const VertexField*, const VertexField*>> pairs;
  auto note_unmatched = [&](const std::string& name) {
    if (std::find(out.unmatched_fields.begin(), out.unmatched_fields.end(), name) == out.unmatched_fields.end())
      out.unmatched_fields.push_back(name);
  };
  for (const auto& f : original.fields) {
    if (find(original, f.name) != &f) continue;  // a later duplicate name
    const VertexField* g = find(simplified, f.name);
    if (g && g->components == f.components) {
      check_field(original, f, "original");
      check_field(simplified, *g, "simplified");
      pairs.emplace_back(&f, g);
    } else {
      note_unmatched(f.name);
    }
  }
  for (const auto& g : simplified.fields) {
    const VertexField* f = find(original, g.name);
    if (!f || f->components != g.components) note_unmatched(g.name);
  }
  if (pairs.empty() || original.tets.empty() || simplified.tets.empty()) return out;

  const std::vector<VertId> orig_q = used_vertices(original);
  const std::vector<VertId> simp_q = used_vertices(simplified);
  const std::vector<Location> orig_loc = locate_all(original, orig_q, simplified);
  const std::vector<Location> simp_loc = locate_all(simplified, simp_q, original);
  out.original_in_simplified = location_stats(orig_loc);
  out.simplified_in_original = location_stats(simp_loc);

  for (const auto& [f, g] : pairs)
    for (int c = 0; c < f->components; ++c) {
      ComponentError e;
      e.field = f->name;
      e.component = c;
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const VertId v : orig_q) {
        const double x = f->values[v * static_cast<std::size_t>(f->components) + c];
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
      e.range = hi - lo;
      const double scale = e.range > 0.0 ? e.range : 1.0;
      const ErrorSums a = direction_error(*f, orig_q, orig_loc, simplified, *g, c);
      const ErrorSums b = direction_error(*g, simp_q, simp_loc, original, *f, c);
      e.original_to_simplified = finish(a, orig_q.size(), scale);
      e.simplified_to_original = finish(b, simp_q.size(), scale);
      e.rms_both = std::sqrt((a.sum_sq + b.sum_sq) / static_cast<double>(orig_q.size() + simp_q.size()));
      e.rms_both_rel = e.rms_both / scale;
      out.worst_rms_rel = std::max(out.worst_rms_rel, e.rms_both_rel);
      out.worst_max_rel = std::max({out.worst_max_rel, e.original_to_simplified.max_rel, e.simplified_to_original.max_rel});
      out.components.push_back(std::move(e));
    }
  return out;
}

}  // namespace topotet
