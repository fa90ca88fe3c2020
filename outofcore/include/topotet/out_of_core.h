// Out-of-core simplification (paper 002; issue #25): a mesh larger than the memory it may use is
// streamed from its file, cut into spatial pieces kept in a scratch folder, each piece simplified
// with its border frozen, and neighbouring pieces merged pairwise, level by level, so that their
// former borders are simplified in turn, until one piece is left or the limit forbids a merge;
// then the borders between the pieces left are simplified in seams (outofcore/seams.h: a band on
// each side of a border, made one piece).
// Only one piece (or one merged pair) is in memory at a time; the output is written from the
// pieces. `topotet simplify IN -o OUT --memory-limit 2G` runs it.
//
// What an in-core run guarantees still holds, piece by piece and so for the whole:
//   - topology of the mesh and of every substructure: every collapse is made in a piece whose
//     border vertices are frozen (no collapse touches them, not even as the end that stays), so
//     the star of both ends is inside the piece and the piece's link conditions are the whole
//     mesh's (the argument topotet::mpi rests on, topotet/mpi.h);
//   - the geometric tolerance H: level l of the hierarchy is given its own tolerance h_l, checked
//     against the surfaces as that level received them, with h_0 + h_1 + ... + h_L = H, so by the
//     triangle inequality every point of the output's surfaces is within H of the input's of its
//     label and the other way round (h_0 = H / 2, the rest shared equally by the merge levels);
//   - quality floors (min_quality, min_dihedral: relative to the tets replaced, as in core);
//   - the limits that relax (relax_tolerance, relax_quality, relax_features): they hold as given
//     while the mesh is in pieces (floors and features would differ from piece to piece); the
//     last level's run, when it holds the whole mesh, relaxes them as in core, its share h_L of H
//     doubling (Report::tolerance is then the sum of the levels' shares, Report::relaxations
//     says which limit and from what, as H); a run left in pieces by its memory limit does not;
//   - determinism: the pieces depend on the input, the limit and the process's resident size at
//     the start rounded up to 64 MiB (outofcore/memory_budget.h), never on timing, and each
//     piece's run is the parallel engine's, identical for every thread count;
//   - the vertex map (vertex_map_path below): each piece's run records the vertices it merged, in
//     global ids, on disk; the chains are followed to the output at the end (vertex_map_log.h);
//   - field error bounds (max_field_error*, track_field_bounds): every input vertex is a sample of
//     one piece and travels with its tet through the levels (SimplifyOptions::field_samples), so
//     the bound holds at every input vertex as in core; the last merge holds every sample, which
//     the memory budget counts (outofcore/memory_budget.h).
// The levels share the work (level l keeps a fraction of its pieces' vertices that halves from
// level to level, so that a merged pair still fits; the last piece goes to the target), and each
// vertex's quadric travels with its piece (SimplifyOptions::quadrics_in/_out), so every level ranks
// collapses by their error against the input, as one run would: on the cube-sphere the field
// error is an in-core run's (docs/performance.md, "Out of core").
//   - the hierarchy file (hierarchy_path below): each piece's run records its collapses with their
//     dependencies, continuing the run's ids across pieces and levels (outofcore/hierarchy_spool.h);
//     the file is the one an in-core run writes, its original the input as read.
// Not available out of core (refused with kInvalidInput-like InputError): isosurfaces (embed them
// in core first).
//
// Memory. The pieces' size comes from the limit by a model of bytes per tet and per vertex
// (outofcore/memory_budget.h); a limit below what the model needs for this input is refused before
// any work, with the limit that would do. The report gives the measured peak (VmHWM).
//
// Input: MEDIT .mesh / .meshb (ASCII or binary; + .sol / .solb), optionally .gz, or Gmsh MSH 4.1 .msh / .msh.gz with its fields ($NodeData, $ElementData), streamed
// (topotet/mesh_stream.h). Output: any format when the
// pieces merged into one (it is then in memory and goes through write_mesh); MEDIT .mesh written
// from the pieces, streaming, when the limit stopped the merges before (then the borders between
// the remaining pieces were simplified in seams; those no seam fits kept their vertices).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "topotet/cell_fields.h"
#include "topotet/simplify.h"

namespace topotet {

struct OutOfCoreOptions {
  std::uint64_t memory_limit_bytes = 0;  // > 0: the peak resident memory to stay under
  std::string scratch_parent;            // where the scratch folder goes; empty = the output's folder
  // Cut into exactly this many pieces (a power of two, <= 4096) whatever the limit (tests,
  // benchmarks); 0 = from the limit.
  std::uint32_t pieces = 0;
  // At most this many tets a piece, at the cut and in every merge, whatever the limit allows
  // (tests, benchmarks: the merges a small limit forbids, on a small mesh); 0 = from the limit.
  std::uint64_t piece_tets = 0;
  std::function<void(const std::string&)> log;  // one line per step; may be empty
  // How cell fields are carried (topotet/cell_fields.h: extensive sums conserved, categorical
  // labels by largest overlap, the rest volume-averaged), remapped piece by piece at every level.
  CellRemapOptions cell_remap;
  // Non-empty: write the vertex map there (topotet/vertex_map_file.h: .npy or .txt), for every
  // input vertex the output vertex it became or merged into, as simplify()'s vertex map gives it
  // in core. Kept on disk during the run (8 bytes an input vertex in the scratch folder).
  std::string vertex_map_path;
  // Non-empty: write the collapse hierarchy there (.tth, topotet/hierarchy.h: `topotet extract`
  // reads it), recorded as an in-core simplify_with_hierarchy would: its original is the input as
  // read (without group names), every collapse of every piece and level with its parents. Kept
  // on disk during the run (the original and ~127 + 16k bytes a collapse, k vertex field
  // components); a piece's records go to disk in batches, which the memory budget counts. As in
  // core, excludes the vertex map and disables the optimisation after the collapses. With vertex
  // fields, set SimplifyOptions::track_field_bounds to record each collapse's field error bound.
  std::string hierarchy_path;
};

struct OutOfCoreLevel {
  std::uint32_t pieces = 0;             // pieces simplified at this level
  std::uint32_t unmerged = 0;           // pairs left apart because together they would not fit
  // At the last level, when pieces are left apart: seams cut between neighbours (their common
  // border simplified in a piece of its own: outofcore/seams.h), and neighbours left without one
  // (their bands would not fit in a piece, or would freeze more vertices than the seam frees).
  std::uint32_t seams = 0, seams_declined = 0;
  std::uint64_t largest_piece_tets = 0;  // tets of the largest piece simplified
  std::uint64_t vertices_after = 0;      // of the whole mesh
  std::uint64_t collapses = 0;
  double tolerance = 0.0;  // h_l
  double seconds = 0.0;
};

struct OutOfCoreReport {
  Report report;  // counts summed over the pieces' runs; status, message, tolerance H, seconds;
                  // with field bounds: field_bound(_rel) over the output's tets (not per tet)
  std::uint32_t pieces = 0;            // after the cut
  std::uint32_t output_pieces = 0;     // left at the end (1 unless the limit stopped the merges)
  std::uint64_t piece_tet_limit = 0;   // the model's largest piece
  std::vector<OutOfCoreLevel> levels;  // level 0 = the cut's pieces
  std::uint64_t peak_rss_bytes = 0;    // VmHWM at the end
  std::uint64_t scratch_peak_bytes = 0;
  double cut_seconds = 0.0, write_seconds = 0.0;
  // With a hierarchy file: its collapses and bytes, and the time to assemble it at the end.
  std::uint64_t hierarchy_collapses = 0, hierarchy_bytes = 0;
  double hierarchy_write_seconds = 0.0;
};

// Throws InputError for bad input, a limit too small, an option not available out of core, or a
// scratch folder that fills up (the message names it). The output appears only when complete.
OutOfCoreReport simplify_out_of_core(const std::string& input, const std::string& output,
                                     const SimplifyOptions& options, const OutOfCoreOptions& ooc);

// Async-signal-safe: removes the scratch folders of runs in progress (topotet's SIGINT handler).
void remove_out_of_core_scratch() noexcept;

// "2G", "256M", "512k", "1.5G", "1073741824" (bytes; binary units); throws InputError otherwise.
std::uint64_t parse_memory_size(const std::string& text);

}  // namespace topotet
