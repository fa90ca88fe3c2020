// Per-thread scratch space: one T per worker thread, created on first use and reused, so hot
// loops never allocate per element. The contents never influence results (only capacity).
#pragma once

#include <tbb/enumerable_thread_specific.h>

namespace topotet::parallel {

template <class T>
using PerThread = tbb::enumerable_thread_specific<T>;

}  // namespace topotet::parallel
