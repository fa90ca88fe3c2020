// Templates of split_tet.h (the crossing lookup is inlined into the embedding's loop).
#pragma once

#include <algorithm>

namespace topotet::iso::detail {

// A convex polygon of at most 5 vertices (a clipped triangle has 4, a cap 4), outward.
struct Polygon {
  int n = 0;
  std::array<VertId, 5> v{};
  std::array<bool, 5> on_cut{};  // the vertex lies on the level (input vertex on it or crossing)
};

// The part of triangle (a, b, c) on side `keep` (-1 or +1), the level's vertices included.
template <class Crossing>
Polygon clip(const std::array<VertId, 3>& tri, const std::array<Side, 3>& side, Side keep, Crossing& crossing) {
  Polygon out;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if (side[i] * keep >= 0) {
      out.v[out.n] = tri[i];
      out.on_cut[out.n++] = side[i] == 0;
    }
    if (side[i] * side[j] < 0) {
      out.v[out.n] = crossing(tri[i], tri[j]);
      out.on_cut[out.n++] = true;
    }
  }
  return out;
}

inline int min_index(const Polygon& p) {
  int m = 0;
  for (int i = 1; i < p.n; ++i)
    if (p.v[i] < p.v[m]) m = i;
  return m;
}

// Fan from the smallest id: triangles (w, p[i], p[i+1]) in the polygon's orientation.
template <class Emit>
void fan(const Polygon& p, Emit&& emit) {
  const int m = min_index(p);
  for (int i = 1; i + 1 < p.n; ++i) emit(p.v[m], p.v[(m + i) % p.n], p.v[(m + i + 1) % p.n]);
}

inline bool contains(const Polygon& p, VertId x) {
  for (int i = 0; i < p.n; ++i)
    if (p.v[i] == x) return true;
  return false;
}

// Pulling triangulation of a convex piece given by its outward faces.
inline void pull(const Polygon* faces, int face_count, TetPieces& out) {
  VertId v0 = faces[0].v[0];
  for (int f = 0; f < face_count; ++f)
    for (int i = 0; i < faces[f].n; ++i) v0 = std::min(v0, faces[f].v[i]);
  for (int f = 0; f < face_count; ++f) {
    if (contains(faces[f], v0)) continue;
    // Outward face (a, b, c) seen from v0 inside: tet (v0, a, c, b) is positively oriented
    // (face 0 of a tet, opposite vertex 0, is (1, 3, 2) outward: mesh_model.h kTetFaces).
    fan(faces[f], [&](VertId a, VertId b, VertId c) { out.tets[out.tet_count++] = {v0, a, c, b}; });
  }
}

// Local faces of a positively oriented tet, outward (mesh_model.h kTetFaces).
inline constexpr int kFaces[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};

}  // namespace topotet::iso::detail

namespace topotet::iso {

template <class Crossing>
TetPieces split_tet(const std::array<VertId, 4>& tet, const std::array<Side, 4>& side, Crossing&& crossing) {
  using detail::Polygon;
  TetPieces out;
  // The cap (the level's polygon) from the piece below: each clipped face that meets the level
  // along an edge p -> q (consecutive, both on the cut) gives the cap the edge q -> p (adjacent
  // outward faces run along a shared edge in opposite directions).
  Polygon below[5], above[5];
  int nb = 0, na = 0;
  VertId cap_from[4], cap_to[4];
  int cap_edges = 0;
  for (const auto& f : detail::kFaces) {
    const std::array<VertId, 3> tri = {tet[f[0]], tet[f[1]], tet[f[2]]};
    const std::array<Side, 3> s = {side[f[0]], side[f[1]], side[f[2]]};
    Polygon b = detail::clip(tri, s, Side{-1}, crossing);
    if (b.n >= 3) {
      for (int i = 0; i < b.n; ++i) {
        const int j = (i + 1) % b.n;
        if (b.on_cut[i] && b.on_cut[j] && cap_edges < 4) cap_from[cap_edges] = b.v[j], cap_to[cap_edges++] = b.v[i];
      }
      below[nb++] = b;
    }
    Polygon a = detail::clip(tri, s, Side{1}, crossing);
    if (a.n >= 3) above[na++] = a;
  }
  // Chain the cap's edges into its polygon (3 or 4 vertices).
  Polygon cap;
  cap.v[cap.n++] = cap_from[0];
  for (VertId at = cap_to[0]; at != cap_from[0] && cap.n < cap_edges;) {
    cap.v[cap.n++] = at;
    int e = 0;
    while (e < cap_edges && cap_from[e] != at) ++e;
    if (e == cap_edges) break;  // cannot happen for a convex section; left to the orientation check
    at = cap_to[e];
  }
  below[nb++] = cap;  // a face of the piece below, oriented like its others
  Polygon reversed = cap;
  for (int i = 0; i < cap.n; ++i) reversed.v[i] = cap.v[cap.n - 1 - i];
  above[na++] = reversed;
  detail::pull(below, nb, out);
  detail::pull(above, na, out);
  detail::fan(cap, [&](VertId a, VertId b, VertId c) { out.cap[out.cap_count++] = {a, b, c}; });
  return out;
}

template <class Crossing>
TrianglePieces split_triangle(const std::array<VertId, 3>& tri, const std::array<Side, 3>& side, Crossing&& crossing) {
  TrianglePieces out;
  for (const Side keep : {Side{-1}, Side{1}}) {
    const detail::Polygon p = detail::clip(tri, side, keep, crossing);
    if (p.n >= 3) detail::fan(p, [&](VertId a, VertId b, VertId c) { out.tris[out.count++] = {a, b, c}; });
  }
  return out;
}

}  // namespace topotet::iso
