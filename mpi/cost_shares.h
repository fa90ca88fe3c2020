// Shares of a pass that follow the cost order instead of the vertex count. The shared-memory
// engine removes the cheapest collapses of the whole mesh first, so a region with a steep field
// keeps more vertices than a smooth one. Split by count, a rank holding the steep region removes as
// many vertices as one holding a smooth region, and the field error grows where the detail is
// (measured, cube-sphere 200k to 10% on 4 ranks: the two parts holding the field's front and peak
// had +19% and +32% RMS at their input vertices, the two smooth ones -1% and -6%).
//
// So each rank first runs its pass as a trial (on an engine mesh built from its part, which stays
// as it is; up to 1.5 times its count share, simplify.cpp), with the costs in the whole mesh's
// units (SimplifyOptions::cost_units), and records after each round how many vertices it
// had removed and the largest cost so far (RoundStats::max_cost). The ranks exchange these
// curves, find the cost T at which they together remove the pass's share, and each removes what
// its own curve removes below T: every rank stops at about the same cost, as one engine would.
#pragma once

#include <cstdint>
#include <vector>

#include <mpi.h>

#include "topotet/mesh_data.h"
#include "topotet/round_log.h"
#include "topotet/simplify.h"

namespace topotet::mpi::detail {

// Running largest cost (non-decreasing) against removed vertices, after each round.
struct CostCurve {
  std::vector<double> cost;
  std::vector<std::uint64_t> removed;
};

CostCurve curve_of(const std::vector<RoundStats>& rounds);

// Collective. This rank's number of vertices to remove so that all ranks together remove `total`
// (or all their curves allow, if less) and stop at about the same cost. Identical on every run:
// every rank computes every share from the same gathered curves.
std::uint64_t share_by_cost(MPI_Comm comm, const CostCurve& mine, std::uint64_t total);

// Collective. The cost units of the mesh made of every rank's `part` (bounding box, field ranges,
// mean tet volume), summed in rank order (deterministic). diagonal == 0 when the mesh is empty or
// flat: then each rank keeps its own units.
CostUnits global_cost_units(MPI_Comm comm, const MeshData& part);

}  // namespace topotet::mpi::detail
