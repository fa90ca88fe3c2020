// Why a run stopped before its target (issue #23): a census of the edges left, each with the
// reason that refuses it, and one change to suggest (Report::stop, topotet/simplify.h).
#pragma once

#include <cstdint>
#include <vector>

#include "cost/cost.h"
#include "kernel/collapse.h"
#include "mesh/mesh_model.h"
#include "topotet/simplify.h"

namespace topotet::detail {

// Fills report.stop from the mesh as the engine left it (not compacted), with the engine's cost
// model (its placements are the ones the run tries) and the kernel options the run used (its tolerance reference and coverage, quality floor, field bounds). Reads only;
// parallel over vertices, deterministic (the counts are sums). Costs one kernel check per live
// edge and placement: run it only when the run stopped before its target (`target` vertices).
// every_edge_refused: the engine stalled (no legal collapse left) under `kernel`, so it has tried
// and refused every placement of every edge since the edge's stars last changed; the census then
// need not prove again the tolerance of the placements it refused for it (same verdicts).
// held_by_tolerance (optional): set to one byte per vertex slot, 1 for the vertices the tolerance
// holds (the census's verdict), for freed_by_tolerance.
// stride > 1: a sampled census, for choosing a step at a stall (relax_limits.cpp), never for the
// report of a run that stops. It asks only the vertex slots that are multiples of `stride` (the
// same ones for any thread count); the pinned vertices are counted exactly, the other verdicts
// scaled to every unpinned live vertex. held_by_tolerance marks the sampled vertices only.
// Returns the scale: the live unpinned vertices one asked vertex stands for (1 when exact).
double diagnose_stop(const MeshModel& mesh, const SimplifyOptions& options, const CollapseOptions& kernel,
                     CostModel& cost, std::uint64_t target, Report& report, bool every_edge_refused,
                     std::vector<std::uint8_t>* held_by_tolerance = nullptr, std::size_t stride = 1);

// Would a tolerance of h (above the kernel's) free at least `wanted` of the vertices the census
// found held by the tolerance (held_by_tolerance)? A vertex is freed when some placement that
// removes it passes the kernel with H = h. Estimated on an evenly spaced sample of at most `sample`
// of them (all when fewer: then exact), whose count must reach its share of `wanted`; the coverage
// is not asked (its H only grows). For choosing a step, never a guarantee. Reads only; parallel,
// deterministic (the count stops at the sample's share, whichever vertices got there).
bool tolerance_frees(const MeshModel& mesh, const CollapseOptions& kernel, CostModel& cost, double h,
                     const std::vector<std::uint8_t>& held_by_tolerance, std::uint64_t wanted, std::size_t sample);

}  // namespace topotet::detail
