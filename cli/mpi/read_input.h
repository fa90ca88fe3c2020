// topotet-mpi's input: a whole mesh read by rank 0 and cut by METIS, or a partitioned Gmsh 4.1
// mesh with one part per rank (gmsh -part N):
//   - split (gmsh -part N -part_split -o IN writes <stem>_1.msh ... <stem>_N.msh, and no IN):
//     rank r reads <stem>_<r+1>.msh; Gmsh's node tags are global over the files and become the
//     global ids (a vertex on a partition border is in both files, with one tag);
//   - one file (IN has $PartitionedEntities): rank 0 reads it and sends each tet to the rank of
//     its partition (partition p -> rank p - 1).
// Either way the number of partitions must equal the number of ranks.
#pragma once

#include <string>

#include <mpi.h>

#include "topotet/cell_fields.h"
#include "topotet/io.h"
#include "topotet/mpi.h"

namespace topotet::cli::mpi {

enum class InputKind { kWhole, kGmshSplit, kGmshPartitioned };

struct Input {
  topotet::mpi::DistributedMesh part;  // this rank's
  InputKind kind = InputKind::kWhole;
  std::uint64_t tets = 0;  // over all ranks
  // Rank 0, when the input's cell arrays are carried: the whole input's positions, tets,
  // materials and cell arrays (their kinds applied), to remap onto the gathered output
  // (topotet/cell_fields.h). Empty elsewhere and when the input has no cell arrays.
  MeshData cell_source;
};

// Collective. Throws std::runtime_error on every rank (the lowest failing rank's message, naming
// the file) when a file is missing or malformed, or the partitions do not match the ranks.
// `options`: --format and --tets-only (keep_partitions is set here); the cells --tets-only leaves
// out are counted in one warning line per file read.
// `carry_cells`: the cell arrays are wanted on a gathered output, with these kinds (an array name
// the input lacks is an error on every rank). They can be carried only from a whole input file
// read by rank 0: the remap needs every input tet that an output tet overlaps. Null (--partitioned
// output) or a split input: a warning says that the file's cell arrays are not carried.
Input read_input(MPI_Comm comm, const std::string& path, std::int32_t metis_seed, const ReadOptions& options = {},
                 const CellRemapOptions* carry_cells = nullptr);

}  // namespace topotet::cli::mpi
