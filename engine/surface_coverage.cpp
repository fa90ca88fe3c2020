// The original surfaces kept within h of the simplified ones (see surface_coverage.h).
#include "surface_coverage.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace topotet {

namespace {

constexpr std::uint8_t kNoGuess = 0xFF;

bool face_has(const std::array<VertId, 4>& tet, std::uint8_t local, VertId x) {
  for (int k = 0; k < 4; ++k)
    if (k != local && tet[k] == x) return true;
  return false;
}

// Is the item's face (local face `local` of tet t) through u or v? Those are the faces a collapse
// u <- v changes; every other face keeps its vertices and positions.
bool moves(const TetMesh& mesh, TetId t, std::uint8_t local, VertId u, VertId v) {
  const auto& tv = mesh.tets[t];
  return face_has(tv, local, u) || face_has(tv, local, v);
}

// The same for a polyline edge (local edge `local` of tet t).
bool edge_moves(const TetMesh& mesh, TetId t, std::uint8_t local, VertId u, VertId v) {
  const VertId a = mesh.tets[t][kTetEdges[local][0]], b = mesh.tets[t][kTetEdges[local][1]];
  return a == u || a == v || b == u || b == v;
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

SurfaceCoverage::SurfaceCoverage(const TetMesh& mesh, const SurfaceReference& reference, double h)
    : reference_(reference), h_(h), lists_(mesh.tet_capacity()) {
  const auto& holders = reference.triangle_holders();
  for (std::uint32_t k = 0; k < holders.size(); ++k) {
    auto& list = lists_[holders[k].tet];
    if (!list) list = std::make_unique<std::vector<CoverageItem>>();
    const auto& t = reference.soup().triangles[k];
    const auto& P = reference.soup().positions;
    list->push_back({{P[t[0]], P[t[1]], P[t[2]]}, k, 0, holders[k].local});
  }
  segment_lists_.resize(mesh.tet_capacity());
  const auto& segment_holders = reference.segment_holders();
  for (std::uint32_t k = 0; k < segment_holders.size(); ++k) {
    auto& list = segment_lists_[segment_holders[k].tet];
    if (!list) list = std::make_unique<std::vector<CoverageSegment>>();
    const auto& e = reference.soup().segments[k];
    const auto& P = reference.soup().positions;
    list->push_back({{P[e[0]], P[e[1]]}, k, 0, segment_holders[k].local});
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
  double best = std::numeric_limits<double>::infinity();
  glm::dvec3 best_normal(0.0), best_point(0.0);
  for (std::size_t i = 0; i < s.targets.size(); ++i)
    for (std::size_t j = i + 1; j < s.targets.size(); ++j) {
      const auto& f = s.targets[i];
      const auto& g = s.targets[j];
      if (f.label != label || g.label != label) continue;
      // Shared edge p-x: one "other" vertex in common (new faces all contain p = pts[0]).
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
          if (f.others[a] != g.others[b]) continue;
          const glm::dvec3 p = f.pts[0], x = f.pts[1 + a];
          const glm::dvec3 n = bisector_normal(p, x, f.pts[2 - a], g.pts[2 - b]);
          if (n == glm::dvec3(0.0)) continue;
          // Corners within a rounding margin of the plane are on it: a piece cut there is not cut
          // again by the same plane because its cut points came out a few ulps off.
          const double eps = 1e-9 * size * glm::length(n);
          const double s0 = glm::dot(n, q[0] - p), s1 = glm::dot(n, q[1] - p), s2 = glm::dot(n, q[2] - p);
          const bool pos = s0 > eps || s1 > eps || s2 > eps, neg = s0 < -eps || s1 < -eps || s2 < -eps;
          if (!pos || !neg) continue;
          const double d = squared_distance_to_segment(centre, p, x);
          if (d < best) {
            best = d;
            best_normal = n;
            best_point = p;
          }
        }
    }
  const auto depth = static_cast<std::uint8_t>(item.depth + 1);
  auto push = [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    s.pending.push_back({{a, b, c}, item.triangle, depth, kNoGuess});
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
      push(q[k], xj, xl);
      push(xj, q[j], q[l]);
      push(xj, q[l], xl);
      return;
    }
  }
  const glm::dvec3 ab = 0.5 * (q[0] + q[1]), bc = 0.5 * (q[1] + q[2]), ca = 0.5 * (q[2] + q[0]);
  push(q[0], ab, ca);
  push(ab, q[1], bc);
  push(ca, bc, q[2]);
  push(ab, bc, ca);
}

bool SurfaceCoverage::place(const TetMesh& mesh, VertId u, VertId v, const std::vector<TetId>& star_u,
                            const std::vector<TetId>& star_v, const std::vector<TetId>& star_uv,
                            const SurfaceStencil& stencil, CoverageScratch& s) const {
  // The distinct new faces with a tet that keeps them (a face made by two merging ones is listed
  // twice; one of the two may be held only by tets of St(uv), which vanish).
  s.targets.clear();
  for (std::size_t i = 0; i < stencil.new_faces.size(); ++i) {
    const SurfaceStencil::NewFace& f = stencil.new_faces[i];
    if (f.holder.tet == kInvalid) continue;
    bool seen = false;
    for (const auto& g : s.targets) seen = seen || (g.label == f.label && g.others == f.others);
    if (!seen) s.targets.push_back({f.pts, f.others, f.label, f.holder});
  }
  if (s.targets.size() >= kNoGuess) return false;  // item indices are bytes: refuse a fan that large
  s.pending.clear();
  s.placed.clear();
  const SurfaceSoup& soup = reference_.soup();
  // Each item's first guess (in `local` while pending): the new face its face becomes, the one
  // with the same two vertices other than u and v. Most items stay on it: one test instead of a
  // scan of the fan.
  for_each_stencil_tet(star_u, star_v, star_uv, [&](TetId t) {
    if (!lists_[t]) return;
    const auto& tv = mesh.tets[t];
    for (const CoverageItem& item : *lists_[t]) {
      if (!moves(mesh, t, item.local, u, v)) continue;
      VertId others[3];
      int n = 0;
      for (int k = 0; k < 4; ++k)
        if (k != item.local && tv[k] != u && tv[k] != v) others[n++] = tv[k];
      std::uint8_t guess = kNoGuess;
      if (n == 2) {
        const std::array<VertId, 2> key{std::min(others[0], others[1]), std::max(others[0], others[1])};
        for (std::size_t k = 0; k < s.targets.size() && guess == kNoGuess; ++k)
          if (s.targets[k].others == key) guess = static_cast<std::uint8_t>(k);
      }
      s.pending.push_back({item.corners, item.triangle, item.depth, guess});
    }
  });
  const double h2 = h_ * h_;
  auto near = [&](const glm::dvec3& x, const CoverageScratch::Target& f) {
    return squared_distance_to_triangle(x, f.pts[0], f.pts[1], f.pts[2]) <= h2;
  };
  // Pieces heal: a piece whose whole original triangle one new face holds goes back to being the
  // whole triangle, once per triangle (pieces of it held elsewhere stay: a part covered twice is
  // harmless). Without this, every re-placement could cut items further and the lists would only
  // grow.
  const bool any_piece =
      std::any_of(s.pending.begin(), s.pending.end(), [](const CoverageItem& item) { return item.depth > 0; });
  if (any_piece) {
    std::sort(s.pending.begin(), s.pending.end(), [](const CoverageItem& a, const CoverageItem& b) {
      return a.triangle != b.triangle ? a.triangle < b.triangle : a.depth < b.depth;
    });
    const auto& P = soup.positions;
    std::size_t out = 0;
    for (std::size_t i = 0; i < s.pending.size();) {
      std::size_t j = i + 1;
      while (j < s.pending.size() && s.pending[j].triangle == s.pending[i].triangle) ++j;
      const std::uint32_t tri = s.pending[i].triangle;
      const auto& t = soup.triangles[tri];
      const std::array<glm::dvec3, 3> whole{P[t[0]], P[t[1]], P[t[2]]};
      const int label = static_cast<int>(soup.triangle_label[tri]);
      bool healed = false;
      if (s.pending[i].depth > 0 || j - i > 1)
        for (const auto& f : s.targets)
          if (f.label == label && near(whole[0], f) && near(whole[1], f) && near(whole[2], f)) {
            healed = true;
            break;
          }
      if (healed) {
        s.pending[out++] = {whole, tri, 0, kNoGuess};
      } else {
        for (std::size_t k = i; k < j; ++k) s.pending[out++] = s.pending[k];
      }
      i = j;
    }
    s.pending.resize(out);
  }
  for (std::size_t i = 0; i < s.pending.size(); ++i) {  // pieces are appended: a FIFO
    if (s.pending.size() > kMaxPieces) return false;
    const CoverageItem item = s.pending[i];
    const int label = static_cast<int>(soup.triangle_label[item.triangle]);
    const auto& q = item.corners;
    int found = -1;
    if (item.local != kNoGuess) {
      const auto& f = s.targets[item.local];
      if (f.label == label && near(q[0], f) && near(q[1], f) && near(q[2], f)) found = item.local;
    }
    for (std::size_t k = 0; k < s.targets.size() && found < 0; ++k) {
      const auto& f = s.targets[k];
      if (f.label == label && near(q[0], f) && near(q[1], f) && near(q[2], f)) found = static_cast<int>(k);
    }
    if (found >= 0) {
      s.placed.push_back({q, item.triangle, item.depth, static_cast<std::uint8_t>(found)});
      continue;
    }
    if (item.depth >= kMaxDepth) return false;
    // Every point of the item must be within h of some new face for any cut to succeed: a corner,
    // the centre or an edge midpoint that no new face holds refuses the placement at once.
    const std::array<glm::dvec3, 7> probes{q[0], q[1], q[2], (q[0] + q[1] + q[2]) / 3.0, 0.5 * (q[0] + q[1]),
                                           0.5 * (q[1] + q[2]), 0.5 * (q[2] + q[0])};
    for (const glm::dvec3& x : probes) {
      bool any = false;
      for (const auto& f : s.targets) any = any || (f.label == label && near(x, f));
      if (!any) return false;
    }
    cut(item, label, s);
  }
  return place_segments(mesh, u, v, star_u, star_v, star_uv, stencil, s);
}

bool SurfaceCoverage::place_segments(const TetMesh& mesh, VertId u, VertId v, const std::vector<TetId>& star_u,
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
    if (!segment_lists_[t]) return;
    for (const CoverageSegment& item : *segment_lists_[t])
      if (edge_moves(mesh, t, item.local, u, v)) s.segment_pending.push_back(item);
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
      const std::array<glm::dvec3, 2> whole{soup.positions[e[0]], soup.positions[e[1]]};
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
  for (std::size_t i = 0; i < s.segment_pending.size(); ++i) {
    if (s.segment_pending.size() > kMaxPieces) return false;
    const CoverageSegment item = s.segment_pending[i];
    const int label = label_of(item.segment);
    int found = -1;
    for (std::size_t k = 0; k < s.segment_targets.size() && found < 0; ++k) {
      const auto& g = s.segment_targets[k];
      if (g.label == label && near(item.ends[0], g) && near(item.ends[1], g)) found = static_cast<int>(k);
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

void SurfaceCoverage::commit(const TetMesh& mesh, VertId u, VertId v, const std::vector<TetId>& star_u,
                             const std::vector<TetId>& star_v, const std::vector<TetId>& star_uv, CoverageScratch& s) {
  for_each_stencil_tet(star_u, star_v, star_uv, [&](TetId t) {
    if (!lists_[t]) return;
    auto& list = *lists_[t];
    list.erase(std::remove_if(list.begin(), list.end(),
                              [&](const CoverageItem& item) { return moves(mesh, t, item.local, u, v); }),
               list.end());
  });
  for (const CoverageItem& item : s.placed) {
    const FaceHolder holder = s.targets[item.local].holder;
    auto& list = lists_[holder.tet];
    if (!list) list = std::make_unique<std::vector<CoverageItem>>();
    list->push_back({item.corners, item.triangle, item.depth, holder.local});
  }
  for_each_stencil_tet(star_u, star_v, star_uv, [&](TetId t) {
    if (!segment_lists_[t]) return;
    auto& list = *segment_lists_[t];
    list.erase(std::remove_if(list.begin(), list.end(),
                              [&](const CoverageSegment& item) { return edge_moves(mesh, t, item.local, u, v); }),
               list.end());
  });
  for (const CoverageSegment& item : s.segment_placed) {
    const FaceHolder holder = s.segment_targets[item.local].holder;
    auto& list = segment_lists_[holder.tet];
    if (!list) list = std::make_unique<std::vector<CoverageSegment>>();
    list->push_back({item.ends, item.segment, item.depth, holder.local});
  }
}

std::size_t SurfaceCoverage::item_count() const {
  std::size_t n = 0;
  for (const auto& list : lists_)
    if (list) n += list->size();
  for (const auto& list : segment_lists_)
    if (list) n += list->size();
  return n;
}

std::size_t SurfaceCoverage::memory_bytes() const {
  std::size_t bytes = lists_.capacity() * sizeof(lists_[0]);
  for (const auto& list : lists_)
    if (list) bytes += sizeof(*list) + list->capacity() * sizeof(CoverageItem);
  bytes += segment_lists_.capacity() * sizeof(segment_lists_[0]);
  for (const auto& list : segment_lists_)
    if (list) bytes += sizeof(*list) + list->capacity() * sizeof(CoverageSegment);
  return bytes;
}

}  // namespace topotet
