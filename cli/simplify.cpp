// topotet simplify IN -o OUT [...]: the simplification pipeline, as a sequence of named steps.
//
//   parse (job_from_args) -> read (read_input) -> build (build_model)
//     -> simplify, level by level, each level written as soon as it is done (simplify_levels)
//     -> measure each output: quality, field error, surface distance, topology against the input's
//        (measure_levels; --no-verify skips the topology, --no-metrics all four)
//     -> report: the text (print_report) and the JSON report (write_json_report), simplify_report.h.
// The outputs are measured after the last level so that the peak memory reported is the one of
// reading, building and simplifying, not of the checker. Each measurement is timed on its own, so
// the report shows what the measurements cost next to the simplification.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "common.h"
#include "simplify_options.h"
#include "simplify_report.h"
#include "topotet/cell_fields.h"
#include "topotet/error.h"
#include "topotet/hierarchy.h"
#include "topotet/isosurface.h"
#include "topotet/io.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/surface_distance.h"
#include "topotet/metrics/topology.h"
#include "topotet/threads.h"
#include "topotet/vertex_map_file.h"

namespace topotet::cli {
namespace {

// Inputs above this use the checker's fast mode (Euler characteristics and components only).
constexpr std::size_t kFastCheckTets = 2'000'000;

// ---- checks before any work ----

// Where the outputs go (stdout at most once, known formats, existing folders), so that a typo
// fails before the run, not after it.
void check_outputs(const SimplifyJob& job) {
  if (job.output_path == "-" && job.report_path == "-")
    throw InputError("-o - and --json -: only one of them can go to stdout");
  if (job.output_path == "-") {
    if (!job.output_format) throw InputError("-o -: the output format must be given (--format mesh, msh or vtu)");
    if (!job.levels.empty()) throw InputError("-o -: --levels writes several meshes, stdout takes one");
  }
  // Data on stdout: the human-readable report moves to stderr.
  if (job.output_path == "-" || job.report_path == "-") send_report_to_stderr();
  if (!job.output_path.empty() && !job.output_format) {
    check_output_format(job.output_path);  // unknown extensions fail before the work
    if (job.output_path.size() >= 3 && job.output_path.compare(job.output_path.size() - 3, 3, ".gz") == 0)
      throw_input_error(job.output_path, "writing compressed (.gz) files is not supported");
  }
  check_output_folder(job.output_path);
  check_output_folder(job.report_path);
  check_output_folder(job.vertex_map_path);
}

// The threads that really run: the default arena follows the process's CPU affinity (taskset),
// which hardware_concurrency() does not. Asking for more only oversubscribes the cores (and makes
// TBB print a warning on stderr); the output is the same for every count, so cap it. Returns the
// number that runs.
int cap_threads(SimplifyOptions& options) {
  const int available = current_thread_limit();
  if (options.num_threads > available) {
    print_note("--threads " + std::to_string(options.num_threads) + ": this process may use " +
               std::to_string(available) + " core" + (available == 1 ? "" : "s") + " (CPU affinity); running " +
               std::to_string(available) + " threads (the output is the same for every count)");
    options.num_threads = available;
  }
  return options.num_threads > 0 ? options.num_threads : available;
}

// ---- build ----

// The engine's model of the input (it validates it); the input loses what the model left out, so
// that the checker compares the output with what the model holds.
TetMesh build_model(SimplifyJob& job, SimplifyRun& run, BuildNotes& notes) {
  TetMesh mesh = build_input(job.input_label, job.input, &run.build_seconds, &notes);
  drop_noted_substructures(job.input, notes);
  run.model_bytes = mesh.memory_bytes();
  run.vertices_in = job.input.vertex_count();
  run.tets_in = job.input.tet_count();
  if (job.reload) {
    // The remap of the cell arrays needs only the input's tets and their arrays: those stay.
    if (!job.input.cell_fields.empty()) {
      job.cell_source.positions = std::move(job.input.positions);
      job.cell_source.tets = std::move(job.input.tets);
      job.cell_source.tet_material = std::move(job.input.tet_material);
      job.cell_source.cell_fields = std::move(job.input.cell_fields);
    }
    job.input = MeshData{};  // see SimplifyJob::reload
  }
  return mesh;
}

// The input again, as the model saw it, when the measurements need it and build_model let it go.
void reload_input(SimplifyJob& job, const BuildNotes& notes, SimplifyRun& run) {
  if (!job.reload || !job.metrics) return;
  log_stage("measure: read the input again");
  const Stopwatch clock;
  job.input = job.reload();
  drop_noted_substructures(job.input, notes);
  run.times.reload = clock.seconds();
}

// ---- simplify, level by level ----

// The options of one level: a --levels ratio becomes a vertex target (0 = the job's own target).
SimplifyOptions level_options(const SimplifyJob& job, double level, std::uint64_t vertices_in) {
  SimplifyOptions options = job.options;
  if (level > 0) {
    options.target_vertices =
        std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(level * static_cast<double>(vertices_in))));
  }
  return options;
}

// Simplifies `mesh` further, to `level`'s target, with a progress bar; the report goes to `result`.
void simplify_level(const SimplifyJob& job, double level, TetMesh& mesh, SimplifyRun& run, LevelResult& result) {
  SimplifyOptions options = level_options(job, level, run.vertices_in);
  ProgressBar bar(level > 0 ? "level " + format_ratio(level) : "simplify", !job.quiet, parse_progress_mode(job.progress),
                  job.progress_interval);
  options.on_progress = [&bar](double done) {
    bar.update(done);
    return true;
  };
  log_stage("simplify" + (level > 0 ? " level " + format_ratio(level) : std::string()) + ": start");
  if (verbosity() >= Verbosity::kDebug) options.round_log = &result.rounds;
  if (!job.hierarchy_path.empty()) result.report = simplify_with_hierarchy(mesh, options, run.hierarchy);
  else if (!job.vertex_map_path.empty()) result.report = simplify(mesh, options, run.vertex_map);
  else result.report = simplify(mesh, options);
  bar.finish();
  log_stage("simplify: " + format_count(result.report.collapses) + " collapses in " +
            format_seconds(result.report.seconds) + ", " + format_count(result.report.vertices_after) + " vertices left");
  if (result.report.status == Status::kInvalidInput) throw_input_error(job.input_label, result.report.message);
  if (result.report.status == Status::kOutOfMemory) throw_input_error(job.input_label, "out of memory while simplifying");
  run.cumulative_seconds += result.report.seconds;
  result.cumulative_seconds = run.cumulative_seconds;
}

// The input's cell arrays onto the level's tets (topotet/cell_fields.h), from the input or, when it
// was released, from the part of it build_model kept.
void remap_cells(const SimplifyJob& job, LevelResult& result) {
  const MeshData& source = job.cell_source.tets.empty() ? job.input : job.cell_source;
  if (source.cell_fields.empty()) return;
  log_stage("cell data: remap " + std::to_string(source.cell_fields.size()) + " arrays");
  result.cell_remap = remap_cell_fields(source, result.output, job.cell_remap);
  log_stage("cell data: " + format_count(result.cell_remap->overlap_pairs) + " overlaps in " +
            format_seconds(result.cell_remap->seconds));
}

// Writes the level's mesh (OUT, or OUT with the ratio before the extension), with the detected
// features when --feature-ref asks for them.
void write_level(const SimplifyJob& job, double level, const TetMesh& mesh, LevelResult& result) {
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
    MeshData with_features = mesh.to_mesh_data(export_options);
    with_features.cell_fields = result.output.cell_fields;  // the same tets, in the same order
    write_mesh_file(result.output_path, with_features, write_options);
  } else {
    write_mesh_file(result.output_path, result.output, write_options);
  }
  result.write_seconds = write_clock.seconds();
  log_stage("write " + result.output_path + " in " + format_seconds(result.write_seconds));
}

// Every level in turn, each simplifying the previous one's output; each is written (and the
// hierarchy rewritten) as soon as it is done. Then the peak memory, and the model is freed.
void simplify_levels(const SimplifyJob& job, TetMesh& mesh, SimplifyRun& run) {
  std::vector<double> levels = job.levels;
  if (levels.empty()) levels.push_back(0.0);
  for (double level : levels) {
    LevelResult& result = run.levels.emplace_back();
    result.target_ratio = level > 0 ? level : (job.options.target_vertices ? 0.0 : job.options.target_vertex_ratio);
    simplify_level(job, level, mesh, run, result);
    result.output = mesh.to_mesh_data();
    remap_cells(job, result);
    if (!job.output_path.empty()) write_level(job, level, mesh, result);
    if (!job.vertex_map_path.empty()) {
      // After the mesh: the map names its vertices. (--levels and --hierarchy exclude --vertex-map.)
      const Stopwatch write_clock;
      run.vertex_map.resize(job.vertex_map_entries);
      write_vertex_map(job.vertex_map_path, run.vertex_map);
      run.vertex_map_write_seconds = write_clock.seconds();
      log_stage("write " + job.vertex_map_path + " in " + format_seconds(run.vertex_map_write_seconds));
    }
    if (!job.hierarchy_path.empty()) {
      const Stopwatch write_clock;
      write_hierarchy(job.hierarchy_path, run.hierarchy);
      run.hierarchy_write_seconds = write_clock.seconds();
    }
  }
  run.peak_bytes = peak_rss_bytes();
  mesh = TetMesh{};  // the checker does not need the model
}

// ---- measure ----

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

// Whether the field error measured at the original vertices stays within the bounds the run
// kept (metrics' field_bound_violations, component by component): a broken bound fails the run.
// With --field-bound-mode everywhere, also at points between them (check_bounds_densely).
constexpr std::uint64_t kDenseBoundPoints = 100000;
void check_field_bounds(const SimplifyJob& job, LevelResult& l) {
  const Report& r = l.report;
  if (!r.field_bounds || !l.field_error) return;
  l.field_bound_failure.clear();
  bool checked = false;
  std::size_t stride = 0;
  for (const topotet::VertexField& f : l.output.fields) stride += static_cast<std::size_t>(f.components);
  if (stride > 0 && r.tet_field_bound.size() == l.output.tets.size() * stride) {
    l.dense_bounds = topotet::check_bounds_densely(job.input, l.output, r.tet_field_bound, kDenseBoundPoints, 1);
    if (r.field_bound_mode == FieldBoundMode::kEverywhere) {
      checked = true;
      if (l.dense_bounds->violations > 0)
        l.field_bound_failure += "field error bound exceeded between the original vertices: " +
                                 std::to_string(l.dense_bounds->violations) + " samples, first " +
                                 l.dense_bounds->first_violation + "\n";
    }
  }
  // At the original vertices: only when none lies outside the output (bounded only approximately there).
  if (l.field_error->original_in_simplified.outside == 0) {
    checked = true;
    for (const std::string& v : field_bound_violations(*l.field_error, r.field_bound))
      l.field_bound_failure += "field error bound exceeded: " + v + "\n";
  }
  if (checked) l.field_bound_ok = l.field_bound_failure.empty();
}

// Quality, field error, distance and topology of every level (as --no-metrics and --no-verify
// allow), and the verdict: a level fails on a changed topology, an inverted tet or a field error
// above the bound the run kept.
void measure_outputs(const SimplifyJob& job, SimplifyRun& run) {
  MeasureTimes& times = run.times;
  if (job.metrics) {
    const Stopwatch clock;
    run.input_quality = compute_quality(job.input);
    times.input_quality = clock.seconds();
    log_stage("measure: quality, field error, surface distance");
    measure_levels(job, run.levels);
  }
  run.fast_topology = run.tets_in > kFastCheckTets;
  if (run.verify) {
    log_stage(std::string("verify: topology of the input and the output") + (run.fast_topology ? " (fast mode)" : ""));
    run.input_topology = verify_levels(job, run.fast_topology, run.levels, times.input_topology);
    log_stage("verify: done");
  }
  for (LevelResult& l : run.levels) {
    if (l.measured && l.quality.inverted != 0) {
      l.topology_ok = false;
      l.differences += "inverted tets (quality check): " + std::to_string(l.quality.inverted) + "\n";
    }
    if (l.measured) {
      const Stopwatch clock;
      check_field_bounds(job, l);  // the dense samples are a field error measurement: timed with it
      l.field_error_seconds += clock.seconds();
    }
    times.quality += l.quality_seconds;
    times.field_error += l.field_error_seconds;
    times.distance += l.distance_seconds;
    times.topology += l.topology_seconds;
    run.all_ok = run.all_ok && l.topology_ok && l.field_bound_ok.value_or(true);
  }
}

// ---- `topotet simplify`: parse, read, run, and the levels of --levels-error ----

// The job the options ask for, without its input (a bad --levels or --format fails here, before
// any reading).
SimplifyJob job_from_args(const SimplifyArgs& args) {
  SimplifyJob job;
  job.levels = normalize_levels(args.levels);
  job.input_label = args.input;
  parse_format(args.format);
  job.output_format = format_for(args.output, args.format);
  job.options = engine_options(args);
  job.feature_ref = args.feature_ref;
  job.output_path = args.output;
  job.hierarchy_path = args.hierarchy;
  job.vertex_map_path = args.vertex_map;
  if (!job.vertex_map_path.empty()) check_vertex_map_path(job.vertex_map_path);
  job.binary = args.binary;
  job.msh22 = args.msh22;
  job.report_path = args.report;
  job.verify = !args.no_verify;
  job.metrics = !args.no_metrics;
  job.quiet = verbosity() == Verbosity::kQuiet;
  job.progress = args.progress;
  job.progress_interval = args.progress_interval;
  job.cell_remap.extensive = args.extensive;
  job.cell_remap.categorical = args.categorical;
  return job;
}

// Whether a file the job writes (an output level, its .sol companion, the hierarchy) may be the
// input or its companion: then the input must stay in memory (SimplifyJob::reload).
bool writes_over(const SimplifyJob& job, const std::string& input) {
  const auto base = [](const std::string& path) {
    std::filesystem::path p(path);
    if (p.extension() == ".gz") p = p.replace_extension();
    std::error_code error;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(p.replace_extension(), error);
    return error ? p.lexically_normal() : canonical;
  };
  const std::filesystem::path in = base(input);
  std::vector<std::string> written{job.output_path, job.hierarchy_path};
  for (double level : job.levels) written.push_back(level_path(job.output_path, level));
  for (const std::string& path : written)
    if (!path.empty() && path != "-" && base(path) == in) return true;
  return false;
}

ReadOptions read_options_of(const SimplifyArgs& args) {
  ReadOptions read_options;
  read_options.tets_only = args.tets_only;
  read_options.format = format_for(args.input, args.format);
  read_options.material_array = args.material_array;
  return read_options;
}

// --levels-error: one run, one hierarchy, every level: the levels are extracted, not re-simplified.
int extract_error_levels(const SimplifyJob& job, Json& rows) {
  WriteOptions write_options;
  write_options.binary = job.binary;
  write_options.msh22 = job.msh22;
  std::fprintf(report_stream(), "\nlevels from %s:\n", job.hierarchy_path.c_str());
  return print_error_levels(read_hierarchy(job.hierarchy_path), job.output_path, job.levels_error, write_options, &rows);
}

// --isosurface: the levels are embedded into the input before the model is built (the output is
// then checked against the embedded input, where the level sets are listed surfaces), and the
// engine is told their refs so that their vertices keep the level. A reload embeds them again
// (deterministic: the same mesh).
void embed_levels(SimplifyJob& job) {
  const std::vector<IsoLevel> levels = job.options.isosurfaces;
  log_stage("isosurfaces: embed " + std::to_string(levels.size()) + " level(s)");
  IsoEmbedReport report;
  try {
    report = embed_isosurfaces(job.input, levels);
  } catch (const InputError& e) {
    throw_input_error(job.input_label, e.what());
  }
  job.options.isosurfaces = report.levels;
  for (std::size_t i = 0; i < report.levels.size(); ++i) {
    const IsoLevel& l = report.levels[i];
    const IsoLevelStats& s = report.stats[i];
    std::string name;
    for (const GroupName& g : job.input.group_names)
      if (g.dim == 2 && g.ref == l.ref) name = g.name;
    std::fprintf(report_stream(), "isosurface %s: ref %d, %s triangles, %s tets split into %s more, %s vertices added%s in %s\n",
                 name.c_str(), l.ref, format_count(s.triangles).c_str(), format_count(s.tets_split).c_str(),
                 format_count(s.tets_added).c_str(), format_count(s.vertices_added).c_str(),
                 s.vertices_snapped ? (", " + format_count(s.vertices_snapped) + " snapped to the level").c_str() : "",
                 format_seconds(s.seconds).c_str());
  }
  if (job.reload)
    job.reload = [reload = job.reload, levels] {
      MeshData data = reload();
      embed_isosurfaces(data, levels);
      return data;
    };
}

int run_simplify(const SimplifyArgs& args) {
  if (!args.memory_limit.empty() || args.pieces != 0 || args.piece_tets != 0) return run_simplify_out_of_core(args);
  SimplifyJob job = job_from_args(args);
  job.input = read_input(args.input, &job.read_seconds, read_options_of(args));
  if (args.input != "-" && !writes_over(job, args.input)) {
    std::error_code time_error, size_error;
    const auto written = std::filesystem::last_write_time(args.input, time_error);
    const auto size = std::filesystem::file_size(args.input, size_error);
    if (!time_error && !size_error) {  // else (not a regular file?) the input stays in memory
      job.reload = [path = args.input, options = read_options_of(args), written, size] {
        std::error_code now;
        if (std::filesystem::last_write_time(path, now) != written || std::filesystem::file_size(path, now) != size || now)
          throw InputError(path + ": the input changed during the run; the output is written, but it cannot be "
                                  "measured against the input (run `topotet check` on a copy)");
        double seconds = 0.0;
        return read_input(path, &seconds, options);
      };
    }
  }
  job.vertex_map_entries = job.input.vertex_count();
  if (!job.options.isosurfaces.empty()) {
    // The split tets share an extensive array's amount by volume: its kind must be known first.
    apply_cell_kinds(job.input.cell_fields, job.cell_remap);
    embed_levels(job);
  }
  // A hierarchy with fields records each collapse's field error bound (Hierarchy::error_bound), so
  // that `extract --max-error` and --levels-error select by a guaranteed error, not by a cost.
  if (!job.hierarchy_path.empty() && !job.input.fields.empty() && !args.no_field_bounds)
    job.options.track_field_bounds = true;
  if (!args.levels_error.empty() && job.hierarchy_path.empty())
    throw InputError("--levels-error needs --hierarchy H.tth (the levels are extracted from it)");
  job.levels_error = args.levels_error;
  return run_simplify_job(job);
}

}  // namespace

int run_simplify_job(SimplifyJob& job) {
  check_outputs(job);
  SimplifyRun run;
  // The kinds of the cell arrays (an --extensive NAME the input lacks fails here, before the work).
  for (const CellField& f : job.input.cell_fields) run.cell_arrays.push_back({f.name, f.components, f.kind, {}});
  apply_cell_kinds(run.cell_arrays, job.cell_remap);
  run.threads = cap_threads(job.options);
  run.is_parallel = job.options.engine == Engine::kParallel;
  run.verify = job.verify && job.metrics;
  // Everything runs within the thread limit, so --threads also bounds building and checking, not
  // only the simplifier.
  run_with_thread_limit(job.options.num_threads, [&] {
    BuildNotes notes;
    TetMesh mesh = build_model(job, run, notes);
    simplify_levels(job, mesh, run);
    job.cell_source = MeshData{};  // the remap is done: the measurements read the input again
    reload_input(job, notes, run);
    measure_outputs(job, run);
    print_report(job, run);
    // After the report (the hierarchy is written), so that the JSON report holds the levels too.
    if (!job.levels_error.empty() && extract_error_levels(job, run.error_levels) != kExitOk) run.all_ok = false;
    if (!job.report_path.empty()) write_json_report(job, run);
  });
  return run.all_ok ? kExitOk : kExitCheckFailed;
}

void add_simplify_command(CLI::App& app, CommandRunner& run) {
  auto args = std::make_shared<SimplifyArgs>();
  CLI::App* cmd = app.add_subcommand(
      "simplify", "Simplify by topology-preserving edge collapses, write OUT, report speed, quality and the topology "
                  "verdict (exit 1 if the topology changed).");
  add_simplify_options(cmd, *args);
  cmd->callback([args, &run] { run = [args] { return run_simplify(*args); }; });
}

}  // namespace topotet::cli
