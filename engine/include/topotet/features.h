// Sharp features found by angle (like Mmg's -ar and CGAL's detect_features), so that the
// simplifier keeps the corners and edges of a shape as it keeps listed polylines and corners.
//
//   topotet::TetMesh mesh = topotet::build_tet_mesh(data);
//   topotet::FeatureStats found = topotet::detect_features(mesh, 45.0);
//
// simplify() calls it itself (SimplifyOptions::feature_angle); `info` and `convert` call it to
// show what would be kept.
#pragma once

#include <cstdint>

#include "topotet/tet_mesh.h"

namespace topotet {

struct FeatureStats {
  std::uint64_t edges = 0;    // edges flagged as feature curves by this call
  std::uint64_t corners = 0;  // vertices pinned by this call
};

// On every surface of the substructure filtration (boundary, material interfaces, listed
// triangles; a surface is the set of special faces of one label: ref and material pair), an edge
// whose two faces of that surface turn by more than `angle_degrees` (the angle between the two
// face normals; 0 for a flat surface, 90 on a box edge) becomes a feature curve: it is flagged
// as a polyline edge with ref kFeatureCurveRef, so the link conditions keep its topology and the
// cost model keeps its vertices on it. Edges already on a listed polyline, with one or three or
// more special faces, or between two labels are curves of the filtration already and are left
// alone. Then every vertex of a new feature curve that is not an inner point of one curve (a
// curve end, a junction of three or more curves, a point where a feature meets a listed polyline
// or a seam) is pinned (vertex_state::kPinned | kFeatureCorner): it keeps its exact position.
// angle_degrees >= 180 finds nothing. Deterministic; runs in the caller's task arena. The flags
// and pins stay on the mesh: a later simplify() of the same TetMesh keeps these features too
// (and detects again on the simplified surfaces), and to_mesh_data omits them unless asked.
FeatureStats detect_features(TetMesh& mesh, double angle_degrees);

}  // namespace topotet
