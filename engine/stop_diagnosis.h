// Why a run stopped before its target (issue #23): a census of the edges left, each with the
// reason that refuses it, and one change to suggest (Report::stop, topotet/simplify.h).
#pragma once

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
void diagnose_stop(const MeshModel& mesh, const SimplifyOptions& options, const CollapseOptions& kernel,
                   CostModel& cost, std::uint64_t target, Report& report, bool every_edge_refused);

}  // namespace topotet::detail
