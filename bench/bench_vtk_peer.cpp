// Side by side with VTK's vtkUnstructuredGridQuadricDecimation (issue #4): the same input, the same
// target, then time, field error, quality and the independent checker's topology verdict for VTK
// and for both topotet engines.
//
//   build-vtk/bench/bench_vtk_peer --dataset cube-sphere --tets 1000000 --ratio 0.1 --repeat 3
//       --json bench/vtk_peer.jsonl                                            (one command line)
//   build-vtk/bench/bench_vtk_peer --input ../shared/data/volume/lox_post_tets.mesh.gz --ratio 0.02
//   build-vtk/bench/bench_vtk_peer --input ../shared/data/volume/Bucky.raw --ratio 0.1   (32^3 bytes,
//       6 tets per voxel: raw_volume.h)
//
// Matching the targets. topotet's target is a vertex count (ratio * input vertices); VTK's
// TargetReduction is a fraction of the *tets*. We run topotet's reference (sequential) engine
// first and give VTK exactly as many collapses as topotet needed (--match vertices, the default:
// NumberOfEdgesToDecimate = used input vertices - topotet's output vertices, TargetReduction 0).
// Every VTK collapse removes exactly one vertex, so both outputs have the same vertex count and
// "collapses/s" counts the same work. --match tets instead sets NumberOfTetsOutput to topotet's
// output tet count. VTK may stop short: it gives up after 1000 refused collapses in a row.
//
// What is timed. VTK: filter->Update(), which builds the filter's own tet structure, runs the
// collapses and writes the output grid. topotet, for the same span: build_tet_mesh + simplify +
// to_mesh_data ("end to end"); its simplify-only time is shown too. The MeshData -> vtkUnstructured
// Grid conversion is not timed (a VTK user already has the grid). Medians over --repeat runs,
// interleaved (VTK, sequential, parallel, VTK, ...) so drifts of a shared machine hit all three.
//
// What VTK is given. Positions and tets, plus ONE scalar: the filter's quadrics are 4D (x, y, z, s)
// and it refuses a grid without point scalars (it reads component 0 of the array named by
// SetScalarsName). We pass component 0 of the mesh's first field (zeros if there is none).
// topotet keeps all of its fields; --first-field-only gives it the same single scalar. Materials,
// listed surfaces, polylines and pinned vertices cannot be expressed to the filter at all.
//
// VTK's scale trap. The filter refuses a collapse if any new tet has 6 * volume <= 1e-6 in
// absolute units (VTK_TEPS), and stops after 1000 refusals in a row. On a unit-sized mesh with
// 1M tets, cells are ~0.01 wide (6V ~ 1e-6): the slab family gets no collapse at all.
// --vtk-scale auto multiplies positions AND the scalar by s (mean 6V of the input becomes 1) and
// BoundaryWeight by s; a uniform scaling of all four quadric coordinates with that boundary
// weight leaves every cost comparison of the filter unchanged (tet quadric errors scale as s^5,
// boundary ones as s^4 * weight), so only the absolute threshold moves. Outputs are scaled back.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <vtkUnstructuredGridQuadricDecimation.h>

#include "mesh/glm_convert.h"
#include "material_transfer.h"
#include "raw_volume.h"
#include "topotet/generate.h"
#include "topotet/io.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"
#include "vtk_convert.h"

namespace {

using namespace topotet;
using Clock = std::chrono::steady_clock;
using json = nlohmann::ordered_json;

constexpr std::uint64_t kFastCheckTets = 2'000'000;  // as the CLI: bigger inputs get the fast checker

struct Args {
  std::string input, dataset = "cube-sphere";
  std::uint64_t tets = 200000, seed = 1;
  double ratio = 0.1;
  int repeat = 3, vtk_repeat = -1;  // -1: same as repeat
  int threads = 0;
  bool match_tets = false, first_field_only = false;
  std::string vtk_scale = "1";  // a number, or "auto"
  // topotet's geometric defaults; VTK has neither (docs/performance.md's table sets both off: 180, 0).
  double feature_angle = SimplifyOptions{}.feature_angle;
  double tolerance_rel = SimplifyOptions{}.tolerance_rel;
  std::string json_path;
};

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

std::uint64_t used_vertex_count(const MeshData& m) {
  std::vector<char> used(m.vertex_count(), 0);
  for (const auto& t : m.tets) for (VertId v : t) used[v] = 1;
  return static_cast<std::uint64_t>(std::count(used.begin(), used.end(), 1));
}

// Positions and tets only, one region: what the mesh is without its substructures.
MeshData mesh_only(const MeshData& m) {
  MeshData out;
  out.positions = m.positions;
  out.tets = m.tets;
  out.tet_material.assign(m.tet_count(), 0);
  return out;
}

// One engine's runs and its last output, which is measured. topotet's outputs are deterministic.
// VTK's are nearly so: we seed rand(), but the filter keeps the previous run's last error in a
// function-local static (DeleteMin's `lasterror`), so a repetition may collapse slightly otherwise.
struct EngineRuns {
  std::string name;
  std::vector<double> end_to_end, simplify_only;
  MeshData output;
  std::string status = "ok";
};

void run_topotet(const MeshData& input, Engine engine, const Args& a, EngineRuns& runs) {
  const auto t0 = Clock::now();
  TetMesh mesh = build_tet_mesh(input);
  SimplifyOptions options;
  options.target_vertex_ratio = a.ratio;
  options.engine = engine;
  options.num_threads = a.threads;
  options.feature_angle = a.feature_angle;
  options.tolerance_rel = a.tolerance_rel;
  const auto t1 = Clock::now();
  const Report report = simplify(mesh, options);
  const double simplify_seconds = since(t1);
  runs.output = mesh.to_mesh_data();
  runs.end_to_end.push_back(since(t0));
  runs.simplify_only.push_back(simplify_seconds);
  runs.status = to_string(report.status);
}

struct VtkTarget {
  int collapses = 0;    // --match vertices
  int tets_output = 0;  // --match tets
};

void run_vtk(vtkUnstructuredGrid* grid, const std::string& scalar_name, const std::string& field_name,
             const VtkTarget& target, double scale, std::uint64_t vertices_in, EngineRuns& runs) {
  auto filter = vtkSmartPointer<vtkUnstructuredGridQuadricDecimation>::New();
  filter->SetInputData(grid);
  filter->SetScalarsName(scalar_name.c_str());
  filter->SetBoundaryWeight(filter->GetBoundaryWeight() * scale);
  if (target.tets_output > 0) {
    filter->SetNumberOfTetsOutput(target.tets_output);
  } else {
    filter->SetTargetReduction(0.0);  // desired tets = input tets: the collapse count alone decides
    filter->SetNumberOfEdgesToDecimate(target.collapses);
  }
  std::srand(1);  // the filter picks candidate edges with rand()
  const auto t0 = Clock::now();
  filter->Update();
  const double seconds = since(t0);
  runs.end_to_end.push_back(seconds);
  runs.simplify_only.push_back(seconds);
  // The filter names its output scalars "scalars"; give them back the field's name to compare.
  runs.output = bench::from_vtk_grid(*filter->GetOutput(), "scalars", field_name, scale);
  // Every collapse removes one output point (unreferenced points stay), so points tell how many ran.
  const auto collapses = static_cast<std::int64_t>(vertices_in) - filter->GetOutput()->GetNumberOfPoints();
  const bool short_of_target = target.tets_output > 0
                                   ? static_cast<std::int64_t>(runs.output.tet_count()) > target.tets_output
                                   : collapses < target.collapses;
  runs.status = !runs.output.tet_count() ? "failed"
                : short_of_target        ? "gave up after " + std::to_string(collapses) + " collapses"
                                         : "ok";
}

// Everything measured on one output, and its JSON.
struct Measured {
  std::uint64_t vertices = 0, tets = 0;
  double seconds = 0, simplify_seconds = 0, collapses_per_second = 0;
  ComponentError scalar;  // first field, component 0
  double worst_rms_rel = 0;        // over every field topotet kept
  bool has_field_error = false;
  QualityStats quality;
  topotet::TopologyReport topology, topology_mesh_only;
  bool same_topology = false, same_mesh_only = false;
  std::string differences;
  std::size_t straddling = 0, relabel_outside = 0;
  double relabel_agreement = -1;  // fraction of tets whose transferred label equals their own
};

int count_lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

Measured measure(const MeshData& input, const MeshData& scalar_reference, const topotet::TopologyReport& input_topology,
                 const topotet::TopologyReport& input_mesh_only, const EngineRuns& runs, bool is_vtk,
                 std::uint64_t vertices_in) {
  Measured m;
  const MeshData& out = runs.output;
  m.vertices = used_vertex_count(out);
  m.tets = out.tet_count();
  m.seconds = median(runs.end_to_end);
  m.simplify_seconds = median(runs.simplify_only);
  m.collapses_per_second = static_cast<double>(vertices_in - m.vertices) / std::max(m.seconds, 1e-9);
  if (!input.fields.empty() && out.tet_count()) {
    const FieldError e = compare_fields(is_vtk ? scalar_reference : input, out);
    for (const auto& c : e.components)
      if (c.field == input.fields[0].name && c.component == 0) m.scalar = c, m.has_field_error = true;
    m.worst_rms_rel = e.worst_rms_rel;
  }
  m.quality = compute_quality(out);
  topotet::TopologyOptions options;
  options.fast = input.tet_count() > kFastCheckTets;
  m.topology = topotet::compute_topology(out, options);
  m.same_topology = topotet::same_topology(input_topology, m.topology, &m.differences);
  const MeshData bare = mesh_only(out);
  m.topology_mesh_only = topotet::compute_topology(bare, options);
  m.same_mesh_only = topotet::same_topology(input_mesh_only, m.topology_mesh_only);

  const bench::MaterialTransfer transfer = bench::transfer_materials(input, bare);
  m.straddling = transfer.straddling;
  m.relabel_outside = transfer.outside;
  if (!is_vtk) {
    std::size_t agree = 0;
    for (std::size_t t = 0; t < out.tet_count(); ++t) agree += transfer.tet_material[t] == out.tet_material[t];
    m.relabel_agreement = static_cast<double>(agree) / std::max<double>(1.0, static_cast<double>(out.tet_count()));
  }
  return m;
}

std::string betti(const topotet::ComplexTopology& c) {
  std::string s = "(";
  for (int k = 0; k < 4; ++k) {
    if (k) s += ',';
    s += c.betti[k] < 0 ? std::string("?") : std::to_string(c.betti[k]);
  }
  return s + ")";
}

json betti_json(const topotet::ComplexTopology& c) {
  json j = json::array();
  for (auto b : c.betti) j.push_back(b < 0 ? json(nullptr) : json(b));
  return j;
}

json to_json(const Measured& m, const EngineRuns& runs, double vtk_seconds) {
  json j;
  j["status"] = runs.status;
  j["vertices_out"] = m.vertices;
  j["tets_out"] = m.tets;
  j["seconds_end_to_end"] = m.seconds;
  j["seconds_simplify"] = m.simplify_seconds;
  j["seconds_runs"] = runs.end_to_end;
  j["collapses_per_second"] = m.collapses_per_second;
  j["vtk_time_ratio"] = vtk_seconds / std::max(m.seconds, 1e-9);
  if (m.has_field_error)
    j["scalar_error"] = {{"field", m.scalar.field},
                         {"range", m.scalar.range},
                         {"rms_rel_original_to_simplified", m.scalar.original_to_simplified.rms_rel},
                         {"rms_rel_simplified_to_original", m.scalar.simplified_to_original.rms_rel},
                         {"rms_both_rel", m.scalar.rms_both_rel},
                         {"max_rel_original_to_simplified", m.scalar.original_to_simplified.max_rel},
                         {"max_rel_simplified_to_original", m.scalar.simplified_to_original.max_rel},
                         {"worst_rms_rel_all_fields", m.worst_rms_rel}};
  j["quality"] = {{"dihedral_std_deg", m.quality.dihedral_deg.std_dev}, {"dihedral_min_deg", m.quality.dihedral_deg.min},
                  {"solid_std_sr", m.quality.solid_sr.std_dev},          {"mean_ratio_min", m.quality.mean_ratio.min},
                  {"inverted", m.quality.inverted},                      {"zero_volume", m.quality.zero_volume}};
  const auto& t = m.topology;
  j["topology"] = {{"same_as_input", m.same_topology},
                   {"differences", m.differences},
                   {"mesh_betti", betti_json(t.mesh)},
                   {"boundary_betti", betti_json(t.boundary)},
                   {"materials", t.materials.size()},
                   {"interfaces", t.interfaces.size()},
                   {"surfaces", t.surfaces.size()},
                   {"polylines", t.polylines.size()},
                   {"pinned_vertices", t.pinned_vertex_count},
                   {"nonmanifold_faces", t.nonmanifold_face_count},
                   {"duplicate_tets", t.duplicate_tet_count},
                   {"degenerate_tets", t.degenerate_tet_count},
                   {"unreferenced_vertices", t.unreferenced_vertex_count}};
  j["topology_mesh_only"] = {{"same_as_input", m.same_mesh_only},
                             {"mesh_betti", betti_json(m.topology_mesh_only.mesh)},
                             {"boundary_betti", betti_json(m.topology_mesh_only.boundary)}};
  j["relabelled_by_centroid"] = {{"tets_straddling_an_input_interface", m.straddling},
                                 {"centroids_outside_input", m.relabel_outside}};
  if (m.relabel_agreement >= 0) j["relabelled_by_centroid"]["agreement_with_own_labels"] = m.relabel_agreement;
  return j;
}

void usage() {
  std::fprintf(stderr,
               "usage: bench_vtk_peer (--input FILE|VOLUME.raw | --dataset cube-sphere|slab|linked-tori --tets N [--seed S])\n"
               "       [--ratio R] [--repeat K] [--vtk-repeat K] [--threads T] [--match vertices|tets]\n"
               "       [--first-field-only] [--vtk-scale auto|S] [--feature-angle A] [--tolerance-rel H] [--json FILE]\n");
}

bool parse(int argc, char** argv, Args& a) {
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    const bool has_value = i + 1 < argc;
    const char* v = has_value ? argv[i + 1] : "";
    auto take = [&] { ++i; return has_value; };
    if (k == "--input") { a.input = v; if (!take()) return false; }
    else if (k == "--dataset") { a.dataset = v; if (!take()) return false; }
    else if (k == "--tets") { a.tets = std::strtoull(v, nullptr, 10); if (!take()) return false; }
    else if (k == "--seed") { a.seed = std::strtoull(v, nullptr, 10); if (!take()) return false; }
    else if (k == "--ratio") { a.ratio = std::atof(v); if (!take()) return false; }
    else if (k == "--repeat") { a.repeat = std::max(1, std::atoi(v)); if (!take()) return false; }
    else if (k == "--vtk-repeat") { a.vtk_repeat = std::max(1, std::atoi(v)); if (!take()) return false; }
    else if (k == "--threads") { a.threads = std::atoi(v); if (!take()) return false; }
    else if (k == "--match") { a.match_tets = std::string(v) == "tets"; if (!take()) return false; }
    else if (k == "--first-field-only") a.first_field_only = true;
    else if (k == "--vtk-scale") { a.vtk_scale = v; if (!take()) return false; }
    else if (k == "--feature-angle") { a.feature_angle = std::atof(v); if (!take()) return false; }
    else if (k == "--tolerance-rel") { a.tolerance_rel = std::atof(v); if (!take()) return false; }
    else if (k == "--json") { a.json_path = v; if (!take()) return false; }
    else return false;
  }
  return a.ratio > 0 && a.ratio < 1;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  if (!parse(argc, argv, a)) {
    usage();
    return 2;
  }
  if (a.vtk_repeat < 0) a.vtk_repeat = a.repeat;

  // ---- input ----
  MeshData input;
  std::string name;
  try {
    if (!a.input.empty()) {
      // A raw byte volume (the Bucky ball) becomes a 6-tets-per-voxel mesh (raw_volume.h).
      input = bench::is_raw_volume(a.input) ? bench::read_raw_volume(a.input) : read_mesh(a.input);
      name = std::filesystem::path(a.input).filename().string();
    } else {
      GenerateOptions g;
      g.family = a.dataset;
      g.target_tets = a.tets;
      g.seed = a.seed;
      input = generate_mesh(g);
      name = a.dataset;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_vtk_peer: error: %s\n", e.what());
    return 2;
  }
  // The one scalar VTK decimates with: component 0 of the first field, or zeros.
  const bool has_field = !input.fields.empty();
  const std::string field_name = has_field ? input.fields[0].name : "zero";
  std::vector<double> scalar(input.vertex_count(), 0.0);
  if (has_field)
    for (std::size_t v = 0; v < input.vertex_count(); ++v)
      scalar[v] = input.fields[0].values[v * static_cast<std::size_t>(input.fields[0].components)];
  MeshData scalar_reference = mesh_only(input);
  if (has_field) scalar_reference.fields.push_back({field_name, 1, scalar});
  if (a.first_field_only && has_field) input.fields = scalar_reference.fields;
  const std::uint64_t vertices_in = used_vertex_count(input);

  double scale = a.vtk_scale == "auto" ? 0.0 : std::atof(a.vtk_scale.c_str());
  if (scale <= 0.0) {  // auto: the mean tet gets 6V = 1
    double sum = 0.0;
    for (const auto& t : input.tets) {
      const glm::dvec3 p0 = to_glm(input.positions[t[0]]), p1 = to_glm(input.positions[t[1]]),
                       p2 = to_glm(input.positions[t[2]]), p3 = to_glm(input.positions[t[3]]);
      sum += std::abs(glm::dot(p1 - p0, glm::cross(p2 - p0, p3 - p0)));
    }
    scale = std::cbrt(static_cast<double>(input.tet_count()) / std::max(sum, 1e-300));
  }
  auto convert_start = Clock::now();
  auto grid = bench::to_vtk_grid(input, scalar, field_name, scale);
  const double convert_seconds = since(convert_start);

  // ---- runs ----
  const int threads = a.threads > 0 ? a.threads : static_cast<int>(std::thread::hardware_concurrency());
  EngineRuns vtk{"VTK quadric"}, sequential{"topotet seq"}, parallel{"topotet par " + std::to_string(threads) + "t"};
  VtkTarget target;
  const int reps = std::max(a.repeat, a.vtk_repeat);
  for (int rep = 0; rep < reps; ++rep) {
    if (rep < a.repeat) {
      run_topotet(input, Engine::kSequential, a, sequential);
      if (rep == 0) {
        const std::uint64_t out_vertices = used_vertex_count(sequential.output);
        target.collapses = static_cast<int>(vertices_in - out_vertices);
        if (a.match_tets) target.tets_output = static_cast<int>(sequential.output.tet_count());
      }
      run_topotet(input, Engine::kParallel, a, parallel);
    }
    if (rep < a.vtk_repeat) run_vtk(grid, field_name, field_name, target, scale, vertices_in, vtk);
    std::fprintf(stderr, "rep %d: vtk %.2f s, seq %.2f s, par %.2f s\n", rep + 1,
                 rep < a.vtk_repeat ? vtk.end_to_end.back() : 0.0, rep < a.repeat ? sequential.end_to_end.back() : 0.0,
                 rep < a.repeat ? parallel.end_to_end.back() : 0.0);
  }

  // ---- measure (once, on the last outputs) ----
  topotet::TopologyOptions options;
  options.fast = input.tet_count() > kFastCheckTets;
  const topotet::TopologyReport input_topology = topotet::compute_topology(input, options);
  const topotet::TopologyReport input_mesh_only = topotet::compute_topology(mesh_only(input), options);
  const QualityStats input_quality = compute_quality(input);
  std::vector<EngineRuns*> engines = {&vtk, &sequential, &parallel};
  std::vector<Measured> m;
  for (EngineRuns* e : engines)
    m.push_back(measure(input, scalar_reference, input_topology, input_mesh_only, *e, e == &vtk, vertices_in));

  // ---- table ----
  const auto& it = input_topology;
  std::printf("\n%s: %llu vertices, %zu tets, %zu materials, %zu interfaces, %zu surface refs, %zu polyline refs, "
              "%llu pinned\n",
              name.c_str(), static_cast<unsigned long long>(vertices_in), input.tet_count(), it.materials.size(),
              it.interfaces.size(), it.surfaces.size(), it.polylines.size(),
              static_cast<unsigned long long>(it.pinned_vertex_count));
  std::printf("target %.3g of the vertices; VTK given %s, scale %.4g; medians of %d topotet / %d VTK runs; "
              "VTK scalar '%s'%s\n",
              a.ratio,
              a.match_tets ? ("NumberOfTetsOutput = " + std::to_string(target.tets_output)).c_str()
                           : ("NumberOfEdgesToDecimate = " + std::to_string(target.collapses)).c_str(),
              scale, a.repeat, a.vtk_repeat, field_name.c_str(),
              input.fields.size() > 1 ? " (topotet keeps every field)" : "");
  auto row = [&](const char* label, auto cell) {
    std::printf("%-34s", label);
    for (std::size_t i = 0; i < engines.size(); ++i) std::printf(" %20s", cell(i).c_str());
    std::printf("\n");
  };
  auto fmt = [](const char* f, auto... v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, f, v...);
    return std::string(buf);
  };
  const double vtk_seconds = m[0].seconds;
  row("", [&](std::size_t i) { return engines[i]->name; });
  row("status", [&](std::size_t i) { return engines[i]->status; });
  row("vertices out", [&](std::size_t i) { return std::to_string(m[i].vertices); });
  row("tets out", [&](std::size_t i) { return std::to_string(m[i].tets); });
  row("seconds (end to end)", [&](std::size_t i) { return fmt("%.2f", m[i].seconds); });
  row("seconds (simplify only)", [&](std::size_t i) { return i == 0 ? std::string("-") : fmt("%.2f", m[i].simplify_seconds); });
  row("collapses/s (end to end)", [&](std::size_t i) { return fmt("%.0f", m[i].collapses_per_second); });
  row("time / VTK time", [&](std::size_t i) { return fmt("%.2f", m[i].seconds / std::max(vtk_seconds, 1e-9)); });
  if (has_field) {
    auto err = [&](auto pick) { return [&, pick](std::size_t i) { return m[i].has_field_error ? pick(m[i]) : std::string("-"); }; };
    row("rms rel orig->simpl / simpl->orig", err([&](const Measured& x) {
          return fmt("%.4f / %.4f", x.scalar.original_to_simplified.rms_rel, x.scalar.simplified_to_original.rms_rel); }));
    row("rms rel both", err([&](const Measured& x) { return fmt("%.4f", x.scalar.rms_both_rel); }));
    row("max rel orig->simpl / simpl->orig", err([&](const Measured& x) {
          return fmt("%.3f / %.3f", x.scalar.original_to_simplified.max_rel, x.scalar.simplified_to_original.max_rel); }));
    if (input.fields.size() > 1) row("worst rms rel, all fields", [&](std::size_t i) { return i == 0 ? std::string("1 field") : fmt("%.4f", m[i].worst_rms_rel); });
  }
  row("dihedral std deg (input)", [&](std::size_t i) { return fmt("%.2f (%.2f)", m[i].quality.dihedral_deg.std_dev, input_quality.dihedral_deg.std_dev); });
  row("solid std sr (input)", [&](std::size_t i) { return fmt("%.3f (%.3f)", m[i].quality.solid_sr.std_dev, input_quality.solid_sr.std_dev); });
  row("min dihedral deg", [&](std::size_t i) { return fmt("%.2f", m[i].quality.dihedral_deg.min); });
  row("inverted / zero-volume tets", [&](std::size_t i) { return fmt("%zu / %zu", m[i].quality.inverted, m[i].quality.zero_volume); });
  row("checker: same topology", [&](std::size_t i) {
    return m[i].same_topology ? std::string("yes") : fmt("NO (%d diffs)", count_lines(m[i].differences)); });
  row("mesh-only (mesh+boundary) same", [&](std::size_t i) { return std::string(m[i].same_mesh_only ? "yes" : "NO"); });
  row("mesh Betti", [&](std::size_t i) { return betti(m[i].topology_mesh_only.mesh); });
  row("boundary Betti", [&](std::size_t i) { return betti(m[i].topology_mesh_only.boundary); });
  row("nonmanifold faces / dup tets", [&](std::size_t i) {
    return fmt("%llu / %llu", static_cast<unsigned long long>(m[i].topology.nonmanifold_face_count),
               static_cast<unsigned long long>(m[i].topology.duplicate_tet_count)); });
  row("unreferenced vertices in output", [&](std::size_t i) {
    return std::to_string(m[i].topology.unreferenced_vertex_count); });
  row("materials / interfaces", [&](std::size_t i) { return fmt("%zu / %zu", m[i].topology.materials.size(), m[i].topology.interfaces.size()); });
  row("surface refs / polyline refs / pins", [&](std::size_t i) {
    return fmt("%zu / %zu / %llu", m[i].topology.surfaces.size(), m[i].topology.polylines.size(),
               static_cast<unsigned long long>(m[i].topology.pinned_vertex_count)); });
  row("tets an input interface cuts", [&](std::size_t i) {
    return fmt("%zu (%.2f%%)", m[i].straddling, 100.0 * static_cast<double>(m[i].straddling) / std::max<double>(1.0, static_cast<double>(m[i].tets))); });
  row("centroid label = own label", [&](std::size_t i) { return m[i].relabel_agreement < 0 ? std::string("-") : fmt("%.4f", m[i].relabel_agreement); });
  std::printf("input: mesh Betti %s, boundary Betti %s. MeshData -> vtkUnstructuredGrid conversion %.2f s (untimed).\n",
              betti(input_mesh_only.mesh).c_str(), betti(input_mesh_only.boundary).c_str(), convert_seconds);
  if (!m[0].same_topology) {
    std::printf("checker, VTK output vs input (first lines):\n");
    std::size_t pos = 0;
    for (int line = 0; line < 8 && pos < m[0].differences.size(); ++line) {
      const std::size_t end = m[0].differences.find('\n', pos);
      std::printf("  %s\n", m[0].differences.substr(pos, end - pos).c_str());
      pos = end == std::string::npos ? end : end + 1;
    }
  }

  // ---- JSON ----
  if (!a.json_path.empty()) {
    json j;
    j["dataset"] = name;
    j["tets_in"] = input.tet_count();
    j["vertices_in"] = vertices_in;
    j["ratio"] = a.ratio;
    j["match"] = a.match_tets ? "tets" : "vertices";
    j["vtk_collapses_requested"] = target.collapses;
    j["vtk_tets_requested"] = target.tets_output;
    j["vtk_scalar"] = field_name;
    j["vtk_scale"] = scale;
    j["first_field_only"] = a.first_field_only;
    j["repeat"] = a.repeat;
    j["vtk_repeat"] = a.vtk_repeat;
    j["parallel_threads"] = threads;
    j["input"] = {{"materials", it.materials.size()},
                  {"interfaces", it.interfaces.size()},
                  {"surfaces", it.surfaces.size()},
                  {"polylines", it.polylines.size()},
                  {"pinned_vertices", it.pinned_vertex_count},
                  {"mesh_betti", betti_json(input_mesh_only.mesh)},
                  {"boundary_betti", betti_json(input_mesh_only.boundary)},
                  {"dihedral_std_deg", input_quality.dihedral_deg.std_dev},
                  {"solid_std_sr", input_quality.solid_sr.std_dev}};
    j["vtk"] = to_json(m[0], vtk, vtk_seconds);
    j["topotet_sequential"] = to_json(m[1], sequential, vtk_seconds);
    j["topotet_parallel"] = to_json(m[2], parallel, vtk_seconds);
    std::ofstream(a.json_path, std::ios::app) << j.dump() << "\n";
  }
  return 0;
}
