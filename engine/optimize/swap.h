// Face and edge swaps after the collapses (issue #26): the 2-3 flip (two tets sharing a face become
// three around the edge joining their apexes) and edge removal (the n <= 7 tets around an edge
// become the 2n - 4 tets that join the best triangulation of its ring to the edge's two ends; n = 3
// is the 3-2 flip), taken where they lift the worst tet of the affected region.
//
// Why every guarantee holds. A flip retriangulates a region without moving a vertex: the union
// of its tets is the same point set before and after. Flips are made only inside one material and
// never remove a face or an edge that lies on a substructure: the face a 2-3 flip removes, and the
// edge and the n faces an edge removal removes, must be unflagged (no listed surface, no interface,
// no polyline or feature curve). Every flagged face and edge of the region is a face or an edge of
// the new tets, with its flags and refs (found by its vertices, as collapse.cpp recomputes them).
// So the mesh, its boundary, every material region and every substructure are the same complexes
// up to subdivision of the unflagged interior: their topology and their geometry (the tolerance)
// are unchanged, and no vertex moves, so the fields are untouched at the vertices; between them the
// interpolated field changes, by at most SwapOptions::max_field_change of its range, and at the
// input's vertices inside the region its squared error grows by max_sample_error_growth at most
// (optimize/input_samples.h). A flip is made
// only when its new tets are certainly positive (orient3d_sign, robust) and their worst mean ratio
// beats the old tets' worst: the worst tet of the mesh never gets worse.
//
// Which tets. Only those the collapses made or moved (a vertex of theirs is reshaped: it survived a
// collapse or was moved by the smoothing; a flip reshapes its region's vertices): a tet of the
// input that the collapses left alone stays as the user's mesher made it. On LOX at 50%, whose
// input has 43% of its tets under 10 degrees, flipping those too took 4.7 s after 1.4 s of
// collapses and multiplied the field RMS by 5.5 (0.00031 -> 0.00173); the reshaped tets alone:
// see docs/performance.md, "Quality after the collapses".
//
// Order and determinism. The tets below the target are taken worst first from a heap keyed by
// (quality, tet id); the tets a flip makes join it when they are below the target too, and each
// vertex's star is kept exact through every flip (a table of its own: the mesh's incidence has no
// room for a star that grows), so flips chain next to each other. A tet that found no flip is
// looked at again in the next pass, if a flip touched one of its vertices; the passes end when one
// makes no flip. The heap's next 64 tets are searched for their best flip in parallel (a search
// only reads; it is ~90% of the time, the field's test at the input's vertices) and their flips
// applied in heap order; a tet a flip of the same batch touched is searched again on the changed
// mesh, and a flip's new bad tets wait for the next batch. Every search is a pure function of the
// mesh, so the result is the same for every thread count. It runs on the mesh the collapses left
// (a tenth of the input or less, dead tets dropped first): on the 1M-tet slab at 10%, ~13k flips,
// 0.92 s sequential, with the search on 2 threads about half of that.
//
// Not done here: field error bounds are kept per tet (guarantees/field_bounds.h) and a flip
// would have to re-locate their samples; the driver does not flip when they are on.
#pragma once

#include <cstdint>

#include "mesh/dihedral.h"
#include "mesh/mesh_model.h"
#include "optimize/input_samples.h"

namespace topotet {

struct SwapOptions {
  double target_quality = 0.4;  // tets below this mean ratio are the ones flips try to remove
  // Later passes find few flips: LOX at 50%, 44k, 12k, 5k, 2.3k, 1.2k... in 210k, 157k, 129k,
  // 98k, 62k evaluations; the families at 10% lose 0-1 tets under 10 degrees with 3 against 8.
  int max_passes = 3;
  // A flip changes the piecewise-linear field inside its region (the vertices keep their values).
  // Two guards (swap.cpp, field_kept). At the input's vertices inside the region (recorded before
  // the collapses: optimize/input_samples.h; where the output's field error is measured), the sum
  // of squared errors may grow by this fraction at most: 1 = it may double. Measured at 10% of the
  // vertices (cube-sphere, slab 100k: field RMS and tets under 10 degrees; LOX at 30%: RMS): 0 keeps
  // every RMS at or below the collapses' (0.0124, 0.0096; LOX 0.00085 for 0.00089) but leaves 329 /
  // 447 slivers; 1: 0.0134 / 0.0104, 142 / 303 (with the smoothing's at 1 too), LOX 0.00091;
  // 4: 120 / 262 slivers, LOX 0.00122. Regions overlap and a flip's tets can flip again, so this
  // bounds each step, not the run: measured, +1-3% RMS over the collapses alone.
  double max_sample_error_growth = 1.0;
  // And everywhere in the region the change is at most this fraction of the component's range
  // (at the points where the old and new tets differ most), which bounds it where no input vertex
  // is left to tell. Thin tets aligned with a steep field are what represents it: with this bound
  // alone (0.03; 0.1 was +34% on LOX at 2%), the flips tripled LOX's field RMS at 30%.
  double max_field_change = 0.03;
  // A flip may not make its region's smallest dihedral angle fall below min(floor, the smallest it
  // had) (SimplifyOptions::min_dihedral, as for the collapses).
  DihedralFloor dihedral_floor;
};

struct SwapStats {
  std::uint64_t flips_23 = 0, edge_removals = 0;  // edge removals: n -> 2n - 4 tets, 3-2 flips included
  int passes = 0;
};

// Drops the dead tets first and at the end (compact_tets: tet ids change, vertex ids do not).
// `samples` (recorded before the collapses; may be null): a flip must not make the field worse
// at the input's vertices inside its region (max_sample_error_growth).
SwapStats swap_bad_tets(MeshModel& mesh, const SwapOptions& options, const InputSamples* samples = nullptr);

}  // namespace topotet
