// Flips where the collapses stall (issue #23): when no legal collapse is left before the target,
// the driver retriangulates the bad tets the collapses made (the flips of optimize/swap.h) and the
// engine looks at every edge again, before it relaxes any limit (relax_limits.h).
//
// Why. Where a run stalls, most of the vertices left are often held by inverted tets: every
// placement that removes them folds a tet of their star (a junction curve's vertex must merge into
// the grain corner next to it, and the corner stays). A flip changes that star without moving a
// vertex. Measured on the generated polycrystal (200k tets, 2%): a run that stopped at 813
// vertices, 43% of them held by inversion, simplified again after the optimisation's flips
// reached its target (720) where the same mesh without them stopped at 812.
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
