// What one `simplify` run produced (SimplifyRun: the input's figures and one LevelResult per
// level), and how it is reported: the text report on report_stream() and the JSON report.
// simplify.cpp fills a SimplifyRun step by step; this file only reads it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common.h"
#include "topotet/cell_fields.h"
#include "topotet/hierarchy.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/surface_distance.h"
#include "topotet/metrics/topology.h"
#include "topotet/round_log.h"
#include "topotet/simplify.h"

namespace topotet::cli {

// One level: its simplification, its written file and its measurements.
struct LevelResult {
  double target_ratio = 0.0;  // 0 = the options' own target (no --levels)
  Report report;
  std::string output_path;  // empty when nothing was written
  double write_seconds = 0.0;
  double cumulative_seconds = 0.0;  // simplify time of this level and the ones before
  MeshData output;
  bool measured = false;  // quality, field error and distance computed (not --no-metrics)
  QualityStats quality;
  double quality_seconds = 0.0;
  std::optional<FieldError> field_error;
  double field_error_seconds = 0.0;
  SurfaceDistance distance;  // boundary, interfaces, surfaces, polylines: output vs input
  double distance_seconds = 0.0;
  double topology_seconds = 0.0;  // the output's topology and the comparison
  bool verified = false;
  bool topology_ok = true;
  // The field error bounds (Report::field_bounds) against the error measured at the original
  // vertices: false when a component's measured error exceeds its bound (a broken guarantee, which
  // fails the run like a changed topology). Unchecked: no bounds kept, no
  // metrics, or original vertices outside the output (bounded only approximately there).
  std::optional<bool> field_bound_ok;
  // The bounds checked at kDenseBoundPoints points inside the input's tets and its vertices
  // (metrics' check_bounds_densely): with --field-bound-mode everywhere an excess fails the run;
  // with vertices it shows how far the error goes between the original vertices.
  std::optional<topotet::DenseBoundCheck> dense_bounds;
  std::string field_bound_failure;  // what exceeded which bound, when field_bound_ok is false
  std::string differences;
  topotet::TopologyReport topology;
  std::vector<RoundStats> rounds;  // filled at -vv only (SimplifyOptions::round_log)
  std::optional<CellRemapReport> cell_remap;  // the input's cell arrays remapped onto this level
};

// Times of the measurements of every level together, for the report's "measure" line.
struct MeasureTimes {
  double input_quality = 0.0, quality = 0.0, field_error = 0.0, distance = 0.0, input_topology = 0.0, topology = 0.0;
  double reload = 0.0;  // reading the input again for the measurements (SimplifyJob::reload)
  double total() const { return reload + input_quality + quality + field_error + distance + input_topology + topology; }
};

// The whole run, as the steps of run_simplify_job fill it.
struct SimplifyRun {
  // the engine that runs
  int threads = 0;  // after the cap (current_thread_limit)
  bool is_parallel = true;
  bool verify = true;  // the topology checker runs (not --no-verify, not --no-metrics)
  // build
  double build_seconds = 0.0;
  std::size_t model_bytes = 0;
  std::uint64_t vertices_in = 0, tets_in = 0;
  // simplify, level by level
  std::vector<LevelResult> levels;
  double cumulative_seconds = 0.0;  // simplify time of every level
  Hierarchy hierarchy;              // --hierarchy
  double hierarchy_write_seconds = 0.0;
  std::vector<VertId> vertex_map;  // --vertex-map
  double vertex_map_write_seconds = 0.0;
  std::uint64_t peak_bytes = 0;  // after simplifying, before measuring
  // cell data: the input's cell arrays with the kinds they are remapped with (empty: none)
  std::vector<CellField> cell_arrays;  // names, components and kinds only (no values)
  // measure
  MeasureTimes times;
  QualityStats input_quality;
  bool fast_topology = false;  // the checker's fast mode (large inputs)
  topotet::TopologyReport input_topology;
  bool all_ok = true;  // every level passed the checks that ran
  Json error_levels = Json::array();  // --levels-error: print_error_levels' rows
};

// The text report: one block (no --levels) or one table row per level, then the rows common to
// both, then the checker's differences when a level failed (on stderr with -q).
void print_report(const SimplifyJob& job, const SimplifyRun& run);

// The JSON report (--json), written to job.report_path.
void write_json_report(const SimplifyJob& job, const SimplifyRun& run);

}  // namespace topotet::cli
