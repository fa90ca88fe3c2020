// Deterministic parallel reduction: [0, n) is cut into blocks of a fixed size (independent of the
// thread count), each block is summarised by one call, and the summaries are folded in block
// order. Floating-point results are then bit-identical for every thread count.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "parallel/for_range.h"

namespace topotet::parallel {

// Returns fold(... fold(fold(init, summarise(0, b)), summarise(b, 2b)) ..., summarise(.., n))
// with b = block. summarise(begin, end) -> T runs concurrently on disjoint blocks; fold(T&, const
// T&) runs on the calling thread, in block order.
template <class T, class Summarise, class Fold>
T block_reduce(std::size_t n, std::size_t block, const char* name, T init, Summarise&& summarise, Fold&& fold) {
  block = std::max<std::size_t>(block, 1);
  const std::size_t blocks = (n + block - 1) / block;
  std::vector<T> partial(blocks, init);
  for_range<std::size_t>(0, blocks, 1, name, [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) partial[b] = summarise(b * block, std::min(n, (b + 1) * block));
  });
  for (const T& p : partial) fold(init, p);
  return init;
}

}  // namespace topotet::parallel
