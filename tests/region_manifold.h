// An independent check that every material region of a mesh is a 3-manifold with boundary, for the
// tests of meshes whose regions must be balls (the polycrystal family, and what simplification
// makes of it).
//
// Betti numbers alone do not see a pinch: two tets of a region meeting only along an edge leave
// b = (1, 0, 0, 0). So the tests pair topotet::compute_topology with this check. A compact
// connected 3-manifold M in the 3-sphere with b1 = b2 = 0 is a ball: b2 = 0 makes its complement
// connected (Alexander duality), so its boundary is one closed surface, of Euler characteristic
// 2 chi(M) = 2, a sphere; and a PL 2-sphere in the 3-sphere bounds a ball (Alexander).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <tuple>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet::testing {

// True when triangles (the link of a vertex) form a disc or a sphere: every edge in one or two of
// them, connected, the triangles around each vertex one fan, and Euler characteristic 1 with a
// boundary or 2 without. Keeps its buffers between calls.
class DiscOrSphereTest {
 public:
  bool operator()(const std::vector<std::array<VertId, 3>>& tris) {
    reset(parent_, tris.size());
    edges_.clear();
    for (std::uint32_t t = 0; t < tris.size(); ++t)
      for (int e = 0; e < 3; ++e) {
        const VertId a = tris[t][e], b = tris[t][(e + 1) % 3];
        edges_.emplace_back(std::min(a, b), std::max(a, b), t);
      }
    std::sort(edges_.begin(), edges_.end());
    std::int64_t edge_count = 0, boundary_edges = 0;
    for (std::size_t a = 0, b = 0; a < edges_.size(); a = b) {
      while (b < edges_.size() && std::get<0>(edges_[b]) == std::get<0>(edges_[a]) &&
             std::get<1>(edges_[b]) == std::get<1>(edges_[a])) {
        ++b;
      }
      if (b - a > 2) return false;
      if (b - a == 1) ++boundary_edges;
      if (b - a == 2) parent_[root(parent_, std::get<2>(edges_[a]))] = root(parent_, std::get<2>(edges_[a + 1]));
      ++edge_count;
    }
    for (std::uint32_t t = 0; t < tris.size(); ++t)
      if (root(parent_, t) != root(parent_, 0)) return false;
    // Fans: around vertex v, the triangles sharing an edge at v must connect them all.
    corners_.clear();
    for (std::uint32_t t = 0; t < tris.size(); ++t)
      for (VertId v : tris[t]) corners_.emplace_back(v, t);
    std::sort(corners_.begin(), corners_.end());
    std::int64_t vertex_count = 0;
    for (std::size_t a = 0, b = 0; a < corners_.size(); a = b) {
      while (b < corners_.size() && corners_[b].first == corners_[a].first) ++b;
      ++vertex_count;
      reset(fan_, b - a);
      for (std::size_t i = a; i < b; ++i)
        for (std::size_t j = i + 1; j < b; ++j) {
          int shared = 0;
          for (VertId v : tris[corners_[i].second])
            shared += static_cast<int>(std::count(tris[corners_[j].second].begin(), tris[corners_[j].second].end(), v));
          if (shared == 2) fan_[root(fan_, static_cast<std::uint32_t>(i - a))] = root(fan_, static_cast<std::uint32_t>(j - a));
        }
      for (std::uint32_t i = 0; i < fan_.size(); ++i)
        if (root(fan_, i) != root(fan_, 0)) return false;
    }
    const std::int64_t chi = vertex_count - edge_count + static_cast<std::int64_t>(tris.size());
    return boundary_edges > 0 ? chi == 1 : chi == 2;
  }

 private:
  static void reset(std::vector<std::uint32_t>& parent, std::size_t n) {
    parent.resize(n);
    std::iota(parent.begin(), parent.end(), 0u);
  }
  static std::uint32_t root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }

  std::vector<std::uint32_t> parent_, fan_;
  std::vector<std::tuple<VertId, VertId, std::uint32_t>> edges_;  // (low, high, triangle)
  std::vector<std::pair<VertId, std::uint32_t>> corners_;         // (vertex, triangle)
};

// The number of (material, vertex) pairs where the region of that material is not a 3-manifold
// with boundary: the triangles opposite the vertex in the region's tets (its link in the region)
// are neither a disc nor a sphere. Tets whose vertices repeat are skipped.
inline std::size_t count_nonmanifold_region_vertices(const MeshData& mesh) {
  struct Corner {
    std::int32_t material;
    VertId vertex;
    std::array<VertId, 3> opposite;
  };
  std::vector<Corner> corners;
  corners.reserve(4 * mesh.tet_count());
  for (std::size_t t = 0; t < mesh.tet_count(); ++t) {
    const auto& v = mesh.tets[t];
    for (int i = 0; i < 4; ++i) {
      std::array<VertId, 3> opposite{};
      int n = 0;
      for (int j = 0; j < 4; ++j)
        if (j != i) opposite[n++] = v[j];
      corners.push_back({mesh.tet_material[t], v[i], opposite});
    }
  }
  std::sort(corners.begin(), corners.end(), [](const Corner& a, const Corner& b) {
    return std::tie(a.material, a.vertex) < std::tie(b.material, b.vertex);
  });
  std::size_t bad = 0;
  DiscOrSphereTest is_disc_or_sphere;
  std::vector<std::array<VertId, 3>> link;
  for (std::size_t a = 0, b = 0; a < corners.size(); a = b) {
    link.clear();
    for (b = a; b < corners.size() && corners[b].material == corners[a].material && corners[b].vertex == corners[a].vertex; ++b) {
      link.push_back(corners[b].opposite);
    }
    bad += !is_disc_or_sphere(link);
  }
  return bad;
}

}  // namespace topotet::testing
