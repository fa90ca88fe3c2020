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
// Sampling. Each primitive's distance to the other side is evaluated at its corners (each vertex
// once per label), then on midpoint subdivisions (4 sub-triangles, 2 sub-segments) wherever an
// upper bound of the distance on the piece could still exceed the floor or the maximum already
// found by more than the sampling error (surface_distance.cpp: a Lipschitz bound and the
// convexity of the distance to one triangle), down to pieces of at most `spacing`. Each sample's
// distance is exact (Embree closest-point queries restricted to the label, exact point-triangle
// distance in double). sampling_error = spacing / sqrt(3).
//
// spacing = sample_spacing_rel x the original's bounding-box diagonal, or, when larger, the side
// of a square whose area is the original's mean special-triangle area / pieces_per_triangle (so
// that a mesh whose surfaces match exactly, where every piece must be refined to the spacing,
// still costs a number of samples proportional to its primitive count; 0 turns this off).
//
// Guarantee. No reported value exceeds a true supremum. With per_label_accuracy (the default,
// what `topotet check` uses), every label's one-sided values are at most sampling_error below its
// true suprema. Without it (what `simplify` reports), the floor of every label is the
// largest corner value of all labels, so refinement stops once a piece cannot beat the overall
// maximum: the overall one-sided values (the maxima over labels, and `hausdorff`) are at most
// sampling_error below the true ones, while a label's own values are lower bounds that are either
// within sampling_error of its truth or at most the overall value + sampling_error.
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
  double pieces_per_triangle = 0.0;  // lower bound of the spacing from the original's resolution (0 = none)
  bool per_label_accuracy = true;    // every label within sampling_error (false: only the overall values)
};

// What `topotet simplify` reports with: spacing from the original's resolution (16 pieces per
// triangle) when coarser than 1e-3 x the diagonal, accuracy for the overall values only. Its cost
// is proportional to the primitive count, whatever the meshes.
inline SurfaceDistanceOptions report_surface_distance_options() {
  SurfaceDistanceOptions options;
  options.pieces_per_triangle = 16.0;
  options.per_label_accuracy = false;
  return options;
}

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
