#include "generate/disc_test.h"

#include <algorithm>
#include <numeric>

namespace topotet::gen {
namespace {

std::uint64_t edge_key(VertId a, VertId b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t{a} << 32) | b;
}

}  // namespace

void UnionFind::reset(std::size_t n) {
  parent_.resize(n);
  std::iota(parent_.begin(), parent_.end(), 0u);
}

std::uint32_t UnionFind::find(std::uint32_t x) {
  while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
  return x;
}

std::size_t UnionFind::components() {
  std::size_t roots = 0;
  for (std::uint32_t x = 0; x < parent_.size(); ++x) roots += find(x) == x;
  return roots;
}

bool DiscTest::operator()(const std::vector<TriangleCorners>& tris) {
  if (tris.empty()) return false;
  // Edges: at most two triangles each; triangles sharing one are connected.
  edges_.clear();
  for (std::uint32_t t = 0; t < tris.size(); ++t)
    for (int e = 0; e < 3; ++e) edges_.emplace_back(edge_key(tris[t][e], tris[t][(e + 1) % 3]), t);
  std::sort(edges_.begin(), edges_.end());
  surface_.reset(tris.size());
  std::int64_t edge_count = 0;
  for (std::size_t a = 0, b = 0; a < edges_.size(); a = b) {
    while (b < edges_.size() && edges_[b].first == edges_[a].first) ++b;
    if (b - a > 2) return false;
    if (b - a == 2) surface_.unite(edges_[a].second, edges_[a + 1].second);
    ++edge_count;
  }
  if (surface_.components() != 1) return false;
  // Vertices: the triangles around each are joined through the edges at the vertex (two of them
  // sharing a second vertex); more than one fan is a pinch.
  corners_.clear();
  for (std::uint32_t t = 0; t < tris.size(); ++t)
    for (VertId v : tris[t]) corners_.emplace_back(v, t);
  std::sort(corners_.begin(), corners_.end());
  std::int64_t vertex_count = 0;
  for (std::size_t a = 0, b = 0; a < corners_.size(); a = b) {
    while (b < corners_.size() && corners_[b].first == corners_[a].first) ++b;
    ++vertex_count;
    fan_.reset(b - a);
    for (std::size_t i = a; i < b; ++i)
      for (std::size_t j = i + 1; j < b; ++j) {
        const TriangleCorners& x = tris[corners_[i].second];
        const TriangleCorners& y = tris[corners_[j].second];
        int common = 0;
        for (VertId v : x) common += std::find(y.begin(), y.end(), v) != y.end();
        if (common == 2) fan_.unite(static_cast<std::uint32_t>(i - a), static_cast<std::uint32_t>(j - a));
      }
    if (fan_.components() != 1) return false;
  }
  return vertex_count - edge_count + static_cast<std::int64_t>(tris.size()) == 1;
}

}  // namespace topotet::gen
