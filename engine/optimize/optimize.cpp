// The optimisation after the collapses (see optimize.h).
#include "optimize/optimize.h"

#include <chrono>

#include "optimize/smooth.h"
#include "optimize/swap.h"

namespace topotet {

void optimize_after_collapses(MeshModel& mesh, const SimplifyOptions& options, CostModel& cost, FieldBounds* bounds,
                              const InputSamples* samples, Report& report) {
  if (options.optimize == Optimize::kNone) return;
  const auto start = std::chrono::steady_clock::now();
  const bool full = options.optimize == Optimize::kFull;
  // Measured on the families at 100k tets, 10% (docs/performance.md, "Quality after the
  // collapses"): the flips remove most slivers, and each smoothing move costs field error (the
  // moved vertex leaves the place its quadric chose), so light is one smoothing call (its passes
  // give every proposal its turn: smooth.h) and the flips to the end; full alternates them 6 times,
  // for 5-7% more field RMS than light. Target 0.4, not 0.3: a tet can have a dihedral under 10 degrees and
  // a mean ratio above 0.3.
  SmoothOptions smooth;  // light: their defaults
  SwapOptions swap;
  smooth.dihedral_floor = swap.dihedral_floor = DihedralFloor::degrees(options.min_dihedral);
  if (full) {
    smooth.max_passes = 2;  // per round
    swap.max_passes = 8;
  }
  // Smoothing and flips alternate: a flip changes the stars a smoothing could not improve, a move
  // makes flips possible that were not.
  const int rounds = full ? 6 : 1;
  for (int round = 0; round < rounds; ++round) {
    const SmoothStats moved = smooth_vertices(mesh, smooth, cost, bounds, samples);
    if (round == 0) report.optimize_candidates = moved.candidates;
    report.optimize_moves += moved.moves;
    report.optimize_passes += moved.passes;
    std::uint64_t flips = 0;
    if (bounds == nullptr) {
      const SwapStats swapped = swap_bad_tets(mesh, swap, samples);
      flips = swapped.flips_23 + swapped.edge_removals;
      report.optimize_flips += flips;
    }
    if (moved.moves == 0 && flips == 0) break;
  }
  report.optimize_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace topotet
