// What SimplifyOptions::optimize runs after the collapses (issue #26): rounds of smoothing
// (smooth.h) and flips (swap.h), each of which says why every guarantee holds.
#pragma once

#include "cost/cost.h"
#include "guarantees/field_bounds.h"
#include "mesh/mesh_model.h"
#include "optimize/input_samples.h"
#include "topotet/simplify.h"

namespace topotet {

// Run by the engines once their collapses are done, with their cost model (the smoothing gives a
// moved vertex its field values from it). Fills the report's optimize_* fields. The flips leave
// dead tets and new ones: the caller compacts, as after the collapses. No flips with field
// bounds (kept per tet).
// `samples`: the input's vertices recorded before the collapses (may be null: then the field is
// guarded by the quadric and the pointwise bound only).
void optimize_after_collapses(MeshModel& mesh, const SimplifyOptions& options, CostModel& cost, FieldBounds* bounds,
                              const InputSamples* samples, Report& report);

}  // namespace topotet
