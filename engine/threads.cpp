// run_with_thread_limit: the public face of parallel::run_with_threads (parallel/ stays private).
#include "topotet/threads.h"

#include "parallel/for_range.h"

namespace topotet {

void run_with_thread_limit(int threads, const std::function<void()>& body) {
  parallel::run_with_threads(threads, [&body] { body(); });
}

int current_thread_limit() { return parallel::current_concurrency(); }

}  // namespace topotet
