// The cell sites of the polycrystal family (generate.h) and nearest-site queries on them.
//
// Sites live in lattice coordinates of a FreudenthalGrid box [0, nx] x [0, ny] x [0, nz]. They are
// kept apart by a minimum separation (dart throwing), so no Voronoi cell is much smaller than a
// ball of half that separation around its site: no cell degenerates to a sliver of a few tets.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "generate/freudenthal_grid.h"

namespace topotet::gen {

// A uniform grid of cubic buckets over the box, each holding the indices of its sites in
// increasing order, for radius and nearest-neighbour queries.
class SiteBuckets {
 public:
  SiteBuckets(const Cells& box, double bucket_size);

  void add(const glm::dvec3& site);
  const std::vector<glm::dvec3>& sites() const { return sites_; }

  bool any_within(const glm::dvec3& p, double radius) const;
  // Index of the site nearest p; the lowest index among equally near ones. Needs a site.
  std::uint32_t nearest(const glm::dvec3& p) const;
  // Replaces `out` with the indices of the sites within `radius` of p, in increasing order.
  void within(const glm::dvec3& p, double radius, std::vector<std::uint32_t>& out) const;

 private:
  std::array<int, 3> bucket_of(const glm::dvec3& p) const;
  std::size_t bucket_index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) + count_[0] * (static_cast<std::size_t>(j) + count_[1] * static_cast<std::size_t>(k));
  }
  // Calls f(site index) for every site in the buckets [lo, hi] (inclusive, clamped to the grid).
  template <class F>
  void for_each_in_buckets(std::array<int, 3> lo, std::array<int, 3> hi, F&& f) const;

  double bucket_size_;
  std::array<int, 3> count_;
  std::vector<std::vector<std::uint32_t>> buckets_;
  std::vector<glm::dvec3> sites_;
};

// `count` sites in the box, at least `min_separation` apart and at least half a cell inside it:
// dart throwing on the fixed splitmix64 stream `stream`, so the same arguments give the same sites
// everywhere. Throws std::logic_error when the separation leaves no room for them all (only when
// min_separation is close to the packing limit, about 0.9 (volume / count)^(1/3)).
std::vector<glm::dvec3> place_separated_sites(const Cells& box, std::uint32_t count, double min_separation,
                                              std::uint64_t stream);

}  // namespace topotet::gen
