// cgal_remesh IN.mesh OUT.mesh --vertices N | --ratio R: CGAL's tetrahedral_isotropic_remeshing
// (CGAL/tetrahedral_remeshing.h) used as a coarsener, for a side-by-side benchmark with topotet
// (bench/quality_vs_remesher.py, issue #26 item 4).
//
// The MEDIT input becomes a Mesh_complex_3_in_triangulation_3 on a
// Tetrahedral_remeshing::Remeshing_triangulation_3, and everything the input lists goes into the
// complex, so that CGAL keeps it as topotet does:
//  - the materials are the subdomain indices (1, 2, ... in the order of the materials: CGAL
//    reserves 0 for "outside");
//  - every listed triangle is a complex facet whose surface patch is its ref (embedded surfaces
//    inside one material included); the material interfaces and the boundary that the input does
//    not list are complex facets too (one patch per pair of materials), not written back;
//  - every listed edge (MEDIT Edges) is a complex edge whose curve is its ref;
//  - Corners and RequiredVertices are complex vertices (corners).
// The surfaces are remeshed (remesh_boundaries = true, CGAL's default, protect off): with frozen
// surfaces a coarsener cannot go below the surface vertex count, and topotet simplifies its
// surfaces too. CGAL adds as features the edges where three or more subdomains or two or more
// patches meet. Complex edges are split and collapsed along themselves, their vertices are not
// smoothed (smooth_constrained_edges false, CGAL's default).
//
// CGAL takes a target edge length, not a vertex count: a short search finds it. A first length
// from the volume (a vertex per 0.54 L^3 of an isotropic mesh), then secant steps on
// log(vertices) against log(length) until the count is within --tolerance (5%) of the target or
// --max-runs runs were made; the run closest to the target is written. Each run starts from the
// input. The time of the chosen run and of the whole search are printed (and written with --json).
//
// Output: MEDIT with the materials, the listed triangles, edges and corners back under their refs.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Random.h>
#include <CGAL/Tetrahedral_remeshing/Remeshing_triangulation_3.h>
#include <CGAL/tetrahedral_remeshing.h>
#include <CGAL/Mesh_3/tet_soup_to_c3t3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>

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
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr, int, int>;  // corner and curve indices: int

// Index ranges in the complex. Surface patches: 1..listed refs, then kUnlistedPatch + pair for the
// interfaces the input does not list. Curves: CGAL gives its own features curve 1; listed edge refs
// from 2. Corners: CGAL numbers its own from 1; listed ones from kCornerBase / kRequiredBase.
constexpr int kUnlistedPatch = 1 << 24;
constexpr int kFirstCurve = 2;
constexpr int kCornerBase = 1 << 24;
constexpr int kRequiredBase = 1 << 25;

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
  std::vector<int> materials;  // subdomain s (1-based) has material materials[s - 1]
  std::vector<int> subdomain;  // [tet] 1, 2, ...
  std::vector<int> triangle_refs, edge_refs;  // sorted distinct: patch i + 1, curve i + kFirstCurve
  std::map<std::array<int, 3>, int> facet_patch;  // (min vertex, other two sorted) -> patch
  std::vector<int> ridge_refs;  // edge refs all of whose edges are Ridges
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
      for (int i = 0; i < 3; ++i) ++edges[{std::min(f[i], f[(i + 1) % 3]), std::max(f[i], f[(i + 1) % 3]), 0}];
    }
    std::size_t non_manifold = 0;
    for (const auto& [e, n] : edges) non_manifold += n > 2 ? 1 : 0;
    // The infinite vertex's link is the boundary: it must be one sphere (Euler characteristic 2).
    std::size_t boundary_faces = 0;
    std::unordered_map<std::uint32_t, char> boundary_vertices;
    for (const auto& [f, n] : faces)
      if (n == 1) {
        ++boundary_faces;
        for (std::uint32_t v : f) boundary_vertices[v] = 1;
      }
    const long long euler = static_cast<long long>(boundary_vertices.size()) - static_cast<long long>(edges.size()) +
                            static_cast<long long>(boundary_faces);
    if (shared > 0)
      throw std::runtime_error(path + ": " + std::to_string(shared) + " faces shared by more than two tets");
    if (non_manifold > 0)
      throw std::runtime_error(path + ": the boundary has " + std::to_string(non_manifold) +
                               " non-manifold edges (more than two boundary faces): CGAL's triangulation cannot "
                               "represent it (CGAL::build_triangulation refuses it)");
    if (euler != 2)
      throw std::runtime_error(path + ": the boundary's Euler characteristic is " + std::to_string(euler) +
                               ", not one sphere's (2): CGAL's triangulation closes the boundary with one infinite "
                               "vertex whose link must be a sphere (CGAL::build_triangulation refuses it)");
  }
  in.materials = m.tet_ref;
  std::sort(in.materials.begin(), in.materials.end());
  in.materials.erase(std::unique(in.materials.begin(), in.materials.end()), in.materials.end());
  in.subdomain.resize(m.tets.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    in.subdomain[t] = static_cast<int>(std::lower_bound(in.materials.begin(), in.materials.end(), m.tet_ref[t]) -
                                       in.materials.begin()) + 1;
  // Surface patches: the listed triangles by ref, then the unlisted interfaces and boundary.
  for (int r : m.triangle_ref) in.triangle_refs.push_back(r);
  std::sort(in.triangle_refs.begin(), in.triangle_refs.end());
  in.triangle_refs.erase(std::unique(in.triangle_refs.begin(), in.triangle_refs.end()), in.triangle_refs.end());
  const auto key = [](std::array<std::uint32_t, 3> f) {
    f = sorted(f);
    return std::array<int, 3>{static_cast<int>(f[0]), static_cast<int>(f[1]), static_cast<int>(f[2])};
  };
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const int patch = static_cast<int>(std::lower_bound(in.triangle_refs.begin(), in.triangle_refs.end(), m.triangle_ref[i]) -
                                       in.triangle_refs.begin()) + 1;
    if (!in.facet_patch.emplace(key(m.triangles[i]), patch).second)
      in.warnings.push_back("a triangle is listed twice; its first ref is kept");
  }
  {
    std::unordered_map<std::array<std::uint32_t, 3>, std::array<int, 2>, FaceHash> sides;  // subdomains, 0 = none
    sides.reserve(m.tets.size() * 3);
    for (std::size_t t = 0; t < m.tets.size(); ++t)
      for (int i = 0; i < 4; ++i) {
        std::array<std::uint32_t, 3> f{};
        for (int j = 0, k = 0; j < 4; ++j)
          if (j != i) f[k++] = m.tets[t][j];
        auto& s = sides[sorted(f)];
        (s[0] == 0 ? s[0] : s[1]) = in.subdomain[t];
      }
    const int n = static_cast<int>(in.materials.size()) + 1;
    for (const auto& [f, s] : sides) {
      if (s[0] == s[1]) continue;
      const std::array<int, 3> k{static_cast<int>(f[0]), static_cast<int>(f[1]), static_cast<int>(f[2])};
      in.facet_patch.try_emplace(k, kUnlistedPatch + std::min(s[0], s[1]) * n + std::max(s[0], s[1]));
    }
  }
  // Curves: the listed edges by ref; ridges by ref.
  for (int r : m.edge_ref) in.edge_refs.push_back(r);
  std::sort(in.edge_refs.begin(), in.edge_refs.end());
  in.edge_refs.erase(std::unique(in.edge_refs.begin(), in.edge_refs.end()), in.edge_refs.end());
  if (!m.ridges.empty()) {
    std::map<int, std::pair<std::size_t, std::size_t>> count;  // ref -> (edges, ridges)
    for (int r : m.edge_ref) ++count[r].first;
    for (std::uint32_t e : m.ridges) ++count[m.edge_ref[e]].second;
    for (const auto& [r, c] : count)
      if (c.second == c.first) in.ridge_refs.push_back(r);
      else if (c.second > 0)
        in.warnings.push_back("edge ref " + std::to_string(r) + " is partly Ridges: written without Ridges");
  }
  if (m.skipped_entries > 0)
    in.warnings.push_back(std::to_string(m.skipped_entries) + " entries of other MEDIT sections not carried");
  return in;
}

// CGAL 5.5 has no tetrahedron_soup_to_triangulation_3 (5.6 adds it): CGAL::build_triangulation
// (CGAL/Mesh_3/tet_soup_to_c3t3.h) is what CGAL's own MEDIT loader and the remesher use. It gives
// the cells their subdomains and the facets of `facet_patch` their patches; the listed edges and
// corners are added to the complex here.
// The listed corners and required vertices, by handle: the remesher renumbers the corners of the
// complex (rescan_after_load_of_triangulation), but never removes a vertex of dimension 0.
struct Pinned {
  std::vector<Tr::Vertex_handle> corners, required;
};

void build_complex(const Input& in, C3t3& c3t3, Pinned& pinned) {
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
  std::vector<Tr::Vertex_handle> handles(points.size() + 1);
  Tr tr;
  if (!CGAL::build_triangulation<Tr, false>(tr, points, cells, in.facet_patch, handles,
                                            std::getenv("CGAL_REMESH_VERBOSE") != nullptr))
    throw std::runtime_error("CGAL::build_triangulation refused the mesh");
  c3t3.triangulation().swap(tr);
  c3t3.rescan_after_load_of_triangulation();  // cells by subdomain, facets by patch
  for (std::size_t e = 0; e < in.mesh.edges.size(); ++e) {
    const auto a = handles[in.mesh.edges[e][0] + 1], b = handles[in.mesh.edges[e][1] + 1];
    Tr::Cell_handle c;
    int i = 0, j = 0;
    if (!c3t3.triangulation().tds().is_edge(a, b, c, i, j))
      throw std::runtime_error("a listed edge is no edge of the tets");
    if (c3t3.is_in_complex(a, b)) continue;  // listed twice
    const int curve = static_cast<int>(std::lower_bound(in.edge_refs.begin(), in.edge_refs.end(), in.mesh.edge_ref[e]) -
                                       in.edge_refs.begin()) + kFirstCurve;
    c3t3.add_to_complex(a, b, curve);
    for (auto v : {a, b})
      if (v->in_dimension() != 0) v->set_dimension(1);
  }
  for (std::size_t k = 0; k < in.mesh.corners.size(); ++k) {
    const auto v = handles[in.mesh.corners[k] + 1];
    c3t3.add_to_complex(v, kCornerBase + static_cast<int>(k));
    v->set_dimension(0);
    pinned.corners.push_back(v);
  }
  for (std::size_t k = 0; k < in.mesh.required_vertices.size(); ++k) {
    const auto v = handles[in.mesh.required_vertices[k] + 1];
    if (c3t3.is_in_complex(v)) continue;  // a corner too
    c3t3.add_to_complex(v, kRequiredBase + static_cast<int>(k));
    v->set_dimension(0);
    pinned.required.push_back(v);
  }
}

struct RunResult {
  double edge_length = 0.0;
  std::size_t vertices = 0, tets = 0;
  double seconds = 0.0;
};

RunResult remesh(const Input& in, double edge_length, int iterations, C3t3* keep, Pinned* keep_pinned) {
  C3t3 c3t3;
  Pinned pinned;
  build_complex(in, c3t3, pinned);
  CGAL::get_default_random() = CGAL::Random(0);
  const auto t0 = std::chrono::steady_clock::now();
  CGAL::tetrahedral_isotropic_remeshing(c3t3, edge_length,
                                        CGAL::parameters::number_of_iterations(iterations).remesh_boundaries(true));
  RunResult r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.edge_length = edge_length;
  r.tets = c3t3.number_of_cells_in_complex();
  r.vertices = c3t3.triangulation().number_of_vertices();
  if (keep) {
    keep->swap(c3t3);
    std::swap(*keep_pinned, pinned);
  }
  return r;
}

cgal_bench::MeditMesh to_medit(const C3t3& c3t3, const Pinned& pinned, const Input& in) {
  cgal_bench::MeditMesh out;
  std::unordered_map<Tr::Vertex_handle, std::uint32_t> index;
  const auto id = [&](Tr::Vertex_handle v) {
    const auto [it, inserted] = index.try_emplace(v, static_cast<std::uint32_t>(out.positions.size()));
    if (inserted) out.positions.push_back({v->point().x(), v->point().y(), v->point().z()});
    return it->second;
  };
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    out.tets.push_back({id(c->vertex(0)), id(c->vertex(1)), id(c->vertex(2)), id(c->vertex(3))});
    out.tet_ref.push_back(in.materials[static_cast<std::size_t>(c3t3.subdomain_index(c) - 1)]);
  }
  for (auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f) {
    const int patch = c3t3.surface_patch_index(*f);
    if (patch < 1 || patch > static_cast<int>(in.triangle_refs.size())) continue;  // not listed in the input
    std::array<std::uint32_t, 3> tri{};
    for (int i = 0, k = 0; i < 4; ++i)
      if (i != f->second) tri[k++] = id(f->first->vertex(i));
    out.triangles.push_back(tri);
    out.triangle_ref.push_back(in.triangle_refs[static_cast<std::size_t>(patch - 1)]);
  }
  for (auto e = c3t3.edges_in_complex_begin(); e != c3t3.edges_in_complex_end(); ++e) {
    const int curve = c3t3.curve_index(*e);
    if (curve < kFirstCurve || curve - kFirstCurve >= static_cast<int>(in.edge_refs.size())) continue;  // CGAL's own
    const int ref = in.edge_refs[static_cast<std::size_t>(curve - kFirstCurve)];
    if (std::binary_search(in.ridge_refs.begin(), in.ridge_refs.end(), ref))
      out.ridges.push_back(static_cast<std::uint32_t>(out.edges.size()));
    out.edges.push_back({id(e->first->vertex(e->second)), id(e->first->vertex(e->third))});
    out.edge_ref.push_back(ref);
  }
  for (auto v : pinned.corners) out.corners.push_back(id(v));
  for (auto v : pinned.required) out.required_vertices.push_back(id(v));
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
  std::printf("IN  %s: %zu vertices, %zu tets, %zu materials, %zu listed triangles, %zu edges, %zu corners, %zu required%s\n",
              args.input.c_str(), nv_in, in.mesh.tets.size(), in.materials.size(), in.mesh.triangles.size(),
              in.mesh.edges.size(), in.mesh.corners.size(), in.mesh.required_vertices.size(),
              in.flipped ? (", " + std::to_string(in.flipped) + " tets reoriented").c_str() : "");
  for (const auto& w : in.warnings) std::printf("warning: %s\n", w.c_str());
  std::fflush(stdout);
  const double target = args.vertices > 0 ? static_cast<double>(args.vertices)
                                          : args.ratio > 0 ? args.ratio * static_cast<double>(nv_in) : 0.0;
  std::vector<RunResult> runs;
  C3t3 best_c3t3;
  Pinned best_pinned;
  std::size_t best = 0;
  const auto miss = [&](const RunResult& r) { return std::abs(std::log(static_cast<double>(r.vertices) / target)); };
  if (args.edge_length > 0) {
    runs.push_back(remesh(in, args.edge_length, args.iterations, &best_c3t3, &best_pinned));
    std::printf("run 1: edge length %.6g -> %zu vertices, %zu tets, %.2f s\n", runs[0].edge_length, runs[0].vertices,
                runs[0].tets, runs[0].seconds);
  } else {
    // A vertex per ~0.54 L^3 in an isotropic mesh of edge length L (about 6 tets per vertex of
    // volume ~0.09 L^3): a first guess, then secant steps in log-log.
    double length = std::cbrt(in.volume / (0.54 * target));
    double slope = -2.5;  // d log(vertices) / d log(length); surfaces make it between -2 and -3
    for (int k = 0; k < args.max_runs; ++k) {
      C3t3 c3t3;
      Pinned pinned;
      std::printf("run %d: edge length %.17g", k + 1, length);
      std::fflush(stdout);
      const RunResult r = remesh(in, length, args.iterations, &c3t3, &pinned);
      std::printf(" -> %zu vertices (target %.0f), %zu tets, %.2f s\n", r.vertices, target, r.tets, r.seconds);
      std::fflush(stdout);
      runs.push_back(r);
      if (runs.size() == 1 || miss(r) < miss(runs[best])) {
        best = runs.size() - 1;
        best_c3t3.swap(c3t3);
        std::swap(best_pinned, pinned);
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
  const cgal_bench::MeditMesh out = to_medit(best_c3t3, best_pinned, in);
  cgal_bench::write_medit(args.output, out);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("OUT %s: %zu vertices, %zu tets, %zu triangles, %zu edges, %zu corners; remeshing %.2f s (edge length %.6g), whole search %.2f s in %zu runs\n",
              args.output.c_str(), out.positions.size(), out.tets.size(), out.triangles.size(), out.edges.size(),
              out.corners.size() + out.required_vertices.size(), chosen.seconds,
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
