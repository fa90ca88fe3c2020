// Meshes for the out-of-core tests (unit_out_of_core*.cpp): generated families, a surface planted
// where the cut puts a piece border, and a polyline through every piece.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "topotet/generate.h"
#include "topotet/mesh_data.h"

namespace topotet::test {

inline MeshData generated(const std::string& family, std::uint64_t tets) {
  GenerateOptions g;
  g.family = family;
  g.target_tets = tets;
  return generate_mesh(g);
}

// A listed surface and a polyline in the grid plane x = (the vertex x nearest the middle): the
// Morton cut's first split is a plane of constant x, and on a Freudenthal grid pieces follow grid
// planes, so these lie in piece borders (their vertices frozen until the last merges).
inline void plant_in_mid_plane(MeshData& m) {
  std::vector<double> xs;
  for (const auto& p : m.positions) xs.push_back(p[0]);
  std::sort(xs.begin(), xs.end());
  const double x = xs[xs.size() / 2];
  const auto on = [&](VertId v) { return m.positions[v][0] == x; };
  std::int32_t ref = 0;
  for (const Triangle& t : m.triangles) ref = std::max(ref, t.ref);
  for (const Segment& s : m.segments) ref = std::max(ref, s.ref);
  std::vector<std::array<VertId, 3>> faces;
  for (const auto& t : m.tets)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<VertId, 3> f;
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != skip) f[j++] = t[k];
      if (on(f[0]) && on(f[1]) && on(f[2])) {
        std::sort(f.begin(), f.end());
        faces.push_back(f);
      }
    }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  // A disc of the plane (faces near its centre), so that its rim is a curve inside the border.
  double cy = 0, cz = 0;
  for (const auto& p : m.positions) cy += p[1], cz += p[2];
  cy /= m.positions.size();
  cz /= m.positions.size();
  double span = 0;
  for (const auto& p : m.positions) span = std::max(span, std::abs(p[1] - cy));
  for (const auto& f : faces) {
    double y = 0, z = 0;
    for (VertId v : f) y += m.positions[v][1] / 3, z += m.positions[v][2] / 3;
    if ((y - cy) * (y - cy) + (z - cz) * (z - cz) < 0.16 * span * span) m.triangles.push_back({f, ref + 1});
  }
  ASSERT_GT(m.triangles.size(), 0u);
}

// A polyline straight through the mesh in x: the shortest edge path from the vertex nearest the
// middle of the x = min face to the one nearest the middle of the x = max face, so that every cut
// plane of constant x crosses it.
inline void plant_line_across(MeshData& m) {
  std::array<double, 3> lo = m.positions[0], hi = m.positions[0];
  for (const auto& p : m.positions)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  const auto nearest = [&](double x) {
    const std::array<double, 3> q = {x, 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    VertId best = 0;
    double best_d = 1e300;
    for (VertId v = 0; v < m.positions.size(); ++v) {
      double d = 0;
      for (int k = 0; k < 3; ++k) d += (m.positions[v][k] - q[k]) * (m.positions[v][k] - q[k]);
      if (d < best_d) best_d = d, best = v;
    }
    return best;
  };
  std::vector<std::vector<VertId>> neighbours(m.positions.size());
  for (const auto& t : m.tets)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        if (a != b) neighbours[t[a]].push_back(t[b]);
  const VertId from = nearest(lo[0]), to = nearest(hi[0]);
  std::vector<double> dist(m.positions.size(), 1e300);
  std::vector<VertId> previous(m.positions.size(), kInvalid);
  std::vector<std::pair<double, VertId>> heap = {{0.0, from}};
  dist[from] = 0;
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), std::greater<>());
    const auto [d, v] = heap.back();
    heap.pop_back();
    if (d > dist[v]) continue;
    for (VertId w : neighbours[v]) {
      double len = 0;
      for (int k = 0; k < 3; ++k) len += (m.positions[v][k] - m.positions[w][k]) * (m.positions[v][k] - m.positions[w][k]);
      if (d + std::sqrt(len) < dist[w]) {
        dist[w] = d + std::sqrt(len);
        previous[w] = v;
        heap.push_back({dist[w], w});
        std::push_heap(heap.begin(), heap.end(), std::greater<>());
      }
    }
  }
  std::int32_t ref = 0;
  for (const Segment& s : m.segments) ref = std::max(ref, s.ref);
  std::size_t edges = 0;
  for (VertId v = to; previous[v] != kInvalid; v = previous[v], ++edges) m.segments.push_back({{previous[v], v}, ref + 1});
  ASSERT_GT(edges, 8u);
}

// The cube-sphere with both: a disc in a border and a polyline through every piece.
inline MeshData planted_cube_sphere(std::uint64_t tets) {
  MeshData m = generated("cube-sphere", tets);
  plant_in_mid_plane(m);
  plant_line_across(m);
  return m;
}

}  // namespace topotet::test
