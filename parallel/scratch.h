// Per-thread scratch space: one T per worker thread, created on first use and reused, so hot
// loops never allocate per element. The contents never influence results (only capacity).
#pragma once

#ifndef TOPOTET_STD_THREADS
#include <tbb/enumerable_thread_specific.h>
#else
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <thread>
#endif

namespace topotet::parallel {

#ifndef TOPOTET_STD_THREADS

template <class T>
using PerThread = tbb::enumerable_thread_specific<T>;

#else  // the std::thread backend of for_range.h (ThreadSanitizer builds)

// The workers of that backend live for one loop, so an instance is keyed by thread id and grows by
// a few entries per loop; it only serves the sanitizer build, on small meshes.
template <class T>
class PerThread {
 public:
  PerThread() : make_([] { return T(); }) {}
  template <class Factory>
  explicit PerThread(Factory make) : make_(std::move(make)) {}

  T& local() {
    const std::lock_guard lock(mutex_);
    auto [it, inserted] = index_.try_emplace(std::this_thread::get_id(), items_.size());
    if (inserted) items_.push_back(make_());  // a deque never moves its elements
    return items_[it->second];
  }

  // Every T created so far (call only when no loop is running, as with TBB's).
  auto begin() { return items_.begin(); }
  auto end() { return items_.end(); }
  auto begin() const { return items_.begin(); }
  auto end() const { return items_.end(); }

 private:
  std::function<T()> make_;
  std::mutex mutex_;
  std::map<std::thread::id, std::size_t> index_;
  std::deque<T> items_;
};

#endif

}  // namespace topotet::parallel
