// Deterministic parallel selection of non-conflicting work items by rank.
//
// Items 0..n-1 are ranked by their index (0 first). Item i needs the resources (integer ids below
// the resource count) listed in stencils[offsets[i] .. offsets[i+1]). select() returns winners
// whose resource lists are pairwise disjoint, so they can run concurrently without locks:
//
//   repeat (at most `passes` times, until a pass adds no winner):
//     every undecided item that touches a resource claimed by an earlier winner is blocked;
//     every other undecided item reserves its resources: owner[r] = min(owner[r], i)  (atomic min)
//     an item that owns all of its resources wins and claims them; all reservations are released
//
// The first pass takes the items that are the best in their neighbourhood; later passes take
// items whose better neighbours were themselves blocked, so the result approaches the
// lexicographically first maximal independent set in rank order. Every pass is a function of the
// ranks and the resource lists alone: the winners are the same for any thread count and schedule.
// Claims stay until the caller releases each winner's resources (after its work is done).
#pragma once

#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "parallel/filter.h"
#include "parallel/for_range.h"

namespace topotet::parallel {

class Reservations {
 public:
  explicit Reservations(std::size_t resource_count)
      : owner_(new std::atomic<std::uint32_t>[resource_count]), claimed_(resource_count, 0) {
    static_assert(std::atomic<std::uint32_t>::is_always_lock_free);
    for (std::size_t r = 0; r < resource_count; ++r) owner_[r].store(kFree, std::memory_order_relaxed);
  }

  // `winners` receives the winning items in ascending order. The grains are small: a round has a
  // few hundred items, each touching a few dozen resources, and every loop must spread over the
  // threads (otherwise the selection is the round's serial part).
  void select(const std::vector<std::uint32_t>& offsets, const std::vector<std::uint32_t>& stencils, int passes,
              std::vector<std::uint32_t>& winners) {
    const std::size_t n = offsets.empty() ? 0 : offsets.size() - 1;
    state_.assign(n, kUndecided);
    const auto resources = [&](std::size_t i) {
      return std::pair(stencils.data() + offsets[i], stencils.data() + offsets[i + 1]);
    };
    for (int pass = 0; pass < passes; ++pass) {
      for_range<std::size_t>(0, n, 64, "reserve", [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          if (state_[i] != kUndecided) continue;
          const auto [first, last] = resources(i);
          bool blocked = false;
          for (const std::uint32_t* r = first; r != last && !blocked; ++r) blocked = claimed_[*r] != 0;
          if (blocked) {
            state_[i] = kBlocked;
            continue;
          }
          const std::uint32_t rank = static_cast<std::uint32_t>(i);
          for (const std::uint32_t* r = first; r != last; ++r) {
            // Relaxed: only the final minimum matters, and it is read after the loop has joined
            // (the join is the synchronisation).
            std::atomic<std::uint32_t>& o = owner_[*r];
            std::uint32_t cur = o.load(std::memory_order_relaxed);
            while (rank < cur && !o.compare_exchange_weak(cur, rank, std::memory_order_relaxed)) {
            }
          }
        }
      });
      // Decide: an item that owns every one of its resources wins and claims them. Each item
      // then frees the reservations it holds (exactly one item holds each reserved resource, so
      // all are free again after the loop). Freeing early cannot change another item's verdict:
      // an item only ever compares the owner with its own rank, and nobody else writes it.
      std::atomic<std::uint64_t> new_winners{0};
      for_range<std::size_t>(0, n, 128, "decide", [&](std::size_t b, std::size_t e) {
        std::uint64_t won = 0;
        for (std::size_t i = b; i < e; ++i) {
          if (state_[i] != kUndecided) continue;
          const auto [first, last] = resources(i);
          bool ok = true;
          for (const std::uint32_t* r = first; r != last && ok; ++r) ok = owner_[*r].load(std::memory_order_relaxed) == i;
          for (const std::uint32_t* r = first; r != last; ++r) {
            if (owner_[*r].load(std::memory_order_relaxed) == i) owner_[*r].store(kFree, std::memory_order_relaxed);
            if (ok) claimed_[*r] = 1;  // disjoint from every other winner's: plain writes
          }
          if (ok) {
            state_[i] = kWon;
            ++won;
          }
        }
        new_winners.fetch_add(won, std::memory_order_relaxed);  // a count, read after the join
      });
      if (new_winners.load() == 0) break;
    }
    filter_map(
        n, winners, [&](std::size_t i) { return state_[i] == kWon; },
        [](std::size_t i) { return static_cast<std::uint32_t>(i); });
  }

  // Gives a winner's resources back. Winners' lists are disjoint, so concurrent calls for
  // different winners are safe.
  void release(const std::uint32_t* first, const std::uint32_t* last) {
    for (const std::uint32_t* r = first; r != last; ++r) claimed_[*r] = 0;
  }

 private:
  static constexpr std::uint32_t kFree = std::numeric_limits<std::uint32_t>::max();
  enum : std::uint8_t { kUndecided, kWon, kBlocked };
  std::unique_ptr<std::atomic<std::uint32_t>[]> owner_;  // per resource: best rank reserving it
  std::vector<std::uint8_t> claimed_;                   // per resource: held by a winner
  std::vector<std::uint8_t> state_;                     // per item of the current selection
};

}  // namespace topotet::parallel
