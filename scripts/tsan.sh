#!/usr/bin/env bash
# ThreadSanitizer job: the parallel engine and the parallel mesh builder under TSan.
# The build defines TOPOTET_STD_THREADS (parallel/for_range.h), so the loops run on std::threads
# TSan can see instead of Debian's uninstrumented libtbb; any report fails the job.
# Usage: bash scripts/tsan.sh   (after scripts/setup.sh --tests has installed the packages)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DTOPOTET_SANITIZE=thread \
  -DTOPOTET_BUILD_BENCH=OFF -DTOPOTET_BUILD_CLI=OFF
tests=(unit_simplify unit_vertex_map unit_tet_mesh unit_mesh_view unit_generate property_hierarchy)
cmake --build build-tsan -j "$(nproc)" --target "${tests[@]}" unit_field_bounds unit_surface_tolerance property_optimize \
  unit_relax_limits
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1"
# Two generator tests are the topology checker's (serial) work across many sizes, 43 s of the 63 s
# unit_generate takes under TSan: the generators' parallel code runs in the others (the 1M-tet
# mesh, the polycrystal size cases, the families), so they are left to the other jobs.
skip_generate='-Polycrystal.EveryCellIsABallAcrossSizesAndCellCounts:Generate.SurfaceTopologyAcrossSizes'
for t in "${tests[@]}"; do
  echo "--- TSan: $t"
  if [[ $t == unit_generate ]]; then
    "build-tsan/tests/$t" --gtest_brief=1 --gtest_filter="$skip_generate"
  else
    "build-tsan/tests/$t" --gtest_brief=1
  fi
done
# The field bounds are written in the parallel apply phase: their thread-count test runs the
# parallel engine with a limit. Their other tests measure with compare_fields, whose Embree scene
# is built by Embree's own threads (invisible to TSan, which then reports races inside Embree).
echo "--- TSan: unit_field_bounds (parallel engine with bounds)"
build-tsan/tests/unit_field_bounds --gtest_brief=1 \
  --gtest_filter='FieldBounds.SameOutputAndBoundsForAnyThreadCount:FieldBoundsEverywhere.SameOutputAndBoundsForAnyThreadCount'
# The tolerance's surface items (engine/guarantees/surface_coverage.h) move in the parallel apply phase.
echo "--- TSan: unit_surface_tolerance (parallel engine with the tolerance, 1/2/4 threads)"
build-tsan/tests/unit_surface_tolerance --gtest_brief=1 --gtest_filter='SimplifyTolerance.ParallelOutputIsIdenticalForEveryThreadCount'
# The smoothing after the collapses (engine/optimize/smooth.h) moves vertices in parallel.
echo "--- TSan: property_optimize (smoothing and flips after the parallel engine, 1 and 2 threads)"
build-tsan/tests/property_optimize --gtest_brief=1 --gtest_filter='*seed1_half_light:*seed7_small_full'
# At a stall the rounds look again at the edges whose refusals may be out of date, in parallel
# (Proposals::refresh_if_stale), and the census runs in parallel: runs that stall and relax.
echo "--- TSan: unit_relax_limits (stalls, census and relaxations, 1/2/4 threads)"
build-tsan/tests/unit_relax_limits --gtest_brief=1 --gtest_filter='RelaxLimits.SameOutputForEveryThreadCount'
echo "TSan: no data race reported"
