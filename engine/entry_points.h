// The entry points of the public API on the engine's MeshModel itself: the TetMesh overloads
// (topotet/simplify.h, topotet/hierarchy.h; detect_features: features/features.h) unwrap the handle and call these,
// and so do the in-tree callers that hold a model (the C API, Python, MPI, tests, benches).
// They live here, on the drivers' floor, not in mesh/mesh_model.h: the model knows nothing of the
// engines that run on it.
#pragma once

#include <vector>

#include "features/features.h"
#include "mesh/mesh_model.h"
#include "topotet/hierarchy.h"
#include "topotet/simplify.h"

namespace topotet {

Report simplify(MeshModel& mesh, const SimplifyOptions& options = {}) noexcept;
Report simplify(MeshModel& mesh, const SimplifyOptions& options, std::vector<VertId>& vertex_map) noexcept;
Report simplify_with_hierarchy(MeshModel& mesh, const SimplifyOptions& options, Hierarchy& hierarchy) noexcept;

// Adds the work of one part's run to a run made of parts (topotet::mpi's passes and ranks, the
// levels and pieces out of core): collapses, evaluations, checks, refusals, rounds, features, the
// largest cost, phase times; tolerance_limited if any part was.
void add_run_counts(Report& total, const Report& part);

}  // namespace topotet
