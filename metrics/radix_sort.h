// Stable LSD radix sort of (key, slot) pairs, private to metrics/: the simplex index and the
// surface labelling find equal simplices by sorting packed sorted-vertex keys (no map per simplex).
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

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

}  // namespace topotet::metrics::detail
