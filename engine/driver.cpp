// topotet::simplify: checks the options, picks an engine, runs it inside the caller's thread
// budget, compacts the result and fills the report. Never throws.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <new>

#include <glm/geometric.hpp>

#include "entry_points.h"
#include "engines.h"
#include "cost/field_pins.h"
#include "guarantees/field_bounds.h"
#include "parallel/for_range.h"
#include "features/features.h"
#include "mesh/reorder.h"
#include "mesh/special_faces.h"
#include "optimize/optimize.h"
#include "guarantees/surface_tolerance.h"
#include "flip_at_stall.h"
#include "relax_limits.h"
#include "stop_diagnosis.h"
#include "topotet/features.h"
#include "topotet/simplify.h"

namespace topotet {

const char* to_string(Status status) {
  switch (status) {
    case Status::kOk: return "ok";
    case Status::kStoppedEarly: return "stopped_early";
    case Status::kInvalidInput: return "invalid_input";
    case Status::kOutOfMemory: return "out_of_memory";
    case Status::kCancelled: return "cancelled";
    case Status::kInternalError: return "internal_error";
  }
  return "?";
}

const char* to_string(Optimize optimize) {
  switch (optimize) {
    case Optimize::kNone: return "none";
    case Optimize::kLight: return "light";
    case Optimize::kFull: return "full";
  }
  return "?";
}

const char* to_string(FieldBoundMode mode) {
  switch (mode) {
    case FieldBoundMode::kVertices: return "vertices";
    case FieldBoundMode::kEverywhere: return "everywhere";
  }
  return "?";
}

const char* to_string(RejectReason reason) { return to_string(static_cast<CollapseReason>(reason)); }

// RejectReason is the public face of the kernel's CollapseReason: same values.
static_assert(static_cast<int>(RejectReason::kLinkK) == static_cast<int>(CollapseReason::kLinkK));
static_assert(static_cast<int>(RejectReason::kLinkKtilde) == static_cast<int>(CollapseReason::kLinkKtilde));
static_assert(static_cast<int>(RejectReason::kPinned) == static_cast<int>(CollapseReason::kPinned));
static_assert(static_cast<int>(RejectReason::kInversion) == static_cast<int>(CollapseReason::kInversion));
static_assert(static_cast<int>(RejectReason::kQuality) == static_cast<int>(CollapseReason::kQuality));
static_assert(static_cast<int>(RejectReason::kTolerance) == static_cast<int>(CollapseReason::kTolerance));
static_assert(static_cast<int>(RejectReason::kFieldError) == static_cast<int>(CollapseReason::kFieldError));
static_assert(kCollapseReasonCount == std::tuple_size_v<decltype(Report::rejected)>);

namespace {

std::string check_options(const SimplifyOptions& o) {
  if (!(o.target_vertex_ratio > 0.0 && o.target_vertex_ratio <= 1.0))
    return "target_vertex_ratio must be in (0, 1], got " + std::to_string(o.target_vertex_ratio);
  if (!(o.max_cost >= 0.0)) return "max_cost must be >= 0";
  if (!(o.min_quality >= 0.0 && o.min_quality < 1.0)) return "min_quality must be in [0, 1)";
  if (!(o.min_dihedral >= 0.0 && o.min_dihedral < 60.0)) return "min_dihedral must be in [0, 60) degrees";
  if (!(o.boundary_weight >= 0.0) || !(o.polyline_weight >= 0.0)) return "weights must be >= 0";
  if (!std::isfinite(o.size_weight)) return "size_weight must be finite (negative = auto)";
  if (!(o.tolerance >= 0.0) || !std::isfinite(o.tolerance)) return "tolerance must be finite and >= 0";
  if (!(o.tolerance_rel >= 0.0) || !std::isfinite(o.tolerance_rel)) return "tolerance_rel must be finite and >= 0";
  if (!(o.max_field_error >= 0.0) || !std::isfinite(o.max_field_error)) return "max_field_error must be finite and >= 0";
  if (!(o.max_field_error_rel >= 0.0) || !std::isfinite(o.max_field_error_rel))
    return "max_field_error_rel must be finite and >= 0";
  if (o.field_bound_mode != FieldBoundMode::kVertices && o.field_bound_mode != FieldBoundMode::kEverywhere)
    return "field_bound_mode must be vertices or everywhere";
  if (o.field_bound_mode == FieldBoundMode::kEverywhere && o.field_samples != nullptr)
    return "field_bound_mode everywhere is not available out of core: the passes carry the original vertices, not "
           "the original tets the bound is measured on";
  if (o.field_bound_mode == FieldBoundMode::kEverywhere && !(o.max_field_error > 0.0 || o.max_field_error_rel > 0.0))
    return "field_bound_mode everywhere needs a limit (max_field_error or max_field_error_rel): only a checked "
           "collapse can be kept from moving a curved boundary, past which the bound would not hold";
  if (o.num_threads < 0) return "num_threads must be >= 0";
  if (!(o.round_fraction > 0.0 && o.round_fraction <= 1.0)) return "round_fraction must be in (0, 1]";
  if (!(o.feature_angle >= 0.0 && o.feature_angle <= 180.0)) return "feature_angle must be in [0, 180] degrees";
  for (const auto& [name, weight] : o.field_weights)
    if (!(weight >= 0.0) || !std::isfinite(weight)) return "field_weights: the weight of '" + name + "' must be finite and >= 0";
  return {};
}

std::string check_against_mesh(const SimplifyOptions& o, const MeshModel& mesh) {
  if (const CostUnits* u = o.cost_units) {
    if (!(u->diagonal > 0.0) || !(u->mean_tet_volume > 0.0)) return "cost_units: diagonal and mean_tet_volume must be > 0";
    const auto stride = static_cast<std::size_t>(mesh.field_stride());
    if (u->field_min.size() != stride || u->field_range.size() != stride)
      return "cost_units: field_min and field_range need one entry per field component (" +
             std::to_string(mesh.field_stride()) + ")";
  }
  if (!o.isosurfaces.empty()) {
    std::vector<std::uint32_t> pins;
    if (std::string why = compute_field_pins(mesh, o.isosurfaces, pins); !why.empty()) return why;
  }
  for (const auto& entry : o.field_weights) {
    const std::string& name = entry.first;
    if (std::none_of(mesh.fields.begin(), mesh.fields.end(), [&](const FieldInfo& f) { return f.name == name; }))
      return "field_weights: the mesh has no field named '" + name + "'";
  }
  if (const FieldBoundSamples* f = o.field_samples; f != nullptr && f->components != 0) {
    const auto k = static_cast<std::size_t>(mesh.field_stride());
    const std::size_t n = f->size();
    if (static_cast<std::size_t>(f->components) != k || f->range.size() != k || f->magnitude.size() != k)
      return "field_samples: " + std::to_string(f->components) + " components, the mesh has " + std::to_string(k);
    if (f->positions.size() != 3 * n || f->values.size() != k * n || f->bounds.size() != k * mesh.tet_capacity())
      return "field_samples: the positions, values and bounds do not match the sample and tet counts";
    for (std::size_t w = 0; w < n; ++w)
      if (f->tet[w] >= mesh.tet_capacity() || mesh.is_dead_tet(f->tet[w]))
        return "field_samples: sample " + std::to_string(w) + " names tet " + std::to_string(f->tet[w]) +
               ", not a tet of the mesh";
  }
  return {};
}


// Fills vertex_map[i] for every input vertex i: the live vertex it became or merged into, as an id
// of the compacted output (`compacted`) or of the mesh as it stands. new2old is the renumbering
// reorder_for_locality made (empty: none yet). A merge chain v -> u -> w ends at a live vertex:
// collapse() kills only v and keeps u.
void resolve_vertex_map(const MeshModel& mesh, std::size_t input_count, const std::vector<VertId>& new2old,
                        bool compacted, std::vector<VertId>& vertex_map) {
  const std::size_t nv = mesh.vertex_capacity();
  // root[v]: the output id of the live vertex at the end of v's merge chain. Chains are walked
  // once each (every vertex on a walked chain is resolved on the way back): O(vertices) in all.
  std::vector<VertId> root(nv, kInvalid);
  VertId next = 0;
  for (VertId v = 0; v < nv; ++v)
    if (!mesh.is_dead_vertex(v)) root[v] = compacted ? next++ : v;
  if (mesh.merged_into.size() == nv) {
    std::vector<VertId> chain;
    for (VertId v = 0; v < nv; ++v) {
      VertId x = v;
      while (root[x] == kInvalid && mesh.merged_into[x] != kInvalid) {
        chain.push_back(x);
        x = mesh.merged_into[x];
      }
      for (VertId y : chain) root[y] = root[x];
      chain.clear();
    }
  }
  vertex_map.assign(input_count, kInvalid);
  if (new2old.empty()) {
    for (VertId v = 0; v < std::min(nv, input_count); ++v) vertex_map[v] = root[v];
  } else {
    for (VertId v = 0; v < new2old.size(); ++v) vertex_map[new2old[v]] = root[v];
  }
}

// `log` (simplify_with_hierarchy) records the collapses in the renumbered ids; new2old_out then
// receives the renumbering, and log_tets_out each output tet's last collapse (CollapseLog::keep_live_tets).
Report simplify_impl(MeshModel& mesh, const SimplifyOptions& given, std::vector<VertId>* vertex_map,
                     detail::CollapseLog* log = nullptr, std::vector<VertId>* new2old_out = nullptr,
                     std::vector<std::uint32_t>* log_tets_out = nullptr) noexcept {
  Report report;
  // The run's options: the caller's, with the carried quadrics in the renumbered vertex order
  // (quadrics_in, set below) and quadrics_out filled here at the end, not by the engines.
  SimplifyOptions options;
  std::vector<double> quadrics_in;
  try {
    options = given;
  } catch (const std::bad_alloc&) {
    report.status = Status::kOutOfMemory;
    report.message = "out of memory";
    return report;
  }
  options.quadrics_in = nullptr;
  options.quadrics_out = nullptr;
  if (given.quadrics_out != nullptr) given.quadrics_out->clear();
  const auto start = std::chrono::steady_clock::now();
  const std::size_t input_vertex_count = mesh.vertex_capacity();
  std::vector<VertId> new2old;  // reorder_for_locality's renumbering, kept for the vertex map and the log
  bool map_done = false;
  try {
    report.message = check_options(options);
    if (report.message.empty()) report.message = check_against_mesh(options, mesh);
    if (!report.message.empty()) {
      report.status = Status::kInvalidInput;
      if (vertex_map != nullptr) resolve_vertex_map(mesh, input_vertex_count, {}, false, *vertex_map);
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
      const bool want_bounds = options.keeps_field_bounds() && mesh.field_stride() > 0;
      // The caller's samples: handed back at the end (`carried`), and taken instead of the mesh's
      // vertices when given (`start_from`), their tets renumbered with the mesh's.
      FieldBoundSamples* const carried = want_bounds ? options.field_samples : nullptr;
      const bool start_from = carried != nullptr && carried->components != 0;
      std::vector<TetId> tet_old2new;
      const bool seeded_log = log != nullptr && log->seeded();  // a log continuing earlier runs (out of core)
      reorder_for_locality(mesh, vertex_map != nullptr || log != nullptr || given.quadrics_in != nullptr ? &new2old : nullptr,
                           start_from || seeded_log ? &tet_old2new : nullptr);
      if (new2old_out != nullptr) *new2old_out = new2old;
      if (seeded_log) log->renumber_tets(tet_old2new, mesh.tet_capacity());
      if (given.quadrics_in != nullptr) {
        // Per vertex in the caller's order -> per vertex in the renumbered order; a wrong count is
        // left for CostModel to refuse.
        const std::size_t nv = mesh.vertex_capacity();
        const std::size_t qs = input_vertex_count > 0 ? given.quadrics_in->size() / input_vertex_count : 0;
        if (qs > 0 && qs * input_vertex_count == given.quadrics_in->size() && new2old.size() == nv) {
          quadrics_in.resize(given.quadrics_in->size());
          for (std::size_t v = 0; v < nv; ++v)
            std::copy_n(given.quadrics_in->data() + static_cast<std::size_t>(new2old[v]) * qs, qs, quadrics_in.data() + v * qs);
          options.quadrics_in = &quadrics_in;
        } else {
          options.quadrics_in = given.quadrics_in;
        }
      }
      if (vertex_map != nullptr) mesh.merged_into.assign(mesh.vertex_capacity(), kInvalid);
      // Before the cost model and the tolerance reference are built: both see the features as
      // polylines (line quadrics; a curve label the tolerance checks).
      // The special faces, found once for both the features and the tolerance's reference.
      report.tolerance = options.tolerance > 0.0 ? options.tolerance : options.tolerance_rel * bounding_box_diagonal(mesh);
      report.tolerance_asked = report.tolerance;
      report.min_quality_used = report.min_quality_lowest = options.min_quality;
      report.min_dihedral_used = report.min_dihedral_lowest = options.min_dihedral;
      if (options.relax_quality) detail::lowest_floors(mesh, options, report);  // before any collapse
      const auto special_start = std::chrono::steady_clock::now();
      SpecialFaces special;
      if (report.tolerance > 0.0) special = find_special_faces(mesh);
      const double special_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - special_start).count();
      const auto feature_start = std::chrono::steady_clock::now();
      report.feature_scale = feature_scale(mesh, options);
      std::vector<std::int32_t> isosurface_refs;  // not searched for creases (features/features.h)
      for (const IsoLevel& level : options.isosurfaces) isosurface_refs.push_back(level.ref);
      const FeatureStats features = detect_features(mesh, options.feature_angle, report.feature_scale,
                                                    report.tolerance > 0.0 ? &special.on_face : nullptr, isosurface_refs);
      report.feature_candidates = features.candidates;
      report.feature_turns = features.turns;
      report.feature_edges = features.edges;
      report.feature_corners = features.corners;
      report.feature_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - feature_start).count();
      CollapseOptions kernel;
      kernel.quality_floor = options.min_quality;
      kernel.dihedral_floor = DihedralFloor::degrees(options.min_dihedral);
      // The original surfaces, built before the first collapse and shared read-only by all threads.
      std::unique_ptr<SurfaceReference> surfaces;
      std::unique_ptr<SurfaceCoverage> coverage;
      if (report.tolerance > 0.0) {
        const auto setup_start = std::chrono::steady_clock::now();
        surfaces = SurfaceReference::from_mesh(mesh, report.tolerance, special);
        special = {};
        coverage = std::make_unique<SurfaceCoverage>(mesh, *surfaces, report.tolerance);
        kernel.surfaces = surfaces.get();
        kernel.coverage = coverage.get();
        kernel.tolerance = report.tolerance;
        report.tolerance_setup_seconds =
            special_seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - setup_start).count();
      }
      // Field error bounds, only when asked for (they cost memory and a point location per sample
      // of every checked stencil). Taken after the renumbering: they are keyed by tet and vertex ids.
      std::unique_ptr<FieldBounds> bounds;
      if (want_bounds) {
        const auto setup_start = std::chrono::steady_clock::now();
        if (start_from) {
          const std::size_t k = static_cast<std::size_t>(carried->components);
          std::vector<float> bound(tet_old2new.size() * k, 0.0f);  // [new tet * k + c]
          for (std::size_t t = 0; t < tet_old2new.size(); ++t)
            if (tet_old2new[t] != kInvalid) std::copy_n(carried->bounds.begin() + t * k, k, bound.begin() + tet_old2new[t] * k);
          carried->bounds = std::move(bound);
          for (std::uint32_t& t : carried->tet) t = tet_old2new[t];
          bounds = std::make_unique<FieldBounds>(mesh, std::move(*carried), options.max_field_error, options.max_field_error_rel);
          if (options.field_bound_mode == FieldBoundMode::kEverywhere) bounds->set_everywhere(mesh);
        } else {
          bounds = std::make_unique<FieldBounds>(mesh, options.max_field_error, options.max_field_error_rel);
          if (options.field_bound_mode == FieldBoundMode::kEverywhere) bounds->set_everywhere(mesh);
        }
        if (log != nullptr) bounds->exact_commits();  // a hierarchy's levels choose by the bounds stored
        kernel.field_bounds = bounds.get();
        report.field_bounds = true;
        report.field_bound_mode = options.field_bound_mode;
        report.field_bounds_bytes = bounds->memory_bytes();
        report.field_bounds_setup_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - setup_start).count();
      }
      // The input's vertices for the optimisation's field guard (optimize/input_samples.h), recorded
      // before the first collapse overwrites a survivor's position and values.
      std::unique_ptr<InputSamples> samples;
      if (options.optimize != Optimize::kNone && log == nullptr && mesh.field_stride() > 0)
        samples = std::make_unique<InputSamples>(mesh);
      // Once the collapses are done, with the engine's cost model: why the run stopped early (it
      // tries collapses on the mesh as the collapses left it, with the coverage, which knows that
      // mesh's tets), then the optimisation. Not with a collapse log: a hierarchy's levels are
      // collapse sequences, and a moved vertex would make its finest level differ from the output.
      const detail::FinishStep finish = [&](CostModel& cost) {
        // Report::stop: why, and what to change (already taken when the last relax step declined:
        // no collapse since).
        if (report.status == Status::kStoppedEarly && report.message == "no legal collapse left" &&
            mesh.live_vertex_count() > target && !report.stop.is_filled)
          detail::diagnose_stop(mesh, options, kernel, cost, target, report, true);  // the engine stalled
        if (samples != nullptr) samples->index(mesh);
        if (log == nullptr) optimize_after_collapses(mesh, options, cost, bounds.get(), samples.get(), report);
        samples.reset();
        if (given.quadrics_out != nullptr) {
          // In the order compact() keeps: the live vertices by id.
          const auto qs = static_cast<std::size_t>(cost.quadric_doubles());
          given.quadrics_out->reserve(mesh.live_vertex_count() * qs);
          for (VertId v = 0; v < mesh.vertex_capacity(); ++v)
            if (!mesh.is_dead_vertex(v)) given.quadrics_out->insert(given.quadrics_out->end(), cost.quadric_of(v), cost.quadric_of(v) + qs);
        }
      };
      // When no legal collapse is left before the target, the census of what holds the vertices
      // left decides (relax_limits.h): where inverted tets hold the most, the bad tets the
      // collapses made are flipped (flip_at_stall.h: no guarantee's price), again after each
      // flip that let collapses through; where the tolerance, the quality floors or the feature
      // corners hold the most, and the options let them, they relax. Flips not in the parts of a
      // larger mesh (frozen borders: out of core, MPI), which keep their own rules.
      const bool relax_any = options.relax_tolerance || options.relax_quality || options.relax_features;
      const bool flip_stalls = options.optimize != Optimize::kNone && bounds == nullptr && log == nullptr &&
                               std::none_of(mesh.vertex_states.begin(), mesh.vertex_states.end(),
                                            [](std::uint8_t s) { return (s & vertex_state::kFrozen) != 0; });
      std::uint64_t live_at_flips = 0;  // vertices left at the last flips (0: none yet)
      const std::function<bool()> flip = [&] {
        const std::uint64_t live = mesh.live_vertex_count();
        if (live == live_at_flips) return false;  // no collapse since: the same stars
        live_at_flips = live;
        return detail::flip_at_stall(mesh, coverage.get(), samples.get(), report);
      };
      detail::RelaxStep relax;
      if (relax_any || flip_stalls)
        relax = [&](CostModel& cost) {
          return detail::relax_limits(mesh, options, kernel, coverage.get(), cost, target, report,
                                      flip_stalls ? flip : std::function<bool()>());
        };
      if (options.engine == Engine::kSequential)
        detail::simplify_sequential(mesh, options, kernel, bounds.get(), target, report, log, finish, relax);
      else
        detail::simplify_parallel(mesh, options, kernel, bounds.get(), target, report, log, finish, relax);
      if (bounds != nullptr) {
        report.field_bound = bounds->max_bounds(mesh);
        report.field_bound_rel = bounds->max_bound_rel(mesh);
        if (carried != nullptr) {
          bounds->release(mesh, *carried);
          report.tet_field_bound = carried->bounds;
        } else {
          report.tet_field_bound = bounds->live_bounds(mesh);
        }
      }
      // Said only where the census does not clear it (after relaxing, the tolerance has refused
      // collapses on the way and may hold few of the vertices left: under 5%, it is not said).
      if (report.status == Status::kStoppedEarly && report.tolerance > 0.0 &&
          report.rejected[static_cast<std::size_t>(CollapseReason::kTolerance)] > 0 &&
          report.message == "no legal collapse left" && (!report.stop.is_filled || 20 * report.stop.tolerance >= report.stop.vertices)) {
        report.tolerance_limited = true;
        report.message = "no legal collapse left; the tolerance (H = " + std::to_string(report.tolerance) +
                         ") refused " +
                         std::to_string(report.rejected[static_cast<std::size_t>(CollapseReason::kTolerance)]) +
                         " collapses, so it may be what stopped the run before the target (compare with tolerance 0)";
      }
      const std::uint64_t field_refusals = report.rejected[static_cast<std::size_t>(CollapseReason::kFieldError)];
      if (report.status == Status::kStoppedEarly && field_refusals > 0)
        report.message += "; the field error limit refused " + std::to_string(field_refusals) + " collapses";
      const auto compact_start = std::chrono::steady_clock::now();
      if (vertex_map != nullptr) {
        resolve_vertex_map(mesh, input_vertex_count, new2old, true, *vertex_map);
        map_done = true;
        std::vector<VertId>().swap(mesh.merged_into);
      }
      if (log != nullptr && log_tets_out != nullptr) *log_tets_out = log->keep_live_tets(mesh);  // compact keeps their order
      // Once, at the end: renumbering mid-run would have to remap every per-vertex array of the
      // engines (proposals, quadrics, orders) for a locality gain the runs here did not need.
      compact(mesh);
      report.phase_seconds[3] = std::chrono::duration<double>(std::chrono::steady_clock::now() - compact_start).count();
    });
  } catch (const std::bad_alloc&) {
    report.status = Status::kOutOfMemory;
    report.message = "out of memory";
  } catch (const std::exception& e) {
    // Internal errors leave the mesh valid (collapses are applied whole) but unfinished.
    report.status = Status::kInternalError;
    report.message = std::string("internal error: ") + e.what();
  }
  if (vertex_map != nullptr && !map_done) {
    // Stopped by an exception: the mesh is valid but not compacted; map onto its ids as they are.
    try {
      resolve_vertex_map(mesh, input_vertex_count, new2old, false, *vertex_map);
    } catch (const std::bad_alloc&) {
      vertex_map->clear();
      report.status = Status::kOutOfMemory;
      report.message = "out of memory";
    }
    std::vector<VertId>().swap(mesh.merged_into);
  }
  report.vertices_after = mesh.live_vertex_count();
  report.tets_after = mesh.live_tet_count();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace

Report detail::simplify_recorded(MeshModel& mesh, const SimplifyOptions& options, CollapseLog& log,
                                 std::vector<VertId>& new2old, std::vector<std::uint32_t>* last_change_out) noexcept {
  return simplify_impl(mesh, options, nullptr, &log, &new2old, last_change_out);
}

Report simplify(MeshModel& mesh, const SimplifyOptions& options) noexcept { return simplify_impl(mesh, options, nullptr); }

void add_run_counts(Report& total, const Report& part) {
  total.collapses += part.collapses;
  total.evaluations += part.evaluations;
  total.legality_checks += part.legality_checks;
  for (std::size_t k = 0; k < total.rejected.size(); ++k) total.rejected[k] += part.rejected[k];
  total.rounds += part.rounds;
  total.feature_edges += part.feature_edges;
  total.feature_corners += part.feature_corners;
  total.max_cost = std::max(total.max_cost, part.max_cost);
  total.tolerance_limited = total.tolerance_limited || part.tolerance_limited;
  for (std::size_t k = 0; k < total.phase_seconds.size(); ++k) total.phase_seconds[k] += part.phase_seconds[k];
}

Report simplify(MeshModel& mesh, const SimplifyOptions& options, std::vector<VertId>& vertex_map) noexcept {
  return simplify_impl(mesh, options, &vertex_map);
}

}  // namespace topotet
