#include "generate/ball_growth.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>

#include "generate/tet_neighbourhood.h"

namespace topotet::gen {
namespace {

class Growth {
 public:
  Growth(const FreudenthalGrid& grid, const std::vector<std::int32_t>& preferred, const std::vector<glm::dvec3>& sites,
         std::vector<std::int32_t>& material)
      : grid_(grid), hood_(grid), preferred_(preferred), sites_(sites), material_(material) {}

  // Within its preferred tets a region competes with no other, so the regions grow one after the
  // other, each breadth first from its seed: the queue stays small and in cache.
  void grow_from(const std::vector<TetId>& seeds) {
    material_.assign(grid_.tet_count(), 0);
    for (std::size_t s = 0; s < seeds.size(); ++s) {
      if (material_[seeds[s]] != 0) throw std::logic_error("grow_ball_regions: two seeds in one tet");
      material_[seeds[s]] = static_cast<std::int32_t>(s + 1);
    }
    std::vector<TetId> queue;
    for (std::size_t s = 0; s < seeds.size(); ++s) {
      const auto m = static_cast<std::int32_t>(s + 1);
      queue.assign(1, seeds[s]);
      for (std::size_t head = 0; head < queue.size(); ++head) {
        hood_.for_each_face_neighbour(queue[head], [&](TetId u) {
          if (material_[u] == 0 && preferred_[u] == m && hood_.joins_as_ball(u, m, material_)) {
            material_[u] = m;
            queue.push_back(u);
          }
        });
      }
    }
  }

  void place_the_rest() {
    for (TetId t = 0; t < material_.size(); ++t)
      if (material_[t] == 0) left_.push_back(t);
    while (!left_.empty()) {
      if (join_pass() || join_by_growing_around()) continue;
      throw std::logic_error("grow_ball_regions: " + std::to_string(left_.size()) + " tets can join no region as a ball");
    }
  }

  GrowthStats finish() {
    for (std::size_t t = 0; t < material_.size(); ++t) stats_.off_preference_tets += material_[t] != preferred_[t];
    return stats_;
  }

 private:
  // The regions across t's faces: its preferred one first, then by distance from t's centroid to
  // their sites, then by id. Returns how many there are.
  int ranked_candidates(TetId t, std::array<std::int32_t, 4>& candidates) const {
    int count = 0;
    hood_.for_each_face_neighbour(t, [&](TetId w) {
      const std::int32_t m = material_[w];
      if (m != 0 && std::find(candidates.begin(), candidates.begin() + count, m) == candidates.begin() + count) {
        candidates[count++] = m;
      }
    });
    const glm::dvec3 c = tet_centroid(grid_, t);
    const auto rank = [&](std::int32_t m) {
      const glm::dvec3 d = sites_[static_cast<std::size_t>(m - 1)] - c;
      return std::tuple(m != preferred_[t], d.x * d.x + d.y * d.y + d.z * d.z, m);
    };
    for (int i = 1; i < count; ++i)  // insertion sort of at most 4
      for (int j = i; j > 0 && rank(candidates[j]) < rank(candidates[j - 1]); --j) std::swap(candidates[j], candidates[j - 1]);
    return count;
  }

  // Keeps in left_ the tets for which `try_join` fails; true if any succeeded.
  template <class TryJoin>
  bool sweep(TryJoin&& try_join) {
    std::size_t kept = 0;
    for (TetId u : left_)
      if (!try_join(u)) left_[kept++] = u;
    const bool progress = kept < left_.size();
    left_.resize(kept);
    return progress;
  }

  bool join_pass() {
    return sweep([&](TetId u) {
      std::array<std::int32_t, 4> candidates{};
      const int count = ranked_candidates(u, candidates);
      for (int i = 0; i < count; ++i) {
        if (hood_.joins_as_ball(u, candidates[i], material_)) {
          material_[u] = candidates[i];
          return true;
        }
      }
      return false;
    });
  }

  // A wedged free tet u: e.g. two regions each touch u across a face and along an edge that the
  // other one's face holds, so u can join neither. Growing one candidate region m around u
  // untangles that: neighbours of u move to m, in rounds, whenever the move keeps both their
  // region and m balls, until u can join m. If it cannot, the moves are undone and the next
  // candidate is tried.
  bool join_by_growing_around() {
    return sweep([&](TetId u) {
      std::array<std::int32_t, 4> candidates{};
      const int count = ranked_candidates(u, candidates);
      for (int i = 0; i < count; ++i) {
        const std::int32_t m = candidates[i];
        moved_.clear();
        for (bool changed = true; changed && !hood_.joins_as_ball(u, m, material_);) {
          changed = false;
          hood_.for_each_neighbour(u, [&](TetId w) {
            const std::int32_t own = material_[w];
            if (own == 0 || own == m || !hood_.leaves_as_ball(w, material_) || !hood_.joins_as_ball(w, m, material_)) {
              return;
            }
            moved_.emplace_back(w, own);
            material_[w] = m;
            changed = true;
          });
        }
        if (hood_.joins_as_ball(u, m, material_)) {
          material_[u] = m;
          ++stats_.wedged_tets;
          stats_.moves += moved_.size();
          return true;
        }
        for (auto it = moved_.rbegin(); it != moved_.rend(); ++it) material_[it->first] = it->second;
      }
      return false;
    });
  }

  const FreudenthalGrid& grid_;
  const TetNeighbourhood hood_;
  const std::vector<std::int32_t>& preferred_;
  const std::vector<glm::dvec3>& sites_;
  std::vector<std::int32_t>& material_;
  std::vector<TetId> left_;                                 // free tets
  std::vector<std::pair<TetId, std::int32_t>> moved_;       // (tet, its region before the move)
  GrowthStats stats_;
};

}  // namespace

GrowthStats grow_ball_regions(const FreudenthalGrid& grid, const std::vector<TetId>& seeds,
                              const std::vector<std::int32_t>& preferred, const std::vector<glm::dvec3>& sites,
                              std::vector<std::int32_t>& material) {
  Growth growth(grid, preferred, sites, material);
  growth.grow_from(seeds);
  growth.place_the_rest();
  return growth.finish();
}

}  // namespace topotet::gen
