// detect_features on the engine's model (the TetMesh overload in topotet/features.h unwraps the
// handle and calls this; simplify() calls it for SimplifyOptions::feature_angle).
#pragma once

#include "mesh/mesh_model.h"
#include "topotet/features.h"
#include "topotet/simplify.h"

namespace topotet {

FeatureStats detect_features(MeshModel& mesh, double angle_degrees);
FeatureStats detect_features(MeshModel& mesh, double angle_degrees, double scale);
double feature_scale(const MeshModel& mesh, const SimplifyOptions& options);

}  // namespace topotet
