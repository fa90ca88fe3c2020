// Face and edge swaps after the collapses (issue #26): the 2-3 flip (two tets sharing a face become
// three around the edge joining their apexes) and the 3-2 flip (the three tets around an edge of
// degree three become two sharing the triangle of its ring), taken where they lift the worst tet of
// the affected region.
//
// Why every guarantee holds. A flip retriangulates a region without moving a vertex: the union
// of its tets is the same point set before and after. Flips are made only inside one material and
// never remove a face or an edge that lies on a substructure: the face a 2-3 flip removes, and the
// edge and the three faces a 3-2 flip removes, must be unflagged (no listed surface, no interface,
// no polyline or feature curve). Every flagged face and edge of the region is a face or an edge of
// the new tets, with its flags and refs (found by its vertices, as collapse.cpp recomputes them).
// So the mesh, its boundary, every material region and every substructure are the same complexes
// up to subdivision of the unflagged interior: their topology and their geometry (the tolerance)
// are unchanged, and no vertex moves, so the fields are untouched at the vertices. A flip is made
// only when its new tets are certainly positive (orient3d_sign, robust) and their worst mean ratio
// beats the old tets' worst: the worst tet of the mesh never gets worse.
//
// Determinism. Sequential passes over the tets below the target, worst first (ties by id); a flip
// whose vertices another flip of the pass touched waits for the next pass (their stars are stale
// until the incidence is rebuilt between passes). The result does not depend on threads at all.
// The flips run on the final mesh (a tenth of the input or less), where a pass costs milliseconds.
//
// Not done here: field error bounds are kept per tet (guarantees/field_bounds.h) and a flip
// would have to re-locate their samples; the driver does not flip when they are on.
#pragma once

#include <cstdint>

#include "mesh/mesh_model.h"

namespace topotet {

struct SwapOptions {
  double target_quality = 0.3;  // tets below this mean ratio are the ones flips try to remove
  int max_passes = 4;
};

struct SwapStats {
  std::uint64_t flips_23 = 0, flips_32 = 0;
  int passes = 0;
};

// Dead tets (from 3-2 flips) are left tombstoned, new ones appended: compact() afterwards.
SwapStats swap_bad_tets(MeshModel& mesh, const SwapOptions& options);

}  // namespace topotet
