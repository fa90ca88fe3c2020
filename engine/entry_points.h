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

}  // namespace topotet
