// Per-round work of the parallel engine, for scaling studies: opt in with
// SimplifyOptions::round_log. bench/bench_simplify builds its work/span projection on it, and
// `topotet simplify -vv` prints it. Not needed to simplify: only this header defines it.
#pragma once

#include <array>
#include <cstdint>

namespace topotet {

struct RoundStats {
  std::uint64_t evaluated = 0;   // dirty vertices re-costed in the evaluate phase
  std::uint64_t candidates = 0;  // verified proposals competing for the independent set
  std::uint64_t winners = 0;     // independent set size
  // Winners whose tolerance proof (deferred to after the selection) refused every placement of
  // their edge: they give their reservation back and propose again in the next round.
  std::uint64_t winners_refused = 0;
  std::uint64_t collapses = 0;   // winners applied (all the proved ones)
  double max_cost = 0.0;         // the largest cost among them (normalised units, SimplifyOptions::max_cost)
  // Wall time: evaluate (costs, then the kernel on the round's candidates, then the winners'
  // tolerance proofs), select (threshold,
  // stencils, reservations), apply (collapses and the updates of their stencils), compact.
  std::array<double, 4> phase_seconds{};
  // The part of phase_seconds spent in sequential code (the quantile sample, prefix sums, table
  // growth): the Amdahl term of the round. The rest runs in parallel loops.
  double serial_seconds = 0.0;
};

}  // namespace topotet
