// A new partition of the current (coarse) mesh: the dual graph (tets, joined by shared faces) is
// gathered on rank 0 and cut by METIS k-way into one part per rank; parts go to the ranks that
// already hold most of their tets, so migration moves as little as it can.
//
// Faces next to a vertex that was frozen in the last pass ("pending": not yet simplified) weigh
// kPendingFaceWeight in the cut, so METIS puts the new borders elsewhere and the old ones become
// interiors. Memory on rank 0: 33 bytes per tet gathered, then ~60 bytes per tet while METIS runs
// (the first version's cost; ParMETIS or PT-Scotch would cut the distributed graph instead).
#pragma once

#include <cstdint>
#include <vector>

#include <mpi.h>

#include "topotet/mpi.h"

namespace topotet::mpi::detail {

inline constexpr int kPendingFaceWeight = 20;
// Bits of the per-vertex marks carried through passes and migrations.
inline constexpr std::uint8_t kFrozenLastPass = 1;  // pending: the next partition avoids it
inline constexpr std::uint8_t kFrozenOnce = 2;      // frozen in some pass (reported, Result::touched_border)

// [local tet] the rank it should move to. `marks` (per vertex, kFrozenLastPass read) may be empty
// (no weights). Collective.
std::vector<int> partition(MPI_Comm comm, const DistributedMesh& mesh, const std::vector<std::uint8_t>& marks,
                           std::int32_t seed, std::uint64_t* bytes_sent);

}  // namespace topotet::mpi::detail
