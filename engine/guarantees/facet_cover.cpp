// The facet cover proof (see facet_cover.h).
#include "guarantees/facet_cover.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "guarantees/surface_tolerance.h"

namespace topotet {
namespace {

constexpr int kMaxFacets = 64;    // candidates (a bit each in a vertex's mask)
constexpr int kMaxVertices = 12;  // of a part: a triangle after a few cuts
// Parts examined before the piece goes back to the caller, which splits it and tries each quarter
// again from scratch (sphere3 at 10%, every candidate taken at once: a budget of 20, 32, 64, 128
// parts ran 8.49, 7.85, 7.16, 6.94 G instructions), and parts waiting at once (depth first: about
// the depth of the cuts).
constexpr int kPartBudget = 128;
constexpr int kMaxWaiting = 32;

struct Facet {
  std::uint32_t tri;
  glm::dvec3 a, b, c;
  glm::dvec3 n;   // unit normal; zero for a degenerate facet (then every point is measured)
  double offset;  // the facet's plane: dot(n, x) = offset
  glm::dvec3 g;   // centroid; every point of the facet lies within `radius` of it
  double radius;
  // The facet's edges in its plane: dot(edge_n[e], x) - edge_o[e] is the signed distance of x's
  // foot from edge e's line, positive towards the facet (unit normals in the plane).
  std::array<glm::dvec3, 3> edge_n;
  std::array<double, 3> edge_o;
  bool degenerate;  // zero normal: no plane, no edges; every point is measured
};

// The facet's bounding sphere (centroid, farthest corner).
void bounding_sphere(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, glm::dvec3& g, double& radius) {
  g = (a + b + c) / 3.0;
  radius = std::sqrt(std::max({glm::dot(a - g, a - g), glm::dot(b - g, b - g), glm::dot(c - g, c - g)}));
}

// Is x farther than d from every point of the sphere's ball? (A refusal that needs no closest point.)
bool beyond(const glm::dvec3& x, const glm::dvec3& g, double radius, double d) {
  const double reach = radius + d;
  return glm::dot(x - g, x - g) > reach * reach;
}

struct Vertex {
  glm::dvec3 x;
  std::uint64_t within;  // bit k: x is within h of facet k, for the first `tested` facets
  int tested;
};

struct Part {
  std::array<Vertex, kMaxVertices> v;
  int count = 0;
};

class Cover {
 public:
  // The candidates: the triangles connected to `nearest` through the label's edges that come
  // within r + h of the piece's centre c (r: c to the farthest corner), the only ones that can be
  // within h of a point of the piece. Taken a ring at a time, breadth-first in a fixed order, when
  // a point is within h of none so far (most pieces need a few facets, not every one within
  // reach): the candidates are one function of the piece.
  Cover(const SurfaceSoup& soup, const std::vector<std::uint32_t>& neighbour, double h, std::uint32_t nearest,
        const glm::dvec3& centre, double reach)
      : soup_(soup), neighbour_(neighbour), h_(h), h2_(h * h), centre_(centre), reach_(reach) {
    slot_tri_.fill(kInvalid);
    add(nearest);
  }

  // The next ring of candidates; false when there is none (or too many).
  bool grow() {
    const int begin = ring_begin_, end = count_;
    ring_begin_ = end;
    const auto& P = soup_.positions;
    for (int i = begin; i < end; ++i)
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t t = neighbour_[3 * std::size_t{facets_[i].tri} + e];
        if (t == kInvalid || index_of(t) >= 0) continue;
        const auto& tv = soup_.triangles[t];
        glm::dvec3 g;
        double radius;
        bounding_sphere(P[tv[0]], P[tv[1]], P[tv[2]], g, radius);
        if (beyond(centre_, g, radius, reach_) ||
            squared_distance_to_triangle(centre_, P[tv[0]], P[tv[1]], P[tv[2]]) > reach_ * reach_)
          continue;
        if (count_ == kMaxFacets) return false;  // a piece wider than the candidates: the caller splits it
        add(t);
      }
    return count_ > end;
  }

  // Brings x's mask up to the candidates found so far.
  void update(Vertex& x) const {
    for (int k = x.tested; k < count_; ++k) {
      const Facet& f = facets_[k];
      if (beyond(x.x, f.g, f.radius, h_)) continue;    // most candidates are far from x
      const double s = glm::dot(f.n, x.x) - f.offset;  // |s| is at most the distance: a cheap refusal
      if (s * s > h2_) continue;
      // The foot inside every edge: the distance is |s|. Outside one by o: at least sqrt(s^2 + o^2)
      // (the facet lies on the inner side of the edge's line). Else measure it.
      double outside = 0.0;
      for (int e = 0; e < 3; ++e) outside = std::max(outside, f.edge_o[e] - glm::dot(f.edge_n[e], x.x));
      if (outside == 0.0 && !f.degenerate) {
        x.within |= std::uint64_t{1} << k;
        continue;
      }
      if (s * s + outside * outside > h2_) continue;
      if (squared_distance_to_triangle(x.x, f.a, f.b, f.c) <= h2_) x.within |= std::uint64_t{1} << k;
    }
    x.tested = count_;
  }

  // Every vertex of the part up to date and within h of some candidate, growing the candidates
  // as needed; false when a vertex is within h of none that can be found.
  bool settle(Part& part) {
    for (;;) {
      bool orphan = false;
      for (int i = 0; i < part.count; ++i) {
        update(part.v[i]);
        orphan |= part.v[i].within == 0;
      }
      if (!orphan) return true;
      if (!grow()) return false;
    }
  }

  bool prove(const std::array<glm::dvec3, 3>& q) {
    Part first;
    for (const glm::dvec3& x : q) first.v[first.count++] = {x, 0, 0};
    std::array<Part, kMaxWaiting> stack;
    int top = 0, examined = 0;
    stack[top++] = first;
    while (top > 0) {
      if (++examined > kPartBudget) return false;
      Part part = stack[--top];
      if (!settle(part)) return false;  // a point within h of no candidate
      std::uint64_t common = ~std::uint64_t{0};
      for (int i = 0; i < part.count; ++i) common &= part.v[i].within;
      if (common != 0) continue;  // one facet holds every vertex, so the whole part
      glm::dvec3 normal, origin;
      cut_plane(part, normal, origin);
      Part pos, neg;
      for (int i = 0; i < part.count; ++i) {
        const Vertex& p = part.v[i];
        const Vertex& r = part.v[(i + 1) % part.count];
        const double sp = glm::dot(normal, p.x - origin), sr = glm::dot(normal, r.x - origin);
        if (sp >= 0.0 && !push(pos, p)) return false;
        if (sp <= 0.0 && !push(neg, p)) return false;
        if ((sp > 0.0 && sr < 0.0) || (sp < 0.0 && sr > 0.0)) {
          // The crossing point, computed once for both parts: they share it exactly.
          Vertex x{p.x + (r.x - p.x) * (sp / (sp - sr)), 0, 0};
          update(x);
          if (!push(pos, x) || !push(neg, x)) return false;
        }
      }
      // A part of fewer than three vertices has no area: it lies on the other part's edge.
      for (const Part* p : {&pos, &neg}) {
        if (p->count < 3) continue;
        if (top == kMaxWaiting) return false;
        stack[top++] = *p;
      }
    }
    return true;
  }

 private:
  // Where to cut a part no facet holds: facet k, the one within h of most of its vertices, keeps
  // them on the positive side. The crease between k and an adjacent facet that a vertex y outside
  // k needs, if it separates y from one of k's vertices (it cuts where the nearest facet changes);
  // else the perpendicular bisector of y and k's vertex farthest from it (it always separates
  // them, and halves the part rather than shaving a sliver off it).
  void cut_plane(const Part& part, glm::dvec3& normal, glm::dvec3& origin) const {
    std::array<std::uint8_t, kMaxFacets> votes{};
    for (int i = 0; i < part.count; ++i)
      for (std::uint64_t m = part.v[i].within; m != 0; m &= m - 1) ++votes[static_cast<std::size_t>(__builtin_ctzll(m))];
    int k = 0;
    for (int f = 1; f < count_; ++f)
      if (votes[f] > votes[k]) k = f;
    const auto inside = [&](const Vertex& x) { return (x.within >> k & 1u) != 0; };
    const auto& P = soup_.positions;
    const auto& fk = soup_.triangles[facets_[k].tri];
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t t = neighbour_[3 * std::size_t{facets_[k].tri} + e];
      const int g = t == kInvalid ? -1 : index_of(t);
      if (g < 0) continue;
      // Only a crease that some vertex outside k needs (it is within h of g).
      bool needed = false;
      for (int i = 0; i < part.count && !needed; ++i) needed = !inside(part.v[i]) && (part.v[i].within >> g & 1u);
      if (!needed) continue;
      const VertId ea = fk[e], eb = fk[(e + 1) % 3], ok = fk[(e + 2) % 3];
      VertId og = kInvalid;
      for (VertId x : soup_.triangles[t])
        if (x != ea && x != eb) og = x;
      if (og == kInvalid) continue;
      const glm::dvec3 a = P[ea];
      // Towards facet k (the crease test's plane); zero for a degenerate edge, which separates none.
      const glm::dvec3 nb = crease_normal(a, P[eb], P[ok], P[og]);
      bool in_pos = false, out_neg = false;
      for (int i = 0; i < part.count; ++i) {
        const double s = glm::dot(nb, part.v[i].x - a);
        if (inside(part.v[i])) in_pos |= s > 0.0;
        else out_neg |= s < 0.0;
      }
      if (in_pos && out_neg) {
        normal = nb;
        origin = a;
        return;
      }
    }
    int y = 0;
    while (inside(part.v[y])) ++y;
    int x = -1;
    double far2 = -1.0;
    for (int i = 0; i < part.count; ++i) {
      if (!inside(part.v[i])) continue;
      const double d2 = glm::dot(part.v[i].x - part.v[y].x, part.v[i].x - part.v[y].x);
      if (d2 > far2) far2 = d2, x = i;
    }
    normal = part.v[x].x - part.v[y].x;
    origin = 0.5 * (part.v[x].x + part.v[y].x);
  }

  void add(std::uint32_t t) {
    const auto& tri = soup_.triangles[t];
    const auto& P = soup_.positions;
    std::size_t i = slot_of(t);
    while (slot_tri_[i] != kInvalid) i = (i + 1) & (kSlots - 1);
    slot_tri_[i] = t;
    slot_index_[i] = static_cast<std::int8_t>(count_);
    Facet& f = facets_[count_++];
    f.tri = t;
    f.a = P[tri[0]];
    f.b = P[tri[1]];
    f.c = P[tri[2]];
    const glm::dvec3 n = glm::cross(f.b - f.a, f.c - f.a);
    const double l = glm::length(n);
    f.n = l > 0.0 ? n / l : glm::dvec3(0.0);
    f.offset = glm::dot(f.n, f.a);
    bounding_sphere(f.a, f.b, f.c, f.g, f.radius);
    const glm::dvec3 corner[3] = {f.a, f.b, f.c};
    for (int e = 0; e < 3; ++e) {
      const glm::dvec3& p = corner[e];
      const glm::dvec3 m = glm::cross(f.n, corner[(e + 1) % 3] - p);  // in the plane, towards the facet
      const double lm = glm::length(m);
      // A degenerate facet (zero normal) has no edge normals: every point is measured.
      f.edge_n[e] = lm > 0.0 ? m / lm : glm::dvec3(0.0);
      f.edge_o[e] = lm > 0.0 ? glm::dot(f.edge_n[e], p) : 0.0;
    }
    f.degenerate = !(l > 0.0);
  }
  // Candidate index of soup triangle t, or -1: an open-addressing table (twice the candidates).
  static std::size_t slot_of(std::uint32_t t) { return (t * 2654435761u) >> 25; }  // 7 bits
  int index_of(std::uint32_t t) const {
    for (std::size_t i = slot_of(t);; i = (i + 1) & (kSlots - 1)) {
      if (slot_tri_[i] == t) return slot_index_[i];
      if (slot_tri_[i] == kInvalid) return -1;
    }
  }
  static bool push(Part& part, const Vertex& x) {
    if (part.count == kMaxVertices) return false;
    part.v[part.count++] = x;
    return true;
  }

  const SurfaceSoup& soup_;
  const std::vector<std::uint32_t>& neighbour_;
  double h_, h2_;
  std::array<Facet, kMaxFacets> facets_;
  static constexpr std::size_t kSlots = 2 * kMaxFacets;
  static_assert(kSlots == 128, "slot_of() hashes to 7 bits");
  std::array<std::uint32_t, kSlots> slot_tri_;
  std::array<std::int8_t, kSlots> slot_index_;
  glm::dvec3 centre_;
  double reach_;
  int count_ = 0;
  int ring_begin_ = 0;  // the last ring's first candidate
};

}  // namespace

bool within_by_facets(const SurfaceSoup& soup, const std::vector<std::uint32_t>& neighbour,
                      const std::array<glm::dvec3, 3>& q, double h, std::uint32_t nearest) {
  if (nearest == kInvalid || nearest >= soup.triangles.size()) return false;
  const glm::dvec3 centre = (q[0] + q[1] + q[2]) / 3.0;
  double r2 = 0.0;
  for (const glm::dvec3& x : q) r2 = std::max(r2, glm::dot(x - centre, x - centre));
  Cover cover(soup, neighbour, h, nearest, centre, std::sqrt(r2) + h);
  return cover.prove(q);
}

}  // namespace topotet
