// Sharp features found by angle at the scale of the tolerance (like Mmg's -ar and CGAL's
// detect_features, judged at a scale as issue #23 asks), so that the simplifier keeps the corners
// and edges of a shape as it keeps listed polylines and corners.
//
//   topotet::TetMesh mesh = topotet::build_tet_mesh(data);
//   topotet::FeatureStats found =
//       topotet::detect_features(mesh, 45.0, topotet::feature_scale(mesh, topotet::SimplifyOptions{}));
//
// simplify() calls it itself (SimplifyOptions::feature_angle, at the scale of its tolerance);
// `info` and `convert` call it to show what would be kept.
#pragma once

#include <cstdint>

#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"

namespace topotet {

struct FeatureStats {
  std::uint64_t candidates = 0;  // creases sharper than the angle (before the scale test)
  std::uint64_t edges = 0;       // edges flagged as feature curves by this call
  std::uint64_t corners = 0;     // vertices pinned by this call (turns included)
  std::uint64_t turns = 0;       // of which inner curve points where the curve turns sharply
};

// On every surface of the substructure filtration (boundary, material interfaces, listed
// triangles; a surface is the set of special faces of one label: ref and material pair), an edge
// whose two faces of that surface turn by more than `angle_degrees` (the angle between the two
// face normals; 0 for a flat surface, 90 on a box edge) is a crease. With `scale` H > 0 a crease
// counts only when it is a feature at that scale: the surface within a geodesic disk of radius 4H
// around it departs from its best-fitting plane by more than H/2 at the crease (a step lower than
// H, such as a voxel staircase, does not count; a 45-degree crease whose faces reach a few H on
// both sides does; engine/features.cpp says why). Each crease that counts becomes a feature curve:
// it is flagged as a polyline edge with ref kFeatureCurveRef, so the link conditions keep its
// topology and the cost model keeps its vertices on it (an inner curve point slides along its
// curve: placements at an end or the midpoint of a curve edge). Edges already on a listed
// polyline, with one or three or more special faces, or between two labels are curves of the
// filtration already and are left alone. Then the corners are pinned (vertex_state::kPinned |
// kFeatureCorner: they keep their exact position): every vertex of a new feature curve that is
// not an inner point of one curve (a curve end, a junction of three or more curves, a point where
// a feature meets a listed polyline or a seam), and every inner point where the curve turns by
// more than `angle_degrees` between its chords to the curve points at distance H on either side
// (the next curve vertices when H = 0). angle_degrees >= 180 finds nothing; scale 0 judges by the
// angle alone. Deterministic; runs in the caller's task arena. The flags and pins stay on the
// mesh: a later simplify() of the same TetMesh keeps these features too (and detects again on the
// simplified surfaces), and to_mesh_data omits them unless asked.
FeatureStats detect_features(TetMesh& mesh, double angle_degrees, double scale);
// The angle alone (scale 0).
FeatureStats detect_features(TetMesh& mesh, double angle_degrees);

// The scale simplify() judges features at with these options: its tolerance H (tolerance, else
// tolerance_rel x the bounding box diagonal of the live vertices) or, when the tolerance is off,
// kDefaultToleranceRel x the diagonal (the features keep their meaning without the tolerance).
double feature_scale(const TetMesh& mesh, const SimplifyOptions& options);

}  // namespace topotet
