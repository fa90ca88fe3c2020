#include "simplify_report.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "distance_report.h"
#include "json_report.h"
#include "simplify_options.h"
#include "stop_report.h"

namespace topotet::cli {
namespace {

// The JSON key of a reject reason: to_string's name in snake_case ("link_K" -> "link_k").
std::string reason_key(RejectReason reason) {
  std::string key = to_string(reason);
  for (char& c : key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return key;
}
constexpr const char* kPhaseKeys[4] = {"evaluate", "select", "apply", "compact"};

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;

std::size_t complex_count(const topotet::TopologyReport& r) {
  return 6 + r.materials.size() + r.surfaces.size() + r.interfaces.size() + r.polylines.size();
}

double per(double a, double b) { return b > 0 ? a / b : 0.0; }

Json direction_json(const DirectionalError& d) {
  return {{"samples", d.samples}, {"rms", d.rms}, {"max_abs", d.max_abs}, {"rms_rel", d.rms_rel}, {"max_rel", d.max_rel}};
}

Json field_error_json(const FieldError& f) {
  Json components = Json::array();
  for (const ComponentError& c : f.components)
    components.push_back({{"field", c.field},
                          {"component", c.component},
                          {"range", c.range},
                          {"rms", c.rms_both},
                          {"rms_rel", c.rms_both_rel},
                          {"original_to_simplified", direction_json(c.original_to_simplified)},
                          {"simplified_to_original", direction_json(c.simplified_to_original)}});
  return {{"rms_rel", f.worst_rms_rel},
          {"max_rel", f.worst_max_rel},
          {"components", components},
          {"unmatched_fields", f.unmatched_fields}};
}


Json field_bounds_json(const LevelResult& l) {
  const Report& r = l.report;
  if (!r.field_bounds) return nullptr;
  Json components = Json::array();
  for (std::size_t c = 0; c < r.field_bound.size(); ++c) {
    Json e = {{"bound", r.field_bound[c]}};
    if (l.field_error && c < l.field_error->components.size()) {
      const ComponentError& m = l.field_error->components[c];
      e["field"] = m.field;
      e["component"] = m.component;
      e["bound_rel"] = m.range > 0 ? r.field_bound[c] / m.range : r.field_bound[c];
      e["measured_max_abs"] = m.original_to_simplified.max_abs;
    }
    components.push_back(e);
  }
  return {{"max_bound_rel", r.field_bound_rel},
          {"mode", to_string(r.field_bound_mode)},  // "vertices" or "everywhere": where the bound holds
          {"components", components},
          {"measured_max_rel", l.field_error ? Json(l.field_error->worst_max_rel_at_original()) : Json(nullptr)},
          // The bound covers these only up to the tet they were attached to (engine/guarantees/field_bounds.h).
          {"original_vertices_outside",
           l.field_error ? Json(l.field_error->original_in_simplified.outside) : Json(nullptr)},
          // "pass" / "fail" (a measured error above its bound: the run fails), null when unchecked.
          // Sampled inside the input's tets (check_bounds_densely): the largest error relative to
          // the range, and how many samples exceed their tet's bound (a failure in everywhere mode).
          {"dense", l.dense_bounds ? Json{{"points", l.dense_bounds->points},
                                          {"outside", l.dense_bounds->outside},
                                          {"max_error_rel", l.dense_bounds->worst_error_rel},
                                          {"above_bound", l.dense_bounds->violations}}
                                   : Json(nullptr)},
          {"check", l.field_bound_ok ? Json(*l.field_bound_ok ? "pass" : "fail") : Json(nullptr)},
          {"check_failures", split_lines(l.field_bound_failure)},
          {"bytes", r.field_bounds_bytes},
          {"setup_seconds", r.field_bounds_setup_seconds}};
}

Json level_json(const LevelResult& l) {
  const Report& r = l.report;
  Json rejected = Json::object();
  for (RejectReason reason : kRejectReasons) rejected[reason_key(reason)] = r.rejected_by(reason);
  Json phases = Json::object();
  for (int i = 0; i < 4; ++i) phases[kPhaseKeys[i]] = r.phase_seconds[static_cast<std::size_t>(i)];
  Json j;
  j["target_vertex_ratio"] = l.target_ratio > 0 ? Json(l.target_ratio) : Json(nullptr);
  j["output_file"] = l.output_path.empty() ? Json(nullptr) : Json(l.output_path);
  j["status"] = to_string(r.status);
  j["message"] = r.message;
  j["vertices_before"] = r.vertices_before;
  j["vertices_after"] = r.vertices_after;
  j["tets_before"] = r.tets_before;
  j["tets_after"] = r.tets_after;
  j["simplify_seconds"] = r.seconds;
  j["cumulative_seconds"] = l.cumulative_seconds;
  j["write_seconds"] = l.write_seconds;
  j["collapses"] = r.collapses;
  j["collapses_per_second"] = per(static_cast<double>(r.collapses), r.seconds);
  j["evaluations"] = r.evaluations;
  j["evaluations_per_collapse"] = per(static_cast<double>(r.evaluations), static_cast<double>(r.collapses));
  j["legality_checks"] = r.legality_checks;
  j["rejected"] = rejected;
  j["rounds"] = r.rounds;
  j["phase_seconds"] = phases;
  j["max_cost"] = r.max_cost;
  j["quality"] = l.measured ? quality_json(l.quality) : Json(nullptr);
  j["quality_seconds"] = l.quality_seconds;
  j["field_error"] = l.field_error ? field_error_json(*l.field_error) : Json(nullptr);
  j["field_error_seconds"] = l.field_error_seconds;
  j["tolerance"] = r.tolerance;
  j["tolerance_setup_seconds"] = r.tolerance_setup_seconds;
  j["tolerance_limited"] = r.tolerance_limited;
  j["tolerance_asked"] = r.tolerance_asked;
  j["min_quality_used"] = r.min_quality_used;
  j["min_dihedral_used"] = r.min_dihedral_used;
  j["min_quality_lowest"] = r.min_quality_lowest;  // how far the floors may relax (the input's worst)
  j["min_dihedral_lowest"] = r.min_dihedral_lowest;
  j["relaxations"] = relaxations_json(r);
  j["relax_seconds"] = r.relax_seconds;
  j["features_dropped"] = r.features_dropped;
  j["stall_flips"] = r.stall_flips;
  j["stall_flip_seconds"] = r.stall_flip_seconds;
  j["field_bounds"] = field_bounds_json(l);
  j["feature_edges"] = r.feature_edges;
  j["feature_corners"] = r.feature_corners;
  j["feature_candidates"] = r.feature_candidates;
  j["feature_turns"] = r.feature_turns;
  j["feature_scale"] = r.feature_scale;
  j["feature_seconds"] = r.feature_seconds;
  j["optimize_moves"] = r.optimize_moves;
  j["optimize_candidates"] = r.optimize_candidates;
  j["optimize_passes"] = r.optimize_passes;
  j["optimize_flips"] = r.optimize_flips;
  j["optimize_seconds"] = r.optimize_seconds;
  j["stopped"] = stop_report_json(r);
  j["surface_distance"] = l.measured ? surface_distance_json(l.distance) : Json(nullptr);
  j["surface_distance_seconds"] = l.distance_seconds;
  if (l.cell_remap) {
    j["cell_remap"] = {{"seconds", l.cell_remap->seconds},
                       {"overlap_pairs", l.cell_remap->overlap_pairs},
                       {"nearest_new_tets", l.cell_remap->nearest_new_tets},
                       {"nearest_original_tets", l.cell_remap->nearest_original_tets},
                       {"covered_volume_fraction", l.cell_remap->covered_volume_fraction}};
  } else {
    j["cell_remap"] = nullptr;
  }
  j["topology_seconds"] = l.topology_seconds;
  if (l.verified) {
    j["topology"] = l.topology_ok ? "pass" : "fail";
    j["topology_differences"] = split_lines(l.differences);
    j["topology_report"] = topology_report_json(l.topology);
  } else {
    j["topology"] = "skipped";
  }
  return j;
}

std::string rejected_text(const Report& r) {
  std::string s;
  for (RejectReason reason : kRejectReasons) {
    if (reason == RejectReason::kFieldError && !r.field_bounds) continue;  // no bounds kept: nothing to refuse
    if (!s.empty()) s += ", ";
    s += std::string(to_string(reason)) + " " + format_count(r.rejected_by(reason));
  }
  return s;
}

std::string angles_text(const QualityStats& q) {
  return format_number(q.dihedral_deg.std_dev * kRadiansPerDegree) + " / " + format_number(q.solid_sr.std_dev) +
         " / " + format_number(q.face_deg.std_dev * kRadiansPerDegree);
}

std::string field_text(const FieldError& f) {
  return "rms " + format_number(f.worst_rms_rel) + ", max " + format_number(f.worst_max_rel) +
         " (relative to the field's range, worst of " + std::to_string(f.components.size()) + " component" +
         (f.components.size() == 1 ? "" : "s") + ")";
}

std::string phases_text(const Report& r) {
  std::string s = "evaluate " + format_seconds(r.evaluate_seconds()) + ", select " + format_seconds(r.select_seconds()) +
                  ", apply " + format_seconds(r.apply_seconds()) + ", compact " + format_seconds(r.compact_seconds());
  if (r.feature_seconds > 0) s += "; feature detection " + format_seconds(r.feature_seconds);
  if (r.tolerance_setup_seconds > 0) s += "; tolerance scene " + format_seconds(r.tolerance_setup_seconds);
  return s;
}

// -vv: one line per parallel round (RoundStats), on the report stream.
void print_rounds(const std::vector<RoundStats>& rounds) {
  std::FILE* out = report_stream();
  if (rounds.empty()) return;
  std::fprintf(out, "%-10s%6s %10s %10s %9s %9s %9s %9s %9s %9s\n", "rounds", "round", "evaluated", "candidates",
               "winners", "collapses", "evaluate", "select", "apply", "serial");
  for (std::size_t i = 0; i < rounds.size(); ++i) {
    const RoundStats& st = rounds[i];
    std::fprintf(out, "%-10s%6zu %10s %10s %9s %9s %9s %9s %9s %9s\n", "", i + 1, format_count(st.evaluated).c_str(),
                 format_count(st.candidates).c_str(), format_count(st.winners).c_str(),
                 format_count(st.collapses).c_str(), format_seconds(st.phase_seconds[0]).c_str(),
                 format_seconds(st.phase_seconds[1]).c_str(), format_seconds(st.phase_seconds[2]).c_str(),
                 format_seconds(st.serial_seconds).c_str());
  }
}

// -v: every field component, both directions.
void print_field_components(const FieldError& f) {
  for (const ComponentError& c : f.components)
    std::fprintf(report_stream(), "%-10s  %-28s rms %s (in->out %s, out->in %s), max in->out %s, out->in %s\n", "",
                 (c.field + (f.components.size() > 1 ? "[" + std::to_string(c.component) + "]" : "")).c_str(),
                 format_number(c.rms_both_rel).c_str(), format_number(c.original_to_simplified.rms_rel).c_str(),
                 format_number(c.simplified_to_original.rms_rel).c_str(),
                 format_number(c.original_to_simplified.max_rel).c_str(),
                 format_number(c.simplified_to_original.max_rel).c_str());
}

void row(const char* key, const std::string& value) { std::fprintf(report_stream(), "%-10s%s\n", key, value.c_str()); }

std::string measure_text(const MeasureTimes& t, double simplify_seconds) {
  std::string s = "quality " + format_seconds(t.input_quality + t.quality) + ", fields " +
                  format_seconds(t.field_error) + ", distance " + format_seconds(t.distance) + ", topology " +
                  format_seconds(t.input_topology + t.topology);
  if (t.reload > 0.0) s += ", input re-read " + format_seconds(t.reload);
  char share[64] = "";
  if (simplify_seconds > 0)
    std::snprintf(share, sizeof share, " = %.0f%% of the simplification", 100.0 * t.total() / simplify_seconds);
  return s + " (total " + format_seconds(t.total()) + share + ")";
}


// "input     torus.mesh: 4,351 vertices, 20,067 tets (read 32 ms, build 30 ms)", then -v's options.
void print_input(const SimplifyJob& job, const SimplifyRun& run) {
  row("input", job.input_label + ": " + format_count(run.vertices_in) + " vertices, " + format_count(run.tets_in) +
                   " tets (" + job.read_verb + " " + format_seconds(job.read_seconds) + ", build " +
                   format_seconds(run.build_seconds) + ")");
  if (verbosity() >= Verbosity::kVerbose) row("options", options_text(job.options, job.levels));
}

std::string engine_text(const SimplifyRun& run) {
  return run.is_parallel ? "parallel, " + std::to_string(run.threads) + " thread" + (run.threads == 1 ? "" : "s")
                         : std::string("sequential");
}

// One level (no --levels): its output, speed, work, refusals and status.
void print_single_level(const SimplifyRun& run) {
  const LevelResult& last = run.levels.back();
  const Report& r = last.report;
  char pct[32];
  std::snprintf(pct, sizeof pct, "%.1f%%", 100.0 * per(static_cast<double>(r.vertices_after), run.vertices_in));
  row("output", (last.output_path.empty() ? std::string("(not written)") : last.output_path) + ": " +
                    format_count(r.vertices_after) + " vertices (" + pct + "), " + format_count(r.tets_after) +
                    " tets" + (last.output_path.empty() ? "" : " (write " + format_seconds(last.write_seconds) + ")"));
  row("time", format_seconds(r.seconds) + " " + engine_text(run) + ", " +
                  format_count(static_cast<std::uint64_t>(per(static_cast<double>(r.collapses), r.seconds))) +
                  " collapses/s" + (run.is_parallel ? ", " + format_count(r.rounds) + " rounds" : ""));
  row("work", format_count(r.collapses) + " collapses, " +
                  format_number(per(static_cast<double>(r.evaluations), static_cast<double>(r.collapses))) +
                  " evaluations/collapse, " + format_count(r.legality_checks) + " legality checks");
  row("rejected", rejected_text(r));
  if (verbosity() >= Verbosity::kVerbose) row("phases", phases_text(r));
  if (verbosity() >= Verbosity::kDebug) print_rounds(last.rounds);
  if (r.status != Status::kOk) row("status", std::string(to_string(r.status)) + (r.message.empty() ? "" : ": " + r.message));
  print_stop_report(r);
}

// --levels: one table row per level (size, field error, cumulative time, angles, topology).
void print_level_table(const SimplifyJob& job, const SimplifyRun& run) {
  const auto angle = [&](const QualityStats& q, const SampleStats QualityStats::*which, double scale) {
    return job.metrics ? format_number((q.*which).std_dev * scale) : std::string("-");
  };
  row("engine", engine_text(run));
  std::fprintf(report_stream(), "\n%6s %10s %9s %8s %9s %7s %7s  %s\n", "%", "#vert", "rms", "time", "dihedral", "solid", "face",
              "topology");
  std::fprintf(report_stream(), "%6s %10s %9s %8s %9s %7s %7s\n", "100", format_count(run.vertices_in).c_str(), "0", "0",
              angle(run.input_quality, &QualityStats::dihedral_deg, kRadiansPerDegree).c_str(),
              angle(run.input_quality, &QualityStats::solid_sr, 1.0).c_str(),
              angle(run.input_quality, &QualityStats::face_deg, kRadiansPerDegree).c_str());
  for (const LevelResult& l : run.levels) {
    char pct[32];
    std::snprintf(pct, sizeof pct, "%.1f", 100.0 * per(static_cast<double>(l.report.vertices_after), run.vertices_in));
    std::fprintf(report_stream(), "%6s %10s %9s %8s %9s %7s %7s  %s\n", pct, format_count(l.report.vertices_after).c_str(),
                l.field_error ? format_number(l.field_error->worst_rms_rel).c_str() : "-",
                format_number(l.cumulative_seconds).c_str(),
                angle(l.quality, &QualityStats::dihedral_deg, kRadiansPerDegree).c_str(),
                angle(l.quality, &QualityStats::solid_sr, 1.0).c_str(),
                angle(l.quality, &QualityStats::face_deg, kRadiansPerDegree).c_str(),
                !l.verified ? (l.topology_ok ? "-" : "FAIL") : (l.topology_ok ? "PASS" : "FAIL"));
  }
  std::fprintf(report_stream(), "(rms relative to the field's range; time = cumulative simplify seconds; std dev of dihedral and "
              "face angles in rad, solid angles in sr)\n\n");
  std::string written;
  for (const LevelResult& l : run.levels)
    if (!l.output_path.empty()) written += (written.empty() ? "" : ", ") + l.output_path;
  if (!written.empty()) row("wrote", written);
  for (const LevelResult& l : run.levels)
    if (l.report.status != Status::kOk)
      row("status", "level " + format_ratio(l.target_ratio) + ": " + to_string(l.report.status) +
                        (l.report.message.empty() ? "" : ": " + l.report.message));
}

void print_hierarchy(const SimplifyJob& job, const SimplifyRun& run) {
  const auto bytes = std::filesystem::file_size(job.hierarchy_path);
  const double n = static_cast<double>(run.hierarchy.collapse_count());
  row("hierarchy", job.hierarchy_path + ": " + format_count(run.hierarchy.collapse_count()) + " collapses, " +
                       format_bytes(bytes) + " (records " +
                       format_number(per(static_cast<double>(hierarchy_collapse_bytes(run.hierarchy)), n)) +
                       " bytes/collapse, " + format_number(per(static_cast<double>(run.hierarchy.parents.size()), n)) +
                       " parents/collapse; write " + format_seconds(run.hierarchy_write_seconds) + ")");
}

// "cell data: 3 arrays (density: intensive, region: categorical, mass: extensive), remapped in ..."
void print_cell_data(const SimplifyRun& run) {
  std::string arrays;
  for (const CellField& f : run.cell_arrays)
    arrays += (arrays.empty() ? "" : ", ") + f.name + ": " + cell_kind_name(f.kind) +
              (f.components == 1 ? "" : " x" + std::to_string(f.components));
  double seconds = 0;
  std::uint64_t nearest_new = 0, nearest_original = 0;
  for (const LevelResult& l : run.levels) {
    if (!l.cell_remap) continue;
    seconds += l.cell_remap->seconds;
    nearest_new += l.cell_remap->nearest_new_tets;
    nearest_original += l.cell_remap->nearest_original_tets;
  }
  row("cell data", std::to_string(run.cell_arrays.size()) + (run.cell_arrays.size() == 1 ? " array (" : " arrays (") +
                       arrays + "), remapped by overlap volume in " + format_seconds(seconds) + " (" +
                       format_number(100.0 * per(seconds, run.cumulative_seconds)) + "% of simplify)");
  if (nearest_new + nearest_original > 0)
    row("", format_count(nearest_new) + " output tets overlap no input tet of their material and took the nearest one's "
            "values; " + format_count(nearest_original) + " input tets are covered by none (extensive amounts moved to the nearest)");
}

void print_memory(const SimplifyRun& run) {
  row("memory", "peak " + format_bytes(run.peak_bytes) + " (" +
                    format_count(run.tets_in ? run.peak_bytes / run.tets_in : 0) + " bytes/input tet); model " +
                    format_count(run.tets_in ? run.model_bytes / run.tets_in : 0) + " bytes/tet");
}

// One level: angles, mean ratio and field error, input -> output.
void print_quality(const SimplifyRun& run) {
  const LevelResult& last = run.levels.back();
  row("quality", "std dev dihedral/solid/face " + angles_text(run.input_quality) + " -> " + angles_text(last.quality) +
                     " (rad/sr/rad)");
  row("", "min mean ratio " + format_number(run.input_quality.mean_ratio.min) + " -> " +
              format_number(last.quality.mean_ratio.min) + ", min dihedral " +
              format_number(run.input_quality.dihedral_deg.min) + " -> " + format_number(last.quality.dihedral_deg.min) +
              " degrees, inverted tets " + std::to_string(last.quality.inverted) + " (" +
              format_seconds(run.times.input_quality + last.quality_seconds) + ")");
  const auto share = [](std::size_t n, std::size_t of) { return format_number(of ? 100.0 * static_cast<double>(n) / static_cast<double>(of) : 0.0); };
  row("", "tets with a dihedral under 10 degrees " + format_count(run.input_quality.under_10_deg) + " (" +
              share(run.input_quality.under_10_deg, run.input_quality.tet_count) + "%) -> " +
              format_count(last.quality.under_10_deg) + " (" + share(last.quality.under_10_deg, last.quality.tet_count) +
              "%), under 5 degrees " + format_count(run.input_quality.under_5_deg) + " -> " +
              format_count(last.quality.under_5_deg));
  if (last.field_error) {
    row("fields", field_text(*last.field_error) + " (" + format_seconds(last.field_error_seconds) + ")");
    if (verbosity() >= Verbosity::kVerbose) print_field_components(*last.field_error);
  }
}

void print_features(const SimplifyJob& job, const SimplifyRun& run) {
  std::uint64_t edges = 0, corners = 0;
  for (const LevelResult& l : run.levels) {
    edges += l.report.feature_edges;
    corners += l.report.feature_corners;
  }
  row("features", format_count(edges) + " sharp edges (> " + format_number(job.options.feature_angle) +
                      " degrees), " + format_count(corners) + " corners pinned (found in " +
                      format_seconds(run.levels.front().report.feature_seconds) + ")" +
                      (job.feature_ref ? "; written as edges with ref " + std::to_string(*job.feature_ref) : ""));
}

void print_optimize(const SimplifyJob& job, const Report& r) {
  row("optimize", std::string(to_string(job.options.optimize)) + ": " + format_count(r.optimize_moves) +
                      " vertex moves in " + std::to_string(r.optimize_passes) + " passes, from " +
                      format_count(r.optimize_candidates) + " movable vertices of badly shaped tets; " +
                      format_count(r.optimize_flips) + " face and edge flips (" +
                      format_seconds(r.optimize_seconds) + ")" +
                      (r.stall_flips > 0 ? "; before that, " + format_count(r.stall_flips) +
                                               " flips where the collapses stalled (" + format_seconds(r.stall_flip_seconds) + ")"
                                         : std::string()));
}

// The limits the run relaxed to reach its target (SimplifyOptions::relax_tolerance, relax_quality),
// from what to what: the output's guarantees hold with the relaxed values.
void print_relaxations(const Report& r) {
  if (r.relaxations.empty()) return;
  const std::string text = relaxations_text(r);
  const bool floors_kept =
      r.status == Status::kStoppedEarly && std::string(r.stop.dominant) == "quality" && !r.floors_may_relax();
  row("relaxed", text + (floors_kept ? " on the way; the quality floors stay at their lowest, min(asked, the input's worst tet) (min dihedral " +
                                           format_number(r.min_dihedral_lowest) + " degrees, min quality " +
                                           format_number(r.min_quality_lowest) + "), which hold the rest"
                                     : std::string(" to reach the target")) +
                     "; the output holds its guarantees with these values (a limit given as "
                     "an option, or --hard-limits, holds as given; choosing took " + format_seconds(r.relax_seconds) + ")");
}

void print_tolerance(const SimplifyJob& job, const Report& r) {
  const bool relaxed = r.tolerance != r.tolerance_asked;
  const bool relative = job.options.tolerance <= 0 && job.options.tolerance_rel > 0;
  const auto of_diagonal = [&](double h) {
    return relative ? " (" + format_number(100.0 * job.options.tolerance_rel * h / r.tolerance_asked) + "% of the diagonal)" : std::string();
  };
  row("tolerance", format_number(r.tolerance) + of_diagonal(r.tolerance) +
                       (relaxed ? ", relaxed from " + format_number(r.tolerance_asked) + of_diagonal(r.tolerance_asked) : "") +
                       (r.tolerance_limited ? ", may have stopped the run before the target (it refused " +
                                                  format_count(r.rejected_by(RejectReason::kTolerance)) + " collapses)"
                                            : "") +
                       " (Embree scene of the input's surfaces built in " +
                       format_seconds(r.tolerance_setup_seconds) + ")");
}

// The field error bound kept through the run, against the error measured at the original vertices.
void print_field_bounds(const SimplifyJob& job, const LevelResult& last) {
  const Report& r = last.report;
  const bool limited = job.options.max_field_error > 0 || job.options.max_field_error_rel > 0;
  std::string limit;
  if (job.options.max_field_error > 0) limit += format_number(job.options.max_field_error) + " (field units)";
  if (job.options.max_field_error_rel > 0)
    limit += (limit.empty() ? "" : " and ") + format_number(job.options.max_field_error_rel) + " of the range";
  const bool everywhere = job.options.field_bound_mode == FieldBoundMode::kEverywhere;
  row("bounds", "field error bound " + format_number(r.field_bound_rel) + " (relative to the range, worst component" +
                    (everywhere ? ", at every point the output covers)" : ", at the original vertices)") +
                    (last.field_error ? ", measured " + format_number(last.field_error->worst_max_rel_at_original()) +
                                            " at the original vertices"
                                      : "") +
                    (last.field_error && last.field_error->original_in_simplified.outside > 0
                         ? " (" + format_count(last.field_error->original_in_simplified.outside) +
                               " of them outside the output: bounded only approximately)"
                         : "") +
                    (last.dense_bounds && last.dense_bounds->points > 0
                         ? ", " + format_number(last.dense_bounds->worst_error_rel) + " at " +
                               format_count(last.dense_bounds->points) + " points inside (" +
                               (last.dense_bounds->violations == 0
                                    ? std::string("none above its tet's bound")
                                    : format_count(last.dense_bounds->violations) + " above their tet's bound") +
                               ")"
                         : "") +
                    (last.field_bound_ok == false ? " FAIL: above the bound" : "") +
                    (limited ? "; limit " + limit + ", refused " +
                                   format_count(r.rejected_by(RejectReason::kFieldError)) + " collapses"
                             : "") +
                    " (" + format_bytes(r.field_bounds_bytes) + ")");
}

// Every level kept the topology (and has no inverted tet); run.all_ok also counts the field bounds.
bool topology_ok(const SimplifyRun& run) {
  return std::all_of(run.levels.begin(), run.levels.end(), [](const LevelResult& l) { return l.topology_ok; });
}

void print_topology(const SimplifyJob& job, const SimplifyRun& run) {
  const bool ok = topology_ok(run);
  if (!job.metrics) {
    row("topology", "not checked (--no-metrics: no quality, field error, distance or topology)");
  } else if (!job.verify) {
    row("topology", std::string("not checked (--no-verify)") + (ok ? "" : "; FAIL: inverted tets"));
  } else {
    const std::string how = run.fast_topology
                                ? "fast mode for inputs > 2M tets: Euler characteristics and components only"
                                : std::to_string(complex_count(run.input_topology)) + " complexes, Betti numbers over Z2";
    row("topology", std::string(ok ? "PASS" : "FAIL") + (job.levels.empty() ? "" : " at every level") + " (" +
                        how + ", " + format_seconds(run.times.input_topology + run.times.topology) + ")");
  }
}

// Each failing level's differences: on the report stream, or alone on stderr with -q.
void print_failures(const SimplifyJob& job, const SimplifyRun& run) {
  std::FILE* out = job.quiet ? stderr : report_stream();
  const auto any = [&](auto failed) { return std::any_of(run.levels.begin(), run.levels.end(), failed); };
  if (job.quiet && any([](const LevelResult& l) { return !l.topology_ok; })) std::fprintf(out, "topology: FAIL\n");
  if (job.quiet && any([](const LevelResult& l) { return l.field_bound_ok == false; }))
    std::fprintf(out, "field bounds: FAIL\n");
  for (const LevelResult& l : run.levels)
    for (const std::string& line : split_lines(l.differences + l.field_bound_failure))
      std::fprintf(out, "  %s%s\n", job.levels.empty() ? "" : ("level " + format_ratio(l.target_ratio) + ": ").c_str(),
                   line.c_str());
}

Json input_json(const SimplifyJob& job, const SimplifyRun& run) {
  // The counts come from the run: the input itself may have been released (SimplifyJob::reload)
  // and not read again (--no-metrics).
  Json input = {{"file", job.input_label},
                {"vertices", run.vertices_in},
                {"tets", run.tets_in},
                {"read_seconds", job.read_seconds}};
  input["generated"] = job.read_verb == "generate";  // the demo's mesh: read_seconds is its generation
  input["build_seconds"] = run.build_seconds;
  input["model_bytes"] = run.model_bytes;
  input["model_bytes_per_tet"] = per(static_cast<double>(run.model_bytes), static_cast<double>(run.tets_in));
  input["quality"] = job.metrics ? quality_json(run.input_quality) : Json(nullptr);
  input["quality_seconds"] = run.times.input_quality;
  input["topology_report"] = run.verify ? topology_report_json(run.input_topology) : Json(nullptr);
  input["topology_seconds"] = run.times.input_topology;
  return input;
}

// --isosurface: each level as embedded (its ref names its triangles in the outputs and in the
// topology reports' "surfaces").
Json isosurfaces_json(const SimplifyJob& job) {
  Json out = Json::array();
  for (const IsoLevel& l : job.options.isosurfaces)
    out.push_back({{"field", l.field}, {"component", l.component}, {"value", l.value}, {"ref", l.ref}});
  return out;
}

Json options_json(const SimplifyJob& job, const SimplifyRun& run) {
  return {{"engine", run.is_parallel ? "parallel" : "sequential"},
          {"threads", run.threads},
          {"target_vertex_ratio", job.levels.empty() ? Json(job.options.target_vertex_ratio) : Json(nullptr)},
          {"target_vertices", job.levels.empty() ? Json(job.options.target_vertices) : Json(nullptr)},
          {"levels", job.levels},
          {"max_cost", job.options.max_cost},
          {"min_quality", job.options.min_quality},
          {"min_dihedral", job.options.min_dihedral},
          {"round_fraction", job.options.round_fraction},
          {"tolerance", job.options.tolerance},
          {"tolerance_rel", job.options.tolerance_rel},
          {"relax_tolerance", job.options.relax_tolerance},
          {"relax_quality", job.options.relax_quality},
          {"relax_features", job.options.relax_features},
          {"max_field_error", job.options.max_field_error},
          {"max_field_error_rel", job.options.max_field_error_rel},
          {"feature_angle", job.options.feature_angle},
          {"optimize", to_string(job.options.optimize)},
          {"field_weights", job.options.field_weights},
          {"isosurfaces", isosurfaces_json(job)},
          {"vertex_map", job.vertex_map_path},
          {"verify", run.verify},
          {"metrics", job.metrics}};
}

}  // namespace

void print_report(const SimplifyJob& job, const SimplifyRun& run) {
  if (!job.quiet) {
    const LevelResult& last = run.levels.back();
    const Report& r = last.report;
    print_input(job, run);
    if (job.levels.empty()) print_single_level(run);
    else print_level_table(job, run);
    if (!job.hierarchy_path.empty()) print_hierarchy(job, run);
    if (!job.vertex_map_path.empty())
      row("vertex map", job.vertex_map_path + ": " + format_count(job.vertex_map_entries) + " input vertices -> their output vertex (write " +
                            format_seconds(run.vertex_map_write_seconds) + ")");
    print_memory(run);
    if (!run.cell_arrays.empty()) print_cell_data(run);
    if (job.levels.empty() && job.metrics) print_quality(run);
    if (job.options.feature_angle < 180.0) print_features(job, run);
    if (job.levels.empty() && job.options.optimize != Optimize::kNone && job.hierarchy_path.empty()) print_optimize(job, r);
    if (job.levels.empty() && r.tolerance > 0) print_tolerance(job, r);
    if (job.levels.empty()) print_relaxations(r);
    if (job.levels.empty() && r.field_bounds) print_field_bounds(job, last);
    if (job.levels.empty() && job.metrics)
      print_surface_distance(last.distance, last.distance_seconds, /*per_label=*/verbosity() >= Verbosity::kVerbose);
    print_topology(job, run);
    if (job.metrics) row("measure", measure_text(run.times, run.cumulative_seconds));
  }
  if (!run.all_ok) print_failures(job, run);
}

void write_json_report(const SimplifyJob& job, const SimplifyRun& run) {
  const MeasureTimes& times = run.times;
  Json j = json_header("simplify");
  j["input"] = input_json(job, run);
  j["options"] = options_json(job, run);
  j["peak_rss_bytes"] = run.peak_bytes;
  j["peak_rss_bytes_per_input_tet"] = per(static_cast<double>(run.peak_bytes), static_cast<double>(run.tets_in));
  j["measure_seconds"] = times.input_quality + times.quality + times.field_error + times.distance;
  j["verify_seconds"] = times.input_topology + times.topology;
  j["reload_seconds"] = times.reload;
  j["metrics_seconds"] = times.total();
  j["metrics_share_of_simplify"] = per(times.total(), run.cumulative_seconds);
  j["topology_mode"] = !run.verify ? "skipped" : (run.fast_topology ? "fast" : "full");
  const bool topology_passed = topology_ok(run);
  j["topology"] = !run.verify ? (topology_passed ? "skipped" : "fail") : (topology_passed ? "pass" : "fail");
  // Every check of the run: the topology (inverted tets included) and the field error bounds.
  j["checks"] = run.all_ok ? "pass" : "fail";
  Json cells = Json::array();
  for (const CellField& f : run.cell_arrays)
    cells.push_back({{"name", f.name}, {"components", f.components}, {"kind", cell_kind_name(f.kind)}});
  j["cell_arrays"] = cells;
  j["levels"] = Json::array();
  for (const LevelResult& l : run.levels) j["levels"].push_back(level_json(l));
  if (!job.levels_error.empty()) j["error_levels"] = run.error_levels;
  write_json_atomically(job.report_path, j);
}

}  // namespace topotet::cli
