// detect_features on the engine's model (the TetMesh overload in topotet/features.h unwraps the
// handle and calls this; simplify() calls it for SimplifyOptions::feature_angle).
#pragma once

#include <cstdint>
#include <vector>

#include "mesh/mesh_model.h"
#include "topotet/features.h"
#include "topotet/simplify.h"

namespace topotet {

FeatureStats detect_features(MeshModel& mesh, double angle_degrees);
FeatureStats detect_features(MeshModel& mesh, double angle_degrees, double scale);
// The same, told which vertices are on a special face (SpecialFaces::on_face): the others are
// skipped without a look at their stars; and the surfaces with a ref in skip_refs are not searched
// for creases (simplify() passes the isosurfaces': their creases are those of the piecewise-linear
// interpolation of the field on the input mesh, not a shape to keep, and pinning their corners
// held the simplification back; the tolerance keeps them within H like every surface).
FeatureStats detect_features(MeshModel& mesh, double angle_degrees, double scale,
                             const std::vector<std::uint8_t>* on_special_face,
                             const std::vector<std::int32_t>& skip_refs = {});
double feature_scale(const MeshModel& mesh, const SimplifyOptions& options);

// Judges the feature curves of the mesh as it is now at larger scales (a run that relaxes its
// tolerance: SimplifyOptions::relax_features) by detect_features' test (high and sharp, continued
// straight on) on the simplified surfaces, which are within the tolerance of the original, at each
// of `scales` in turn; at the first where some fail (FeatureDrop::scale), those edges stop being
// polyline edges and the feature corners no kept edge touches are unpinned (vertices also listed
// as corners or required stay pinned). None fails at any: the mesh is left as it is. A box edge stays
// a feature at any scale its faces hold a disk of; a staircase of steps lower than `scale` does
// not. The caller drops what else knew the curves: the cost model's orders, the coverage's segments.
struct FeatureDrop {
  std::uint64_t edges_before = 0, edges_after = 0, unpinned = 0;
  double scale = 0.0;  // the scale that dropped them; 0 = none did
};
FeatureDrop drop_features_below(MeshModel& mesh, double angle_degrees, const std::vector<double>& scales);

}  // namespace topotet
