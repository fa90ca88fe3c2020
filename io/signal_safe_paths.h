// A fixed set of paths that a signal handler may read: the temporary files in progress
// (atomic_file.cpp) and the live scratch folders (outofcore/scratch.cpp), removed on SIGINT/SIGTERM.
// A handler may not allocate and must never read freed memory, so the storage is fixed (static
// objects are zero-initialised: every slot free); a slot's path is written, then published with
// `ready` (release), and the handler reads only published slots (acquire).
#pragma once

#include <limits.h>

#include <atomic>
#include <cstring>
#include <string>

namespace topotet::io {

template <int Slots>
class SignalSafePaths {
  static_assert(std::atomic<bool>::is_always_lock_free, "a signal handler needs lock-free flags");

 public:
  // The slot now holding `path`, or -1 when every slot is taken or the path is longer than
  // PATH_MAX - reserve (`reserve`: what the handler appends): then only the handler misses it.
  int add(const std::string& path, std::size_t reserve = 0) {
    if (path.size() + reserve >= PATH_MAX) return -1;
    for (int i = 0; i < Slots; ++i) {
      bool expected = false;
      if (!taken_[i].compare_exchange_strong(expected, true, std::memory_order_acquire)) continue;
      std::memcpy(paths_[i], path.c_str(), path.size() + 1);
      ready_[i].store(true, std::memory_order_release);
      return i;
    }
    return -1;
  }

  void remove(int slot) {
    if (slot < 0) return;
    ready_[slot].store(false, std::memory_order_release);
    taken_[slot].store(false, std::memory_order_release);
  }

  // Calls f(const char* path) for every published path; async-signal-safe when f is.
  template <class F>
  void for_each(F&& f) const noexcept {
    for (int i = 0; i < Slots; ++i)
      if (ready_[i].load(std::memory_order_acquire)) f(static_cast<const char*>(paths_[i]));
  }

 private:
  std::atomic<bool> taken_[Slots];
  std::atomic<bool> ready_[Slots];
  char paths_[Slots][PATH_MAX];
};

}  // namespace topotet::io
