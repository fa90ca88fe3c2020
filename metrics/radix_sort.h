// Sorts of (key, slot) pairs, private to metrics/: the simplex index finds equal simplices by
// sorting packed sorted-vertex keys (no map per simplex). radix_sort for narrow keys (Morton codes,
// smallest vertices), bucket_sort (by smallest vertex, then each bucket) for edge and face keys.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "parallel/for_range.h"

namespace topotet::metrics::detail {

__extension__ typedef unsigned __int128 U128;  // face keys when n^3 does not fit in 64 bits

template <class Key>
struct KeyedSlot {
  Key key;
  std::uint32_t slot;  // where the simplex came from (each caller documents its slot layout)
};

inline int bit_width_of(std::uint64_t x) { return std::bit_width(x); }
inline int bit_width_of(U128 x) {
  const auto high = static_cast<std::uint64_t>(x >> 64);
  return high != 0 ? 64 + std::bit_width(high) : std::bit_width(static_cast<std::uint64_t>(x));
}

// LSD radix sort on the low key_bits bits. It is stable, so items with equal keys stay in
// generation order (increasing slot), which the callers' tie rules rely on.
template <class Key>
void radix_sort(std::vector<KeyedSlot<Key>>& items, int key_bits) {
  if (items.size() < 2 || key_bits <= 0) return;
  const int pass_count = (key_bits + 10) / 11;  // digits of at most 11 bits: counts stay in L1
  const int digit_bits = (key_bits + pass_count - 1) / pass_count;
  const std::size_t bucket_count = std::size_t{1} << digit_bits;
  const Key mask = static_cast<Key>(bucket_count - 1);
  std::vector<std::size_t> offsets(bucket_count);
  std::vector<KeyedSlot<Key>> sorted(items.size());
  for (int pass = 0; pass < pass_count; ++pass) {
    const int shift = pass * digit_bits;
    auto digit = [&](const KeyedSlot<Key>& item) {
      return static_cast<std::size_t>((item.key >> shift) & mask);
    };
    std::fill(offsets.begin(), offsets.end(), 0);
    for (const auto& item : items) ++offsets[digit(item)];
    if (offsets[digit(items[0])] == items.size()) continue;  // one bucket: nothing would move
    std::size_t running = 0;
    for (auto& offset : offsets) running += std::exchange(offset, running);
    for (const auto& item : items) sorted[offsets[digit(item)]++] = item;
    items.swap(sorted);
  }
}

// Sorts by (key, slot), the order of a stable sort by key when items come in increasing slot
// order: a counting sort by bucket_of(key) (a monotone function of the key into [0,
// bucket_count): the smallest vertex of a simplex), then every bucket on its own, in parallel.
// Simplices have few cofaces per smallest vertex, so buckets are small; this beats the radix
// sort's passes over the whole array when keys are wide.
template <class Key, class BucketOf>
void bucket_sort(std::vector<KeyedSlot<Key>>& items, std::size_t bucket_count, BucketOf&& bucket_of) {
  if (items.size() < 2) return;
  std::vector<std::size_t> start(bucket_count + 1, 0);
  for (const auto& item : items) ++start[bucket_of(item.key) + 1];
  for (std::size_t b = 0; b < bucket_count; ++b) start[b + 1] += start[b];
  std::vector<KeyedSlot<Key>> sorted(items.size());
  {
    std::vector<std::size_t> cursor(start.begin(), start.end() - 1);
    for (const auto& item : items) sorted[cursor[bucket_of(item.key)]++] = item;
  }
  parallel::for_range<std::size_t>(0, bucket_count, 2048, "bucket_sort", [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b)
      std::sort(sorted.begin() + static_cast<std::ptrdiff_t>(start[b]), sorted.begin() + static_cast<std::ptrdiff_t>(start[b + 1]),
                [](const KeyedSlot<Key>& x, const KeyedSlot<Key>& y) { return x.key != y.key ? x.key < y.key : x.slot < y.slot; });
  });
  items.swap(sorted);
}

}  // namespace topotet::metrics::detail
