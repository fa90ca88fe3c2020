// Manifold certificates and the Betti numbers they give; see manifold_betti.h for the reasoning.
//
// Both certificates reduce "the top simplices around a simplex are connected" to one union-find
// over (simplex, top simplex) incidences: around vertex v (or edge e), the incidences of v in the
// tets containing it are joined across every interior triangle containing v. Each vertex (edge) is
// in at least one top simplex, so the union-find ends with exactly one class per vertex (edge)
// iff every star is connected.
#include "manifold_betti.h"

#include <algorithm>

namespace topotet::metrics::detail {
namespace {

constexpr std::uint32_t kNone = ~std::uint32_t{0};

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];  // path halving
    x = parent[x];
  }
  return x;
}

// Union-find over [0, n): count() is the number of classes.
class UnionFind {
 public:
  UnionFind(std::vector<std::uint32_t>& parent, std::size_t n) : parent_(parent), classes_(n) {
    parent_.resize(n);
    for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<std::uint32_t>(i);
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find_root(parent_, a);
    b = find_root(parent_, b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    parent_[a] = b;
    --classes_;
  }
  std::uint32_t root(std::uint32_t x) { return find_root(parent_, x); }
  std::size_t count() const { return classes_; }

 private:
  std::vector<std::uint32_t>& parent_;
  std::size_t classes_;
};

// The three vertices of a triangle given by its edges.
std::array<std::uint32_t, 3> triangle_vertices(const LocalComplex& c, std::uint32_t f) {
  const auto& e0 = c.edges[c.faces[f][0]];
  const auto& e1 = c.edges[c.faces[f][1]];
  const std::uint32_t third = e1[0] != e0[0] && e1[0] != e0[1] ? e1[0] : e1[1];
  return {e0[0], e0[1], third};
}

int index_in(const std::array<std::uint32_t, 3>& a, std::uint32_t x) {
  return a[0] == x ? 0 : a[1] == x ? 1 : 2;
}

// Records the (at most 2) cofaces of each of `n` cells; false when one has more.
template <class ForEachIncidence>
bool collect_cofaces(std::size_t n, ManifoldScratch& s, ForEachIncidence&& for_each_incidence) {
  s.coface_count.assign(n, 0);
  s.face_cofaces.assign(2 * n, kNone);
  bool ok = true;
  for_each_incidence([&](std::uint32_t cell, std::uint32_t coface) {
    if (s.coface_count[cell] == 2) {
      ok = false;
      return;
    }
    s.face_cofaces[2 * cell + s.coface_count[cell]++] = coface;
  });
  return ok;
}

// b0 and the number of components that contain none of the vertices flagged in is_on_boundary.
std::pair<std::int64_t, std::int64_t> components_and_closed(const LocalComplex& c, ManifoldScratch& s) {
  UnionFind uf(s.parent, c.vertex_count);
  for (const auto& e : c.edges) uf.unite(e[0], e[1]);
  std::vector<std::uint8_t> bounded(c.vertex_count, 0);
  for (std::uint32_t v = 0; v < c.vertex_count; ++v)
    if (s.is_on_boundary[v]) bounded[uf.root(v)] = 1;
  std::int64_t closed = 0;
  for (std::uint32_t v = 0; v < c.vertex_count; ++v) closed += uf.root(v) == v && !bounded[v];
  return {static_cast<std::int64_t>(uf.count()), closed};
}

}  // namespace

bool surface_betti(const LocalComplex& c, ManifoldScratch& s, std::array<std::int64_t, 4>& betti) {
  if (c.faces.empty() || !c.tets.empty()) return false;
  const std::size_t edge_count = c.edges.size(), face_count = c.faces.size();
  const bool has_two_faces_per_edge_at_most = collect_cofaces(edge_count, s, [&](auto&& add) {
    for (std::uint32_t f = 0; f < face_count; ++f)
      for (std::uint32_t e : c.faces[f]) add(e, f);
  });
  if (!has_two_faces_per_edge_at_most) return false;

  // Vertex stars: incidence 3f + k (vertex k of triangle f), joined across interior edges.
  s.face_vertices.resize(face_count);
  for (std::uint32_t f = 0; f < face_count; ++f) s.face_vertices[f] = triangle_vertices(c, f);
  // Cheap first: a fan has one more edge than triangles around its vertex when it is an arc (the
  // vertex has boundary edges), as many when it is a cycle; more fans break that count, except
  // for several cycles, which the union-find below catches.
  s.is_on_boundary.assign(c.vertex_count, 0);
  s.link_euler.assign(c.vertex_count, 0);
  for (std::uint32_t e = 0; e < edge_count; ++e) {
    for (std::uint32_t v : c.edges[e]) ++s.link_euler[v];
    if (s.coface_count[e] == 1) s.is_on_boundary[c.edges[e][0]] = s.is_on_boundary[c.edges[e][1]] = 1;
  }
  for (const auto& fv : s.face_vertices)
    for (std::uint32_t v : fv) --s.link_euler[v];
  for (std::uint32_t v = 0; v < c.vertex_count; ++v)
    if (s.link_euler[v] != (s.is_on_boundary[v] ? 1 : 0)) return false;
  {
    UnionFind stars(s.parent, 3 * face_count);
    for (std::uint32_t e = 0; e < edge_count; ++e) {
      if (s.coface_count[e] != 2) continue;
      const std::uint32_t f1 = s.face_cofaces[2 * e], f2 = s.face_cofaces[2 * e + 1];
      for (std::uint32_t v : c.edges[e])
        stars.unite(3 * f1 + index_in(s.face_vertices[f1], v), 3 * f2 + index_in(s.face_vertices[f2], v));
    }
    if (stars.count() != c.vertex_count) return false;
  }

  const auto [b0, closed] = components_and_closed(c, s);
  const std::int64_t chi = std::int64_t{c.vertex_count} - static_cast<std::int64_t>(edge_count) +
                           static_cast<std::int64_t>(face_count);
  betti = {b0, b0 + closed - chi, closed, 0};
  return betti[1] >= 0;
}

bool solid_betti(const LocalComplex& c, ManifoldScratch& s, std::array<std::int64_t, 4>& betti) {
  if (c.tets.empty()) return false;
  const std::size_t face_count = c.faces.size(), tet_count = c.tets.size();
  const bool has_two_tets_per_face_at_most = collect_cofaces(face_count, s, [&](auto&& add) {
    for (std::uint32_t t = 0; t < tet_count; ++t)
      for (std::uint32_t f : c.tets[t]) add(f, t);
  });
  if (!has_two_tets_per_face_at_most) return false;

  s.face_vertices.resize(face_count);
  for (std::uint32_t f = 0; f < face_count; ++f) s.face_vertices[f] = triangle_vertices(c, f);
  // Vertex links: Euler characteristic (edges - triangles + tets around the vertex) 2 inside
  // (a sphere), 1 on the boundary (a disk); the stars below make the links connected surfaces.
  // Checked first: it is cheap and already refuses most non-manifolds (pinched vertices). A tet
  // around v has 3 of its triangles around v, so 3 x the tets around v is the sum, over the
  // triangles around v, of their tet counts: counted in thirds, no tet's vertices are needed.
  s.link_euler.assign(c.vertex_count, 0);  // 3 x the link's Euler characteristic
  s.is_on_boundary.assign(c.vertex_count, 0);
  for (const auto& e : c.edges) s.link_euler[e[0]] += 3, s.link_euler[e[1]] += 3;
  for (std::uint32_t f = 0; f < face_count; ++f)
    for (std::uint32_t v : s.face_vertices[f]) {
      s.link_euler[v] += s.coface_count[f] - 3;
      if (s.coface_count[f] == 1) s.is_on_boundary[v] = 1;
    }
  for (std::uint32_t v = 0; v < c.vertex_count; ++v)
    if (s.link_euler[v] != (s.is_on_boundary[v] ? 3 : 6)) return false;

  // Per tet, vertex k is the one opposite its local face k, and edge kPair[i][j] is the one its
  // local faces i and j share; so local face i has the vertices k != i and the edges kPair[i][j].
  static constexpr int kPair[4][4] = {{-1, 0, 1, 2}, {0, -1, 3, 4}, {1, 3, -1, 5}, {2, 4, 5, -1}};
  s.tet_vertices.resize(tet_count);
  s.tet_edges.resize(tet_count);
  for (std::uint32_t t = 0; t < tet_count; ++t) {
    const auto& faces = c.tets[t];
    const auto& f0 = s.face_vertices[faces[0]];
    auto& v = s.tet_vertices[t];
    for (std::uint32_t x : s.face_vertices[faces[1]])
      if (x != f0[0] && x != f0[1] && x != f0[2]) v[0] = x;
    for (int k = 1; k < 4; ++k) {
      const auto& fk = s.face_vertices[faces[k]];
      for (std::uint32_t x : f0)
        if (x != fk[0] && x != fk[1] && x != fk[2]) v[k] = x;
    }
  }
  const auto local_face = [&](std::uint32_t t, std::uint32_t f) {
    const auto& faces = c.tets[t];
    return faces[0] == f ? 0 : faces[1] == f ? 1 : faces[2] == f ? 2 : 3;
  };
  const auto slot_of = [](const auto& items, auto x) {
    return static_cast<std::uint32_t>(std::find(items.begin(), items.end(), x) - items.begin());
  };

  // Edge e of local face i misses one vertex of that face, v[j]: e is shared by faces i and j.
  // Faces 0, 1 and 2 hold all six edges.
  for (std::uint32_t t = 0; t < tet_count; ++t) {
    const auto& faces = c.tets[t];
    const auto& v = s.tet_vertices[t];
    for (int i = 0; i < 3; ++i)
      for (std::uint32_t e : c.faces[faces[i]]) {
        const auto& ends = c.edges[e];
        int j = 0;
        for (int k = 0; k < 4; ++k)
          if (k != i && v[k] != ends[0] && v[k] != ends[1]) j = k;
        s.tet_edges[t][kPair[i][j]] = e;
      }
  }

  // Vertex stars (incidence 4t + k) and edge stars (incidence 6t + pair), joined across every
  // interior triangle; one union-find over both, vertex incidences first.
  {
    UnionFind stars(s.parent, 10 * tet_count);
    const std::uint32_t edge_base = static_cast<std::uint32_t>(4 * tet_count);
    for (std::uint32_t f = 0; f < face_count; ++f) {
      if (s.coface_count[f] != 2) continue;
      const std::uint32_t t1 = s.face_cofaces[2 * f], t2 = s.face_cofaces[2 * f + 1];
      const int i1 = local_face(t1, f);
      for (int j = 0; j < 4; ++j) {
        if (j == i1) continue;
        const std::uint32_t v = s.tet_vertices[t1][j];
        stars.unite(4 * t1 + j, 4 * t2 + slot_of(s.tet_vertices[t2], v));
        const std::uint32_t e = s.tet_edges[t1][kPair[i1][j]];
        stars.unite(edge_base + 6 * t1 + kPair[i1][j], edge_base + 6 * t2 + slot_of(s.tet_edges[t2], e));
      }
    }
    // Classes never mix vertex and edge incidences, so they add up.
    if (stars.count() != c.vertex_count + c.edges.size()) return false;
  }

  const auto [b0, closed] = components_and_closed(c, s);
  if (closed != 0) return false;  // a closed 3-manifold: no embedding in R^3, use the algebra
  // Components of the boundary surface (a closed 2-manifold: vertex-connected = edge-connected).
  UnionFind boundary(s.parent, c.vertex_count);
  for (std::uint32_t f = 0; f < face_count; ++f)
    if (s.coface_count[f] == 1) {
      const auto& v = s.face_vertices[f];
      boundary.unite(v[0], v[1]);
      boundary.unite(v[0], v[2]);
    }
  std::int64_t boundary_components = 0;
  for (std::uint32_t v = 0; v < c.vertex_count; ++v) boundary_components += s.is_on_boundary[v] && boundary.root(v) == v;
  const std::int64_t chi = std::int64_t{c.vertex_count} - static_cast<std::int64_t>(c.edges.size()) +
                           static_cast<std::int64_t>(face_count) - static_cast<std::int64_t>(tet_count);
  const std::int64_t b2 = boundary_components - b0;
  betti = {b0, b0 + b2 - chi, b2, 0};
  return betti[1] >= 0 && b2 >= 0;
}

}  // namespace topotet::metrics::detail
