// Whether a set of triangles is a 2-disc, for the polycrystal family's guarantees.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet::gen {

using TriangleCorners = std::array<VertId, 3>;

class UnionFind {
 public:
  void reset(std::size_t n);
  std::uint32_t find(std::uint32_t x);
  void unite(std::uint32_t a, std::uint32_t b) { parent_[find(a)] = find(b); }
  std::size_t components();

 private:
  std::vector<std::uint32_t> parent_;
};

// True when the triangles (distinct, as vertex triples) form a disc: connected, every edge in at
// most two of them, the triangles around every vertex one fan (no pinch), Euler characteristic 1
// (a connected compact surface with chi = 1 is a disc). Keeps its buffers between calls.
class DiscTest {
 public:
  bool operator()(const std::vector<TriangleCorners>& tris);

 private:
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges_;  // (edge key, triangle)
  std::vector<std::pair<VertId, std::uint32_t>> corners_;       // (vertex, triangle)
  UnionFind surface_, fan_;
};

}  // namespace topotet::gen
