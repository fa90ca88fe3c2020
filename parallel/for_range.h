// Thin wrappers over oneTBB, so that the rest of the code never includes <tbb/...>.
//
// Every parallel loop runs in the caller's current task arena: a library caller who wraps a call
// in its own tbb::task_arena (or uses run_with_threads) keeps control of the thread count. Loops
// take an explicit grain size and a name (for profiles and for reading the code).
//
// With TOPOTET_STD_THREADS defined (the ThreadSanitizer build, see CMakeLists.txt) the same
// interface runs on plain std::threads instead: Debian's libtbb is not instrumented, so TSan would
// not see the happens-before edges TBB creates between a task's spawn and its execution and would
// report races that do not exist. The std::thread backend makes every edge visible (thread
// creation and join), so what TSan reports there is real.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#ifdef TOPOTET_STD_THREADS
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>
#else
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>
#endif

namespace topotet::parallel {

// True in the ThreadSanitizer build. Libraries that start their own TBB workers (Embree's BVH
// builder) must then run single-threaded, or TSan reports their uninstrumented synchronisation as
// races inside them.
#ifdef TOPOTET_STD_THREADS
inline constexpr bool kStdThreads = true;
#else
inline constexpr bool kStdThreads = false;
#endif

#ifndef TOPOTET_STD_THREADS

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

#else  // TOPOTET_STD_THREADS

namespace detail {
// The thread count run_with_threads set for this thread (0 = all hardware threads); inherited by
// the workers a loop starts, as a nested arena would be.
inline thread_local int arena_threads = 0;
}  // namespace detail

inline int current_concurrency() {
  if (detail::arena_threads > 0) return detail::arena_threads;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// Workers take grain-sized chunks from a shared counter; the caller works too. Exceptions are
// carried to the caller (the first one wins), as tbb::parallel_for does.
template <class Index, class Body>
void for_range(Index begin, Index end, Index grain, const char* /*name*/, Body&& body) {
  if (end <= begin) return;
  grain = std::max<Index>(grain, 1);
  if (end - begin <= grain) {
    body(begin, end);
    return;
  }
  const Index chunks = (end - begin + grain - 1) / grain;
  const int concurrency = current_concurrency();
  const int workers = static_cast<int>(std::min<Index>(static_cast<Index>(concurrency), chunks));
  std::atomic<Index> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    try {
      for (Index c = next.fetch_add(1); c < chunks; c = next.fetch_add(1)) {
        const Index b = begin + c * grain;
        body(b, std::min<Index>(end, b + grain));
      }
    } catch (...) {
      const std::lock_guard lock(error_mutex);
      if (!error) error = std::current_exception();
      next.store(chunks);
    }
  };
  {
    std::vector<std::jthread> threads;
    threads.reserve(static_cast<std::size_t>(workers));
    for (int i = 1; i < workers; ++i)
      threads.emplace_back([&work, concurrency] {
        detail::arena_threads = concurrency;
        work();
      });
    work();
  }  // joins
  if (error) std::rethrow_exception(error);
}

template <class Iterator, class Less>
void sort(Iterator first, Iterator last, Less less) {
  std::sort(first, last, less);
}

template <class Fn>
decltype(auto) run_with_threads(int threads, Fn&& fn) {
  struct Restore {
    int saved = detail::arena_threads;
    ~Restore() { detail::arena_threads = saved; }
  } restore;
  if (threads > 0) detail::arena_threads = threads;
  return fn();
}

#endif

// Sorts with the default order.
template <class Iterator>
void sort(Iterator first, Iterator last) {
  parallel::sort(first, last, std::less<>());
}

}  // namespace topotet::parallel
