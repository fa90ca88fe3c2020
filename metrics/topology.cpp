// compute_topology: one global simplex index, then each complex of the report as the closure of
// its top simplices. A complex certified to be a surface or a solid (manifold_betti.h) gets its
// Betti numbers from counts; any other is reduced and eliminated over Z2 (z2_homology.cpp). Large
// meshes check their complexes in parallel; the result does not depend on the thread count.
#include "topotet/metrics/topology.h"

#include <algorithm>
#include <vector>

#include "parallel/for_range.h"
#include "parallel/reduce.h"
#include "parallel/scratch.h"
#include "mesh/glm_convert.h"
#include "manifold_betti.h"
#include "robust_orient.h"
#include "simplex_index.h"
#include "z2_homology.h"

namespace topotet {
using namespace metrics;  // the checker's internals (z2_homology.h, manifold_betti.h, ...)
namespace {

using detail::SimplexIndex;
using detail::TopSimplices;

// Below this many tets a check takes a few milliseconds at most: threads would cost more than
// they save, and tests call the checker thousands of times, often from parallel test runners.
constexpr std::size_t kParallelTetThreshold = 20'000;
// Largest mesh (vertices + edges + triangles) whose scratch a thread keeps between calls (~8 MB).
constexpr std::size_t kCachedScratchSlots = 1u << 20;

struct Workspace {
  detail::ClosureScratch closure;
  detail::LocalComplex complex;
  detail::HomologyScratch homology;
  detail::ManifoldScratch manifold;
};

// Which manifold certificates a complex may try (manifold_betti.h).
struct FastPaths {
  bool surface = false;  // pure 2-complexes
  bool solid = false;    // pure 3-complexes; only when every tet is positively oriented
};

// `certified` is set when a manifold certificate gave the Betti numbers.
ComplexTopology compute_complex(const SimplexIndex& index, const TopSimplices& tops, bool fast, FastPaths paths,
                                Workspace& ws, bool& certified) {
  detail::extract_closure(index, tops, ws.closure, ws.complex);
  const detail::LocalComplex& c = ws.complex;
  ComplexTopology result;
  result.simplex_count = {static_cast<std::int64_t>(c.vertex_count), static_cast<std::int64_t>(c.edges.size()),
                          static_cast<std::int64_t>(c.faces.size()), static_cast<std::int64_t>(c.tets.size())};
  const auto& n = result.simplex_count;
  result.euler_characteristic = n[0] - n[1] + n[2] - n[3];
  if (!fast) {
    const bool is_pure_solid = !tops.tets.empty() && tops.faces.empty() && tops.edges.empty() && tops.vertices.empty();
    const bool is_pure_surface = tops.tets.empty() && !tops.faces.empty() && tops.edges.empty() && tops.vertices.empty();
    certified = (paths.solid && is_pure_solid && detail::solid_betti(c, ws.manifold, result.betti)) ||
                (paths.surface && is_pure_surface && detail::surface_betti(c, ws.manifold, result.betti));
    if (certified) return result;
    result.betti = detail::z2_betti(c, ws.homology);
    return result;
  }
  const int dimension = n[3] > 0 ? 3 : n[2] > 0 ? 2 : n[1] > 0 ? 1 : 0;
  result.betti = {static_cast<std::int64_t>(detail::count_components(c, ws.homology)), kUnknownBetti, kUnknownBetti,
                  kUnknownBetti};
  for (int k = dimension + 1; k < 4; ++k) result.betti[k] = 0;
  // For a graph chi = b0 - b1, so b1 is known without any elimination.
  if (dimension <= 1) result.betti[1] = result.betti[0] - result.euler_characteristic;
  return result;
}

void count_tet_faults(const MeshData& mesh, TopologyReport& report) {
  const std::size_t n = mesh.positions.size();
  using Counts = std::array<std::uint64_t, 2>;  // inverted, degenerate
  const Counts counts = parallel::block_reduce(
      mesh.tets.size(), 16384, "tet_orientation", Counts{},
      [&](std::size_t begin, std::size_t end) {
        Counts c{};
        for (std::size_t t = begin; t < end; ++t) {
          const auto& tet = mesh.tets[t];
          if (tet[0] >= n || tet[1] >= n || tet[2] >= n || tet[3] >= n) continue;  // invalid, counted by the index
          const bool has_repeat = tet[0] == tet[1] || tet[0] == tet[2] || tet[0] == tet[3] || tet[1] == tet[2] ||
                                  tet[1] == tet[3] || tet[2] == tet[3];
          const int sign = has_repeat ? 0
                                      : detail::orient3d_sign(to_glm(mesh.positions[tet[0]]), to_glm(mesh.positions[tet[1]]),
                                                              to_glm(mesh.positions[tet[2]]), to_glm(mesh.positions[tet[3]]));
          c[0] += sign < 0;
          c[1] += sign == 0;
        }
        return c;
      },
      [](Counts& total, const Counts& part) { total[0] += part[0], total[1] += part[1]; });
  report.inverted_tet_count += counts[0];
  report.degenerate_tet_count += counts[1];
}

// The top simplices of every complex, owned here so that jobs can refer to them by span.
struct TopLists {
  std::map<std::int32_t, std::vector<TetId>> material_tets;
  std::map<std::int32_t, std::vector<std::uint32_t>> surface_faces;
  std::map<MaterialPair, std::vector<std::uint32_t>> interface_faces;
  std::vector<std::uint32_t> all_surface_faces;
  std::map<std::int32_t, std::vector<std::uint32_t>> polyline_edges;
  std::vector<std::uint32_t> all_polyline_edges;
  std::vector<VertId> pinned;
};

TopLists collect_top_lists(const MeshData& mesh, const SimplexIndex& index, std::uint64_t& invalid_pinned) {
  TopLists lists;
  std::vector<TetId>* current = nullptr;  // materials come in runs: skip most map lookups
  std::int32_t current_material = 0;
  for (TetId t : index.kept_tets) {
    const std::int32_t m = detail::material_of(mesh, index.mesh_tet(t));
    if (current == nullptr || m != current_material) {
      current = &lists.material_tets[m];
      current_material = m;
    }
    current->push_back(t);
  }
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const std::uint32_t f = index.triangle2face[i];
    if (f == kInvalid) continue;
    lists.surface_faces[mesh.triangles[i].ref].push_back(f);
    lists.all_surface_faces.push_back(f);
  }
  for (const auto& face : index.interface_faces) {
    lists.interface_faces[{face.material_a, face.material_b}].push_back(face.face);
    lists.all_surface_faces.push_back(face.face);
  }
  for (std::size_t i = 0; i < mesh.segments.size(); ++i) {
    const std::uint32_t e = index.segment2edge[i];
    if (e == kInvalid) continue;
    lists.polyline_edges[mesh.segments[i].ref].push_back(e);
    lists.all_polyline_edges.push_back(e);
  }
  for (const auto* pinned : {&mesh.corners, &mesh.required_vertices})
    for (VertId v : *pinned) {
      if (v < mesh.positions.size()) {
        lists.pinned.push_back(index.vertex_of(v));
      } else {
        ++invalid_pinned;
      }
    }
  std::sort(lists.pinned.begin(), lists.pinned.end());
  lists.pinned.erase(std::unique(lists.pinned.begin(), lists.pinned.end()), lists.pinned.end());
  return lists;
}

struct Job {
  ComplexTopology* out = nullptr;
  TopSimplices tops;
  bool certified = false;
  std::size_t size() const { return 8 * tops.tets.size() + 4 * tops.faces.size() + 2 * tops.edges.size() + tops.vertices.size(); }
};

}  // namespace

TopologyReport compute_topology(const MeshData& mesh, const TopologyOptions& options) {
  TopologyReport report;
  report.is_fast = options.fast;
  count_tet_faults(mesh, report);

  const SimplexIndex index = detail::build_simplex_index(mesh);
  report.nonmanifold_face_count = index.nonmanifold_face_count;
  report.unreferenced_vertex_count = index.unreferenced_vertex_count;
  report.duplicate_tet_count = index.duplicate_tet_count;
  report.invalid_element_count = index.invalid_tet_count + index.invalid_triangle_count + index.invalid_segment_count;
  report.detached_triangle_count = index.detached_triangle_count;
  report.detached_segment_count = index.detached_segment_count;

  const TopLists lists = collect_top_lists(mesh, index, report.invalid_element_count);
  report.pinned_vertex_count = lists.pinned.size();

  // Complexes whose top simplices equal another's are computed once and copied (the common case
  // of a single material, whose region is the whole mesh).
  std::vector<Job> jobs;
  std::vector<std::pair<ComplexTopology*, const ComplexTopology*>> copies;
  jobs.push_back({&report.mesh, {.tets = index.kept_tets}});
  jobs.push_back({&report.boundary, {.faces = index.boundary_faces}});
  for (const auto& [material, tets] : lists.material_tets) {
    if (lists.material_tets.size() == 1) {
      copies.push_back({&report.materials[material], &report.mesh});
    } else {
      jobs.push_back({&report.materials[material], {.tets = tets}});
    }
  }
  for (const auto& [ref, faces] : lists.surface_faces) jobs.push_back({&report.surfaces[ref], {.faces = faces}});
  for (const auto& [pair, faces] : lists.interface_faces) jobs.push_back({&report.interfaces[pair], {.faces = faces}});
  jobs.push_back({&report.all_surfaces, {.faces = lists.all_surface_faces}});
  for (const auto& [ref, edges] : lists.polyline_edges) jobs.push_back({&report.polylines[ref], {.edges = edges}});
  jobs.push_back({&report.all_polylines, {.edges = lists.all_polyline_edges}});
  if (lists.all_polyline_edges.empty() && lists.pinned.empty()) {
    copies.push_back({&report.embedded, &report.all_surfaces});
  } else {
    jobs.push_back({&report.embedded,
                    {.faces = lists.all_surface_faces, .edges = lists.all_polyline_edges, .vertices = lists.pinned}});
  }

  // Jobs hold spans: the union of boundary and surface faces must outlive them.
  std::vector<std::uint32_t> feature_faces = lists.all_surface_faces;
  feature_faces.insert(feature_faces.end(), index.boundary_faces.begin(), index.boundary_faces.end());
  std::sort(feature_faces.begin(), feature_faces.end());
  feature_faces.erase(std::unique(feature_faces.begin(), feature_faces.end()), feature_faces.end());
  jobs.push_back({&report.features, {.faces = feature_faces, .edges = lists.all_polyline_edges, .vertices = lists.pinned}});

  FastPaths paths;
  paths.surface = options.manifold_fast_path;
  paths.solid = options.manifold_fast_path && report.inverted_tet_count == 0 && report.degenerate_tet_count == 0;
  if (index.kept_tets.size() < kParallelTetThreshold) {
    // Reused across calls on this thread, so the thousands of small checks a property test makes
    // allocate (and page-fault) much less; only small meshes use it, so it never holds much.
    thread_local Workspace cached;
    Workspace uncached;
    const std::size_t slot_count = index.vertex_count + index.edge2verts.size() + index.face2edges.size();
    Workspace& ws = slot_count < kCachedScratchSlots ? cached : uncached;
    for (Job& job : jobs) *job.out = compute_complex(index, job.tops, options.fast, paths, ws, job.certified);
  } else {
    // Biggest first so that the long jobs do not end up last on one thread. Every job writes its
    // own ComplexTopology (map nodes are stable and all inserted above), so no synchronisation.
    std::stable_sort(jobs.begin(), jobs.end(), [](const Job& a, const Job& b) { return a.size() > b.size(); });
    parallel::PerThread<Workspace> workspaces;
    parallel::for_range<std::size_t>(0, jobs.size(), 1, "topology_complexes", [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i)
        *jobs[i].out = compute_complex(index, jobs[i].tops, options.fast, paths, workspaces.local(), jobs[i].certified);
    });
  }
  for (const auto& [to, from] : copies) *to = *from;
  for (const Job& job : jobs) report.certified_manifold_count += job.certified;
  return report;
}

}  // namespace topotet
