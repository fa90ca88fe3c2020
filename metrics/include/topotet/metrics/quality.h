// Element quality statistics of a tet mesh: the angle columns of the simplification report.
//
// Paper 001 (Table 7.1) reports, before and after simplification, the standard deviation of the
// dihedral, solid and face angles of the mesh (their means stay near 1.22, 0.53 and 1.05 rad, the
// values of a regular tet: 70.53 deg, 0.551 sr, 60 deg). We compute the same samples:
//   dihedral  6 per tet, the interior angle between the two faces at each edge;
//   solid     4 per tet, at each vertex, by the van Oosterom-Strackee formula
//             tan(O/2) = |a.(b x c)| / (abc + (a.b)c + (a.c)b + (b.c)a);
//   face      12 per tet: the 3 corner angles of each of the tet's 4 faces. A face shared by two
//             tets is sampled once per tet, so every tet weighs the same in every statistic
//             (the paper does not say; per-tet sampling needs no face deduplication).
// plus the mean-ratio shape quality 12 (3|V|)^(2/3) / sum of squared edge lengths (1 for the
// regular tet, -> 0 for degenerate ones) and orientation counts.
//
// Units: dihedral and face angles in DEGREES, solid angles in STERADIANS. Paper 001 prints its
// standard deviations in radians: multiply ours by pi/180 to compare (solid angles need nothing).
// Standard deviations are population ones: sqrt(sum (x - mean)^2 / count).
//
// Angles describe the shape and ignore orientation, so inverted tets contribute the angles of
// their mirror image, and flat tets contribute 0/180 deg dihedral and 0/2pi sr solid angles
// (degenerate edges or faces give 0 deg). Nothing is skipped: counts are 6, 4, 12 and 1 per tet.
//
// The result is bit-identical for any thread count: tets are processed in fixed-size blocks in
// parallel and the block summaries are merged in block order.
#pragma once

#include <cstddef>
#include <cstdint>

#include "topotet/mesh_data.h"

namespace topotet {

// Summary of one sampled quantity (all zero when count == 0).
struct SampleStats {
  std::uint64_t count = 0;
  double min = 0.0;
  double max = 0.0;
  double mean = 0.0;
  double std_dev = 0.0;  // population standard deviation
  friend bool operator==(const SampleStats&, const SampleStats&) = default;
};

struct QualityStats {
  std::size_t tet_count = 0;
  SampleStats dihedral_deg;  // 6 per tet, degrees
  SampleStats solid_sr;      // 4 per tet, steradians
  SampleStats face_deg;      // 12 per tet (3 per face of each tet), degrees
  SampleStats mean_ratio;    // 1 per tet, unsigned (uses |V|), in [0, 1]
  // Orientation of det[p1-p0, p2-p0, p3-p0] evaluated in double with Shewchuk's static error bound
  // for orient3d: `zero_volume` tets are those whose sign double precision cannot certify (exactly
  // flat, or flat to within rounding); `inverted` ones have a certified negative sign.
  std::size_t inverted = 0;
  std::size_t zero_volume = 0;
  // Tets with a dihedral angle under 10 and under 5 degrees: the slivers a solver pays for (the
  // thresholds issue #26 measures against a remesher).
  std::size_t under_10_deg = 0;
  std::size_t under_5_deg = 0;
  friend bool operator==(const QualityStats&, const QualityStats&) = default;
};

// Quality statistics over all tets of `mesh` (positions and tets only; other members unused).
// Throws InputError (topotet/error.h) if a tet has a vertex index out of range.
QualityStats compute_quality(const MeshData& mesh);

}  // namespace topotet
