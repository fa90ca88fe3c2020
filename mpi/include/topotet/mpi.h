// Distributed simplification over MPI: the mesh stays where a simulation spread it, each rank
// simplifies its part with the existing parallel engine (hybrid MPI + oneTBB), and the partition
// moves so that what was frozen at a border is simplified in a later pass (paper 002's segments
// with frozen borders, ParMmg's displaced interfaces).
//
//   topotet::mpi::DistributedMesh part = ...;        // this rank's tets, with global vertex ids
//   topotet::mpi::Options options;
//   options.simplify.target_vertex_ratio = 0.1;      // of the GLOBAL vertex count
//   topotet::mpi::Result r = topotet::mpi::simplify(MPI_COMM_WORLD, part, options);
//   // part: this rank's share of the simplified mesh; r.vertex_map: for each vertex of `part` as
//   // passed, the global id it became or merged into; r.report: the same on every rank.
//
// The algorithm, each pass:
//   1. find the vertices this rank shares with another (a directory of global ids, hashed over
//      the ranks); they are FROZEN (vertex_state::kFrozen): no collapse touches them, so every
//      collapse left has the whole stars of both ends on this rank and the local decision is the
//      global one (a partition face has three shared vertices, so it is never seen as boundary);
//   2. simplify locally towards this rank's share of the global target (the pass's share: in
//      pass 1 every vertex's fair share, later the rest), split over the ranks so that they stop
//      at about the same cost (Options::shares_by_cost), costs in the whole mesh's units;
//   3. repartition the coarse mesh with METIS (the dual graph is gathered on rank 0: 33 bytes per
//      coarse tet there), faces near still-unsimplified former borders weighted so that the new
//      cut avoids them, parts matched to ranks by overlap, and migrate the tets (with their
//      vertices, materials, listed triangles and segments, pins and fields).
// Until the global target is reached, a pass removes nothing, or max_passes. Where the run would
// stop before its target (a pass removes nothing, max_passes, or every part stopped short of its
// share), the limits the options let relax (relax_tolerance, relax_quality) relax as in one
// process, by the same rule on the census of the whole mesh (the sum of the parts'): H doubled or
// the floors halved, for every rank alike, recorded in Report::relaxations; max_passes then counts
// again. The feature curves are not dropped over MPI (each pass's parts find their own).
//
// Every call is collective over `comm`. The output is identical from run to run for a fixed rank
// count and any thread count per rank. Errors (bad input, out of memory) throw std::runtime_error
// on the rank that found them after being agreed on every rank (all ranks throw together).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <mpi.h>

#include "topotet/mesh_data.h"
#include "topotet/simplify.h"

namespace topotet::mpi {

using GlobalId = std::uint64_t;

// One rank's part: a MeshData over LOCAL vertex indices (the vertices of its tets only) plus
// their global ids. `local.triangles` / `local.segments` are the listed faces / edges of its
// tets (a face or edge on a partition border may be listed on both sides; they are merged by
// global ids). Each must be listed on at least one rank whose tets have it: elsewhere it is
// ignored (a code may list it on every rank holding its vertices). Corners and required vertices are listed by every rank holding them. Field
// layouts (names, components) must be the same on every rank that has tets.
struct DistributedMesh {
  MeshData local;
  std::vector<GlobalId> global_ids;  // [local vertex], unique over the mesh
  // [local vertex] the rank that owns the vertex: the lowest rank holding it. Filled by simplify
  // and distribute (input values are not read; gather finds the owners itself).
  std::vector<int> owner;
};

struct Options {
  SimplifyOptions simplify;  // targets are global; tolerance_rel is of the global bounding box
  int max_passes = 8;
  // true: passes after the first remove only vertices that were frozen on a border in an
  // earlier pass (the others are pinned: they may absorb a collapse but neither move nor go), as
  // paper 002 simplifies its segments' borders in a second pass; should such a pass fall short of
  // half its share, the following ones are unrestricted. Off by default: measured worse (cube-
  // sphere 200k to 10%, 4 ranks: field RMS 0.98% vs 0.92%, dihedral spread 37.3 vs 36.8 deg):
  // pinned neighbours take the optimal placements away from the border vertices.
  bool later_passes_on_former_borders = false;
  std::int32_t metis_seed = 1;  // METIS_OPTION_SEED: fixed, so that partitions repeat
  // true: a pass's share is split over the ranks by cost, not by vertex count: each rank first
  // runs the pass as a trial (up to 1.5 times its count share), and the ranks then remove what
  // their trials removed below one common cost, as the shared-memory engine's global cost order
  // would (mpi/cost_shares.h). Costs are always in the whole mesh's units. Needs the parallel
  // engine and two ranks (else shares are by count). Costs about one more local simplification
  // per pass. Measured (cube-sphere 200k to 10%, field RMS against the shared-memory engine: +8.7%
  // at 4 ranks, +14.9% by count): docs/mpi.md.
  bool shares_by_cost = true;
};

// What one pass did, over all ranks.
struct PassStats {
  double seconds = 0.0;           // wall time of the pass (slowest rank)
  double simplify_seconds = 0.0;  // local simplification, slowest rank
  double trial_seconds = 0.0;      // shares_by_cost's trial runs (part of simplify_seconds), slowest rank
  double partition_seconds = 0.0;  // graph gather + METIS + migration, slowest rank
  std::uint64_t vertices_after = 0;   // global live vertices after the pass
  std::uint64_t collapses = 0;
  std::uint64_t frozen_vertices = 0;  // shared (frozen) vertex copies during the pass
  std::uint64_t migrated_tets = 0;    // tets that changed rank after the pass
  std::uint64_t bytes_sent = 0;       // migration + graph + directory traffic, all ranks
};

struct Result {
  Report report;  // reduced over ranks: counts summed, seconds the slowest rank's
  std::vector<PassStats> passes;
  // [vertex of the DistributedMesh as passed] the global id of the output vertex it became or
  // merged into (a surviving vertex keeps its global id).
  std::vector<GlobalId> vertex_map;
  // [vertex of the output part] 1 if the vertex was frozen on a partition border in some pass:
  // the tets around such vertices are where seams would show (quality reported separately).
  std::vector<std::uint8_t> touched_border;
  std::uint64_t peak_rss_bytes = 0;         // the largest over ranks (VmHWM)
  std::vector<std::uint64_t> peak_rss_per_rank;  // [rank] VmHWM, bytes
};

Result simplify(MPI_Comm comm, DistributedMesh& mesh, const Options& options);

// Partitions a mesh held anywhere (typically all on rank 0, empty elsewhere) into one part per
// rank with METIS (k-way on the dual graph) and moves the tets there. Collective.
void distribute(MPI_Comm comm, DistributedMesh& mesh, std::int32_t metis_seed = 1);

// The same with the parts given: local tet t goes to rank dest[t] (dest.size() == local tets;
// e.g. a partitioned Gmsh file's partitions, read on one rank). Collective.
void distribute_to(MPI_Comm comm, DistributedMesh& mesh, const std::vector<int>& dest);

// A whole MeshData on one rank as a DistributedMesh (global id = index); other ranks pass {}.
DistributedMesh from_whole(const MeshData& whole);

// Gathers the parts on rank `root`: vertices renumbered by increasing global id, tets in rank
// order, listed triangles and segments merged. `global_ids` (root only, may be null) receives the
// global id of each output vertex. Other ranks get an empty MeshData. Collective.
MeshData gather(MPI_Comm comm, const DistributedMesh& mesh, int root = 0, std::vector<GlobalId>* global_ids = nullptr);

// Writes one piece per rank for ParaView: `<stem>.pvtu` (by rank 0) listing `<stem>_<rank>.vtu`
// (each by its rank, beside the .pvtu), so that no rank ever holds the whole mesh. A piece is the
// rank's part as topotet's .vtu writer writes it (materials, fields; listed triangles and segments
// in `<stem>_<rank>_substructures.vtp`) plus a point array "global_id" (Float64, exact up to
// 2^53): a vertex on a partition border is in every piece holding it, with the same global id.
// Ranks without tets write no piece. Every file goes to a temporary name and is renamed, the .pvtu
// last, so a reader never sees a set with missing pieces. `pvtu_path` must end in .pvtu.
// Collective; errors throw std::runtime_error on every rank (the lowest failing rank's message).
void write_partitioned(MPI_Comm comm, const DistributedMesh& mesh, const std::string& pvtu_path);

}  // namespace topotet::mpi
