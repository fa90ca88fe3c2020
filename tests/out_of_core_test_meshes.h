// Meshes for the out-of-core tests (unit_out_of_core*.cpp): generated families, and a surface
// planted where the cut puts a piece border.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
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

}  // namespace topotet::test
