#include "common.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <thread>

#include "topotet/error.h"
#include "topotet/io.h"
#if TOPOTET_HAVE_VTK
#include "vtk_loader.h"
#endif

namespace topotet::cli {

// ---- formatting ----

std::string format_number(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

namespace {
// 3 significant digits without switching to exponent notation for values in [0.01, 1000).
std::string three_digits(double x) {
  char buf[64];
  if (x >= 99.95)
    std::snprintf(buf, sizeof buf, "%.0f", x);
  else if (x >= 9.995)
    std::snprintf(buf, sizeof buf, "%.1f", x);
  else
    std::snprintf(buf, sizeof buf, "%.2f", x);
  return buf;
}
}  // namespace

std::string format_seconds(double seconds) {
  if (!(seconds >= 0.0)) return "?";
  if (seconds < 0.9995) {
    const double ms = seconds * 1e3;
    if (ms < 0.01) return "0 ms";
    return three_digits(ms) + " ms";
  }
  return three_digits(seconds) + " s";
}

std::string format_count(std::uint64_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i != 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string format_bytes(std::uint64_t bytes) {
  const double b = static_cast<double>(bytes);
  if (b < 1e3) return std::to_string(bytes) + " B";
  if (b < 999.5e3) return three_digits(b / 1e3) + " kB";
  if (b < 999.5e6) return three_digits(b / 1e6) + " MB";
  return three_digits(b / 1e9) + " GB";
}

std::string format_ratio(double x) {
  // The shortest of %.1g .. %.6g that reads back to x (0.3 -> "0.3", 0.25 -> "0.25").
  for (int digits = 1; digits <= 17; ++digits) {
    const std::string s = format_number(x, digits);
    if (std::strtod(s.c_str(), nullptr) == x) return s;
  }
  return format_number(x, 17);
}

std::string relaxations_text(const Report& r) {
  struct Span {
    const char* limit;
    double from, to;
    int steps;
  };
  std::vector<Span> spans;  // per limit, in the order first relaxed
  for (const Relaxation& x : r.relaxations) {
    auto it = std::find_if(spans.begin(), spans.end(), [&](const Span& s) { return std::string(s.limit) == x.limit; });
    if (it == spans.end()) spans.push_back({x.limit, x.from, x.to, 1});
    else it->to = x.to, ++it->steps;
  }
  std::string text;
  for (const Span& s : spans) {
    const std::string limit = s.limit;
    if (limit == "features") {  // from and to: the feature edges before and after
      text += (text.empty() ? "" : ", ") + std::string("feature edges ") + format_count(static_cast<std::uint64_t>(s.from)) +
              " -> " + format_count(static_cast<std::uint64_t>(s.to)) + " (those lower than the relaxed H dropped)";
      continue;
    }
    const std::string name = limit == "tolerance" ? "tolerance H" : limit == "min_dihedral" ? "min dihedral" : "min quality";
    text += (text.empty() ? "" : ", ") + name + " " + format_number(s.from) + " -> " + format_number(s.to) +
            (limit == "min_dihedral" ? " degrees" : "") + " (" + std::to_string(s.steps) + (s.steps == 1 ? " step)" : " steps)");
  }
  return text;
}

Json relaxations_json(const Report& r) {
  Json a = Json::array();
  for (const Relaxation& x : r.relaxations)
    a.push_back({{"limit", x.limit}, {"from", x.from}, {"to", x.to}, {"vertices_left", x.vertices_left}, {"share", x.share}});
  return a;
}

// ---- system ----

std::uint64_t peak_rss_bytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) {
      // "VmHWM:     12345 kB"
      const unsigned long long kb = std::strtoull(line.c_str() + 6, nullptr, 10);
      return static_cast<std::uint64_t>(kb) * 1024u;
    }
  }
  return 0;
}

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

int hardware_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

// ---- errors ----

std::string prefix_file(const std::string& file, const std::string& message) {
  if (file.empty() || message.rfind(file, 0) == 0) return message;
  return file + ": " + message;
}

void throw_input_error(const std::string& file, const std::string& message) {
  throw InputError(prefix_file(file, message));
}

const char* const kMaterialArrayHelp =
    "VTK formats: the integer cell array that gives the materials (and the refs of triangles and edges); default: "
    "the first of material, gmsh:physical, ObjectId, ElementBlockIds, CellEntityIds (Exodus II: the element block ids; "
    "CGNS: the zone numbers)";

namespace {
bool ends_with_ci(std::string_view s, std::string_view suffix) {
  if (s.size() < suffix.size()) return false;
  for (std::size_t i = 0; i < suffix.size(); ++i) {
    char c = s[s.size() - suffix.size() + i];
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    if (c != suffix[i]) return false;
  }
  return true;
}
bool exodus_path(std::string_view path) {
  return ends_with_ci(path, ".exo") || ends_with_ci(path, ".e") || ends_with_ci(path, ".ex2");
}
}  // namespace

MeshData read_mesh_file(const std::string& path, const ReadOptions& options, ReadNotes* notes) {
#if TOPOTET_HAVE_VTK
  // As topotet::read_any_mesh (topotet/io_vtk.h), through the module loaded on first use.
  if (options.format ? *options.format == MeshFormat::kVtu : path != "-" && is_vtk_path(path))
    return read_vtk_via_module(path, options, notes);
  return read_mesh(path, options, notes);
#else
  return read_mesh(path, options, notes);
#endif
}

void write_mesh_file(const std::string& path, const MeshData& mesh, const WriteOptions& options) {
  if (!options.format && exodus_path(path)) {
    std::string left;
    const auto add = [&](std::size_t n, const char* what) {
      if (n != 0) left += (left.empty() ? "" : ", ") + format_count(n) + " " + what;
    };
    add(mesh.ridges.size(), "ridges (the edges are written, not their ridge mark)");
    add(static_cast<std::size_t>(std::count_if(mesh.vertex_refs.begin(), mesh.vertex_refs.end(), [](std::int32_t r) { return r != 0; })),
        "vertex refs");
    if (!left.empty()) print_warning(path, "Exodus II output: not written: " + left);
  }
#if TOPOTET_HAVE_VTK
  if (!options.format && is_exodus_path(path)) return write_exodus_via_module(path, mesh);
  write_mesh(path, mesh, options);
#else
  write_mesh(path, mesh, options);
#endif
}

bool is_vtk_input(const std::string& path) {
#if TOPOTET_HAVE_VTK
  return path != "-" && is_vtk_path(path);
#else
  (void)path;
  return false;
#endif
}

void check_output_format(const std::string& path) {
  for (const char* ext : {".pvtu", ".vtk", ".cgns"})
    if (ends_with_ci(path, ext))
      throw_input_error(path, std::string("writing ") + ext +
                                  " is not supported (written: .mesh, .meshb, .msh, .vtu, Exodus II .exo/.e/.ex2; topotet-mpi "
                                  "--partitioned writes .pvtu)");
#if TOPOTET_HAVE_VTK
  if (exodus_path(path)) return;
#endif
  format_from_path(path);
}

void warn_about_read_notes(const std::string& path, const ReadNotes& notes, const char* tool) {
  const auto warn = [&](const std::string& message) {
    if (std::string_view(tool) == "topotet") return print_warning(path, message);
    std::fprintf(stderr, "%s: warning: %s: %s\n", tool, path.c_str(), message.c_str());
  };
  if (notes.volume_cells() != 0) {
    std::string what;
    const auto add = [&](std::uint64_t n, const char* kind) {
      if (n == 0) return;
      what += (what.empty() ? "" : ", ") + std::to_string(n) + " " + kind;
    };
    add(notes.hexahedra, "hexahedra");
    add(notes.prisms, "prisms");
    add(notes.pyramids, "pyramids");
    add(notes.polyhedra, "polyhedra");
    warn("--tets-only: left out " + what + "; the output mesh covers the tets only");
  }
  if (notes.dropped_corners != 0)
    warn("left out " + std::to_string(notes.dropped_corners) +
         " Corners whose vertex index is out of range (TetGen -g lists its input points)");
  if (notes.quadrilaterals != 0)
    warn("left out " + std::to_string(notes.quadrilaterals) + " quadrilaterals (a quadrilateral is never a face of a tet)");
  if (!notes.unread_arrays.empty()) {
    std::string list, cells;
    for (const std::string& a : notes.unread_arrays) {
      if (a.rfind("cell array ", 0) == 0)
        cells += (cells.empty() ? "" : ", ") + a.substr(11);
      else
        list += (list.empty() ? "" : "; ") + a;
    }
    if (!cells.empty()) list += (list.empty() ? "" : "; ") + std::string("cell arrays ") + cells + " (cell data are not carried yet)";
    warn("not carried into the output: " + list);
  }
}

MeshData read_input(const std::string& path, double* seconds, const ReadOptions& options) {
  const Stopwatch clock;
  // The readers name the file in their errors; a missing file is checked here so that the message
  // is the usual one whatever the reader does.
  std::error_code ec;
  if (path != "-" && !std::filesystem::exists(path, ec)) throw_input_error(path, "no such file");
  MeshData data;
  log_stage("read " + path + ": start");
  try {
    ReadNotes notes;
    data = read_mesh_file(path, options, &notes);
    warn_about_read_notes(path, notes);
  } catch (const InputError& e) {
    throw_input_error(path, e.what());
  }
  if (seconds) *seconds = clock.seconds();
  log_stage("read " + path + ": " + format_count(data.vertex_count()) + " vertices, " + format_count(data.tet_count()) +
            " tets, " + format_count(data.triangles.size()) + " triangles, " + format_count(data.segments.size()) +
            " edges, " + std::to_string(data.fields.size()) + " fields in " + format_seconds(clock.seconds()));
  return data;
}

namespace {
std::FILE* g_report_stream = nullptr;  // nullptr = stdout (stdout is not a constant expression)
// The CLI's own settings (one process, one command): the library has no global state.
int g_verbose_count = 0;  // -v given this many times
bool g_quiet = false;
const Stopwatch g_process_clock;  // for the -vv log

// Where a -q report goes: a sink, so that the commands print the same way at every level.
std::FILE* null_stream() {
  static std::FILE* sink = std::fopen("/dev/null", "w");
  return sink;
}
}  // namespace

std::FILE* report_stream() {
  if (g_quiet) {
    if (std::FILE* sink = null_stream()) return sink;
  }
  return g_report_stream ? g_report_stream : stdout;
}

Verbosity verbosity() {
  if (g_quiet) return Verbosity::kQuiet;
  return g_verbose_count >= 2 ? Verbosity::kDebug : g_verbose_count == 1 ? Verbosity::kVerbose : Verbosity::kNormal;
}

void add_verbosity_flags(CLI::App* cmd) {
  auto* verbose = cmd->add_flag("-v,--verbose", g_verbose_count,
                                "More detail: the effective options, phase times, every field and surface label, notes; "
                                "twice (-vv): also a timed log of every stage on stderr");
  cmd->add_flag("-q,--quiet", g_quiet, "No report and no progress (errors, warnings and a failed check still print)")
      ->excludes(verbose);
}

void print_note(const std::string& message) {
  if (verbosity() < Verbosity::kVerbose) return;
  std::fprintf(stderr, "topotet: note: %s\n", message.c_str());
}

void log_stage(const std::string& message) {
  if (verbosity() < Verbosity::kDebug) return;
  std::fprintf(stderr, "topotet: [%s] %s\n", format_seconds(g_process_clock.seconds()).c_str(), message.c_str());
  std::fflush(stderr);
}

void send_report_to_stderr() { g_report_stream = stderr; }

std::optional<MeshFormat> parse_format(const std::string& name) {
  if (name.empty()) return std::nullopt;
  if (name == "mesh") return MeshFormat::kMedit;
  if (name == "msh") return MeshFormat::kGmsh;
  if (name == "vtu") return MeshFormat::kVtu;
  throw InputError("--format: '" + name + "' is not a format (mesh, msh or vtu)");
}

std::optional<MeshFormat> format_for(const std::string& path, const std::string& format_option) {
  if (format_option.empty()) return std::nullopt;
#if TOPOTET_HAVE_VTK
  if (path != "-" && is_vtk_path(path)) return std::nullopt;  // goes by its extension
#endif
  if (path != "-") {
    try {
      format_from_path(path);
      return std::nullopt;
    } catch (const InputError&) {
    }
  }
  return parse_format(format_option);
}

CLI::Validator number_in(double lo, double hi, bool lo_open) {
  const std::string range = std::string(lo_open ? "(" : "[") + format_number(lo, 6) + ", " +
                            (std::isinf(hi) ? std::string("inf)") : format_number(hi, 6) + "]");
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double x = 0.0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, x);
        if (ec != std::errc() || ptr != end || !std::isfinite(x)) return "'" + text + "' is not a number";
        if (x < lo || (lo_open && x == lo) || x > hi) return text + " is not in " + range;
        return {};
      },
      "NUMBER in " + range);
}

CLI::Validator whole_number_at_least(long long lo) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        long long x = 0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, x);
        if (ec != std::errc() || ptr != end || x < lo)
          return "'" + text + "' is not a whole number >= " + std::to_string(lo);
        return {};
      },
      "INTEGER >= " + std::to_string(lo));
}

void print_warning(const std::string& file, const std::string& message) {
  std::string line = prefix_file(file, message);
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  std::fprintf(stderr, "topotet: warning: %s\n", line.c_str());
}

namespace {

void warn_about(const std::string& label, const BuildNotes& notes) {
  const auto count = [](std::size_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
  };
  if (!notes.repeated_triangles.empty())
    print_warning(label, count(notes.repeated_triangles.size(), "triangle is", "triangles are") +
                             " listed again with the same vertices and ref (first: triangle " +
                             std::to_string(notes.repeated_triangles.front()) + "); each is kept once");
  if (!notes.repeated_segments.empty())
    print_warning(label, count(notes.repeated_segments.size(), "edge is", "edges are") +
                             " listed again with the same vertices and ref (first: edge " +
                             std::to_string(notes.repeated_segments.front()) + "); each is kept once");
  if (!notes.detached_triangles.empty())
    print_warning(label, count(notes.detached_triangles.size(), "listed triangle is", "listed triangles are") +
                             " not a face of any tet (first: triangle " +
                             std::to_string(notes.detached_triangles.front()) +
                             "); left out: they lie outside the tetrahedral mesh");
  if (!notes.detached_segments.empty())
    print_warning(label, count(notes.detached_segments.size(), "listed edge is", "listed edges are") +
                             " not an edge of any tet (first: edge " + std::to_string(notes.detached_segments.front()) +
                             "); left out: they lie outside the tetrahedral mesh");
}

}  // namespace

TetMesh build_input(const std::string& label, const MeshData& data, double* seconds, BuildNotes* notes) {
  const Stopwatch clock;
  try {
    BuildOptions options;
    options.skip_detached_substructures = true;
    BuildNotes local_notes;
    log_stage("build " + label + ": start");
    TetMesh mesh = build_tet_mesh(data, options, &local_notes);
    warn_about(label, local_notes);
    if (notes) *notes = std::move(local_notes);
    if (seconds) *seconds = clock.seconds();
    log_stage("build " + label + ": " + format_bytes(mesh.memory_bytes()) + " in " + format_seconds(clock.seconds()));
    return mesh;
  } catch (const InputError& e) {
    throw_input_error(label, e.what());
  }
}

std::vector<double> normalize_levels(std::vector<double> levels) {
  for (double level : levels)
    if (!(level > 0.0 && level <= 1.0))
      throw InputError("--levels: " + format_number(level, 6) + " is not a vertex ratio in (0, 1]");
  std::sort(levels.begin(), levels.end(), [](double a, double b) { return a > b; });
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  return levels;
}

std::string level_path(const std::string& path, double level) {
  const std::filesystem::path p(path);
  std::string name = p.filename().string();
  std::string extension;
  std::string stem = name;
  const auto ends_with = [](const std::string& s, const char* suffix) {
    const std::size_t n = std::strlen(suffix);
    return s.size() > n && s.compare(s.size() - n, n, suffix) == 0;
  };
  if (ends_with(stem, ".gz")) {
    extension = ".gz";
    stem.resize(stem.size() - 3);
  }
  const std::size_t dot = stem.rfind('.');
  if (dot != std::string::npos && dot != 0) {
    extension = stem.substr(dot) + extension;
    stem.resize(dot);
  }
  name = stem + "_" + format_ratio(level) + extension;
  return (p.parent_path() / name).string();
}

void check_output_folder(const std::string& path) {
  if (path.empty() || path == "-") return;
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!folder.empty() && !std::filesystem::is_directory(folder, ec))
    throw_input_error(path, "no such folder: " + folder.string());
}

void write_text_atomically(const std::string& path, const std::string& text) {
  try {
    write_text_file(path, text);
  } catch (const InputError& e) {
    throw_input_error(path, e.what());
  }
}

void write_json_atomically(const std::string& path, const Json& json) {
  write_text_atomically(path, json.dump(2) + "\n");
}

// ---- progress ----

ProgressMode parse_progress_mode(const std::string& text) {
  if (text == "auto") return ProgressMode::kAuto;
  if (text == "bar") return ProgressMode::kBar;
  if (text == "lines") return ProgressMode::kLines;
  if (text == "none") return ProgressMode::kNone;
  throw InputError("--progress: expected auto, bar, lines or none, got '" + text + "'");
}

ProgressBar::ProgressBar(std::string label, bool enabled, ProgressMode mode, double interval_seconds)
    : label_(std::move(label)),
      mode_(!enabled ? ProgressMode::kNone
            : mode == ProgressMode::kAuto ? (stderr_is_terminal() ? ProgressMode::kBar : ProgressMode::kNone)
                                          : mode),
      interval_seconds_(interval_seconds) {}

void ProgressBar::update(double done_fraction) {
  if (mode_ == ProgressMode::kNone) return;
  const double now = clock_.seconds();
  const double f = std::clamp(done_fraction, 0.0, 1.0);
  if (mode_ == ProgressMode::kLines) {
    // The first line after one interval, then one per interval.
    const double next = last_draw_seconds_ < 0.0 ? interval_seconds_ : last_draw_seconds_ + interval_seconds_;
    if (now < next) return;
    last_draw_seconds_ = now;
    std::fprintf(stderr, "%s: %d%% after %s\n", label_.c_str(), static_cast<int>(f * 100.0), format_seconds(now).c_str());
    std::fflush(stderr);
    return;
  }
  if (now < 1.0 || now - last_draw_seconds_ < 0.1) return;
  last_draw_seconds_ = now;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(f * kWidth + 0.5);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kWidth - filled), '.');
  std::fprintf(stderr, "\r%s [%s] %3d%%  %s\033[K", label_.c_str(), bar.c_str(), static_cast<int>(f * 100.0),
               format_seconds(now).c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (!drawn_) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  drawn_ = false;
}

}  // namespace topotet::cli
