// Thread limits for library callers: the one place outside the engine's own code where the thread
// pool is controlled (the CLI's --threads, tests that compare thread counts). Every parallel loop
// of the library (building, simplifying, measuring, checking) runs inside the limit.
#pragma once

#include <functional>

namespace topotet {

// Runs body() so that every parallel loop inside it uses at most `threads` threads (0 = no new
// limit: the caller's current one, all cores by default). Exceptions thrown by body propagate.
void run_with_thread_limit(int threads, const std::function<void()>& body);

// How many threads a parallel loop started here may use (the current limit, or all cores).
int current_thread_limit();

}  // namespace topotet
