// Vertex smoothing after the collapses (issue #26): interior vertices of badly shaped stars move to
// where the worst tet of their star is better, so that fewer slivers reach a solver.
//
// Which vertices. *Free* ones: live, not pinned or frozen, every tet of the star of one material,
// no surface face and no polyline edge through the vertex, and not on the boundary (every face
// through it is shared by two tets of its star). Such a vertex lies on no substructure, so moving
// it inside its star (no tet of the star inverts) changes neither the topology of the mesh nor
// that of any substructure, nor any surface: the tolerance proof and the coverage are untouched.
// And vertices *inside a flat sheet*: the faces through the vertex that lie on the boundary or on
// a surface (interface, listed triangle) all carry one label, form one loop around it (a disk),
// with no polyline, feature or seam edge through it, and the vertex and every vertex of that loop
// share one coordinate exactly (an axis plane: box faces, the sheets of CAD and generated meshes).
// Such a vertex moves in that plane only, keeping the coordinate to the last bit. No tet of its
// star inverts, so the disk's triangles keep their orientation in the plane, and a disk with a
// fixed rim and no fold covers the same polygon: every surface, as a point set, stays what it was,
// and so does its label; the combinatorics do not change, so neither does any topology. Flat
// sheets off the axis planes stay where they are (a moved vertex could not stay exactly on them
// in floating point), as do vertices on curved surfaces and curves (constrained moves there would
// have to re-prove the tolerance; not done).
//
// And only near the tets the collapses made or moved (a vertex of theirs is reshaped:
// mesh_model.h): a bad tet of the input that the collapses left alone stays as the input had it,
// with its field (swap.h says what flipping those cost on LOX). A moved vertex is reshaped.
//
// Where to. The move maximises the star's worst (mean ratio)^3 (mesh/moved_corner.h): first the
// centroid of the link (Laplacian) if it is better, then steps along the gradient of the worst tets'
// log quality (the tets within 1% of the worst: the direction that lifts them together), each
// accepted only when the star's worst tet improves and every tet stays certainly positive. So the
// worst quality of the mesh never decreases, and a move never inverts a tet.
//
// Fields. The moved vertex takes the values its own quadric (cost/cost.h, the engine's) likes best
// at the new point, blended with the mesh's field there as a collapse's placement is
// (CostModel::fields_at_point). The quadric placed the vertex where it fits the field, so a move
// is pulled back toward the old point until the quadric's error at the new one is at most 1.2x
// the old (kCostBudget), and until the squared errors at the input's vertices inside the star grow
// by SmoothOptions::max_sample_error_growth at most (the quadric alone let LOX's field RMS grow by
// a third at 30% of the vertices). Unguarded, the moves cost 9-20% of field RMS on the families at
// 10%, guarded 1-4%. Moves that lift the worst tet by less than kMinGain are not proposed.
// With field error bounds (guarantees/field_bounds.h) the move re-locates the samples of the star
// like a collapse without removed tets; under a limit a move that would exceed it is not made.
//
// Determinism. Passes of: evaluate every candidate (read-only, parallel); select the candidates
// whose key (worst quality of the star, vertex id) is the smallest among the candidates they share
// a tet with (two winners never share a tet, so their moves commute); apply the winners
// (parallel, each writes its own vertex and its star's bounds). The next pass evaluates the losers,
// the winners and the winners' neighbours. The selection is the greedy independent set in key
// order, found in parallel sub-rounds. The result is the same for every thread count.
#pragma once

#include <cstdint>

#include "cost/cost.h"
#include "guarantees/field_bounds.h"
#include "mesh/dihedral.h"
#include "mesh/mesh_model.h"
#include "optimize/input_samples.h"

namespace topotet {

struct SmoothOptions {
  // Vertices whose star has a tet below this mean ratio are smoothed (1 = regular tet).
  double target_quality = 0.4;
  // A pass moves only an independent set of the proposals (no two share a tet), about one in six;
  // the next pass re-evaluates the rest. 4 passes: on the families at 10% (100k tets), tets under
  // 10 degrees 1 -> 4 passes: slab 284 -> 251, cube-sphere 137 -> 108, linked tori 227 -> 196,
  // Palace circular_hole 11 -> 7, for +1-2% field RMS; 8 passes gained 0-4% more.
  int max_passes = 4;
  // At the input's vertices inside the star (optimize/input_samples.h), the sum of squared field
  // errors may grow by this fraction at most (1: double), as for the flips (swap.h, where the
  // measurements are); a move is pulled back toward the old point until it holds.
  double max_sample_error_growth = 1.0;
  // A move may not make the star's smallest dihedral angle fall below min(floor, the smallest it
  // had) (SimplifyOptions::min_dihedral, as for the collapses).
  DihedralFloor dihedral_floor;
};

struct SmoothStats {
  std::uint64_t candidates = 0;  // free vertices of bad stars at the start
  std::uint64_t moves = 0;       // moves applied over all passes
  int passes = 0;
};

// Nothing else may touch the mesh during the call; runs in the caller's task arena. `cost` (the
// engine's, built on this mesh) gives a moved vertex its field values and follows it (on_move).
// `samples` (recorded before the collapses; may be null): a move must not make the field worse at
// the input's vertices inside the star.
SmoothStats smooth_vertices(MeshModel& mesh, const SmoothOptions& options, CostModel& cost, FieldBounds* bounds,
                            const InputSamples* samples = nullptr);


// The vertex lies on no substructure and not on the boundary, and may move (see above).
bool is_free_vertex(const MeshModel& mesh, VertId v);

// The axis (0..2) of the flat sheet the vertex lies inside and may move in (see above), or -1.
int flat_sheet_axis(const MeshModel& mesh, VertId v);

}  // namespace topotet
