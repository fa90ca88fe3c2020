// topotet simplify IN -o OUT [...]: the simplification pipeline and its report.
//
//   read -> build (validates) -> for each level: simplify, to_mesh_data, write
//        -> measure each output: quality, field error, surface distance, topology against the input's
//           (--no-verify skips the topology, --no-metrics all four)
//        -> print the report (one block, or one table row per level) and the JSON report.
// The outputs are measured after the last level so that the peak memory reported is the one of
// reading, building and simplifying, not of the checker. Each measurement is timed on its own, so
// the report shows what the measurements cost next to the simplification.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <limits>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <optional>

#include "common.h"
#include "distance_report.h"
#include "json_report.h"
#include "stop_report.h"
#include "topotet/error.h"
#include "topotet/hierarchy.h"
#include "topotet/io.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/topology.h"
#include "topotet/round_log.h"
#include "topotet/threads.h"

namespace topotet::cli {
namespace {

// Inputs above this use the checker's fast mode (Euler characteristics and components only).
constexpr std::size_t kFastCheckTets = 2'000'000;

// The JSON key of a reject reason: to_string's name in snake_case ("link_K" -> "link_k").
std::string reason_key(RejectReason reason) {
  std::string key = to_string(reason);
  for (char& c : key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return key;
}
constexpr const char* kPhaseKeys[4] = {"evaluate", "select", "apply", "compact"};

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;

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
  std::string differences;
  topotet::TopologyReport topology;
  std::vector<RoundStats> rounds;  // filled at -vv only (SimplifyOptions::round_log)
};

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
          {"components", components},
          {"measured_max_rel", l.field_error ? Json(l.field_error->worst_max_rel_at_original()) : Json(nullptr)},
          // The bound covers these only up to the tet they were attached to (engine/guarantees/field_bounds.h).
          {"original_vertices_outside",
           l.field_error ? Json(l.field_error->original_in_simplified.outside) : Json(nullptr)},
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
  j["field_bounds"] = field_bounds_json(l);
  j["feature_edges"] = r.feature_edges;
  j["feature_corners"] = r.feature_corners;
  j["feature_candidates"] = r.feature_candidates;
  j["feature_turns"] = r.feature_turns;
  j["feature_scale"] = r.feature_scale;
  j["feature_seconds"] = r.feature_seconds;
  j["stopped"] = stop_report_json(r);
  j["surface_distance"] = l.measured ? surface_distance_json(l.distance) : Json(nullptr);
  j["surface_distance_seconds"] = l.distance_seconds;
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

// -v: what the run was asked for, after the defaults and the thread cap.
std::string options_text(const SimplifyOptions& o, const std::vector<double>& levels) {
  std::string s;
  if (!levels.empty()) {
    s = "levels";
    for (double l : levels) s += " " + format_ratio(l);
  } else if (o.target_vertices) {
    s = "target " + format_count(o.target_vertices) + " vertices";
  } else {
    s = "ratio " + format_number(o.target_vertex_ratio);
  }
  if (o.max_cost > 0) s += ", max cost " + format_number(o.max_cost);
  s += ", min quality " + format_number(o.min_quality);
  s += o.tolerance > 0 ? ", tolerance " + format_number(o.tolerance)
       : o.tolerance_rel > 0 ? ", tolerance " + format_number(100.0 * o.tolerance_rel) + "% of the diagonal"
                             : std::string(", no tolerance");
  s += o.feature_angle < 180.0 ? ", feature angle " + format_number(o.feature_angle) : std::string(", no features");
  if (o.engine == Engine::kParallel) s += ", round fraction " + format_number(o.round_fraction);
  s += ", boundary weight " + format_number(o.boundary_weight) + ", polyline weight " + format_number(o.polyline_weight);
  for (const auto& [name, weight] : o.field_weights) s += ", weight of " + name + " " + format_number(weight);
  return s;
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

}  // namespace

namespace {

// Times of the measurements of every level together, for the report's "measure" line.
struct MeasureTimes {
  double input_quality = 0.0, quality = 0.0, field_error = 0.0, distance = 0.0, input_topology = 0.0, topology = 0.0;
  double total() const { return input_quality + quality + field_error + distance + input_topology + topology; }
};

// Quality, field error and surface distance of every level's output against the input.
void measure_levels(const SimplifyJob& job, std::vector<LevelResult>& results) {
  const bool has_fields = !job.input.fields.empty();
  // The input's side of the field comparison is prepared once for all levels.
  std::optional<FieldErrorReference> input_fields;
  if (has_fields) input_fields.emplace(job.input);
  for (LevelResult& l : results) {
    Stopwatch clock;
    l.quality = compute_quality(l.output);
    l.quality_seconds = clock.seconds();
    if (has_fields) {
      clock = Stopwatch();
      l.field_error = input_fields->compare(l.output);
      l.field_error_seconds = clock.seconds();
    }
    clock = Stopwatch();
    l.distance = surface_distance(job.input, l.output, report_surface_distance_options());
    l.distance_seconds = clock.seconds();
    l.measured = true;
  }
}

// The output of every level against the input's topology; returns the input's.
topotet::TopologyReport verify_levels(const SimplifyJob& job, bool fast, std::vector<LevelResult>& results,
                                      double& input_seconds) {
  topotet::TopologyOptions options;
  options.fast = fast;
  const Stopwatch input_clock;
  topotet::TopologyReport input_topology = topotet::compute_topology(job.input, options);
  input_seconds = input_clock.seconds();
  for (LevelResult& l : results) {
    const Stopwatch clock;
    l.topology = topotet::compute_topology(l.output, options);
    l.topology_ok = topotet::same_topology(input_topology, l.topology, &l.differences);
    l.verified = true;
    l.topology_seconds = clock.seconds();
  }
  return input_topology;
}

std::string measure_text(const MeasureTimes& t, double simplify_seconds) {
  std::string s = "quality " + format_seconds(t.input_quality + t.quality) + ", fields " +
                  format_seconds(t.field_error) + ", distance " + format_seconds(t.distance) + ", topology " +
                  format_seconds(t.input_topology + t.topology);
  char share[64] = "";
  if (simplify_seconds > 0)
    std::snprintf(share, sizeof share, " = %.0f%% of the simplification", 100.0 * t.total() / simplify_seconds);
  return s + " (total " + format_seconds(t.total()) + share + ")";
}

}  // namespace

int run_simplify_job(SimplifyJob& job) {
  if (job.output_path == "-" && job.report_path == "-")
    throw InputError("-o - and --json -: only one of them can go to stdout");
  if (job.output_path == "-") {
    if (!job.output_format) throw InputError("-o -: the output format must be given (--format mesh, msh or vtu)");
    if (!job.levels.empty()) throw InputError("-o -: --levels writes several meshes, stdout takes one");
  }
  // Data on stdout: the human-readable report moves to stderr.
  if (job.output_path == "-" || job.report_path == "-") send_report_to_stderr();
  if (!job.output_path.empty() && !job.output_format) {
    format_from_path(job.output_path);  // unknown extensions fail before the work
    if (job.output_path.size() >= 3 && job.output_path.compare(job.output_path.size() - 3, 3, ".gz") == 0)
      throw_input_error(job.output_path, "writing compressed (.gz) files is not supported");
  }
  check_output_folder(job.output_path);
  check_output_folder(job.report_path);
  // The threads that really run: the default arena follows the process's CPU affinity (taskset),
  // which hardware_concurrency() does not. Asking for more only oversubscribes the cores (and
  // makes TBB print a warning on stderr); the output is the same for every count, so cap it.
  const int available = current_thread_limit();
  if (job.options.num_threads > available) {
    print_note("--threads " + std::to_string(job.options.num_threads) + ": this process may use " +
               std::to_string(available) + " core" + (available == 1 ? "" : "s") + " (CPU affinity); running " +
               std::to_string(available) + " threads (the output is the same for every count)");
    job.options.num_threads = available;
  }
  const int threads = job.options.num_threads > 0 ? job.options.num_threads : available;
  const bool is_parallel = job.options.engine == Engine::kParallel;
  const bool verify = job.verify && job.metrics;

  // Everything runs within `threads` threads, so --threads also bounds building and checking, not
  // only the simplifier.
  int exit_code = kExitOk;
  run_with_thread_limit(job.options.num_threads, [&] {
    double build_seconds = 0.0;
    BuildNotes notes;
    TetMesh mesh = build_input(job.input_label, job.input, &build_seconds, &notes);
    // The checker must compare the output with what the model holds, not with left-out elements.
    drop_noted_substructures(job.input, notes);
    const std::size_t model_bytes = mesh.memory_bytes();
    const std::uint64_t vertices_in = job.input.vertex_count(), tets_in = job.input.tet_count();

    // ---- simplify, level by level ----
    std::vector<double> levels = job.levels;
    if (levels.empty()) levels.push_back(0.0);
    std::vector<LevelResult> results;
    double cumulative = 0.0;
    Hierarchy hierarchy;  // --hierarchy
    double hierarchy_write_seconds = 0.0;
    for (double level : levels) {
      LevelResult& result = results.emplace_back();
      result.target_ratio = level > 0 ? level : (job.options.target_vertices ? 0.0 : job.options.target_vertex_ratio);
      SimplifyOptions options = job.options;
      if (level > 0) {
        options.target_vertices = std::max<std::uint64_t>(
            1, static_cast<std::uint64_t>(std::llround(level * static_cast<double>(vertices_in))));
      }
      ProgressBar bar(level > 0 ? "level " + format_ratio(level) : "simplify", !job.quiet,
                      parse_progress_mode(job.progress), job.progress_interval);
      options.on_progress = [&bar](double done) {
        bar.update(done);
        return true;
      };
      log_stage("simplify" + (level > 0 ? " level " + format_ratio(level) : std::string()) + ": start");
      if (verbosity() >= Verbosity::kDebug) options.round_log = &result.rounds;
      result.report = job.hierarchy_path.empty() ? simplify(mesh, options)
                                                 : simplify_with_hierarchy(mesh, options, hierarchy);
      bar.finish();
      log_stage("simplify: " + format_count(result.report.collapses) + " collapses in " +
                format_seconds(result.report.seconds) + ", " + format_count(result.report.vertices_after) + " vertices left");
      if (result.report.status == Status::kInvalidInput) throw_input_error(job.input_label, result.report.message);
      if (result.report.status == Status::kOutOfMemory)
        throw_input_error(job.input_label, "out of memory while simplifying");
      cumulative += result.report.seconds;
      result.cumulative_seconds = cumulative;
      result.output = mesh.to_mesh_data();
      if (!job.output_path.empty()) {
        result.output_path = level > 0 ? level_path(job.output_path, level) : job.output_path;
        const Stopwatch write_clock;
        WriteOptions write_options;
        write_options.binary = job.binary;
        write_options.msh22 = job.msh22;
        write_options.format = job.output_format;
        if (job.feature_ref) {
          // The features go to the file only: the checks compare the substructures of the input.
          MeshExportOptions export_options;
          export_options.feature_edges = true;
          export_options.feature_ref = *job.feature_ref;
          write_mesh(result.output_path, mesh.to_mesh_data(export_options), write_options);
        } else {
          write_mesh(result.output_path, result.output, write_options);
        }
        result.write_seconds = write_clock.seconds();
        log_stage("write " + result.output_path + " in " + format_seconds(result.write_seconds));
      }
      if (!job.hierarchy_path.empty()) {
        const Stopwatch write_clock;
        write_hierarchy(job.hierarchy_path, hierarchy);
        hierarchy_write_seconds = write_clock.seconds();
      }
    }
    const std::uint64_t peak_bytes = peak_rss_bytes();
    mesh = TetMesh{};  // the checker does not need the model

    // ---- measure and verify ----
    MeasureTimes times;
    QualityStats input_quality;
    if (job.metrics) {
      const Stopwatch clock;
      input_quality = compute_quality(job.input);
      times.input_quality = clock.seconds();
      log_stage("measure: quality, field error, surface distance");
      measure_levels(job, results);
    }
    const bool fast = tets_in > kFastCheckTets;
    topotet::TopologyReport input_topology;
    if (verify) {
      log_stage(std::string("verify: topology of the input and the output") + (fast ? " (fast mode)" : ""));
      input_topology = verify_levels(job, fast, results, times.input_topology);
      log_stage("verify: done");
    }
    bool all_ok = true;
    for (LevelResult& l : results) {
      if (l.measured && l.quality.inverted != 0) {
        l.topology_ok = false;
        l.differences += "inverted tets (quality check): " + std::to_string(l.quality.inverted) + "\n";
      }
      times.quality += l.quality_seconds;
      times.field_error += l.field_error_seconds;
      times.distance += l.distance_seconds;
      times.topology += l.topology_seconds;
      all_ok = all_ok && l.topology_ok;
    }

    // ---- print ----
    const LevelResult& last = results.back();
    const Report& r = last.report;
    if (!job.quiet) {
      row("input", job.input_label + ": " + format_count(vertices_in) + " vertices, " + format_count(tets_in) +
                       " tets (" + job.read_verb + " " + format_seconds(job.read_seconds) + ", build " + format_seconds(build_seconds) +
                       ")");
      if (verbosity() >= Verbosity::kVerbose) row("options", options_text(job.options, job.levels));
      const std::string engine_text = is_parallel ? "parallel, " + std::to_string(threads) + " thread" +
                                                        (threads == 1 ? "" : "s")
                                                  : std::string("sequential");
      if (job.levels.empty()) {
        char pct[32];
        std::snprintf(pct, sizeof pct, "%.1f%%", 100.0 * per(static_cast<double>(r.vertices_after), vertices_in));
        row("output", (last.output_path.empty() ? std::string("(not written)") : last.output_path) + ": " +
                          format_count(r.vertices_after) + " vertices (" + pct + "), " + format_count(r.tets_after) +
                          " tets" + (last.output_path.empty() ? "" : " (write " + format_seconds(last.write_seconds) + ")"));
        row("time", format_seconds(r.seconds) + " " + engine_text + ", " +
                        format_count(static_cast<std::uint64_t>(per(static_cast<double>(r.collapses), r.seconds))) +
                        " collapses/s" + (is_parallel ? ", " + format_count(r.rounds) + " rounds" : ""));
        row("work", format_count(r.collapses) + " collapses, " +
                        format_number(per(static_cast<double>(r.evaluations), static_cast<double>(r.collapses))) +
                        " evaluations/collapse, " + format_count(r.legality_checks) + " legality checks");
        row("rejected", rejected_text(r));
        if (verbosity() >= Verbosity::kVerbose) row("phases", phases_text(r));
        if (verbosity() >= Verbosity::kDebug) print_rounds(last.rounds);
        if (r.status != Status::kOk) row("status", std::string(to_string(r.status)) + (r.message.empty() ? "" : ": " + r.message));
        print_stop_report(r);
      } else {
        const auto angle = [&](const QualityStats& q, const SampleStats QualityStats::*which, double scale) {
          return job.metrics ? format_number((q.*which).std_dev * scale) : std::string("-");
        };
        row("engine", engine_text);
        std::fprintf(report_stream(), "\n%6s %10s %9s %8s %9s %7s %7s  %s\n", "%", "#vert", "rms", "time", "dihedral", "solid", "face",
                    "topology");
        std::fprintf(report_stream(), "%6s %10s %9s %8s %9s %7s %7s\n", "100", format_count(vertices_in).c_str(), "0", "0",
                    angle(input_quality, &QualityStats::dihedral_deg, kRadiansPerDegree).c_str(),
                    angle(input_quality, &QualityStats::solid_sr, 1.0).c_str(),
                    angle(input_quality, &QualityStats::face_deg, kRadiansPerDegree).c_str());
        for (const LevelResult& l : results) {
          char pct[32];
          std::snprintf(pct, sizeof pct, "%.1f", 100.0 * per(static_cast<double>(l.report.vertices_after), vertices_in));
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
        for (const LevelResult& l : results)
          if (!l.output_path.empty()) written += (written.empty() ? "" : ", ") + l.output_path;
        if (!written.empty()) row("wrote", written);
        for (const LevelResult& l : results)
          if (l.report.status != Status::kOk)
            row("status", "level " + format_ratio(l.target_ratio) + ": " + to_string(l.report.status) +
                              (l.report.message.empty() ? "" : ": " + l.report.message));
      }
      if (!job.hierarchy_path.empty()) {
        const auto bytes = std::filesystem::file_size(job.hierarchy_path);
        const double n = static_cast<double>(hierarchy.collapse_count());
        row("hierarchy", job.hierarchy_path + ": " + format_count(hierarchy.collapse_count()) + " collapses, " +
                             format_bytes(bytes) + " (records " +
                             format_number(per(static_cast<double>(hierarchy_collapse_bytes(hierarchy)), n)) +
                             " bytes/collapse, " + format_number(per(static_cast<double>(hierarchy.parents.size()), n)) +
                             " parents/collapse; write " + format_seconds(hierarchy_write_seconds) + ")");
      }
      row("memory", "peak " + format_bytes(peak_bytes) + " (" +
                        format_count(tets_in ? peak_bytes / tets_in : 0) + " bytes/input tet); model " +
                        format_count(tets_in ? model_bytes / tets_in : 0) + " bytes/tet");
      if (job.levels.empty() && job.metrics) {
        row("quality", "std dev dihedral/solid/face " + angles_text(input_quality) + " -> " +
                           angles_text(last.quality) + " (rad/sr/rad)");
        row("", "min mean ratio " + format_number(input_quality.mean_ratio.min) + " -> " +
                    format_number(last.quality.mean_ratio.min) + ", inverted tets " +
                    std::to_string(last.quality.inverted) + " (" +
                    format_seconds(times.input_quality + last.quality_seconds) + ")");
        if (last.field_error) {
          row("fields", field_text(*last.field_error) + " (" + format_seconds(last.field_error_seconds) + ")");
          if (verbosity() >= Verbosity::kVerbose) print_field_components(*last.field_error);
        }
      }
      if (job.options.feature_angle < 180.0) {
        std::uint64_t edges = 0, corners = 0;
        for (const LevelResult& l : results) {
          edges += l.report.feature_edges;
          corners += l.report.feature_corners;
        }
        row("features", format_count(edges) + " sharp edges (> " + format_number(job.options.feature_angle) +
                            " degrees), " + format_count(corners) + " corners pinned (found in " +
                            format_seconds(results.front().report.feature_seconds) + ")" +
                            (job.feature_ref ? "; written as edges with ref " + std::to_string(*job.feature_ref) : ""));
      }
      if (job.levels.empty() && r.tolerance > 0)
        row("tolerance", format_number(r.tolerance) + (job.options.tolerance > 0 ? "" : " (" + format_number(100.0 * job.options.tolerance_rel) + "% of the diagonal)") +
                             (r.tolerance_limited ? ", may have stopped the run before the target (it refused " +
                                                        format_count(r.rejected_by(RejectReason::kTolerance)) + " collapses)"
                                                  : "") +
                             " (Embree scene of the input's surfaces built in " +
                             format_seconds(r.tolerance_setup_seconds) + ")");
      if (job.levels.empty() && r.field_bounds) {
        const bool limited = job.options.max_field_error > 0 || job.options.max_field_error_rel > 0;
        std::string limit;
        if (job.options.max_field_error > 0) limit += format_number(job.options.max_field_error) + " (field units)";
        if (job.options.max_field_error_rel > 0)
          limit += (limit.empty() ? "" : " and ") + format_number(job.options.max_field_error_rel) + " of the range";
        row("bounds", "field error bound " + format_number(r.field_bound_rel) + " (relative to the range, worst component)" +
                          (last.field_error ? ", measured " + format_number(last.field_error->worst_max_rel_at_original()) +
                                                  " at the original vertices"
                                            : "") +
                          (last.field_error && last.field_error->original_in_simplified.outside > 0
                               ? " (" + format_count(last.field_error->original_in_simplified.outside) +
                                     " of them outside the output: bounded only approximately)"
                               : "") +
                          (limited ? "; limit " + limit + ", refused " +
                                         format_count(r.rejected_by(RejectReason::kFieldError)) + " collapses"
                                   : "") +
                          " (" + format_bytes(r.field_bounds_bytes) + ")");
      }
      if (job.levels.empty() && job.metrics) print_surface_distance(last.distance, last.distance_seconds,
                                                                      /*per_label=*/verbosity() >= Verbosity::kVerbose);
      if (!job.metrics) {
        row("topology", "not checked (--no-metrics: no quality, field error, distance or topology)");
      } else if (!job.verify) {
        row("topology", std::string("not checked (--no-verify)") + (all_ok ? "" : "; FAIL: inverted tets"));
      } else {
        const std::string how = fast ? "fast mode for inputs > 2M tets: Euler characteristics and components only"
                                     : std::to_string(complex_count(input_topology)) + " complexes, Betti numbers over Z2";
        row("topology", std::string(all_ok ? "PASS" : "FAIL") + (job.levels.empty() ? "" : " at every level") + " (" +
                            how + ", " + format_seconds(times.input_topology + times.topology) + ")");
      }
      if (job.metrics) row("measure", measure_text(times, cumulative));
    }
    if (!all_ok) {
      std::FILE* out = job.quiet ? stderr : report_stream();
      if (job.quiet) std::fprintf(out, "topology: FAIL\n");
      for (const LevelResult& l : results)
        for (const std::string& line : split_lines(l.differences))
          std::fprintf(out, "  %s%s\n", job.levels.empty() ? "" : ("level " + format_ratio(l.target_ratio) + ": ").c_str(),
                       line.c_str());
    }

    // ---- JSON report ----
    if (!job.report_path.empty()) {
      Json j = json_header("simplify");
      Json input = mesh_json(job.input_label, job.input, job.read_seconds);
      input["generated"] = job.read_verb == "generate";  // the demo's mesh: read_seconds is its generation
      input["build_seconds"] = build_seconds;
      input["model_bytes"] = model_bytes;
      input["model_bytes_per_tet"] = per(static_cast<double>(model_bytes), static_cast<double>(tets_in));
      input["quality"] = job.metrics ? quality_json(input_quality) : Json(nullptr);
      input["quality_seconds"] = times.input_quality;
      input["topology_report"] = verify ? topology_report_json(input_topology) : Json(nullptr);
      input["topology_seconds"] = times.input_topology;
      j["input"] = input;
      j["options"] = {{"engine", is_parallel ? "parallel" : "sequential"},
                      {"threads", threads},
                      {"target_vertex_ratio", job.levels.empty() ? Json(job.options.target_vertex_ratio) : Json(nullptr)},
                      {"target_vertices", job.levels.empty() ? Json(job.options.target_vertices) : Json(nullptr)},
                      {"levels", job.levels},
                      {"max_cost", job.options.max_cost},
                      {"min_quality", job.options.min_quality},
                      {"round_fraction", job.options.round_fraction},
                      {"tolerance", job.options.tolerance},
                      {"tolerance_rel", job.options.tolerance_rel},
                      {"max_field_error", job.options.max_field_error},
                      {"max_field_error_rel", job.options.max_field_error_rel},
                      {"feature_angle", job.options.feature_angle},
                      {"field_weights", job.options.field_weights},
                      {"verify", verify},
                      {"metrics", job.metrics}};
      j["peak_rss_bytes"] = peak_bytes;
      j["peak_rss_bytes_per_input_tet"] = per(static_cast<double>(peak_bytes), static_cast<double>(tets_in));
      j["measure_seconds"] = times.input_quality + times.quality + times.field_error + times.distance;
      j["verify_seconds"] = times.input_topology + times.topology;
      j["metrics_seconds"] = times.total();
      j["metrics_share_of_simplify"] = per(times.total(), cumulative);
      j["topology_mode"] = !verify ? "skipped" : (fast ? "fast" : "full");
      j["topology"] = !verify ? (all_ok ? "skipped" : "fail") : (all_ok ? "pass" : "fail");
      j["levels"] = Json::array();
      for (const LevelResult& l : results) j["levels"].push_back(level_json(l));
      write_json_atomically(job.report_path, j);
    }
    exit_code = all_ok ? kExitOk : kExitCheckFailed;
  });
  return exit_code;
}

namespace {

struct SimplifyArgs {
  std::string input;
  std::string output;
  std::string hierarchy;  // --hierarchy
  std::vector<double> levels_error;  // --levels-error
  double ratio = 0.25;
  std::uint64_t target_vertices = 0;
  double max_cost = 0.0;
  double min_quality = SimplifyOptions{}.min_quality;
  double tolerance = -1.0;  // < 0: not given (the relative default applies)
  double tolerance_rel = SimplifyOptions{}.tolerance_rel;
  double max_field_error = 0.0;
  double max_field_error_rel = 0.0;
  bool field_bounds = false;
  bool no_field_bounds = false;  // --hierarchy without the bounds (cheaper; levels by cost)
  double feature_angle = SimplifyOptions{}.feature_angle;
  std::optional<std::int32_t> feature_ref;
  bool sequential = false;
  int threads = 0;
  double round_fraction = SimplifyOptions{}.round_fraction;
  std::string report;
  bool no_verify = false;
  bool no_metrics = false;
  std::vector<double> levels;
  std::vector<std::string> field_weights;  // NAME=W, checked by field_weight_syntax
  std::string progress = "auto";
  double progress_interval = 10.0;
  bool binary = false;
  bool tets_only = false;
  bool msh22 = false;
  std::string format;
};

// "NAME=W" with a non-empty NAME and W a finite number >= 0 (split at the last '=': a field name
// may contain one). Returns the CLI11 validator's message, empty when the value is fine.
std::string field_weight_syntax(const std::string& value, std::string* name = nullptr, double* weight = nullptr) {
  const std::size_t eq = value.rfind('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == value.size()) return "expected NAME=W, got '" + value + "'";
  char* end = nullptr;
  const double w = std::strtod(value.c_str() + eq + 1, &end);
  if (*end != '\0' || !std::isfinite(w) || w < 0.0) return "the weight in '" + value + "' must be a number >= 0";
  if (name) *name = value.substr(0, eq);
  if (weight) *weight = w;
  return {};
}

int run_simplify(const SimplifyArgs& args) {
  SimplifyJob job;
  job.levels = normalize_levels(args.levels);
  job.input_label = args.input;
  ReadOptions read_options;
  read_options.tets_only = args.tets_only;
  parse_format(args.format);  // a bad --format fails before reading
  read_options.format = format_for(args.input, args.format);
  job.output_format = format_for(args.output, args.format);
  job.input = read_input(args.input, &job.read_seconds, read_options);
  job.options.target_vertex_ratio = args.ratio;
  job.options.target_vertices = args.target_vertices;
  job.options.max_cost = args.max_cost;
  job.options.min_quality = args.min_quality;
  if (args.tolerance >= 0.0) {
    job.options.tolerance = args.tolerance;
    job.options.tolerance_rel = 0.0;  // --tolerance 0 turns the check off
  } else {
    job.options.tolerance_rel = args.tolerance_rel;
  }
  job.options.max_field_error = args.max_field_error;
  job.options.max_field_error_rel = args.max_field_error_rel;
  job.options.track_field_bounds = args.field_bounds;
  job.options.feature_angle = args.feature_angle;
  job.feature_ref = args.feature_ref;
  job.options.engine = args.sequential ? Engine::kSequential : Engine::kParallel;
  job.options.num_threads = args.threads;
  job.options.round_fraction = args.round_fraction;
  for (const std::string& entry : args.field_weights) {
    std::string name;
    double weight = 1.0;
    field_weight_syntax(entry, &name, &weight);  // checked when parsing
    job.options.field_weights[name] = weight;    // the last one given wins
  }
  job.output_path = args.output;
  job.hierarchy_path = args.hierarchy;
  // A hierarchy with fields records each collapse's field error bound (Hierarchy::error_bound), so
  // that `extract --max-error` and --levels-error select by a guaranteed error, not by a cost.
  if (!job.hierarchy_path.empty() && !job.input.fields.empty() && !args.no_field_bounds)
    job.options.track_field_bounds = true;
  if (!args.levels_error.empty() && job.hierarchy_path.empty())
    throw InputError("--levels-error needs --hierarchy H.tth (the levels are extracted from it)");
  job.binary = args.binary;
  job.msh22 = args.msh22;
  job.report_path = args.report;
  job.verify = !args.no_verify;
  job.metrics = !args.no_metrics;
  job.quiet = verbosity() == Verbosity::kQuiet;
  job.progress = args.progress;
  job.progress_interval = args.progress_interval;
  const int code = run_simplify_job(job);
  if (args.levels_error.empty()) return code;
  // One run, one hierarchy, every level: the levels are extracted, not re-simplified.
  WriteOptions write_options;
  write_options.binary = job.binary;
  write_options.msh22 = job.msh22;
  std::fprintf(report_stream(), "\nlevels from %s:\n", job.hierarchy_path.c_str());
  return std::max(code, print_error_levels(read_hierarchy(job.hierarchy_path), job.output_path, args.levels_error,
                                           write_options));
}

}  // namespace

void add_simplify_command(CLI::App& app, CommandRunner& run) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  auto args = std::make_shared<SimplifyArgs>();
  CLI::App* cmd = app.add_subcommand(
      "simplify", "Simplify by topology-preserving edge collapses, write OUT, report speed, quality and the topology "
                  "verdict (exit 1 if the topology changed).");
  cmd->add_option("IN", args->input, "Input mesh (.mesh, .msh, optionally .gz; - = stdin, with --format)")->required();
  cmd->add_option("-o,--output", args->output, "Output mesh (.mesh, .msh or .vtu; - = stdout, with --format)")->required();
  cmd->add_option("--format", args->format,
                  "Format of - (stdin/stdout) and of paths without a mesh extension (/dev/null, a FIFO): mesh, msh, vtu");
  auto* ratio = cmd->add_option("--ratio", args->ratio, "Keep this fraction of the vertices, in (0, 1]")
                    ->check(number_in(0.0, 1.0, true))
                    ->capture_default_str();
  auto* target = cmd->add_option("--target-vertices", args->target_vertices, "Stop at this many vertices");
  cmd->add_option("--max-cost,--max-error", args->max_cost,
                  "Stop when the cheapest collapse costs more (quadric error / bbox diagonal^2; 0 = no limit)")
      ->check(number_in(0.0, kInfinity, false))
      ->capture_default_str();
  cmd->add_option("--min-quality", args->min_quality, "Reject collapses creating tets below this mean ratio")
      ->check(number_in(0.0, 1.0, false))
      ->capture_default_str();
  auto* tolerance = cmd->add_option("--tolerance", args->tolerance,
                                    "Keep boundary, interfaces, surfaces and polylines within this distance of the "
                                    "original ones (mesh units; 0 = unchecked; default: --tolerance-rel)")
                       ->check(number_in(0.0, kInfinity, false));
  cmd->add_option("--tolerance-rel", args->tolerance_rel,
                  "The same, relative to the bounding box diagonal (0 = unchecked)")
      ->check(number_in(0.0, kInfinity, false))
      ->excludes(tolerance)
      ->capture_default_str();
  auto* max_field_error =
      cmd->add_option("--max-field-error", args->max_field_error,
                      "Refuse collapses that would let the field error at an original vertex exceed E (field units, "
                      "every component; a per-tet bound kept exact through the run); 0 = no limit")
          ->type_name("E")
          ->check(number_in(0.0, kInfinity, false));
  auto* max_field_error_rel =
      cmd->add_option("--max-field-error-rel", args->max_field_error_rel,
                      "The same, relative to each field component's range (both given: the smaller)")
          ->type_name("E")
          ->check(number_in(0.0, kInfinity, false));
  auto* field_bounds = cmd->add_flag("--field-bounds", args->field_bounds,
                                     "Keep the per-tet field error bounds and report them, without a limit");
  cmd->add_option("--feature-angle", args->feature_angle,
                  "Keep as feature curves (like polylines) the surface edges whose faces turn by more than this "
                  "angle in degrees, and pin their corners; 180 = off")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  cmd->add_option("--feature-ref", args->feature_ref,
                  "Also write the detected feature curves as edges (MEDIT ridges) with this ref, their corners as "
                  "corners (to inspect them)");
  cmd->add_flag("--sequential", args->sequential, "Use the sequential reference engine (lazy priority queue)");
  cmd->add_option("--threads", args->threads, "Threads (0 = all cores; the output is the same for every value)")
      ->check(whole_number_at_least(0))
      ->capture_default_str();
  cmd->add_option("--round-fraction", args->round_fraction,
                  "Parallel engine: the cheapest fraction of the proposals that compete in one round")
      ->check(number_in(0.0, 1.0, true))
      ->capture_default_str();
  cmd->add_option("--field-weight", args->field_weights,
                  "Weight W of field NAME in the cost (repeatable; fields not given weigh 1; 0 = carried but not "
                  "preserved); errors are relative to each field's range")
      ->type_name("NAME=W")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check([](const std::string& value) { return field_weight_syntax(value); });
  cmd->add_option("--json,--report", args->report, "Write the report as JSON to this file (- = stdout)");
  cmd->add_flag("--no-verify", args->no_verify, "Skip the topology checker (quality, field error and distance are still measured)");
  cmd->add_flag("--no-metrics", args->no_metrics,
                "Skip every measurement (quality, field error, Hausdorff distance, topology): report only counts, "
                "times and memory");
  auto* levels = cmd->add_option("--levels", args->levels,
                                 "Simplify successively to each vertex ratio, writing OUT with the ratio before the "
                                 "extension (out_0.3.mesh), one table row per level")
                     ->delimiter(',');
  levels->excludes(ratio)->excludes(target);
  // Each level simplifies the previous one's output: its bounds would be against that, not the input.
  for (CLI::Option* bounds_option : {max_field_error, max_field_error_rel, field_bounds}) levels->excludes(bounds_option);
  auto* hierarchy = cmd->add_option("--hierarchy", args->hierarchy,
                                    "Also record every collapse into this hierarchy file (.tth): `topotet extract` then "
                                    "gives any level, uniform or fine in a volume of interest; with fields, each "
                                    "collapse's field error bound too (levels by a guaranteed error)")
                        ->excludes(levels);
  cmd->add_flag("--no-field-bounds", args->no_field_bounds,
                "With --hierarchy: record no field error bounds (recording then costs a few percent instead of "
                "~20%; levels by error use the collapse cost)")
      ->needs(hierarchy)
      ->excludes(field_bounds);
  cmd->add_option("--levels-error", args->levels_error,
                  "With --hierarchy: also extract one uniform level per error threshold from it, written as OUT "
                  "with the threshold before the extension, with a table (the columns of --levels, the field "
                  "error and its bound)")
      ->delimiter(',')
      ->check(number_in(0.0, std::numeric_limits<double>::infinity(), false))
      ->excludes(levels);
  ratio->excludes(target);
  add_verbosity_flags(cmd);
  cmd->add_option("--progress", args->progress,
                  "auto (a bar when stderr is a terminal), bar, lines (one line every --progress-interval seconds, "
                  "for batch logs) or none")
      ->check(CLI::IsMember({"auto", "bar", "lines", "none"}))
      ->capture_default_str();
  cmd->add_option("--progress-interval", args->progress_interval, "Seconds between --progress lines")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--binary", args->binary, "Binary Gmsh 4.1 / raw appended VTU data");
  cmd->add_flag("--msh22", args->msh22, "Write .msh as Gmsh 2.2 ASCII (for tools that read only the old format)")
      ->excludes("--binary");
  cmd->add_flag("--tets-only", args->tets_only, "Leave hexahedra, prisms and pyramids out of a mixed mesh (with a warning and their count) instead of refusing it");
  cmd->callback([args, &run] { run = [args] { return run_simplify(*args); }; });
}

}  // namespace topotet::cli
