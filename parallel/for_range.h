// Thin wrappers over oneTBB, so that the rest of the code never includes <tbb/...>.
//
// Every parallel loop runs in the caller's current task arena: a library caller who wraps a call
// in its own tbb::task_arena (or uses topotet::parallel::ThreadLimit) keeps control of the thread
// count. Loops take an explicit grain size and a name (for profiles and for reading the code).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

namespace topotet::parallel {

// Calls body(begin, end) on disjoint sub-ranges of [begin, end) that cover it.
// `name` documents the kernel (visible in profiles through the call stack).
template <class Index, class Body>
void for_range(Index begin, Index end, Index grain, const char* /*name*/, Body&& body) {
  if (end <= begin) return;
  if (end - begin <= grain) {
    body(begin, end);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<Index>(begin, end, grain),
                    [&](const tbb::blocked_range<Index>& r) { body(r.begin(), r.end()); },
                    tbb::simple_partitioner());
}

template <class Iterator, class Less>
void sort(Iterator first, Iterator last, Less less) {
  tbb::parallel_sort(first, last, less);
}

// Number of threads the current arena may use.
inline int current_concurrency() { return tbb::this_task_arena::max_concurrency(); }

// Runs fn inside an arena limited to `threads` threads (0 = the current arena, unchanged).
template <class Fn>
decltype(auto) run_with_threads(int threads, Fn&& fn) {
  if (threads <= 0) return fn();
  tbb::task_arena arena(threads);
  return arena.execute(std::forward<Fn>(fn));
}

}  // namespace topotet::parallel
