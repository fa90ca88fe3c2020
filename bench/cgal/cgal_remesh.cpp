// cgal_remesh IN.mesh OUT.mesh --vertices N | --ratio R: CGAL's tetrahedral_isotropic_remeshing
// (CGAL/tetrahedral_remeshing.h) used as a coarsener, for a side-by-side benchmark with topotet
// (bench/quality_vs_remesher.py, issue #26 item 4).
//
// The MEDIT input (positions, tets, materials, listed triangles) becomes a
// Tetrahedral_remeshing::Remeshing_triangulation_3 whose cells carry the materials as subdomain
// indices (1, 2, ... in the order of the materials: CGAL reserves 0 for "outside"), so every
// material interface and the boundary are surfaces the remesher keeps as surfaces. It remeshes
// them too (remesh_boundaries = true, CGAL's default): with frozen surfaces a coarsener cannot go
// below the surface vertex count, and topotet simplifies its surfaces too. Edges where three or
// more surface patches meet are CGAL's features (it computes them); the input's listed polylines and
// corners are not given to it (this program reports them as not carried).
//
// CGAL takes a target edge length, not a vertex count: a short search finds it. A first length
// from the volume (a vertex per 0.54 L^3 of an isotropic mesh), then secant steps on
// log(vertices) against log(length) until the count is within --tolerance (5%) of the target or
// --max-runs runs were made; the run closest to the target is written. Each run starts from the
// input. The time of the chosen run and of the whole search are printed (and written with --json).
//
// Output: MEDIT, the materials back as tet refs, and the surface facets (subdomain interfaces and
// the boundary) as Triangles whose ref is the input's ref for that pair of materials.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Random.h>
#include <CGAL/Tetrahedral_remeshing/Remeshing_triangulation_3.h>
#include <CGAL/tetrahedral_remeshing.h>
#include <CGAL/Mesh_3/tet_soup_to_c3t3.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "medit_io.h"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Tr = CGAL::Tetrahedral_remeshing::Remeshing_triangulation_3<K>;

constexpr const char* kUsage = R"(usage: cgal_remesh IN.mesh OUT.mesh (--vertices N | --ratio R) [options]

CGAL's tetrahedral_isotropic_remeshing as a coarsener: materials become subdomains, their
interfaces and the boundary are remeshed as surfaces (remesh_boundaries). The target edge length
is searched for so that OUT has about N vertices (or R x IN's vertices). IN: MEDIT ASCII (convert
other formats with `topotet convert IN IN.mesh`).

options:
  --vertices N        target vertex count
  --ratio R           target vertex count as a fraction of IN's (0 < R <= 1)
  --edge-length L     no search: one run with this target edge length
  --iterations K      CGAL's number_of_iterations (default 1, CGAL's default)
  --tolerance T       stop the search within T of the target (default 0.05)
  --max-runs M        at most M remeshing runs in the search (default 4)
  --json FILE         write the runs, the chosen one and the counts as JSON
  -h, --help          this text
)";

struct Args {
  std::string input, output, json;
  long long vertices = 0;
  double ratio = 0.0, edge_length = 0.0, tolerance = 0.05;
  int iterations = 1, max_runs = 4;
};

[[noreturn]] void usage_error(const std::string& what) { throw std::runtime_error(what + " (see --help)"); }

double positive(const std::string& s, const char* what) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used == s.size() && std::isfinite(v) && v > 0.0) return v;
  } catch (const std::exception&) {
  }
  usage_error(std::string(what) + ": '" + s + "' is not a positive number");
}

Args parse(int argc, char** argv) {
  Args a;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&](const char* name) -> std::string {
      if (i + 1 >= argc) usage_error(std::string(name) + " needs a value");
      return argv[++i];
    };
    if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (arg == "--vertices") {
      a.vertices = static_cast<long long>(positive(value("--vertices"), "--vertices"));
    } else if (arg == "--ratio") {
      a.ratio = positive(value("--ratio"), "--ratio");
      if (a.ratio > 1.0) usage_error("--ratio: must be <= 1");
    } else if (arg == "--edge-length") {
      a.edge_length = positive(value("--edge-length"), "--edge-length");
    } else if (arg == "--iterations") {
      a.iterations = static_cast<int>(positive(value("--iterations"), "--iterations"));
    } else if (arg == "--tolerance") {
      a.tolerance = positive(value("--tolerance"), "--tolerance");
    } else if (arg == "--max-runs") {
      a.max_runs = static_cast<int>(positive(value("--max-runs"), "--max-runs"));
    } else if (arg == "--json") {
      a.json = value("--json");
    } else if (!arg.empty() && arg[0] == '-') {
      usage_error("unknown option '" + arg + "'");
    } else {
      positional.push_back(arg);
    }
  }
  if (positional.size() != 2) usage_error("expected IN.mesh OUT.mesh");
  a.input = positional[0];
  a.output = positional[1];
  if ((a.vertices > 0) + (a.ratio > 0) + (a.edge_length > 0) != 1)
    usage_error("give exactly one of --vertices, --ratio, --edge-length");
  return a;
}

std::array<std::uint32_t, 3> sorted(std::array<std::uint32_t, 3> f) {
  std::sort(f.begin(), f.end());
  return f;
}

struct FaceHash {
  std::size_t operator()(const std::array<std::uint32_t, 3>& f) const {
    return (static_cast<std::size_t>(f[0]) * 0x9E3779B97F4A7C15ull) ^ (static_cast<std::size_t>(f[1]) * 0xC2B2AE3D27D4EB4Full) ^
           (static_cast<std::size_t>(f[2]) * 0x165667B19E3779F9ull);
  }
};

// The input in CGAL's terms.
struct Input {
  cgal_bench::MeditMesh mesh;
  std::vector<int> materials;                   // subdomain s (1-based) has material materials[s - 1]
  std::vector<int> subdomain;                   // [tet] 1, 2, ...
  std::map<std::pair<int, int>, int> pair_ref;  // (subdomain a <= b; 0 = outside) -> triangle ref
  std::vector<std::string> warnings;
  double volume = 0.0;
  std::size_t flipped = 0;
};

double signed_volume(const cgal_bench::MeditMesh& m, const std::array<std::uint32_t, 4>& t) {
  const auto& a = m.positions[t[0]];
  const auto& b = m.positions[t[1]];
  const auto& c = m.positions[t[2]];
  const auto& d = m.positions[t[3]];
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0])) / 6.0;
}

Input prepare(const std::string& path) {
  Input in;
  in.mesh = cgal_bench::read_medit(path);
  auto& m = in.mesh;
  // CGAL wants positively oriented cells (orientation(p0, p1, p2, p3) == POSITIVE).
  for (auto& t : m.tets) {
    const double v = signed_volume(m, t);
    if (v == 0.0) throw std::runtime_error(path + ": a tet of zero volume; CGAL's triangulation cannot hold it");
    if (v < 0) {
      std::swap(t[2], t[3]);
      ++in.flipped;
    }
    in.volume += std::abs(v);
  }
  // CGAL's triangulation closes the boundary with cells on an infinite vertex: a boundary edge with
  // more than two boundary faces (a non-manifold boundary) cannot be represented. Say so up front.
  {
    std::unordered_map<std::array<std::uint32_t, 3>, int, FaceHash> faces;
    faces.reserve(m.tets.size() * 3);
    for (const auto& t : m.tets)
      for (int i = 0; i < 4; ++i) {
        std::array<std::uint32_t, 3> f{};
        for (int j = 0, k = 0; j < 4; ++j)
          if (j != i) f[k++] = t[j];
        ++faces[sorted(f)];
      }
    std::unordered_map<std::array<std::uint32_t, 3>, int, FaceHash> edges;  // [a, b, 0]
    std::size_t shared = 0;
    for (const auto& [f, n] : faces) {
      if (n > 2) ++shared;
      if (n != 1) continue;
      for (int i = 0; i < 3; ++i) ++edges[{f[i], f[(i + 1) % 3], 0}];
    }
    std::size_t non_manifold = 0;
    for (const auto& [e, n] : edges) non_manifold += n > 2 ? 1 : 0;
    if (shared > 0)
      throw std::runtime_error(path + ": " + std::to_string(shared) + " faces shared by more than two tets");
    if (non_manifold > 0)
      throw std::runtime_error(path + ": the boundary has " + std::to_string(non_manifold) +
                               " non-manifold edges (more than two boundary faces): CGAL's triangulation cannot "
                               "represent it (CGAL::build_triangulation refuses it)");
  }
  in.materials = m.tet_ref;
  std::sort(in.materials.begin(), in.materials.end());
  in.materials.erase(std::unique(in.materials.begin(), in.materials.end()), in.materials.end());
  in.subdomain.resize(m.tets.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    in.subdomain[t] = static_cast<int>(std::lower_bound(in.materials.begin(), in.materials.end(), m.tet_ref[t]) -
                                       in.materials.begin()) + 1;
  // The refs of the listed triangles, per pair of subdomains they separate.
  if (!m.triangles.empty()) {
    std::unordered_map<std::array<std::uint32_t, 3>, std::array<int, 2>, FaceHash> sides;
    sides.reserve(m.triangles.size() * 2);
    for (const auto& tri : m.triangles) sides.try_emplace(sorted(tri), std::array<int, 2>{0, 0});
    for (std::size_t t = 0; t < m.tets.size(); ++t)
      for (int i = 0; i < 4; ++i) {
        std::array<std::uint32_t, 3> f{};
        for (int j = 0, k = 0; j < 4; ++j)
          if (j != i) f[k++] = m.tets[t][j];
        const auto it = sides.find(sorted(f));
        if (it == sides.end()) continue;
        (it->second[0] == 0 ? it->second[0] : it->second[1]) = in.subdomain[t];
      }
    std::map<std::pair<int, int>, std::map<int, std::size_t>> refs;
    std::size_t inside = 0;
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
      const auto& s = sides.at(sorted(m.triangles[i]));
      if (s[0] == s[1] || s[0] == 0) {  // inside one material (or not a face of any tet)
        ++inside;
        continue;
      }
      ++refs[{std::min(s[0], s[1]), std::max(s[0], s[1])}][m.triangle_ref[i]];
    }
    for (const auto& [pair, counts] : refs) {
      auto best = counts.begin();
      for (auto it = counts.begin(); it != counts.end(); ++it)
        if (it->second > best->second) best = it;
      in.pair_ref[pair] = best->first;
      if (counts.size() > 1)
        in.warnings.push_back("the surface between materials " + std::to_string(pair.first ? in.materials[pair.first - 1] : 0) +
                              " and " + std::to_string(in.materials[pair.second - 1]) + " carries " +
                              std::to_string(counts.size()) + " triangle refs: the remeshed one gets ref " +
                              std::to_string(best->first) + " only (materials do not determine the others)");
    }
    if (inside > 0)
      in.warnings.push_back(std::to_string(inside) +
                            " listed triangles lie inside one material (embedded surfaces): not given to the remesher, lost");
  }
  if (m.skipped_entries > 0)
    in.warnings.push_back(std::to_string(m.skipped_entries) +
                          " entries of other MEDIT sections (Edges, Corners, Ridges, ...) not carried: polylines and corners are lost");
  return in;
}

// CGAL 5.5 has no tetrahedron_soup_to_triangulation_3 (5.6 adds it): CGAL::build_triangulation
// (CGAL/Mesh_3/tet_soup_to_c3t3.h) is what CGAL's own MEDIT loader and the remesher use.
Tr build_triangulation(const Input& in) {
  std::vector<Point> points;
  points.reserve(in.mesh.positions.size());
  for (const auto& p : in.mesh.positions) points.emplace_back(p[0], p[1], p[2]);
  std::vector<std::array<int, 5>> cells;  // 4 vertices (0-based) and the subdomain
  cells.reserve(in.mesh.tets.size());
  for (std::size_t t = 0; t < in.mesh.tets.size(); ++t) {
    const auto& v = in.mesh.tets[t];
    cells.push_back({static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2]), static_cast<int>(v[3]),
                     in.subdomain[t]});
  }
  const std::map<std::array<int, 3>, Tr::Cell::Surface_patch_index> no_border_facets;  // from the subdomains
  std::vector<Tr::Vertex_handle> handles(points.size() + 1);
  Tr tr;
  if (!CGAL::build_triangulation<Tr, false>(tr, points, cells, no_border_facets, handles, std::getenv("CGAL_REMESH_VERBOSE") != nullptr))
    throw std::runtime_error("CGAL::build_triangulation refused the mesh (a non-manifold boundary or a face "
                             "shared by more than two tets?)");
  return tr;
}

struct RunResult {
  double edge_length = 0.0;
  std::size_t vertices = 0, tets = 0;
  double seconds = 0.0;
};

std::size_t vertices_in_complex(const Tr& tr) {
  std::size_t n = 0;
  for (auto v : tr.finite_vertex_handles()) {
    (void)v;
    ++n;
  }
  return n;
}

RunResult remesh(const Input& in, double edge_length, int iterations, Tr* keep) {
  Tr tr = build_triangulation(in);
  CGAL::get_default_random() = CGAL::Random(0);
  const auto t0 = std::chrono::steady_clock::now();
  CGAL::tetrahedral_isotropic_remeshing(tr, edge_length,
                                        CGAL::parameters::number_of_iterations(iterations).remesh_boundaries(true));
  RunResult r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.edge_length = edge_length;
  std::size_t cells = 0;
  for (auto c : tr.finite_cell_handles())
    if (c->subdomain_index() != 0) ++cells;
  r.tets = cells;
  r.vertices = vertices_in_complex(tr);
  if (keep) *keep = std::move(tr);
  return r;
}

cgal_bench::MeditMesh to_medit(const Tr& tr, const Input& in) {
  cgal_bench::MeditMesh out;
  std::unordered_map<Tr::Vertex_handle, std::uint32_t> index;
  const auto id = [&](Tr::Vertex_handle v) {
    const auto [it, inserted] = index.try_emplace(v, static_cast<std::uint32_t>(out.positions.size()));
    if (inserted) out.positions.push_back({v->point().x(), v->point().y(), v->point().z()});
    return it->second;
  };
  const auto sub = [&](Tr::Cell_handle c) { return tr.is_infinite(c) ? 0 : static_cast<int>(c->subdomain_index()); };
  for (auto c : tr.finite_cell_handles()) {
    const int s = sub(c);
    if (s == 0) continue;
    out.tets.push_back({id(c->vertex(0)), id(c->vertex(1)), id(c->vertex(2)), id(c->vertex(3))});
    out.tet_ref.push_back(in.materials[static_cast<std::size_t>(s - 1)]);
  }
  for (auto f : tr.finite_facets()) {
    const auto c = f.first;
    const auto n = c->neighbor(f.second);
    const int a = sub(c), b = sub(n);
    if (a == b) continue;
    const auto it = in.pair_ref.find({std::min(a, b), std::max(a, b)});
    if (it == in.pair_ref.end()) continue;  // a surface the input does not list
    std::array<std::uint32_t, 3> tri{};
    for (int i = 0, k = 0; i < 4; ++i)
      if (i != f.second) tri[k++] = id(c->vertex(i));
    out.triangles.push_back(tri);
    out.triangle_ref.push_back(it->second);
  }
  return out;
}

std::string json_escape(const std::string& s) {
  std::string o;
  for (char ch : s) {
    if (ch == '"' || ch == '\\') o += '\\';
    o += ch;
  }
  return o;
}

int run(const Args& args) {
  const auto t0 = std::chrono::steady_clock::now();
  const Input in = prepare(args.input);
  const std::size_t nv_in = in.mesh.positions.size();
  std::printf("IN  %s: %zu vertices, %zu tets, %zu materials, %zu listed triangles%s\n", args.input.c_str(), nv_in,
              in.mesh.tets.size(), in.materials.size(), in.mesh.triangles.size(),
              in.flipped ? (", " + std::to_string(in.flipped) + " tets reoriented").c_str() : "");
  for (const auto& w : in.warnings) std::printf("warning: %s\n", w.c_str());
  const double target = args.vertices > 0 ? static_cast<double>(args.vertices)
                                          : args.ratio > 0 ? args.ratio * static_cast<double>(nv_in) : 0.0;
  std::vector<RunResult> runs;
  Tr best_tr;
  std::size_t best = 0;
  const auto miss = [&](const RunResult& r) { return std::abs(std::log(static_cast<double>(r.vertices) / target)); };
  if (args.edge_length > 0) {
    runs.push_back(remesh(in, args.edge_length, args.iterations, &best_tr));
    std::printf("run 1: edge length %.6g -> %zu vertices, %zu tets, %.2f s\n", runs[0].edge_length, runs[0].vertices,
                runs[0].tets, runs[0].seconds);
  } else {
    // A vertex per ~0.54 L^3 in an isotropic mesh of edge length L (about 6 tets per vertex of
    // volume ~0.09 L^3): a first guess, then secant steps in log-log.
    double length = std::cbrt(in.volume / (0.54 * target));
    double slope = -2.5;  // d log(vertices) / d log(length); surfaces make it between -2 and -3
    for (int k = 0; k < args.max_runs; ++k) {
      Tr tr;
      const RunResult r = remesh(in, length, args.iterations, &tr);
      std::printf("run %d: edge length %.6g -> %zu vertices (target %.0f), %zu tets, %.2f s\n", k + 1, r.edge_length,
                  r.vertices, target, r.tets, r.seconds);
      std::fflush(stdout);
      runs.push_back(r);
      if (runs.size() == 1 || miss(r) < miss(runs[best])) {
        best = runs.size() - 1;
        best_tr = std::move(tr);
      }
      if (std::abs(static_cast<double>(r.vertices) / target - 1.0) <= args.tolerance) break;
      if (runs.size() >= 2) {
        const RunResult& p = runs[runs.size() - 2];
        const double dl = std::log(r.edge_length / p.edge_length);
        if (std::abs(dl) > 1e-9 && r.vertices != p.vertices) {
          const double s = std::log(static_cast<double>(r.vertices) / static_cast<double>(p.vertices)) / dl;
          if (s < -0.5 && s > -6.0) slope = s;
        }
      }
      length = r.edge_length * std::exp(std::log(static_cast<double>(r.vertices) / target) / -slope);
    }
  }
  const RunResult& chosen = runs[best];
  const cgal_bench::MeditMesh out = to_medit(best_tr, in);
  cgal_bench::write_medit(args.output, out);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("OUT %s: %zu vertices, %zu tets, %zu triangles; remeshing %.2f s (edge length %.6g), whole search %.2f s in %zu runs\n",
              args.output.c_str(), out.positions.size(), out.tets.size(), out.triangles.size(), chosen.seconds,
              chosen.edge_length, total, runs.size());
  if (!args.json.empty()) {
    std::FILE* f = std::fopen(args.json.c_str(), "w");
    if (!f) throw std::runtime_error(args.json + ": cannot write");
    const auto run_json = [](const RunResult& r) {
      char buf[256];
      std::snprintf(buf, sizeof buf, "{\"edge_length\": %.9g, \"vertices\": %zu, \"tets\": %zu, \"seconds\": %.4f}",
                    r.edge_length, r.vertices, r.tets, r.seconds);
      return std::string(buf);
    };
    std::fprintf(f, "{\"input\": \"%s\", \"output\": \"%s\", \"vertices_in\": %zu, \"target_vertices\": %.0f,\n",
                 json_escape(args.input).c_str(), json_escape(args.output).c_str(), nv_in, target);
    std::fprintf(f, " \"iterations\": %d, \"remesh_boundaries\": true,\n \"runs\": [", args.iterations);
    for (std::size_t i = 0; i < runs.size(); ++i) std::fprintf(f, "%s%s", i ? ", " : "", run_json(runs[i]).c_str());
    std::fprintf(f, "],\n \"chosen\": %s,\n \"vertices_out\": %zu, \"tets_out\": %zu, \"total_seconds\": %.4f,\n \"warnings\": [",
                 run_json(chosen).c_str(), out.positions.size(), out.tets.size(), total);
    for (std::size_t i = 0; i < in.warnings.size(); ++i)
      std::fprintf(f, "%s\"%s\"", i ? ", " : "", json_escape(in.warnings[i]).c_str());
    std::fprintf(f, "]}\n");
    std::fclose(f);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cgal_remesh: %s\n", e.what());
    return 2;
  }
}
