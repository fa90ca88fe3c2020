#include "generate/voronoi_sites.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace topotet::gen {
namespace {

double squared_distance(const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 d = a - b;
  return d.x * d.x + d.y * d.y + d.z * d.z;
}

}  // namespace

SiteBuckets::SiteBuckets(const Cells& box, double bucket_size) : bucket_size_(bucket_size) {
  for (int a = 0; a < 3; ++a) count_[a] = std::max(1, static_cast<int>(std::ceil(box[a] / bucket_size)));
  buckets_.resize(static_cast<std::size_t>(count_[0]) * count_[1] * count_[2]);
}

std::array<int, 3> SiteBuckets::bucket_of(const glm::dvec3& p) const {
  std::array<int, 3> b{};
  for (int a = 0; a < 3; ++a) b[a] = std::clamp(static_cast<int>(std::floor(p[a] / bucket_size_)), 0, count_[a] - 1);
  return b;
}

template <class F>
void SiteBuckets::for_each_in_buckets(std::array<int, 3> lo, std::array<int, 3> hi, F&& f) const {
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(lo[a], 0);
    hi[a] = std::min(hi[a], count_[a] - 1);
  }
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i)
        for (std::uint32_t s : buckets_[bucket_index(i, j, k)]) f(s);
}

void SiteBuckets::add(const glm::dvec3& site) {
  const auto b = bucket_of(site);
  buckets_[bucket_index(b[0], b[1], b[2])].push_back(static_cast<std::uint32_t>(sites_.size()));
  sites_.push_back(site);
}

bool SiteBuckets::any_within(const glm::dvec3& p, double radius) const {
  const auto lo = bucket_of(p - glm::dvec3(radius)), hi = bucket_of(p + glm::dvec3(radius));
  bool found = false;
  for_each_in_buckets(lo, hi, [&](std::uint32_t s) { found |= squared_distance(p, sites_[s]) < radius * radius; });
  return found;
}

std::uint32_t SiteBuckets::nearest(const glm::dvec3& p) const {
  if (sites_.empty()) throw std::logic_error("SiteBuckets::nearest: no sites");
  const auto center = bucket_of(p);
  const int max_ring = std::max({count_[0], count_[1], count_[2]});
  double best = std::numeric_limits<double>::infinity();
  std::uint32_t best_site = 0;
  const auto consider = [&](std::uint32_t s) {
    const double d = squared_distance(p, sites_[s]);
    if (d < best || (d == best && s < best_site)) {
      best = d;
      best_site = s;
    }
  };
  for (int ring = 0; ring <= max_ring; ++ring) {
    // The buckets at Chebyshev distance `ring` from the centre bucket: the faces of the ring's cube.
    for (int dk = -ring; dk <= ring; ++dk)
      for (int dj = -ring; dj <= ring; ++dj) {
        const bool side = std::abs(dk) == ring || std::abs(dj) == ring;
        const int step = side ? 1 : 2 * ring;
        for (int di = -ring; di <= ring; di += step) {
          const std::array<int, 3> b = {center[0] + di, center[1] + dj, center[2] + dk};
          if (b[0] < 0 || b[1] < 0 || b[2] < 0 || b[0] >= count_[0] || b[1] >= count_[1] || b[2] >= count_[2]) continue;
          for (std::uint32_t s : buckets_[bucket_index(b[0], b[1], b[2])]) consider(s);
        }
      }
    // Any bucket of the next ring is `ring` whole buckets away from p's bucket.
    const double reach = ring * bucket_size_;
    if (best <= reach * reach) break;
  }
  return best_site;
}

void SiteBuckets::within(const glm::dvec3& p, double radius, std::vector<std::uint32_t>& out) const {
  out.clear();
  const auto lo = bucket_of(p - glm::dvec3(radius)), hi = bucket_of(p + glm::dvec3(radius));
  for_each_in_buckets(lo, hi, [&](std::uint32_t s) {
    if (squared_distance(p, sites_[s]) <= radius * radius) out.push_back(s);
  });
  std::sort(out.begin(), out.end());
}

std::vector<glm::dvec3> place_separated_sites(const Cells& box, std::uint32_t count, double min_separation,
                                              std::uint64_t stream) {
  SiteBuckets placed(box, std::max(min_separation, 1.0));
  const std::uint64_t key = splitmix64(stream);
  // Random sequential adsorption saturates near a packing fraction of 0.38; far below it, as the
  // family uses it, a dart lands in a free spot with high probability, so 1000 misses per site
  // only ever run out when the request is impossible.
  const std::uint64_t max_darts = 1000ull * count + 1000;
  for (std::uint64_t dart = 0; placed.sites().size() < count; ++dart) {
    if (dart == max_darts) throw std::logic_error("place_separated_sites: no room for the sites");
    const std::uint64_t base = splitmix64(key ^ (dart * 4));
    glm::dvec3 p;
    for (int a = 0; a < 3; ++a) p[a] = 0.5 + to_unit(splitmix64(base + 1 + a)) * (box[a] - 1.0);
    if (!placed.any_within(p, min_separation)) placed.add(p);
  }
  return placed.sites();
}

}  // namespace topotet::gen
