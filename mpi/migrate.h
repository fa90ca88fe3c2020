// Moving tets between ranks with everything that belongs to them: their vertices (global id,
// position, ref, corner / required marks, field values, the pass's pending mark), material, and
// the listed triangles and segments on their faces and edges (a face or edge on a new partition
// border goes to both sides; the receiver merges copies by global ids).
#pragma once

#include <cstdint>
#include <vector>

#include <mpi.h>

#include "topotet/mpi.h"

namespace topotet::mpi::detail {

// Sends local tet t to rank dest[t] (itself included) and replaces `mesh` by what this rank
// receives, in rank order of the senders, so the result depends only on the inputs. `pending`
// (per-vertex marks, partition.h) is carried along (OR of the copies). Returns the tets sent to other ranks.
std::uint64_t migrate(MPI_Comm comm, DistributedMesh& mesh, std::vector<std::uint8_t>& pending,
                      const std::vector<int>& dest, std::uint64_t* bytes_sent);

// Makes every rank's field layout and group names those of the lowest rank holding tets (ranks
// without tets adopt them; a rank with tets and another layout is an error on every rank).
void agree_layout(MPI_Comm comm, DistributedMesh& mesh);

// Checks sizes and indices of a part (throws on every rank when one is malformed).
void check_part(MPI_Comm comm, const DistributedMesh& mesh);

}  // namespace topotet::mpi::detail
