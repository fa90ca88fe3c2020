// topotet::simplify: checks the options, picks an engine, runs it inside the caller's thread
// budget, compacts the result and fills the report. Never throws.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <new>

#include <glm/geometric.hpp>

#include "engines.h"
#include "parallel/for_range.h"
#include "reorder.h"
#include "surface_tolerance.h"
#include "topotet/simplify.h"

namespace topotet {

const char* to_string(Status status) {
  switch (status) {
    case Status::kOk: return "ok";
    case Status::kStoppedEarly: return "stopped_early";
    case Status::kInvalidInput: return "invalid_input";
    case Status::kOutOfMemory: return "out_of_memory";
    case Status::kCancelled: return "cancelled";
  }
  return "?";
}

namespace {

std::string check_options(const SimplifyOptions& o) {
  if (!(o.target_vertex_ratio > 0.0 && o.target_vertex_ratio <= 1.0))
    return "target_vertex_ratio must be in (0, 1], got " + std::to_string(o.target_vertex_ratio);
  if (!(o.max_cost >= 0.0)) return "max_cost must be >= 0";
  if (!(o.min_quality >= 0.0 && o.min_quality < 1.0)) return "min_quality must be in [0, 1)";
  if (!(o.boundary_weight >= 0.0) || !(o.polyline_weight >= 0.0)) return "weights must be >= 0";
  if (!(o.tolerance >= 0.0) || !std::isfinite(o.tolerance)) return "tolerance must be finite and >= 0";
  if (!(o.tolerance_rel >= 0.0) || !std::isfinite(o.tolerance_rel)) return "tolerance_rel must be finite and >= 0";
  if (o.num_threads < 0) return "num_threads must be >= 0";
  if (!(o.round_fraction > 0.0 && o.round_fraction <= 1.0)) return "round_fraction must be in (0, 1]";
  for (const auto& [name, weight] : o.field_weights)
    if (!(weight >= 0.0) || !std::isfinite(weight)) return "field_weights: the weight of '" + name + "' must be finite and >= 0";
  return {};
}

std::string check_field_names(const SimplifyOptions& o, const TetMesh& mesh) {
  for (const auto& entry : o.field_weights) {
    const std::string& name = entry.first;
    if (std::none_of(mesh.fields.begin(), mesh.fields.end(), [&](const FieldInfo& f) { return f.name == name; }))
      return "field_weights: the mesh has no field named '" + name + "'";
  }
  return {};
}

double bounding_box_diagonal(const TetMesh& mesh) {
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (VertId v = 0; v < mesh.vertex_capacity(); ++v) {
    if (mesh.is_dead_vertex(v)) continue;
    lo = glm::min(lo, mesh.positions[v]);
    hi = glm::max(hi, mesh.positions[v]);
  }
  return lo.x <= hi.x ? glm::length(hi - lo) : 0.0;
}

}  // namespace

Report simplify(TetMesh& mesh, const SimplifyOptions& options) noexcept {
  Report report;
  const auto start = std::chrono::steady_clock::now();
  try {
    report.message = check_options(options);
    if (report.message.empty()) report.message = check_field_names(options, mesh);
    if (!report.message.empty()) {
      report.status = Status::kInvalidInput;
      return report;
    }
    report.vertices_before = mesh.live_vertex_count();
    report.tets_before = mesh.live_tet_count();
    std::uint64_t target = options.target_vertices != 0
                               ? options.target_vertices
                               : static_cast<std::uint64_t>(std::llround(options.target_vertex_ratio *
                                                                         static_cast<double>(report.vertices_before)));
    target = std::max<std::uint64_t>(target, 4);
    parallel::run_with_threads(options.num_threads, [&] {
      // Neighbours in space become neighbours in memory: every phase walks stars (reorder.h).
      reorder_for_locality(mesh);
      CollapseOptions kernel;
      kernel.quality_floor = options.min_quality;
      // The original surfaces, built before the first collapse and shared read-only by all threads.
      std::unique_ptr<SurfaceReference> surfaces;
      report.tolerance = options.tolerance > 0.0 ? options.tolerance : options.tolerance_rel * bounding_box_diagonal(mesh);
      if (report.tolerance > 0.0) {
        const auto setup_start = std::chrono::steady_clock::now();
        surfaces = SurfaceReference::from_mesh(mesh);
        kernel.surfaces = surfaces.get();
        kernel.tolerance = report.tolerance;
        report.tolerance_setup_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - setup_start).count();
      }
      if (options.engine == Engine::kSequential)
        detail::simplify_sequential(mesh, options, kernel, target, report);
      else
        detail::simplify_parallel(mesh, options, kernel, target, report);
      // Once, at the end: renumbering mid-run would have to remap every per-vertex array of the
      // engines (proposals, quadrics, orders) for a locality gain the runs here did not need.
      const auto compact_start = std::chrono::steady_clock::now();
      compact(mesh);
      report.phase_seconds[3] = std::chrono::duration<double>(std::chrono::steady_clock::now() - compact_start).count();
    });
  } catch (const std::bad_alloc&) {
    report.status = Status::kOutOfMemory;
    report.message = "out of memory";
  } catch (const std::exception& e) {
    // Internal errors leave the mesh valid (collapses are applied whole) but unfinished.
    report.status = Status::kStoppedEarly;
    report.message = std::string("internal error: ") + e.what();
  }
  report.vertices_after = mesh.live_vertex_count();
  report.tets_after = mesh.live_tet_count();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace topotet
