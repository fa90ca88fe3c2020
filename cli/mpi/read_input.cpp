#include "read_input.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <utility>
#include <vector>

#include "common.h"  // read_mesh_file
#include "exchange.h"
#include "topotet/error.h"
#include "topotet/io.h"
#include "topotet/tet_mesh.h"

namespace topotet::cli::mpi {

namespace {

using topotet::mpi::detail::rank_of;
using topotet::mpi::detail::size_of;

// Every rank learns whether some rank failed; all throw the lowest failing rank's message.
void agree(MPI_Comm comm, const std::string& error) {
  const int ranks = size_of(comm);
  int mine = error.empty() ? ranks : rank_of(comm), first = ranks;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == ranks) return;
  std::string message = error;
  int size = static_cast<int>(message.size());
  MPI_Bcast(&size, 1, MPI_INT, first, comm);
  message.resize(static_cast<std::size_t>(size));
  MPI_Bcast(message.data(), size, MPI_CHAR, first, comm);
  throw std::runtime_error(message);
}

// As `topotet simplify` warns (cli/common.cpp read_input): the output covers the tets only.
void warn_about_left_out_cells(const std::string& path, const ReadNotes& notes) {
  if (notes.volume_cells() == 0) return;
  std::string what;
  const auto add = [&](std::uint64_t n, const char* kind) {
    if (n != 0) what += (what.empty() ? "" : ", ") + std::to_string(n) + " " + kind;
  };
  add(notes.hexahedra, "hexahedra");
  add(notes.prisms, "prisms");
  add(notes.pyramids, "pyramids");
  add(notes.polyhedra, "polyhedra");
  std::fprintf(stderr, "topotet-mpi: warning: %s: --tets-only: left out %s; the output mesh covers the tets only\n",
               path.c_str(), what.c_str());
}

// A file checked by the mesh builder (its errors name the file and element), with the listed
// elements the builder leaves out dropped, so that the checker later compares like with like.
MeshData read_checked(const std::string& path, ReadOptions options, ReadNotes* notes) {  // notes: never null
  options.keep_partitions = true;
  MeshData data = read_mesh_file(path, options, notes);  // with the VTK formats when built
  warn_about_left_out_cells(path, *notes);
  BuildOptions build;
  build.skip_detached_substructures = true;
  BuildNotes built;
  try {
    (void)build_tet_mesh(data, build, &built);
  } catch (const InputError& e) {
    const std::string what = e.what();
    throw InputError(what.rfind(path, 0) == 0 ? what : path + ": " + what);
  }
  drop_noted_substructures(data, built);
  return data;
}

// The cell arrays of a file that no output will carry, said once (rank 0 or the reading rank).
void warn_cells_not_carried(const std::string& path, const MeshData& data, const char* why) {
  if (data.cell_fields.empty()) return;
  std::fprintf(stderr, "topotet-mpi: warning: %s: %zu cell array%s not carried: %s\n", path.c_str(),
               data.cell_fields.size(), data.cell_fields.size() == 1 ? " is" : "s are", why);
}

// What the remap on rank 0 needs of the whole input (topotet/cell_fields.h), taken from it once
// the ranks' parts are cut from it, the kinds applied before the passes so that a wrong
// --extensive / --categorical name stops the run on every rank (agree).
MeshData cell_source_of(MeshData&& whole, const CellRemapOptions& carry) {
  MeshData source;
  source.cell_fields = std::move(whole.cell_fields);
  apply_cell_kinds(source.cell_fields, carry);  // throws for a name the input lacks
  if (source.cell_fields.empty()) return source;
  source.positions = std::move(whole.positions);
  source.tets = std::move(whole.tets);
  source.tet_material = std::move(whole.tet_material);
  return source;
}

std::string split_name(const std::string& path, int part) {
  std::string stem = path;
  if (stem.size() > 4 && stem.compare(stem.size() - 4, 4, ".msh") == 0) stem.resize(stem.size() - 4);
  return stem + "_" + std::to_string(part) + ".msh";
}

std::string partitions_error(const std::string& path, std::uint64_t partitions, int ranks) {
  return path + ": partitioned in " + std::to_string(partitions) + " parts (gmsh -part " + std::to_string(partitions) +
         "), but " + std::to_string(ranks) + " ranks run: run as many ranks as parts (mpirun -np " +
         std::to_string(partitions) + ")";
}

}  // namespace

Input read_input(MPI_Comm comm, const std::string& path, std::int32_t metis_seed, const ReadOptions& options,
                 const CellRemapOptions* carry_cells) {
  const int me = rank_of(comm), ranks = size_of(comm);
  Input in;
  // Rank 0 decides which form IN is, so that every rank takes the same branch.
  int kind = 0;
  if (me == 0 && !std::filesystem::exists(path) && std::filesystem::exists(split_name(path, 1))) kind = 1;
  MPI_Bcast(&kind, 1, MPI_INT, 0, comm);
  std::string error;
  if (kind == 1) {
    in.kind = InputKind::kGmshSplit;
    const std::string mine = split_name(path, me + 1);
    try {
      ReadNotes notes;
      MeshData d = read_checked(mine, options, &notes);
      if (me == 0)  // every part holds the same arrays: one line for the run
        warn_cells_not_carried(mine, d, "each rank reads one part of a split mesh, and the remap needs every input tet "
                               "an output tet overlaps: give the whole mesh (one file) and a gathered output");
      if (notes.partitions == 0) throw InputError(mine + ": not a partitioned Gmsh 4.1 file (no $PartitionedEntities)");
      if (notes.partitions != static_cast<std::uint64_t>(ranks)) throw InputError(partitions_error(mine, notes.partitions, ranks));
      in.part.global_ids.assign(notes.node_tags.begin(), notes.node_tags.end());
      in.part.local = std::move(d);
    } catch (const std::exception& e) {
      error = e.what();
    }
    agree(comm, error);
    // Every tet stays: the migration to itself keeps only the vertices of the part's tets (a part
    // file may list others), agrees the field layout and finds the owners.
    topotet::mpi::distribute_to(comm, in.part, std::vector<int>(in.part.local.tet_count(), me));
  } else {
    std::vector<int> dest;
    if (me == 0) {
      try {
        ReadNotes notes;
        MeshData d = read_checked(path, options, &notes);
        if (!carry_cells)
          warn_cells_not_carried(path, d, "with --partitioned each rank writes its piece, and the remap needs every input "
                                 "tet an output tet overlaps: leave out --partitioned to carry them");
        if (notes.partitions != 0) {
          if (notes.partitions != static_cast<std::uint64_t>(ranks)) throw InputError(partitions_error(path, notes.partitions, ranks));
          std::vector<std::uint8_t> seen(static_cast<std::size_t>(ranks), 0);
          for (std::size_t t = 0; t < notes.tet_partition.size(); ++t) {
            const std::int32_t p = notes.tet_partition[t];
            if (p < 1 || p > ranks)
              throw InputError(path + ": tetrahedron " + std::to_string(t + 1) + " is on no partition 1.." + std::to_string(ranks));
            dest.push_back(p - 1);
            seen[static_cast<std::size_t>(p - 1)] = 1;
          }
          // One piece of a split mesh (gmsh -part_split) says N partitions but holds one.
          const auto missing = std::find(seen.begin(), seen.end(), 0);
          if (missing != seen.end())
            throw InputError(path + ": partition " + std::to_string(missing - seen.begin() + 1) + " of " +
                             std::to_string(ranks) + " has no tets here: for the parts of gmsh -part_split, name the "
                             "mesh without its _<part> suffix");
        }
        in.part = topotet::mpi::from_whole(d);
        if (carry_cells) in.cell_source = cell_source_of(std::move(d), *carry_cells);  // d's last use
      } catch (const std::exception& e) {
        error = e.what();
      }
    }
    agree(comm, error);
    int partitioned = dest.empty() ? 0 : 1;
    MPI_Bcast(&partitioned, 1, MPI_INT, 0, comm);
    if (partitioned) {
      in.kind = InputKind::kGmshPartitioned;
      topotet::mpi::distribute_to(comm, in.part, dest);
    } else {
      topotet::mpi::distribute(comm, in.part, metis_seed);
    }
  }
  std::uint64_t local = in.part.local.tet_count();
  MPI_Allreduce(&local, &in.tets, 1, MPI_UINT64_T, MPI_SUM, comm);
  return in;
}

}  // namespace topotet::cli::mpi
