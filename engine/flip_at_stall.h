// Flips where the collapses stall (issue #23): when no legal collapse is left before the target
// and the stop census says inverted tets hold the most of the vertices left (at least as many as
// any limit an option sets: relax_limits.h), the driver retriangulates the bad tets the collapses
// made (the flips of optimize/swap.h) and the engine looks at every edge again, rather than relax
// a limit. Again at the next such stall if collapses went through since.
//
// Why. Where a run stalls, the vertices left are often held by inverted tets: every placement
// that removes them folds a tet of their star (a junction curve's vertex must merge into the
// grain corner next to it, and the corner stays). A flip changes that star without moving a
// vertex. Measured on the generated polycrystal (200k tets, 2%): it stopped at 813 vertices, 43%
// of them held by inversion, after relaxing H to 12.8% of the diagonal and the dihedral floor to
// 0.078 degrees; with these flips it reaches its target (719) with H at 3.2% and the floor at 2.5
// degrees, in the same time. Flipping at every stall first instead (whatever held it) took
// 1.3-1.6x as long on the runs that relax anyway (cube-sphere, linked tori, the CGAL
// segmentation), for the same H on most: each flip is followed by a look at every edge, and the
// edges the flips free are few when inversion does not hold the run.
//
// Why every guarantee holds. A flip keeps every face and edge on a substructure, the boundary and
// every material region as point sets, moves no vertex, and only lifts the worst tet of its region
// (swap.h); the coverage of the original surfaces moves with the faces that hold it
// (SurfaceCoverage::detach / attach). So the topology, the tolerance, the quality floors and the
// field guard of the flips hold as after the collapses. The collapses that follow are checked by
// the kernel as any other.
#pragma once

#include "guarantees/surface_coverage.h"
#include "mesh/mesh_model.h"
#include "optimize/input_samples.h"
#include "topotet/simplify.h"

namespace topotet::detail {

// Flips the bad tets of `mesh` (those the collapses made below a mean ratio of 0.4, worst first:
// swap_bad_tets with the optimisation's light settings and the dihedral floor in force,
// report.min_dihedral_used), compacting its tets, and moves the coverage's items to the faces that
// now hold them. `samples` (may be null): the input's vertices, the flips' field guard (indexed
// here). Adds the flips to report.stall_flips and their time to report.stall_flip_seconds.
// Returns true when a flip was made (the engine then looks at every edge again).
// Not with field error bounds (kept per tet) or a collapse log (a hierarchy's levels are collapse
// sequences): the driver does not ask then.
bool flip_at_stall(MeshModel& mesh, SurfaceCoverage* coverage, InputSamples* samples, Report& report);

}  // namespace topotet::detail
