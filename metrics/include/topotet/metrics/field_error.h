// Error of a simplified mesh's vertex fields against the original's: the "rms" column of the
// simplification report.
//
// Paper 001 (ch. 7) measures "the root mean square error, computed as the difference between the
// scalar field value at vertices of the original and the simplified meshes". Both fields are
// piecewise linear over their own tets, so we compare them in both directions:
//   original_to_simplified  at every original vertex, its value minus the simplified field
//                           interpolated (barycentric, in the simplified tet containing it);
//   simplified_to_original  at every simplified vertex, its value minus the original field
//                           interpolated in the original mesh;
// and `rms_both` pools the samples of both directions (the paper's single number).
//
// Details:
//  - Fields are matched by name (the first field of that name in each mesh) and must have the
//    same component count; every component is compared as one scalar (as the simplifier
//    preserves them). Names without such a partner are listed in `unmatched_fields`.
//  - Only vertices used by at least one tet are sampled: the field is defined on the tets.
//  - A vertex outside every tet of the other mesh (the boundary moved a little) takes the value
//    at the closest point of the closest tet (exact point-tet distance; its barycentric
//    coordinates are then within [0, 1]). LocationStats count them and the largest distance.
//  - Relative errors divide by the component's range (max - min over the used original vertices),
//    so numbers compare across datasets; a constant component (range 0) divides by 1 instead.
//  - Point location uses a bounding volume hierarchy (Embree) over the tets' boxes, queried in
//    parallel; the result is bit-identical for any thread count.
//  - If either mesh has no tets, or no field matches, nothing is located and `components` is
//    empty.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet {

// Error samples of one component in one direction (all zero when samples == 0).
struct DirectionalError {
  std::size_t samples = 0;  // vertices compared
  double rms = 0.0;         // sqrt(mean of squared differences), field units
  double max_abs = 0.0;     // largest |difference|, field units
  double rms_rel = 0.0;     // rms / range
  double max_rel = 0.0;     // max_abs / range
  friend bool operator==(const DirectionalError&, const DirectionalError&) = default;
};

struct ComponentError {
  std::string field;   // field name
  int component = 0;   // 0-based component of that field
  double range = 0.0;  // max - min of the component over the used original vertices
  DirectionalError original_to_simplified;
  DirectionalError simplified_to_original;
  double rms_both = 0.0;      // RMS over the samples of both directions together
  double rms_both_rel = 0.0;  // rms_both / range
  friend bool operator==(const ComponentError&, const ComponentError&) = default;
};

// How the vertices of one mesh were located in the other.
struct LocationStats {
  std::size_t points = 0;   // vertices located (those used by a tet)
  std::size_t outside = 0;  // found outside every tet: the closest tet was used
  double max_outside_distance = 0.0;  // largest distance from such a vertex to the other mesh
  friend bool operator==(const LocationStats&, const LocationStats&) = default;
};

struct FieldError {
  std::vector<ComponentError> components;     // in the original's field and component order
  std::vector<std::string> unmatched_fields;  // names (original's first, then simplified's)
                                              // with no same-named, same-size partner
  LocationStats original_in_simplified;       // original vertices located in the simplified mesh
  LocationStats simplified_in_original;       // simplified vertices located in the original mesh
  double worst_rms_rel = 0.0;  // max over components of rms_both_rel
  double worst_max_rel = 0.0;  // max over components and both directions of max_rel
  // The largest error at the original vertices (original_to_simplified.max_rel, worst component):
  // what the per-tet field error bounds (SimplifyOptions::track_field_bounds) cover.
  double worst_max_rel_at_original() const {
    double worst = 0.0;
    for (const ComponentError& c : components)
      if (c.original_to_simplified.max_rel > worst) worst = c.original_to_simplified.max_rel;
    return worst;
  }
  friend bool operator==(const FieldError&, const FieldError&) = default;
};

// Compares every field present in both meshes (see above). Uses positions, tets and fields.
// Throws InputError (topotet/error.h) if a tet has a vertex index out of range or a non-finite
// vertex, or a field's value count is not vertex_count * components.
FieldError compare_fields(const MeshData& original, const MeshData& simplified);

// The components whose error at the original vertices (original_to_simplified.max_abs) exceeds
// the bound a run kept for it (`bounds`: field units, in `measured.components`' order, as
// Report::field_bound lists them): one line each, "field[c] measured E at an original vertex,
// bound B"; empty when every bound holds. The simplifier's bounds are exact at the original
// vertices (engine/guarantees/field_bounds.h), but this measurement interpolates on its own, so
// rounding may put it a hair above: 1e-9 of the bound and 1e-12 of the range are allowed. Only
// meaningful when no original vertex lies outside the simplified mesh (LocationStats::outside).
std::vector<std::string> field_bound_violations(const FieldError& measured, const std::vector<double>& bounds);

// A dense check of per-tet field error bounds that claim to hold at every point (simplify
// --field-bound-mode everywhere; engine/guarantees/field_bounds.h): `points` points inside the
// original's tets (point i in tet i mod T, uniformly distributed in it; deterministic for a
// seed), plus every original vertex, are located in the simplified mesh (as compare_fields does);
// at each, every field component matched by name (same component count) is interpolated in both
// meshes, and the error is compared with the bound of the simplified tet holding the point
// (`tet_bounds`: [tet * c_total + offset], the simplified mesh's fields in order, as
// Report::tet_field_bound gives them). Points outside the simplified mesh (its boundary moved
// inward past them) are counted and not compared: no tet holds them. A bound counts as exceeded
// above bound * (1 + 1e-9) + 1e-12 * range (the interpolations round on their own).
struct DenseBoundCheck {
  std::uint64_t points = 0;      // points located inside the simplified mesh and compared
  std::uint64_t outside = 0;     // points outside it (not compared)
  std::uint64_t violations = 0;  // (point, component) pairs above their tet's bound
  double worst_error_rel = 0.0;  // the largest error relative to its component's range
  double worst_excess_rel = -std::numeric_limits<double>::infinity();  // max (error - bound) / range
  std::string first_violation;   // "field[c] error E at (x, y, z) in tet T, bound B", or empty
};
DenseBoundCheck check_bounds_densely(const MeshData& original, const MeshData& simplified, const std::vector<float>& tet_bounds,
                                     std::uint64_t points, std::uint64_t seed);

// The original prepared once (its checked tets, its used vertices, and its point locator, built
// on the first comparison that needs it), for comparing several simplified meshes with it, as
// `simplify --levels` does: compare() gives what compare_fields gives. `original` must outlive
// it. compare() may run concurrently.
class FieldErrorReference {
 public:
  explicit FieldErrorReference(const MeshData& original);  // throws InputError like compare_fields
  ~FieldErrorReference();
  FieldErrorReference(const FieldErrorReference&) = delete;
  FieldErrorReference& operator=(const FieldErrorReference&) = delete;

  FieldError compare(const MeshData& simplified) const;

 private:
  struct Prepared;
  std::unique_ptr<Prepared> prepared_;
};

}  // namespace topotet
