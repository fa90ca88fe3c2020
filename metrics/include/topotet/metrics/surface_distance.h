// Geometric fidelity of a simplified mesh: two-sided Hausdorff distances between the original's
// and the simplified mesh's boundary, material interfaces, listed surfaces and polylines, overall
// and per label (issue #6; what `--tolerance` bounds during simplification).
//
// Labels. A special face is a boundary face (one tet), a face between two materials, or a listed
// triangle; its label is (listed ref or "unlisted", the two materials, or the material and
// "outside" for a boundary face) -- the notion the simplifier's link conditions and tolerance
// use. A listed triangle that is no face of a tet gets the materials "none". A polyline's label is
// its segment ref. Distances are only measured between primitives of the same label: a sample of
// the original sphere interface is compared with the simplified sphere interface, never with a
// nearby boundary. The overall numbers are the maxima over labels, hence upper bounds of the
// label-blind Hausdorff distance between the unions.
//
// Sampling. Each primitive's distance to the other side is evaluated at its corners, then on
// midpoint subdivisions (4 sub-triangles, 2 sub-segments) wherever an upper bound of the distance
// on the piece could still exceed the maximum already found by more than the sampling error
// (surface_distance.cpp: a Lipschitz bound and the convexity of the distance to one triangle),
// down to pieces of at most `spacing` = sample_spacing_rel x the original's bounding-box
// diagonal. Each sample's distance is exact (Embree closest-point queries restricted to the
// label, exact point-triangle distance in double). The reported one-sided values never exceed
// the true suprema and are at most `sampling_error` = spacing / sqrt(3) below them.
// The result is identical for every thread count (each triangle's maximum is exact; maxima are
// order independent).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet {

struct SurfaceDistanceOptions {
  double sample_spacing_rel = 1e-3;  // smallest piece / the original's bounding box diagonal
};

inline constexpr std::int32_t kSurfaceUnlistedRef = INT32_MIN + 1;  // LabelDistance::ref of unlisted faces
inline constexpr std::int32_t kSurfaceOutside = INT32_MIN;          // material on the outer side of the boundary
inline constexpr std::int32_t kSurfaceNoMaterial = INT32_MIN + 2;   // listed triangle that is no tet face

struct LabelDistance {
  bool polyline = false;
  std::int32_t ref = 0;
  std::int32_t material_low = 0, material_high = 0;  // faces only
  std::size_t original_primitives = 0, simplified_primitives = 0;
  std::size_t original_samples = 0, simplified_samples = 0;
  // max over original samples of the distance to the simplified surface of this label, and back;
  // +infinity when the other side has no primitive of this label.
  double original_to_simplified = 0.0, simplified_to_original = 0.0;
  double hausdorff = 0.0;  // the max of both
  std::string name() const;  // "boundary ref 10 (material 1)", "interface 1|2", "polyline ref 1", ...
};

struct SurfaceDistance {
  double hausdorff = 0.0;  // max over labels
  double original_to_simplified = 0.0, simplified_to_original = 0.0;
  double diagonal = 0.0;        // of the original's bounding box
  double sample_spacing = 0.0;  // mesh units
  double sampling_error = 0.0;  // bound of the underestimate, see the file comment
  std::size_t samples = 0;      // distance queries, both directions
  std::size_t unmatched_labels = 0;  // labels present on one side only (their distance is infinite)
  std::vector<LabelDistance> labels;  // sorted by ref, then materials (a polyline after the faces of its ref)
};

// Throws InputError (topotet/error.h) on an index out of range.
SurfaceDistance surface_distance(const MeshData& original, const MeshData& simplified,
                                 const SurfaceDistanceOptions& options = {});

}  // namespace topotet
