// Shared pieces of the `topotet` command-line tool: command registration, timing, formatting,
// peak memory, error reporting, the progress bar and atomic JSON output. topotet-mpi (cli/mpi/)
// uses the verbosity, the report stream and the format and output checks too (topotet_cli_common).
//
// Every command file defines one add_*_command(app, run): it registers the subcommand and its
// options, and when CLI11 selects it, stores in `run` the function main() calls (inside its
// try/catch) after parsing. A command returns its exit code:
//   kExitOk (0) success, kExitCheckFailed (1) a failed check (topology, inverted tets),
//   kExitBadInput (2) bad usage or bad input.
// Errors are thrown, never printed by commands: main() prints exactly one line
//   topotet: error: <file>: <message>
// (InputError messages from the readers already start with the file; input_error() adds it to
// those that do not, e.g. the builder's "tet 17: zero volume ...").
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "topotet/cell_fields.h"
#include "topotet/hierarchy.h"
#include "topotet/io.h"
#include "topotet/mesh_data.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"

namespace topotet::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitCheckFailed = 1;
inline constexpr int kExitBadInput = 2;

using CommandRunner = std::function<int()>;
using Json = nlohmann::ordered_json;  // keeps keys in insertion order: stable, readable reports

void add_info_command(CLI::App& app, CommandRunner& run);
void add_generate_command(CLI::App& app, CommandRunner& run);
void add_convert_command(CLI::App& app, CommandRunner& run);
void add_simplify_command(CLI::App& app, CommandRunner& run);
void add_check_command(CLI::App& app, CommandRunner& run);
void add_demo_command(CLI::App& app, CommandRunner& run);
void add_extract_command(CLI::App& app, CommandRunner& run);

// ---- simplification pipeline, shared by `simplify` and `demo` (simplify.cpp) ----
struct SimplifyJob {
  std::string input_label;  // file name, or a description of a generated mesh
  MeshData input;           // the input as read (for verification and field errors)
  // Reads (or generates) the input again. When set, the input is released once the model is built
  // and brought back only for the measurements, so it does not sit in memory beside the model
  // during the simplification (about 26 bytes per input tet; the model keeps what the engine
  // needs). Empty (standard input): the input stays.
  std::function<MeshData()> reload;
  double read_seconds = 0.0;
  std::string read_verb = "read";  // "generate" for the demo
  SimplifyOptions options;     // target and engine settings (targets overridden by `levels`)
  std::vector<double> levels;  // descending vertex ratios; empty = one run with `options`
  // --levels-error: after the run, one level per field error bound, extracted from the hierarchy
  // (needs hierarchy_path); printed after the report and in the JSON report's "error_levels".
  std::vector<double> levels_error;
  std::string output_path;     // empty = write nothing
  std::string hierarchy_path;  // --hierarchy: also record the collapses into this .tth file
  // --vertex-map: also write, for each of the first vertex_map_entries input vertices (the file's:
  // an isosurface's vertices come after them), the output vertex it became (topotet/vertex_map_file.h).
  std::string vertex_map_path;
  std::uint64_t vertex_map_entries = 0;
  std::optional<std::int32_t> feature_ref;  // also write detected features, with this ref
  bool binary = false;         // WriteOptions::binary
  bool msh22 = false;          // WriteOptions::msh22
  std::optional<MeshFormat> output_format;  // format of output_path "-" (stdout)
  std::string report_path;     // empty = no JSON report
  bool verify = true;        // run the topology checker (--no-verify skips only it)
  bool metrics = true;       // measure quality, field error, distance and topology (--no-metrics: none)
  bool quiet = false;
  std::string progress = "auto";     // ProgressMode, parsed before any reading
  double progress_interval = 10.0;  // seconds between lines (--progress lines)
  // Cell data (topotet/cell_fields.h): the kinds --extensive / --categorical give, and the part of
  // the input the remap needs (positions, tets, materials, cell fields) when `reload` releases the
  // input: about a third of it; empty when the input has no cell arrays or stays in memory.
  CellRemapOptions cell_remap;
  MeshData cell_source;
};
// Builds, simplifies, writes, measures and verifies; prints the report. Returns the exit code.
int run_simplify_job(SimplifyJob& job);
// topotet simplify --memory-limit / --pieces: out of core (cli/simplify_out_of_core.cpp).
struct SimplifyArgs;
int run_simplify_out_of_core(const SimplifyArgs& args);

// ---- levels of a collapse hierarchy (extract.cpp) ----
// One uniform level per error threshold, written as `output` with the threshold before the
// extension; prints one table row per level (size, field error, error bound, angles, topology
// against the original). Returns kExitCheckFailed if a level fails the check. `rows` (optional):
// the same rows for a JSON report, one object per level, appended to it (an array).
int print_error_levels(const Hierarchy& hierarchy, const std::string& output, std::vector<double> levels,
                       const WriteOptions& write_options, Json* rows = nullptr);

// ---- timing ----
class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// ---- formatting (timings with 2-3 significant digits) ----
std::string format_seconds(double seconds);      // "0.8 ms", "12.3 ms", "1.23 s", "45.6 s", "123 s"
std::string format_count(std::uint64_t n);       // "1,234,567"
std::string format_bytes(std::uint64_t bytes);   // "812 kB", "12.3 MB", "1.23 GB" (decimal)
std::string format_number(double x, int digits = 3);  // %.*g
std::string format_ratio(double x);              // "0.3" / "0.25": shortest text of a level
// The limits a run relaxed (Report::relaxations), per limit from its first value to its last:
// "tolerance H 1.32 -> 42.1 (5 steps), min dihedral 5 -> 0.625 degrees (3 steps), ..."; empty if
// none. The `relaxed` row of topotet simplify (in core and out of core) and of topotet-mpi.
std::string relaxations_text(const Report& r);
Json relaxations_json(const Report& r);  // [{limit, from, to, vertices_left, share}], for --json

// ---- system ----
std::uint64_t peak_rss_bytes();  // VmHWM of /proc/self/status; 0 if unavailable
bool stderr_is_terminal();
int hardware_threads();

// ---- errors ----
// An InputError whose message starts with `file` (unless it already does).
[[noreturn]] void throw_input_error(const std::string& file, const std::string& message);
std::string prefix_file(const std::string& file, const std::string& message);

// Where the human-readable report goes: stdout, or stderr once a command sends data (a mesh or
// the JSON report, path "-") to stdout, so that the two never mix; nowhere with -q.
std::FILE* report_stream();
void send_report_to_stderr();

// ---- verbosity: -q, (default), -v, -vv on every command ----
//   kQuiet    errors, warnings and a failed check only (a batch job's log stays empty when all is well)
//   kNormal   the report
//   kVerbose  also details: the effective options, phase times, every field component and surface
//             label, and notes on stderr ("topotet: note: ...") for what the tool decided for the
//             user (a --threads value capped to the cores it may use, a format guessed)
//   kDebug    also a log of every stage on stderr with the time since start ("topotet: [1.23 s]
//             build: ..."), and one line per parallel round
// Warnings (input left out, repeated elements) print at every level: they say the output is not
// what the input asked for.
enum class Verbosity : int { kQuiet = 0, kNormal = 1, kVerbose = 2, kDebug = 3 };
Verbosity verbosity();
// Registers -v/--verbose (give it twice for kDebug) and -q/--quiet on a command.
void add_verbosity_flags(CLI::App* cmd);
void print_note(const std::string& message);  // kVerbose and above
void log_stage(const std::string& message);   // kDebug

// --format: "mesh", "msh" or "vtu"; empty = none. Throws InputError.
std::optional<MeshFormat> parse_format(const std::string& name);
// The format --format gives `path`: it applies to "-" and to paths without a mesh extension
// (/dev/null, a FIFO); others go by their extension (nullopt).
std::optional<MeshFormat> format_for(const std::string& path, const std::string& format_option);

// Option checks with plain messages, run while parsing (before any file is read): CLI11's own
// print "not in range 0.000000 to 1797693...(309 digits)" for any bad value, even "abc".
//   number_in(lo, hi, lo_open): "'abc' is not a number", "0 is not in (0, 1]"
//   whole_number_at_least(lo): "-3 is not a whole number >= 0"
CLI::Validator number_in(double lo, double hi, bool lo_open);
CLI::Validator whole_number_at_least(long long lo);

// One line on stderr: "topotet: warning: <file>: <message>".
void print_warning(const std::string& file, const std::string& message);

// The reading and writing of the tools: topotet::read_mesh / write_mesh, with the VTK formats of
// topotet/io_vtk.h (read_any_mesh / write_any_mesh) when the build has that component
// (TOPOTET_HAVE_VTK); without it the core refuses those paths with a message that says so.
MeshData read_mesh_file(const std::string& path, const ReadOptions& options, ReadNotes* notes);
// Warns (print_warning) about what an Exodus II output leaves out (edges, corners).
void write_mesh_file(const std::string& path, const MeshData& mesh, const WriteOptions& options);
// True when `path` is read through the VTK component (never without it).
bool is_vtk_input(const std::string& path);
// Throws InputError unless the tools can write `path` (by its extension), before any work.
void check_output_format(const std::string& path);
// The warnings of ReadNotes: cells and arrays left out. `tool` prefixes the lines.
void warn_about_read_notes(const std::string& path, const ReadNotes& notes, const char* tool = "topotet");
// The help of --material-array (the same text on every command that reads).
extern const char* const kMaterialArrayHelp;

// read_mesh / build_tet_mesh with the file named in every error. build_input leaves out listed
// triangles and segments that are not on any tet, and keeps a repeated one (same element, same
// ref) once, with one warning line each (BuildOptions::skip_detached_substructures says why);
// `notes` receives what was left out, for drop_noted_substructures.
// read_input warns about the cells it left out (ReadNotes; mixed meshes need tets_only).
MeshData read_input(const std::string& path, double* seconds = nullptr, const ReadOptions& options = {});
TetMesh build_input(const std::string& label, const MeshData& data, double* seconds = nullptr,
                    BuildNotes* notes = nullptr);

// The values of --levels (CLI11 splits "0.5,0.3,0.1" at the commas): checks each is in (0, 1],
// sorts them descending and drops repeats. Throws InputError on a bad value.
std::vector<double> normalize_levels(std::vector<double> levels);

// `out.mesh` + 0.3 -> `out_0.3.mesh` (the extension includes a trailing .gz).
std::string level_path(const std::string& path, double level);

// Throws InputError unless the folder `path` would be written in exists (checked before long work,
// so that a typo in -o does not cost the whole run).
void check_output_folder(const std::string& path);

// Writes `text` like write_mesh (topotet/io.h: atomically, or straight through "-", FIFOs and
// devices); throws InputError naming the path.
void write_text_atomically(const std::string& path, const std::string& text);
void write_json_atomically(const std::string& path, const Json& json);

// ---- progress on stderr ----
// kAuto draws a bar when stderr is a terminal and nothing otherwise; kLines prints one plain line
// every `interval` seconds (batch schedulers' logs, where a bar's carriage returns are noise);
// kNone stays silent. Nothing shows before the work has run for a second. update() may be called
// from any thread but never concurrently (SimplifyOptions::on_progress's contract).
enum class ProgressMode { kAuto, kBar, kLines, kNone };
ProgressMode parse_progress_mode(const std::string& text);  // "auto", "bar", "lines", "none"

class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool enabled = true, ProgressMode mode = ProgressMode::kAuto,
                       double interval_seconds = 10.0);
  ~ProgressBar() { finish(); }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  void update(double done_fraction);
  void finish();  // erases the bar if it was drawn

 private:
  std::string label_;
  ProgressMode mode_;  // kBar, kLines or kNone once resolved
  double interval_seconds_;
  bool drawn_ = false;
  double last_draw_seconds_ = -1.0;
  Stopwatch clock_;
};

}  // namespace topotet::cli
