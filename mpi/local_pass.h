// One rank's share of a pass: its part simplified by the shared-memory engine with the vertices it
// shares with other ranks frozen (vertex_state::kFrozen), so that every collapse it makes is one
// the whole mesh allows (the stars of both ends are local).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "topotet/mpi.h"
#include "topotet/simplify.h"

namespace topotet::mpi::detail {

struct LocalPass {
  Report report;
  std::vector<std::pair<GlobalId, GlobalId>> merges;  // removed global id -> the id it merged into
  std::vector<VertId> origin;  // [output vertex] the part's vertex (before the pass) it is
};

// Simplifies `mesh` towards `target_vertices` local vertices (options.target_vertices is
// overridden). shared[v]: vertex v is frozen. keep (may be empty) [v]: vertex v is pinned (it may
// absorb a collapse, but neither moves nor goes). The part keeps its global ids on the surviving
// vertices; `owner` is carried over. Throws InputError when the part is not a valid mesh.
// The same run on the part without changing it (the TetMesh is built from mesh.local, which is
// left as it was): shares_by_cost's trial, which wants only the report and options.round_log.
Report trial_part(DistributedMesh& mesh, const std::vector<std::uint8_t>& shared, const std::vector<std::uint8_t>& keep,
                  SimplifyOptions options, std::uint64_t target_vertices);

LocalPass simplify_part(DistributedMesh& mesh, const std::vector<std::uint8_t>& shared,
                        const std::vector<std::uint8_t>& keep, SimplifyOptions options, std::uint64_t target_vertices);

}  // namespace topotet::mpi::detail
