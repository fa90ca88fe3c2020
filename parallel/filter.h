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

// The same for a keep that selects few items (the rounds' per-round candidates, about 1.5% of the
// vertices): keep is called once per index, each chunk keeps what it selects in its own buffer and
// the buffers are concatenated in chunk order. The rounds filter every vertex once per round, and
// filter_map's second pass was 3.5% of a parallel run's instructions. Not for dense selections:
// the buffers would double the output's memory.
// `maybe(i, j)` is a cheap screen: false when no index in [i, j) can be kept (blocks of 8 indices
// are skipped without calling keep); always true is correct.
template <class T, class Maybe, class Keep, class Make>
void filter_map_sparse(std::size_t n, std::vector<T>& out, Maybe&& maybe, Keep&& keep, Make&& make) {
  constexpr std::size_t kChunk = 16384, kBlock = 8;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<std::vector<T>> parts(chunks);
  for_range<std::size_t>(0, chunks, 1, "filter_sparse", [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c)
      for (std::size_t i = c * kChunk, end = std::min(n, i + kChunk); i < end; i += kBlock) {
        const std::size_t block_end = std::min(end, i + kBlock);
        if (!maybe(i, block_end)) continue;
        for (std::size_t k = i; k < block_end; ++k)
          if (keep(k)) parts[c].push_back(make(k));
      }
  });
  std::size_t total = 0;
  for (const std::vector<T>& part : parts) total += part.size();
  out.clear();
  out.reserve(total);
  for (const std::vector<T>& part : parts) out.insert(out.end(), part.begin(), part.end());
}

}  // namespace topotet::parallel
