// Questions about global vertex ids answered by a directory hashed over the ranks (global id g
// lives on rank g mod ranks): no rank ever holds a table of all vertices.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <mpi.h>

#include "topotet/mpi.h"

namespace topotet::mpi::detail {

// For each local vertex: whether another rank also holds it (then it is frozen for this pass),
// and its owner, the lowest rank holding it.
struct Sharing {
  std::vector<std::uint8_t> shared;  // [local vertex] 0 or 1
  std::vector<int> owner;            // [local vertex]
};
Sharing find_sharing(MPI_Comm comm, const std::vector<GlobalId>& global_ids, std::uint64_t* bytes_sent);

// Merges of one pass (removed id -> id it merged into, each removed id reported by exactly one
// rank) applied to `ids` in place: an id that merged becomes its survivor's id.
void apply_merges(MPI_Comm comm, const std::vector<std::pair<GlobalId, GlobalId>>& merges, std::vector<GlobalId>& ids,
                  std::uint64_t* bytes_sent);

}  // namespace topotet::mpi::detail
