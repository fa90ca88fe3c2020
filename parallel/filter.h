// Deterministic parallel filter: the selected items come out in index order for every thread
// count, which the rounds need (their candidate lists feed ranks and tie-breaks).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "parallel/for_range.h"

namespace topotet::parallel {

// out = [make(i) for i in [0, n) if keep(i)], in order. keep is called twice per index (count,
// then write), so it must be cheap and pure during the call.
template <class T, class Keep, class Make>
void filter_map(std::size_t n, std::vector<T>& out, Keep&& keep, Make&& make) {
  constexpr std::size_t kChunk = 16384;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<std::size_t> start(chunks + 1, 0);
  for_range<std::size_t>(0, chunks, 1, "filter_count", [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      std::size_t count = 0;
      for (std::size_t i = c * kChunk, end = std::min(n, i + kChunk); i < end; ++i) count += keep(i) ? 1 : 0;
      start[c + 1] = count;
    }
  });
  for (std::size_t c = 0; c < chunks; ++c) start[c + 1] += start[c];
  out.resize(start[chunks]);
  for_range<std::size_t>(0, chunks, 1, "filter_write", [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      std::size_t pos = start[c];
      for (std::size_t i = c * kChunk, end = std::min(n, i + kChunk); i < end; ++i)
        if (keep(i)) out[pos++] = make(i);
    }
  });
}

}  // namespace topotet::parallel
