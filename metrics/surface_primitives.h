// The labelled special faces and polylines of a mesh, private to metrics/ (surface_distance.cpp).
//
// A special face is a boundary face (one tet), a face between two materials, or a listed triangle;
// each appears once. Its label is (listed ref or kSurfaceUnlistedRef, the two materials; a
// boundary face has kSurfaceOutside as the lower one, a listed triangle that is no tet face
// kSurfaceNoMaterial twice). A polyline segment's label is (its ref, kPolylineMarker, 0); each
// (edge, ref) appears once.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet::metrics::detail {

using SurfaceLabel = std::array<std::int32_t, 3>;
inline constexpr std::int32_t kPolylineMarker = INT32_MAX;

struct SurfacePrimitives {
  std::vector<std::array<VertId, 3>> triangles;  // in increasing sorted-vertex order
  std::vector<SurfaceLabel> triangle_label;
  std::vector<std::array<VertId, 2>> segments;  // (low, high), by (edge, ref)
  std::vector<SurfaceLabel> segment_label;
};

// Throws InputError naming `which` ("original", "simplified") on a vertex index out of range.
SurfacePrimitives special_primitives(const MeshData& mesh, const char* which);

}  // namespace topotet::metrics::detail
