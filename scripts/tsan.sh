#!/usr/bin/env bash
# ThreadSanitizer job: the parallel engine and the parallel mesh builder under TSan.
# The build defines TOPOTET_STD_THREADS (parallel/for_range.h), so the loops run on std::threads
# TSan can see instead of Debian's uninstrumented libtbb; any report fails the job.
# Usage: bash scripts/tsan.sh   (after scripts/setup.sh has installed the packages)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTOPOTET_SANITIZE=thread \
  -DTOPOTET_BUILD_BENCH=OFF -DTOPOTET_BUILD_CLI=OFF
tests=(unit_simplify unit_vertex_map unit_tet_mesh unit_generate property_hierarchy)
cmake --build build-tsan -j "$(nproc)" --target "${tests[@]}"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1"
for t in "${tests[@]}"; do
  echo "--- TSan: $t"
  "build-tsan/tests/$t" --gtest_brief=1
done
echo "TSan: no data race reported"
