// The surface distance (metrics/surface_distance.h) in the text and JSON reports of `simplify`
// and `check`.
#pragma once

#include "common.h"
#include "topotet/metrics/surface_distance.h"

namespace topotet::cli {

// One "distance" row (two-sided Hausdorff, both one-sided values, the worst label, the sampling
// error), then one row per label when per_label.
void print_surface_distance(const SurfaceDistance& d, double seconds, bool per_label);
// Infinite distances (a label on one side only) are written as null.
Json surface_distance_json(const SurfaceDistance& d);

}  // namespace topotet::cli
