// The two simplification engines behind topotet::simplify (driver.cpp chooses one).
// Both use the same kernel (collapse.h), cost (cost.h) and report; both stop at `target_vertices`
// live vertices, when no legal collapse is left, at options.max_cost, or when on_progress says so.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "cost/cost.h"
#include "kernel/collapse.h"
#include "hierarchy/hierarchy_log.h"
#include "mesh/mesh_model.h"
#include "topotet/simplify.h"

namespace topotet::detail {

// Throttled progress reporting shared by the engines. Returns false when the caller cancels.
class Progress {
 public:
  Progress(const SimplifyOptions& options, std::uint64_t start_vertices, std::uint64_t target_vertices)
      : options_(options), start_(start_vertices), target_(target_vertices) {}
  bool update(std::uint64_t live_vertices) {
    if (!options_.on_progress) return true;
    const double span = static_cast<double>(start_ - target_);
    const double done = span > 0 ? static_cast<double>(start_ - live_vertices) / span : 1.0;
    return options_.on_progress(done < 0 ? 0.0 : (done > 1 ? 1.0 : done));
  }

 private:
  const SimplifyOptions& options_;
  std::uint64_t start_, target_;
};

// What the driver does once the collapses are done, while the engine's cost model still lives
// (the stop diagnosis, then the optimisation of optimize/optimize.h, which needs the quadrics).
using FinishStep = std::function<void(CostModel&)>;

// What the driver does when no legal collapse is left before the target: flip the bad tets the
// collapses made (flip_at_stall.h: the tets are renumbered and the side table grows, so the engine
// takes its next side-table slots after the table's end), or relax a limit in the kernel options
// the engine was given, or drop the feature curves and tell the engine's cost model
// (relax_limits.h), and return true; the engine takes the options again, looks at every edge once
// more and goes on; false: the run stops there. Called only at a stall: the engine has tried and
// refused every placement of every edge since the edge's stars last changed (relax_limits'
// census relies on it: stop_diagnosis.h).
using RelaxStep = std::function<bool(CostModel&)>;

// `kernel` carries the kernel settings derived from the options (quality floor, tolerance, the
// field bound limits); `bounds` (kernel.field_bounds, writable; nullptr = none) is updated by
// every applied collapse. `log`, when given, records every accepted collapse (hierarchy_log.h),
// with the field bound of its new star when `bounds` is given. `finish` (may be empty) runs at the
// end unless the run was cancelled. `relax` (may be empty) is asked before the run stops early.
void simplify_sequential(MeshModel& mesh, const SimplifyOptions& options, const CollapseOptions& kernel,
                         FieldBounds* bounds, std::uint64_t target_vertices, Report& report,
                         CollapseLog* log = nullptr, const FinishStep& finish = {}, const RelaxStep& relax = {});
void simplify_parallel(MeshModel& mesh, const SimplifyOptions& options, const CollapseOptions& kernel,
                       FieldBounds* bounds, std::uint64_t target_vertices, Report& report, CollapseLog* log = nullptr,
                       const FinishStep& finish = {}, const RelaxStep& relax = {});

// simplify() with a collapse log (topotet::simplify_with_hierarchy; out of core, a log seeded
// from the levels before). new2old receives the locality renumbering (reorder.h) that the log's
// vertex ids are in (old = the mesh as passed); last_change_out, when given, each output tet's
// last collapse (in the output's tet order), for a next run's seeds.
Report simplify_recorded(MeshModel& mesh, const SimplifyOptions& options, CollapseLog& log,
                         std::vector<VertId>& new2old, std::vector<std::uint32_t>* last_change_out = nullptr) noexcept;

}  // namespace topotet::detail
