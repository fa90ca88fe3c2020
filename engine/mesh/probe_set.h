// A set of integer keys for the few dozen items of one star (vertices, or faces keyed by their two
// other vertices): open addressing with linear probing in caller-provided storage.
//
// The kernel groups the items of a star many times per collapse (neighbours, faces through a
// vertex); sorting 72 items to find ~14 distinct ones was a large part of its time. Inserting into
// a table twice the size of the item count costs about one probe per item. Iteration order is
// never taken from the table: callers keep their own insertion-ordered lists (deterministic).
#pragma once

#include <cstdint>
#include <span>
#include <utility>

namespace topotet {

// Smallest power of two >= 1.5 * items (at least 16): the table size for `items` insertions
// (linear probing stays short below that load, and the table is cleared on every use).
constexpr std::size_t probe_slots_for(std::size_t items) {
  std::size_t n = 16;
  while (n < items + items / 2) n *= 2;
  return n;
}

template <class Key>  // std::uint32_t or std::uint64_t
class ProbeSet {
 public:
  static constexpr Key kEmpty = ~Key{0};

  // `storage` has a power-of-two size greater than the number of keys that will be inserted
  // (probe_slots_for); it is cleared here.
  explicit ProbeSet(std::span<Key> storage) : slots_(storage), mask_(static_cast<std::uint32_t>(storage.size() - 1)) {
    for (Key& k : slots_) k = kEmpty;
  }

  // Storage whose slots are all kEmpty already (a large table reused across calls): not cleared
  // here. The caller empties the slots it filled (erase_slots) before the next use.
  struct AlreadyEmpty {};
  ProbeSet(std::span<Key> storage, AlreadyEmpty) : slots_(storage), mask_(static_cast<std::uint32_t>(storage.size() - 1)) {}
  // Empties the given slots (those insert() returned): the whole table, when they are all.
  void erase_slots(std::span<const std::uint32_t> slots) {
    for (std::uint32_t h : slots) slots_[h] = kEmpty;
  }

  // The slot of `key` and whether it was inserted now (false: it was already there).
  std::pair<std::uint32_t, bool> insert(Key key) {
    std::uint32_t h = hash(key) & mask_;
    while (slots_[h] != kEmpty) {
      if (slots_[h] == key) return {h, false};
      h = (h + 1) & mask_;
    }
    slots_[h] = key;
    return {h, true};
  }

  static constexpr std::uint32_t kNotFound = ~0u;

  // The slot of `key`, or kNotFound.
  std::uint32_t find(Key key) const {
    for (std::uint32_t h = hash(key) & mask_; slots_[h] != kEmpty; h = (h + 1) & mask_)
      if (slots_[h] == key) return h;
    return kNotFound;
  }
  bool contains(Key key) const { return find(key) != kNotFound; }

  std::uint32_t size() const { return mask_ + 1; }
  Key at(std::uint32_t slot) const { return slots_[slot]; }

 private:
  // Fibonacci hashing: the high bits of the product mix every bit of the key.
  static std::uint32_t hash(std::uint64_t key) {
    return static_cast<std::uint32_t>((key * 0x9E3779B97F4A7C15ull) >> 40);
  }
  std::span<Key> slots_;
  std::uint32_t mask_;
};

}  // namespace topotet
