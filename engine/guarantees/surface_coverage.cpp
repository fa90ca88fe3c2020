// The original surfaces kept within h of the simplified ones (see surface_coverage.h).
#include "guarantees/surface_coverage.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "parallel/for_range.h"

namespace topotet {
namespace {

constexpr std::uint8_t kNoGuess = 0xFF;
constexpr std::uint8_t kDropped = 0xFF;  // depth of a pending piece replaced by its whole triangle

// Geometric order of points and of faces through p (by their other two corners, as a set): ties
// between equally good faces are broken by geometry, never by ids, so that the result does not
// depend on the numbering.
bool less(const glm::dvec3& a, const glm::dvec3& b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}
bool face_less(const std::array<glm::dvec3, 3>& f, const std::array<glm::dvec3, 3>& g) {
  const glm::dvec3& f0 = less(f[1], f[2]) ? f[1] : f[2];
  const glm::dvec3& f1 = less(f[1], f[2]) ? f[2] : f[1];
  const glm::dvec3& g0 = less(g[1], g[2]) ? g[1] : g[2];
  const glm::dvec3& g1 = less(g[1], g[2]) ? g[2] : g[1];
  if (f0 != g0) return less(f0, g0);
  return less(f1, g1);
}

// Corners in geometric order: how a piece is cut (the diagonal of the quadrilateral side) follows
// its corner order, which must not come from the numbering either.
std::array<glm::dvec3, 3> sorted(std::array<glm::dvec3, 3> q) {
  std::sort(q.begin(), q.end(), less);
  return q;
}

// The corners of a whole original triangle, as every item of depth 0 has them: a stored whole
// triangle keeps only its index, so this is also how its corners are read back.
std::array<glm::dvec3, 3> whole_corners(const SurfaceSoup& soup, std::uint32_t triangle) {
  const auto& t = soup.triangles[triangle];
  return sorted({soup.positions[t[0]], soup.positions[t[1]], soup.positions[t[2]]});
}

// A float not below x (bounds are stored as floats and must stay upper bounds).
float round_up(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) >= x ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
}

// Two vertex pairs alike (std::array's == calls memcmp here: millions of calls a run).
bool same_pair(const std::array<VertId, 2>& x, const std::array<VertId, 2>& y) { return x[0] == y[0] && x[1] == y[1]; }

bool face_has(const std::array<VertId, 4>& tet, std::uint8_t local, VertId x) {
  for (int k = 0; k < 4; ++k)
    if (k != local && tet[k] == x) return true;
  return false;
}

// Is the item's face (local face `local` of tet t) through u or v? Those are the faces a collapse
// u <- v changes; every other face keeps its vertices and positions.
bool moves(const MeshModel& mesh, TetId t, std::uint8_t local, VertId u, VertId v) {
  const auto& tv = mesh.tets[t];
  return face_has(tv, local, u) || face_has(tv, local, v);
}

// The same for a polyline edge (local edge `local` of tet t).
bool edge_moves(const MeshModel& mesh, TetId t, std::uint8_t local, VertId u, VertId v) {
  const VertId a = mesh.tets[t][kTetEdges[local][0]], b = mesh.tets[t][kTetEdges[local][1]];
  return a == u || a == v || b == u || b == v;
}

// Face `local` of tet tv as seen from its tet (outward, kTetFaces' order), rotated so that its
// smallest vertex comes first: the tets on the two sides of a face see opposite cyclic orders.
std::array<VertId, 3> oriented_face(const std::array<VertId, 4>& tv, int local) {
  const auto& f = kTetFaces[static_cast<std::size_t>(local)];
  std::array<VertId, 3> k{tv[f[0]], tv[f[1]], tv[f[2]]};
  std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
  return k;
}

std::array<VertId, 2> edge_of(const std::array<VertId, 4>& tv, int local) {
  const auto& e = kTetEdges[static_cast<std::size_t>(local)];
  return {std::min(tv[e[0]], tv[e[1]]), std::max(tv[e[0]], tv[e[1]])};
}

struct KeyHash {
  std::size_t operator()(const std::array<VertId, 3>& k) const {
    return (std::size_t{k[0]} * 0x9E3779B97F4A7C15ull) ^ (std::size_t{k[1]} * 0xC2B2AE3D27D4EB4Full) ^ k[2];
  }
  std::size_t operator()(const std::array<VertId, 2>& k) const { return (std::size_t{k[0]} * 0x9E3779B97F4A7C15ull) ^ k[1]; }
};

// The local index of edge xy (x < y) in tet tv, which has both.
int local_edge_of(const std::array<VertId, 4>& tv, const std::array<VertId, 2>& xy) {
  for (int e = 0; e < 6; ++e)
    if (edge_of(tv, e) == xy) return e;
  return -1;
}

// The first tet (by id) of St(u) ∪ St(v) minus St(uv) with edge xy, kInvalid if none.
TetId first_tet_with_edge(const MeshModel& mesh, const std::vector<TetId>& star_u, const std::vector<TetId>& star_v,
                          const std::vector<TetId>& star_uv, const std::array<VertId, 2>& xy) {
  TetId best = kInvalid;
  for (const std::vector<TetId>* star : {&star_u, &star_v})
    for (TetId t : *star)
      if (t < best && local_edge_of(mesh.tets[t], xy) >= 0 && !std::binary_search(star_uv.begin(), star_uv.end(), t))
        best = t;
  return best;
}

// Calls f(t) for every tet of St(u) ∪ St(v) once, in the stars' sorted order.
template <class F>
void for_each_stencil_tet(const std::vector<TetId>& star_u, const std::vector<TetId>& star_v,
                          const std::vector<TetId>& star_uv, F&& f) {
  for (TetId t : star_u) f(t);
  for (TetId t : star_v)
    if (!std::binary_search(star_uv.begin(), star_uv.end(), t)) f(t);
}

}  // namespace

SurfaceCoverage::SurfaceCoverage(const MeshModel& mesh, const SurfaceReference& reference, double h)
    : reference_(reference), h_(h), held_(mesh.tet_capacity()) {
  const auto& holders = reference.triangle_holders();
  for (std::uint32_t k = 0; k < holders.size(); ++k)
    append(held_[holders[k].tet], CoverageItem{whole_corners(reference.soup(), k), k, 0.0f, 0, holders[k].local});
  const auto& segment_holders = reference.segment_holders();
  for (std::uint32_t k = 0; k < segment_holders.size(); ++k) {
    const auto& e = reference.soup().segments[k];
    const auto& P = reference.soup().positions;
    append(held_[segment_holders[k].tet], CoverageSegment{less(P[e[1]], P[e[0]]) ? std::array<glm::dvec3, 2>{P[e[1]], P[e[0]]}
                                            : std::array<glm::dvec3, 2>{P[e[0]], P[e[1]]},
                     k, 0, segment_holders[k].local});
  }
}

namespace {

// The plane through the edge a-b shared by two new faces, bisecting the angle between them (o1, o2
// their third corners): it separates the faces, and on each side the points of a piece are
// nearest to that side's face when the piece lies close to both. Returns the plane's normal,
// oriented towards face 1, or zero when the faces are degenerate or folded flat onto each other.
glm::dvec3 bisector_normal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& o1, const glm::dvec3& o2) {
  const glm::dvec3 ab = b - a;
  const double ab2 = glm::dot(ab, ab);
  if (!(ab2 > 0.0)) return glm::dvec3(0.0);
  auto inward = [&](const glm::dvec3& o) {
    const glm::dvec3 w = (o - a) - ab * (glm::dot(o - a, ab) / ab2);
    const double l = glm::length(w);
    return l > 0.0 ? w / l : glm::dvec3(0.0);
  };
  // w1 - w2 (unit vectors) is orthogonal to the edge and to the bisecting direction w1 + w2, and
  // stays well defined when the faces are coplanar (w2 = -w1), where w1 + w2 vanishes.
  const glm::dvec3 n = inward(o1) - inward(o2);
  return glm::dot(n, n) > 1e-12 ? n : glm::dvec3(0.0);
}

// The squared distance from x to new face f, exact, or any value above `cutoff2` when a lower
// bound shows the distance is (the distance to the face's plane; that and the distance to the
// line of an edge x lies beyond). Most queries fall inside the face's prism (the plane distance)
// or are rejected by the bounds; the rest lie beyond one or two edges, and the closest point of
// the face is then on one of those edges (outside the triangle's shadow the closest point is on
// its boundary, and no point beyond edge k alone lies in the region of the other edges or of the
// opposite corner), so two segment distances at most replace the general closest-point search.
double face_distance2(const glm::dvec3& x, const CoverageScratch::Target& f, double cutoff2) {
  if (!(f.inv_normal2 > 0.0)) return squared_distance_to_triangle(x, f.pts[0], f.pts[1], f.pts[2]);  // degenerate
  const glm::dvec3 ax = x - f.pts[0];
  const double height = glm::dot(f.normal, ax);
  const double plane2 = height * height * f.inv_normal2;
  if (plane2 > cutoff2) return plane2;
  const double e0 = glm::dot(f.edge_in[0], ax), e1 = glm::dot(f.edge_in[1], x - f.pts[1]),
               e2 = glm::dot(f.edge_in[2], x - f.pts[2]);
  if (e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) return plane2;
  double out2 = 0.0;
  if (e0 < 0.0) out2 = std::max(out2, e0 * e0 * f.inv_edge_in2[0]);
  if (e1 < 0.0) out2 = std::max(out2, e1 * e1 * f.inv_edge_in2[1]);
  if (e2 < 0.0) out2 = std::max(out2, e2 * e2 * f.inv_edge_in2[2]);
  if (plane2 + out2 > cutoff2) return plane2 + out2;
  double d2 = std::numeric_limits<double>::infinity();
  if (e0 < 0.0) d2 = std::min(d2, squared_distance_to_segment(x, f.pts[0], f.pts[1]));
  if (e1 < 0.0) d2 = std::min(d2, squared_distance_to_segment(x, f.pts[1], f.pts[2]));
  if (e2 < 0.0) d2 = std::min(d2, squared_distance_to_segment(x, f.pts[2], f.pts[0]));
  return d2;
}

}  // namespace

// Splits an item no single new face holds. Preferably along the bisecting plane of two adjacent
// new faces that separates its corners (the pair whose shared edge is closest to the item): the
// two sides then usually each fit one face, as on a flat fan, where halving would need pieces
// of about h. Without such a plane, at the midpoints of its edges (four pieces).
void SurfaceCoverage::cut(const CoverageItem& item, int label, CoverageScratch& s) const {
  const auto& q = item.corners;
  const glm::dvec3 centre = (q[0] + q[1] + q[2]) / 3.0;
  const double size = std::sqrt(std::max({glm::dot(q[1] - q[0], q[1] - q[0]), glm::dot(q[2] - q[1], q[2] - q[1]),
                                          glm::dot(q[0] - q[2], q[0] - q[2])}));
  if (!s.hinges_found) {
    s.hinges.clear();
    for (std::size_t i = 0; i < s.targets.size(); ++i)
      for (std::size_t j = i + 1; j < s.targets.size(); ++j) {
        const auto& f = s.targets[i];
        const auto& g = s.targets[j];
        if (f.label != g.label) continue;
        // Shared edge p-x: one "other" vertex in common (new faces all contain p = pts[0]).
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b) {
            if (f.others[a] != g.others[b]) continue;
            const glm::dvec3 n = bisector_normal(f.pts[0], f.pts[1 + a], f.pts[2 - a], g.pts[2 - b]);
            if (n == glm::dvec3(0.0)) continue;
            s.hinges.push_back({f.pts[0], f.pts[1 + a], n, glm::length(n), f.label, static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(j)});
          }
      }
    s.hinges_found = true;
  }
  double best = std::numeric_limits<double>::infinity();
  glm::dvec3 best_normal(0.0), best_point(0.0);
  std::uint8_t side_pos = kNoGuess, side_neg = kNoGuess;  // the faces on either side of the cut
  glm::dvec3 best_edge(0.0);
  for (const CoverageScratch::Hinge& hinge : s.hinges) {
    if (hinge.label != label) continue;
    const glm::dvec3& n = hinge.normal;
    const glm::dvec3& p = hinge.p;
    // Corners within a rounding margin of the plane are on it: a piece cut there is not cut
    // again by the same plane because its cut points came out a few ulps off.
    const double eps = 1e-9 * size * hinge.normal_length;
    const double s0 = glm::dot(n, q[0] - p), s1 = glm::dot(n, q[1] - p), s2 = glm::dot(n, q[2] - p);
    const bool pos = s0 > eps || s1 > eps || s2 > eps, neg = s0 < -eps || s1 < -eps || s2 < -eps;
    if (!pos || !neg) continue;
    const double d = squared_distance_to_segment(centre, p, hinge.x);
    if (d < best || (d == best && less(hinge.x, best_edge))) {
      best_edge = hinge.x;
      best = d;
      best_normal = n;
      best_point = p;
      side_pos = hinge.first;
      side_neg = hinge.second;
    }
  }
  const auto depth = static_cast<std::uint8_t>(item.depth + 1);
  auto push = [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, std::uint8_t guess = kNoGuess) {
    s.pending.push_back({sorted({a, b, c}), item.triangle, std::numeric_limits<float>::infinity(), depth, guess});
  };
  if (best < std::numeric_limits<double>::infinity()) {
    std::array<double, 3> d{};
    for (int k = 0; k < 3; ++k) d[k] = glm::dot(best_normal, q[k] - best_point);
    // The corner alone on its side (k), and the crossing points on its two edges.
    int k = 0;
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, l = (i + 2) % 3;
      if ((d[i] > 0.0) != (d[j] > 0.0) && (d[i] > 0.0) != (d[l] > 0.0)) k = i;
    }
    const int j = (k + 1) % 3, l = (k + 2) % 3;
    auto cross = [&](int a, int b) { return q[a] + (q[b] - q[a]) * (d[a] / (d[a] - d[b])); };
    if (d[j] != d[k] && d[l] != d[k] && (d[k] > 0.0) != (d[j] > 0.0) && (d[k] > 0.0) != (d[l] > 0.0)) {
      const glm::dvec3 xj = cross(k, j), xl = cross(k, l);
      const std::uint8_t alone = d[k] > 0.0 ? side_pos : side_neg, pair = d[k] > 0.0 ? side_neg : side_pos;
      push(q[k], xj, xl, alone);
      push(xj, q[j], q[l], pair);
      push(xj, q[l], xl, pair);
      return;
    }
  }
  const glm::dvec3 ab = 0.5 * (q[0] + q[1]), bc = 0.5 * (q[1] + q[2]), ca = 0.5 * (q[2] + q[0]);
  push(q[0], ab, ca);
  push(ab, q[1], bc);
  push(ca, bc, q[2]);
  push(ab, bc, ca);
}

bool SurfaceCoverage::place(const MeshModel& mesh, VertId u, VertId v, const std::vector<TetId>& star_u,
                            const std::vector<TetId>& star_v, const std::vector<TetId>& star_uv,
                            const SurfaceStencil& stencil, CoverageScratch& s) const {
  // The distinct new faces with a tet that keeps them (a face made by two merging ones is listed
  // twice; one of the two may be held only by tets of St(uv), which vanish).
  s.targets.clear();
  for (std::size_t i = 0; i < stencil.new_faces.size(); ++i) {
    const SurfaceStencil::NewFace& f = stencil.new_faces[i];
    if (f.holder.tet == kInvalid) continue;
    bool seen = false;
    for (const auto& g : s.targets) seen = seen || (g.label == f.label && same_pair(g.others, f.others));
    if (seen) continue;
    const glm::dvec3 c = (f.pts[0] + f.pts[1] + f.pts[2]) / 3.0;
    const double r = std::sqrt(std::max({glm::dot(f.pts[0] - c, f.pts[0] - c), glm::dot(f.pts[1] - c, f.pts[1] - c),
                                         glm::dot(f.pts[2] - c, f.pts[2] - c)}));
    const glm::dvec3 n = glm::cross(f.pts[1] - f.pts[0], f.pts[2] - f.pts[0]);
    const double n2 = glm::dot(n, n);
    CoverageScratch::Target target{f.pts, f.others, f.label, f.holder, c, r, n, n2 > 0.0 ? 1.0 / n2 : 0.0,
                                   {glm::cross(n, f.pts[1] - f.pts[0]), glm::cross(n, f.pts[2] - f.pts[1]),
                                    glm::cross(n, f.pts[0] - f.pts[2])},
                                   {}};
    for (int k = 0; k < 3; ++k) {
      const double l2 = glm::dot(target.edge_in[k], target.edge_in[k]);
      target.inv_edge_in2[k] = l2 > 0.0 ? 1.0 / l2 : 0.0;
    }
    s.targets.push_back(target);
  }
  if (s.targets.size() >= kNoGuess) return false;  // item indices are bytes: refuse a fan that large
  s.hinges_found = false;
  s.pending.clear();
  s.placed.clear();
  const SurfaceSoup& soup = reference_.soup();
  // Each item's first guess (in `local` while pending): the new face its face becomes, the one
  // with the same two vertices other than u and v (its corner at u or v moved to p). Most items
  // stay on it, and most of those need no distance at all: `bound` plus the corner's move.
  // How far an item's guessed face moved: a face u x y becomes p x y, and every point of it moves
  // to within dist(u, p x y) of the new face (the distance to a convex set is convex, and x and y
  // stay), so bound + dist(u, new face) still bounds the item. That is |u - p| at most, and about
  // 0 when p slides within the surface: most items of a fan then need no distance at all.
  // One distance per new face and moving end, computed when first needed.
  s.moved_by.assign(2 * s.targets.size(), -1.0);
  const auto moved_by = [&](std::uint8_t target, bool at_u) {
    double& d = s.moved_by[2 * target + (at_u ? 0 : 1)];
    if (d < 0.0) {
      const auto& f = s.targets[target];
      d = std::sqrt(face_distance2(mesh.positions[at_u ? u : v], f, std::numeric_limits<double>::infinity()));
    }
    return d;
  };
  for_each_stencil_tet(star_u, star_v, star_uv, [&](TetId t) {
    const auto& tv = mesh.tets[t];
    const Records& list = held_[t];
    for (std::size_t i = 0; i < list.size(); i += records_of(list[i])) {
      if (is_segment(list[i]) || !moves(mesh, t, list[i].local, u, v)) continue;
      const CoverageItem item = decode(&list[i]);
      VertId others[3];
      int n = 0;
      bool at_u = false;
      for (int k = 0; k < 4; ++k) {
        if (k == item.local) continue;
        if (tv[k] == u) at_u = true;
        if (tv[k] != u && tv[k] != v) others[n++] = tv[k];
      }
      std::uint8_t guess = kNoGuess;
      float bound = std::numeric_limits<float>::infinity();  // while pending: on the guessed face
      if (n == 2) {
        const std::array<VertId, 2> key{std::min(others[0], others[1]), std::max(others[0], others[1])};
        for (std::size_t k = 0; k < s.targets.size() && guess == kNoGuess; ++k)
          if (same_pair(s.targets[k].others, key)) guess = static_cast<std::uint8_t>(k);
        if (guess != kNoGuess) bound = round_up(static_cast<double>(item.bound) + moved_by(guess, at_u));
      } else if (n == 1) {
        // Its face u v x vanishes into the edge p x: first try the new face through p x nearest to
        // the item (there are two on a manifold surface), without a bound, before all the others.
        const int label = static_cast<int>(soup.triangle_label[item.triangle]);
        const glm::dvec3 c = (item.corners[0] + item.corners[1] + item.corners[2]) / 3.0;
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < s.targets.size(); ++k) {
          const auto& f = s.targets[k];
          if (f.label != label || (f.others[0] != others[0] && f.others[1] != others[0])) continue;
          const double d = face_distance2(c, f, std::numeric_limits<double>::infinity());
          if (d < best || (d == best && guess != kNoGuess && face_less(f.pts, s.targets[guess].pts))) {
            best = d;
            guess = static_cast<std::uint8_t>(k);
          }
        }
      }
      s.pending.push_back({item.corners, item.triangle, bound, item.depth, guess});
    }
  });
  const double h2 = h_ * h_;
  // The exact squared distance, or any value above h^2 when a lower bound shows it is (the
  // bounding sphere first, then face_distance2's).
  auto dist2 = [&](const glm::dvec3& x, const CoverageScratch::Target& f) {
    const double reach = h_ + f.radius;
    const glm::dvec3 d = x - f.centre;
    if (glm::dot(d, d) > reach * reach * (1.0 + 1e-12)) return std::numeric_limits<double>::infinity();
    return face_distance2(x, f, h2);
  };
  auto near = [&](const glm::dvec3& x, const CoverageScratch::Target& f) { return dist2(x, f) <= h2; };
  // The largest distance of the corners to f, if all are within h; negative otherwise.
  auto holds = [&](const std::array<glm::dvec3, 3>& q, const CoverageScratch::Target& f) {
    double worst = 0.0;
    for (const glm::dvec3& x : q) {
      const double d2 = dist2(x, f);
      if (d2 > h2) return -1.0;
      worst = std::max(worst, d2);
    }
    return std::sqrt(worst);
  };
  // Pieces heal: when a new face holds the whole original triangle of a piece (of the faces the
  // triangle's pieces here would go to, the closest), its pieces here are replaced by the whole
  // triangle (pieces of it held elsewhere stay: a part covered twice is harmless). Without this,
  // re-placements would keep cutting items and the lists would only grow. Grouped by triangle;
  // every choice is geometric, so that the result does not depend on how the mesh is numbered
  // (a replay of the same collapses on the input numbering, as the hierarchy's downward-closed
  // sets do, must hold the same items as the run did).
  const bool any_piece =
      std::any_of(s.pending.begin(), s.pending.end(), [](const CoverageItem& item) { return item.depth > 0; });
  if (any_piece) {
    s.order.clear();
    for (std::uint32_t i = 0; i < s.pending.size(); ++i) s.order.push_back({s.pending[i].triangle, i});
    std::sort(s.order.begin(), s.order.end());
    s.healed_items.clear();
    for (std::size_t i = 0; i < s.order.size();) {
      std::size_t j = i + 1;
      while (j < s.order.size() && s.order[j].first == s.order[i].first) ++j;
      bool pieces = false;
      for (std::size_t k = i; k < j; ++k) pieces = pieces || s.pending[s.order[k].second].depth > 0;
      int heal = -1;
      double heal_d = 0.0;
      const std::uint32_t tri = s.order[i].first;
      const std::array<glm::dvec3, 3> whole = whole_corners(soup, tri);
      if (pieces) {
        const int label = static_cast<int>(soup.triangle_label[tri]);
        for (std::size_t k = i; k < j; ++k) {
          const std::uint8_t g = s.pending[s.order[k].second].local;
          if (g == kNoGuess || g == heal || s.targets[g].label != label) continue;
          const double d = holds(whole, s.targets[g]);
          if (d >= 0.0 && (heal < 0 || d < heal_d || (d == heal_d && face_less(s.targets[g].pts, s.targets[heal].pts)))) {
            heal = g;
            heal_d = d;
          }
        }
      }
      if (heal >= 0) {
        s.healed_items.push_back({whole, tri, round_up(heal_d), 0, static_cast<std::uint8_t>(heal)});
        for (std::size_t k = i; k < j; ++k) s.pending[s.order[k].second].depth = kDropped;
      }
      i = j;
    }
    s.pending.erase(std::remove_if(s.pending.begin(), s.pending.end(),
                                   [](const CoverageItem& item) { return item.depth == kDropped; }),
                    s.pending.end());
    s.pending.insert(s.pending.end(), s.healed_items.begin(), s.healed_items.end());
  }
  for (std::size_t i = 0; i < s.pending.size(); ++i) {  // pieces are appended: a FIFO
    if (s.pending.size() > kMaxPieces) return false;
    const CoverageItem item = s.pending[i];
    const int label = static_cast<int>(soup.triangle_label[item.triangle]);
    const auto& q = item.corners;
    if (item.local != kNoGuess && static_cast<double>(item.bound) <= h_ && s.targets[item.local].label == label) {
      s.placed.push_back(item);  // the bound proves it: no distance computed
      continue;
    }
    int found = -1;
    double found_bound = 0.0;
    if (item.local != kNoGuess && s.targets[item.local].label == label) {
      found_bound = holds(q, s.targets[item.local]);
      if (found_bound >= 0.0) found = item.local;
    }
    // Else the face that holds it closest (geometric, so independent of the numbering).
    const bool guessed = found >= 0;
    for (std::size_t k = 0; k < s.targets.size() && !guessed; ++k) {
      if (s.targets[k].label != label) continue;
      const double d = holds(q, s.targets[k]);
      if (d >= 0.0 && (found < 0 || d < found_bound ||
                       (d == found_bound && face_less(s.targets[k].pts, s.targets[found].pts)))) {
        found = static_cast<int>(k);
        found_bound = d;
      }
    }
    if (found >= 0) {
      s.placed.push_back({q, item.triangle, round_up(found_bound), item.depth, static_cast<std::uint8_t>(found)});
      continue;
    }
    if (item.depth >= kMaxDepth) return false;
    // Every point of the item must be within h of some new face for any cut to succeed: a corner,
    // the centre or an edge midpoint that no new face holds refuses the placement at once. (Whole
    // items only: pieces are bounded by the depth and piece limits.)
    if (item.depth == 0) {
      const std::array<glm::dvec3, 7> probes{q[0], q[1], q[2], (q[0] + q[1] + q[2]) / 3.0, 0.5 * (q[0] + q[1]),
                                             0.5 * (q[1] + q[2]), 0.5 * (q[2] + q[0])};
      for (const glm::dvec3& x : probes) {
        bool any = false;
        for (const auto& f : s.targets) any = any || (f.label == label && near(x, f));
        if (!any) return false;
      }
    }
    cut(item, label, s);
  }
  return place_segments(mesh, u, v, star_u, star_v, star_uv, stencil, s);
}

bool SurfaceCoverage::place_segments(const MeshModel& mesh, VertId u, VertId v, const std::vector<TetId>& star_u,
                                     const std::vector<TetId>& star_v, const std::vector<TetId>& star_uv,
                                     const SurfaceStencil& stencil, CoverageScratch& s) const {
  s.segment_targets.clear();
  for (const SurfaceStencil::NewEdge& e : stencil.new_edges) {
    if (e.holder.tet == kInvalid) continue;
    bool seen = false;
    for (const auto& g : s.segment_targets) seen = seen || (g.label == e.label && g.other == e.other);
    if (!seen) s.segment_targets.push_back({e.pts, e.other, e.label, e.holder});
  }
  if (s.segment_targets.size() >= kNoGuess) return false;
  s.segment_pending.clear();
  s.segment_placed.clear();
  for_each_stencil_tet(star_u, star_v, star_uv, [&](TetId t) {
    const Records& list = held_[t];
    for (std::size_t i = 0; i < list.size(); i += records_of(list[i]))
      if (is_segment(list[i]) && edge_moves(mesh, t, list[i].local & ~kSegment, u, v))
        s.segment_pending.push_back(decode_segment(&list[i]));
  });
  if (s.segment_pending.empty()) return true;
  const SurfaceSoup& soup = reference_.soup();
  const double h2 = h_ * h_;
  auto near = [&](const glm::dvec3& x, const CoverageScratch::SegmentTarget& e) {
    return squared_distance_to_segment(x, e.pts[0], e.pts[1]) <= h2;
  };
  auto label_of = [&](std::uint32_t segment) { return static_cast<int>(soup.face_labels + soup.segment_label[segment]); };
  // Pieces heal, as for triangles.
  std::sort(s.segment_pending.begin(), s.segment_pending.end(), [](const auto& a, const auto& b) {
    return a.segment != b.segment ? a.segment < b.segment : a.depth < b.depth;
  });
  {
    std::size_t out = 0;
    for (std::size_t i = 0; i < s.segment_pending.size();) {
      std::size_t j = i + 1;
      while (j < s.segment_pending.size() && s.segment_pending[j].segment == s.segment_pending[i].segment) ++j;
      const std::uint32_t seg = s.segment_pending[i].segment;
      const auto& e = soup.segments[seg];
      const glm::dvec3 &e0 = soup.positions[e[0]], &e1 = soup.positions[e[1]];
      const std::array<glm::dvec3, 2> whole = less(e1, e0) ? std::array<glm::dvec3, 2>{e1, e0} : std::array<glm::dvec3, 2>{e0, e1};
      bool healed = false;
      if (s.segment_pending[i].depth > 0 || j - i > 1)
        for (const auto& g : s.segment_targets)
          healed = healed || (g.label == label_of(seg) && near(whole[0], g) && near(whole[1], g));
      if (healed) {
        s.segment_pending[out++] = {whole, seg, 0, 0};
      } else {
        for (std::size_t k = i; k < j; ++k) s.segment_pending[out++] = s.segment_pending[k];
      }
      i = j;
    }
    s.segment_pending.resize(out);
  }
  // A geometric order and the closest edge: independent of the numbering, as for triangles.
  std::sort(s.segment_pending.begin(), s.segment_pending.end(), [](const auto& a, const auto& b) {
    if (a.depth != b.depth) return a.depth < b.depth;
    for (int k = 0; k < 2; ++k)
      for (int c = 0; c < 3; ++c)
        if (a.ends[k][c] != b.ends[k][c]) return a.ends[k][c] < b.ends[k][c];
    return false;
  });
  for (std::size_t i = 0; i < s.segment_pending.size(); ++i) {
    if (s.segment_pending.size() > kMaxPieces) return false;
    const CoverageSegment item = s.segment_pending[i];
    const int label = label_of(item.segment);
    int found = -1;
    double found_d2 = 0.0;
    for (std::size_t k = 0; k < s.segment_targets.size(); ++k) {
      const auto& g = s.segment_targets[k];
      if (g.label != label) continue;
      const double d2 = std::max(squared_distance_to_segment(item.ends[0], g.pts[0], g.pts[1]),
                                 squared_distance_to_segment(item.ends[1], g.pts[0], g.pts[1]));
      if (d2 <= h2 && (found < 0 || d2 < found_d2 ||
                       (d2 == found_d2 && less(g.pts[1], s.segment_targets[found].pts[1])))) {
        found = static_cast<int>(k);
        found_d2 = d2;
      }
    }
    if (found >= 0) {
      s.segment_placed.push_back({item.ends, item.segment, item.depth, static_cast<std::uint8_t>(found)});
      continue;
    }
    if (item.depth >= kMaxDepth) return false;
    for (const glm::dvec3& x : {item.ends[0], item.ends[1], 0.5 * (item.ends[0] + item.ends[1])}) {
      bool any = false;
      for (const auto& g : s.segment_targets) any = any || (g.label == label && near(x, g));
      if (!any) return false;
    }
    cut(item, label, s);
  }
  return true;
}

// A segment piece no single new edge holds: cut where the plane through p bisecting two new
// edges p-x and p-y separates its ends, else at its midpoint.
void SurfaceCoverage::cut(const CoverageSegment& item, int label, CoverageScratch& s) const {
  const auto& q = item.ends;
  const double size = glm::length(q[1] - q[0]);
  const auto depth = static_cast<std::uint8_t>(item.depth + 1);
  for (std::size_t i = 0; i < s.segment_targets.size(); ++i)
    for (std::size_t j = i + 1; j < s.segment_targets.size(); ++j) {
      const auto& f = s.segment_targets[i];
      const auto& g = s.segment_targets[j];
      if (f.label != label || g.label != label) continue;
      const glm::dvec3 p = f.pts[0];
      const glm::dvec3 a = f.pts[1] - p, b = g.pts[1] - p;
      const double la = glm::length(a), lb = glm::length(b);
      if (!(la > 0.0) || !(lb > 0.0)) continue;
      const glm::dvec3 n = a / la - b / lb;
      const double eps = 1e-9 * size * glm::length(n);
      const double d0 = glm::dot(n, q[0] - p), d1 = glm::dot(n, q[1] - p);
      if (!((d0 > eps && d1 < -eps) || (d0 < -eps && d1 > eps))) continue;
      const glm::dvec3 x = q[0] + (q[1] - q[0]) * (d0 / (d0 - d1));
      s.segment_pending.push_back({{q[0], x}, item.segment, depth, 0});
      s.segment_pending.push_back({{x, q[1]}, item.segment, depth, 0});
      return;
    }
  const glm::dvec3 m = 0.5 * (q[0] + q[1]);
  s.segment_pending.push_back({{q[0], m}, item.segment, depth, 0});
  s.segment_pending.push_back({{m, q[1]}, item.segment, depth, 0});
}

void SurfaceCoverage::commit(const MeshModel& mesh, VertId u, VertId v, const std::vector<TetId>& star_u,
                             const std::vector<TetId>& star_v, const std::vector<TetId>& star_uv, CoverageScratch& s) {
  // Drop the moved items and segments from the stencil's lists, then store the placed ones with
  // their new holder (`local` indexed the targets until now).
  for_each_stencil_tet(star_u, star_v, star_uv, [&](TetId t) {
    erase_records_if(held_[t], [&](const ItemRecord* head) {
      return is_segment(*head) ? edge_moves(mesh, t, head->local & ~kSegment, u, v) : moves(mesh, t, head->local, u, v);
    });
  });
  keep_segments_of_removed_tets(mesh, star_u, star_v, star_uv);
  for (CoverageItem item : s.placed) {
    const FaceHolder holder = s.targets[item.local].holder;
    item.local = holder.local;
    append(held_[holder.tet], item);
  }
  for (CoverageSegment item : s.segment_placed) {
    const FaceHolder holder = s.segment_targets[item.local].holder;
    item.local = holder.local;
    append(held_[holder.tet], item);
  }
  // Lists only grow in capacity otherwise: free the empty ones (dead tets, faces that left the
  // surface) and trim the slack of the others.
  for_each_stencil_tet(star_u, star_v, star_uv, [&](TetId t) {
    Records& list = held_[t];
    if (list.capacity() > list.size() + list.size() / 2 + 4 || list.size() == 0) list.shrink_to_fit();
  });
}

void SurfaceCoverage::keep_segments_of_removed_tets(const MeshModel& mesh, const std::vector<TetId>& star_u,
                                                   const std::vector<TetId>& star_v, const std::vector<TetId>& star_uv) {
  for (TetId t : star_uv) {
    // Each segment that goes is appended to its new holder (a tet outside St(uv): another list).
    erase_records_if(held_[t], [&](const ItemRecord* head) {
      if (!is_segment(*head)) return false;  // (none: every face of the tet is through u or v)
      const auto xy = edge_of(mesh.tets[t], head->local & ~kSegment);
      const TetId to = first_tet_with_edge(mesh, star_u, star_v, star_uv, xy);
      if (to == kInvalid) return false;  // no tet keeps xy (the collapse removes the edge)
      CoverageSegment item = decode_segment(head);
      item.local = static_cast<std::uint8_t>(local_edge_of(mesh.tets[to], xy));
      append(held_[to], item);
      return true;
    });
  }
}

std::size_t SurfaceCoverage::item_count() const {
  std::size_t n = 0;
  for (const Records& list : held_)
    for (std::size_t i = 0; i < list.size(); i += records_of(list[i])) ++n;
  return n;
}

SurfaceCoverage::Records::Header SurfaceCoverage::Records::header() const {
  Header h;
  std::memcpy(&h, &data_[0], sizeof h);
  return h;
}

void SurfaceCoverage::Records::set_header(std::uint32_t size, std::uint32_t capacity) {
  const Header h{size, capacity, 0};
  std::memcpy(&data_[0], &h, sizeof h);
}

void SurfaceCoverage::Records::reallocate(std::size_t capacity) {
  const std::size_t n = size();  // <= capacity: callers only grow it or fit it
  std::unique_ptr<ItemRecord[]> block(new ItemRecord[capacity + 1]);
  if (n > 0) std::copy_n(&data_[1], n, &block[1]);
  data_ = std::move(block);
  set_header(static_cast<std::uint32_t>(n), static_cast<std::uint32_t>(capacity));
}

void SurfaceCoverage::Records::resize(std::size_t n) {
  if (n > capacity()) reallocate(std::max(n, 2 * capacity()));
  if (data_) set_header(static_cast<std::uint32_t>(n), header().capacity);
}

void SurfaceCoverage::Records::shrink_to_fit() {
  if (size() == 0)
    data_.reset();
  else if (size() < capacity())
    reallocate(size());
}

void SurfaceCoverage::append(Records& list, const CoverageItem& item) {
  const std::size_t at = list.size();
  list.resize(at + (item.depth == 0 ? 1 : 1 + kCornerRecords));
  list[at] = {item.triangle, item.bound, item.depth, item.local};
  // (a whole triangle: its corners are the soup's)
  if (item.depth > 0) std::memcpy(static_cast<void*>(&list[at + 1]), item.corners.data(), sizeof(item.corners));
}

void SurfaceCoverage::append(Records& list, const CoverageSegment& item) {
  const std::size_t at = list.size();
  list.resize(at + 1 + kEndRecords);
  list[at] = {item.segment, 0.0f, item.depth, static_cast<std::uint8_t>(item.local | kSegment)};
  std::memcpy(static_cast<void*>(&list[at + 1]), item.ends.data(), sizeof(item.ends));
}

void SurfaceCoverage::drop_unheld_segments(const MeshModel& mesh, std::int32_t ref) {
  const int id = reference_.polyline_label_id(ref);
  if (id < 0) return;
  const auto label = static_cast<std::uint32_t>(id - static_cast<int>(reference_.face_label_count()));
  const auto& segment_label = reference_.soup().segment_label;
  parallel::for_range<std::size_t>(0, held_.size(), 4096, "drop_segments", [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      Records& list = held_[t];
      const bool dropped = erase_records_if(list, [&](const ItemRecord* head) {
        return is_segment(*head) && segment_label[head->triangle] == label &&
               !is_polyline_edge(mesh.flags[t], head->local & ~kSegment);
      });
      if (dropped) list.shrink_to_fit();
    }
  });
}

SurfaceCoverage::Detached SurfaceCoverage::detach(const MeshModel& mesh) {
  Detached d;
  for (TetId t = 0; t < held_.size(); ++t)
    if (held_[t].size() > 0) {
      d.tets.push_back(mesh.tets[t]);
      d.lists.push_back(std::move(held_[t]));
    }
  held_.clear();
  return d;
}

void SurfaceCoverage::attach(const MeshModel& mesh, Detached&& d) {
  // The faces and edges that held items, then where they are now.
  std::unordered_map<std::array<VertId, 3>, FaceHolder, KeyHash> faces;
  std::unordered_map<std::array<VertId, 2>, FaceHolder, KeyHash> edges;
  constexpr FaceHolder kNone{kInvalid, 0};
  for (std::size_t i = 0; i < d.lists.size(); ++i)
    for (std::size_t r = 0; r < d.lists[i].size(); r += records_of(d.lists[i][r])) {
      const ItemRecord& head = d.lists[i][r];
      if (is_segment(head))
        edges.emplace(edge_of(d.tets[i], head.local & ~kSegment), kNone);
      else
        faces.emplace(oriented_face(d.tets[i], head.local), kNone);
    }
  for (TetId t = 0; t < mesh.tets.size(); ++t) {
    if (mesh.is_dead_tet(t)) continue;
    const auto& tv = mesh.tets[t];
    for (int f = 0; f < 4; ++f)
      if (const auto it = faces.find(oriented_face(tv, f)); it != faces.end() && it->second.tet == kInvalid)
        it->second = {t, static_cast<std::uint8_t>(f)};
    for (int e = 0; e < 6; ++e)
      if (is_polyline_edge(mesh.flags[t], e))
        if (const auto it = edges.find(edge_of(tv, e)); it != edges.end() && it->second.tet == kInvalid)
          it->second = {t, static_cast<std::uint8_t>(e)};
  }
  held_.clear();
  held_.resize(mesh.tets.size());
  for (std::size_t i = 0; i < d.lists.size(); ++i) {
    const Records& list = d.lists[i];
    for (std::size_t r = 0; r < list.size(); r += records_of(list[r])) {
      const ItemRecord& head = list[r];
      const FaceHolder to = is_segment(head) ? edges.at(edge_of(d.tets[i], head.local & ~kSegment))
                                             : faces.at(oriented_face(d.tets[i], head.local));
      if (to.tet == kInvalid)
        throw std::logic_error("SurfaceCoverage::attach: a face or edge holding an original surface is gone");
      Records& out = held_[to.tet];
      const std::size_t at = out.size(), n = records_of(head);
      out.resize(at + n);
      std::copy_n(&list[r], n, &out[at]);
      out[at].local = is_segment(head) ? static_cast<std::uint8_t>(to.local | kSegment) : to.local;
    }
  }
  for (Records& list : held_) list.shrink_to_fit();
}

CoverageSegment SurfaceCoverage::decode_segment(const ItemRecord* head) {
  CoverageSegment item{{}, head->triangle, head->depth, static_cast<std::uint8_t>(head->local & ~kSegment)};
  std::memcpy(item.ends.data(), static_cast<const void*>(head + 1), sizeof(item.ends));
  return item;
}

bool SurfaceCoverage::held_triangles(const std::vector<TetId>& star_u, const std::vector<TetId>& star_v,
                                     const std::vector<TetId>& star_uv, std::size_t most,
                                     std::vector<std::uint32_t>& out) const {
  out.clear();
  bool fits = true;
  for_each_stencil_tet(star_u, star_v, star_uv, [&](TetId t) {
    const Records& list = held_[t];
    for (std::size_t i = 0; fits && i < list.size(); i += records_of(list[i])) {
      if (is_segment(list[i])) continue;
      const std::uint32_t k = list[i].triangle;
      if (std::find(out.begin(), out.end(), k) != out.end()) continue;  // pieces of one triangle
      if (out.size() == most) fits = false;
      else out.push_back(k);
    }
  });
  if (!fits) out.clear();
  return fits;
}

CoverageItem SurfaceCoverage::decode(const ItemRecord* head) const {
  CoverageItem item{{}, head->triangle, head->bound, head->depth, head->local};
  if (head->depth == 0)
    item.corners = whole_corners(reference_.soup(), head->triangle);
  else
    std::memcpy(item.corners.data(), static_cast<const void*>(head + 1), sizeof(item.corners));
  return item;
}

std::size_t SurfaceCoverage::memory_bytes() const {
  std::size_t bytes = held_.capacity() * sizeof(held_[0]);
  for (const Records& list : held_)
    if (list) bytes += (list.capacity() + 1) * sizeof(ItemRecord);
  return bytes;
}

}  // namespace topotet
