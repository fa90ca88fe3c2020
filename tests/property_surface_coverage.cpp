// The tolerance guarantee of issue #12 part 3, checked independently of the engines' schedules:
// thousands of random collapses through the kernel (may_collapse + collapse with the surface
// coverage) on small meshes whose surfaces are curved and jittered (the hard case) or flat with
// sharp features, then
//   - the coverage invariant itself, recomputed from scratch: every item (an original triangle or
//     segment, or a piece of one) lies within h of the live face (edge) that holds it, that face
//     has the item's label, and the pieces of every original triangle (segment) add up to at
//     least its area (length): nothing of the original is left without a holder;
//   - the two-sided Hausdorff distance the metric measures (metrics/surface_distance.h), with no
//     slack: <= h for every label;
//   - planted faults: moving a surface vertex by 3h after the run breaks the invariant and the
//     metric sees the distance grow above h, so neither check passes vacuously.
// The same with the flips of a stalled run between the collapses (engine/flip_at_stall.h: the
// tets are retriangulated and renumbered, and the coverage moves with its faces and edges).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include <glm/geometric.hpp>

#include "flip_at_stall.h"
#include "kernel/collapse.h"
#include "mesh/glm_convert.h"
#include "entry_points.h"
#include "mesh/mesh_model.h"
#include "guarantees/surface_coverage.h"
#include "guarantees/surface_tolerance.h"
#include "topotet/features.h"
#include "topotet/generate.h"
#include "topotet/metrics/surface_distance.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

double diagonal(const MeshModel& mesh) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const glm::dvec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return glm::length(hi - lo);
}

struct CollapseRun {
  MeshModel mesh;
  std::unique_ptr<SurfaceReference> reference;
  std::unique_ptr<SurfaceCoverage> coverage;
  double h = 0.0;
  MeshData input;
  std::size_t applied = 0, refused_tolerance = 0;
  std::uint64_t flips = 0;
};

// Random edges, placed at either end or the midpoint, through the full kernel with the coverage;
// with flip_every > 0, the flips of a stalled run every that many attempts.
void random_collapses(CollapseRun& r, int attempts, std::uint64_t seed, int flip_every = 0) {
  std::mt19937_64 rng(seed);
  CollapseOptions kernel;
  kernel.surfaces = r.reference.get();
  kernel.tolerance = r.h;
  kernel.coverage = r.coverage.get();
  CollapseScratch scratch;
  std::uint32_t refs_used = static_cast<std::uint32_t>(r.mesh.refs_table.size());
  std::vector<VertId> nbrs;
  for (int i = 0; i < attempts; ++i) {
    if (flip_every > 0 && i > 0 && i % flip_every == 0) {
      Report report;
      detail::flip_at_stall(r.mesh, r.coverage.get(), nullptr, report);
      r.flips += report.stall_flips;
      refs_used = std::max(refs_used, static_cast<std::uint32_t>(r.mesh.refs_table.size()));  // as the engines do
    }
    const auto u = static_cast<VertId>(rng() % r.mesh.vertex_capacity());
    if (r.mesh.is_dead_vertex(u)) continue;
    r.mesh.neighbours(u, nbrs);
    if (nbrs.empty()) continue;
    const VertId v = nbrs[rng() % nbrs.size()];
    const int where = static_cast<int>(rng() % 3);
    const glm::dvec3 p = where == 0 ? r.mesh.positions[u] : where == 1 ? r.mesh.positions[v]
                                                                     : 0.5 * (r.mesh.positions[u] + r.mesh.positions[v]);
    const CollapseReason reason = may_collapse(r.mesh, u, v, p, kernel, scratch);
    if (reason == CollapseReason::kTolerance) ++r.refused_tolerance;
    if (reason != CollapseReason::kOk) continue;
    reserve_refs_headroom(r.mesh, refs_used, scratch.star_u.size() + scratch.star_v.size());
    collapse(r.mesh, u, v, p, nullptr, scratch, refs_used, nullptr, r.coverage.get());
    ++r.applied;
  }
}

CollapseRun make_run(const std::string& family, std::uint64_t tets, double h_rel, std::uint64_t seed) {
  GenerateOptions g;
  g.family = family;
  g.target_tets = tets;
  g.seed = seed;
  CollapseRun r;
  r.mesh = build_mesh_model(generate_mesh(g));
  detect_features(r.mesh, SimplifyOptions{}.feature_angle);
  r.input = r.mesh.to_mesh_data();
  r.h = h_rel * diagonal(r.mesh);
  r.reference = SurfaceReference::from_mesh(r.mesh, r.h);
  r.coverage = std::make_unique<SurfaceCoverage>(r.mesh, *r.reference, r.h);
  return r;
}

double area(const std::array<glm::dvec3, 3>& q) { return 0.5 * glm::length(glm::cross(q[1] - q[0], q[2] - q[0])); }

// Recomputes the invariant from the mesh and the items. Returns the number of violations.
std::size_t invariant_violations(const CollapseRun& r, std::string* first) {
  const SurfaceSoup& soup = r.reference->soup();
  const auto& P = r.mesh.positions;
  std::vector<double> covered(soup.triangles.size(), 0.0);
  std::size_t bad = 0;
  const double h2 = r.h * r.h * (1.0 + 1e-12);
  for (TetId t = 0; t < r.mesh.tet_capacity(); ++t) {
    bool live = !r.mesh.is_dead_tet(t);
    r.coverage->for_each_item(t, [&](const CoverageItem& item) {
      const auto& tv = r.mesh.tets[t];
      std::array<glm::dvec3, 3> face;
      int n = 0;
      for (int k = 0; k < 4; ++k)
        if (k != item.local) face[n++] = P[tv[k]];
      bool ok = live;
      for (const glm::dvec3& x : item.corners)
        ok = ok && squared_distance_to_triangle(x, face[0], face[1], face[2]) <= h2;
      if (!ok && ++bad == 1 && first != nullptr)
        *first = "triangle " + std::to_string(item.triangle) + " held by tet " + std::to_string(t) +
                 (live ? " is farther than h from its face" : " (dead tet)");
      covered[item.triangle] += area(item.corners);
    });
  }
  // Polyline segments: held by a live tet at one of its polyline edges, both ends within h of that edge, and
  // the pieces of each original segment add up to its length.
  std::vector<double> length(soup.segments.size(), 0.0);
  for (TetId t = 0; t < r.mesh.tet_capacity(); ++t) {
    const bool live = !r.mesh.is_dead_tet(t);
    r.coverage->for_each_segment(t, [&](const CoverageSegment& s) {
      const auto& tv = r.mesh.tets[t];
      const glm::dvec3 a = P[tv[kTetEdges[s.local][0]]], b = P[tv[kTetEdges[s.local][1]]];
      bool ok = live && is_polyline_edge(r.mesh.flags[t], s.local);
      for (const glm::dvec3& x : s.ends) ok = ok && squared_distance_to_segment(x, a, b) <= h2;
      if (!ok && ++bad == 1 && first != nullptr)
        *first = "segment " + std::to_string(s.segment) + " held by tet " + std::to_string(t) +
                 (live ? (is_polyline_edge(r.mesh.flags[t], s.local) ? " is farther than h from its edge"
                                                                      : " at an edge that is no polyline edge")
                       : " (dead tet)");
      length[s.segment] += glm::length(s.ends[1] - s.ends[0]);
    });
  }
  // (the polyline segments: the soup's first ones; the rest are surfaces' border edges, which the
  // proof reads and the coverage does not hold)
  for (std::size_t k = 0; k < r.reference->segment_holders().size(); ++k) {
    const double whole = glm::length(soup.positions[soup.segments[k][1]] - soup.positions[soup.segments[k][0]]);
    if (length[k] < whole * (1.0 - 1e-9) && ++bad == 1 && first != nullptr)
      *first = "original segment " + std::to_string(k) + " is not fully held";
  }
  for (std::size_t k = 0; k < soup.triangles.size(); ++k) {
    const auto& t = soup.triangles[k];
    const double whole = area({soup.positions[t[0]], soup.positions[t[1]], soup.positions[t[2]]});
    if (covered[k] < whole * (1.0 - 1e-9)) {
      if (++bad == 1 && first != nullptr) *first = "original triangle " + std::to_string(k) + " is not fully held";
    }
  }
  return bad;
}

double worst_label_distance(const MeshData& input, const MeshData& output) {
  SurfaceDistanceOptions options;
  options.sample_spacing_rel = 5e-4;
  const SurfaceDistance d = surface_distance(input, output, options);
  double worst = 0.0;
  for (const LabelDistance& l : d.labels)
    if (l.hausdorff >= 0.0) worst = std::max(worst, l.hausdorff);
  return std::max(worst, d.hausdorff);
}

struct Case {
  const char* family;
  std::uint64_t tets;
  double h_rel;
};

class Coverage : public testing::TestWithParam<Case> {};

void check_random_collapses(const Case& c, int flip_every) {
  for (std::uint64_t seed : {1u, 2u}) {
    CollapseRun r = make_run(c.family, c.tets, c.h_rel, seed);
    const std::size_t before = r.mesh.live_vertex_count();
    random_collapses(r, 30000, seed, flip_every);
    std::printf("[ coverage ] %s seed %llu h = %.3g: %zu collapses (%zu -> %zu vertices), %llu flips, %zu refused by the "
                "tolerance, %zu items and segments, %zu original segments\n",
                c.family, (unsigned long long)seed, r.h, r.applied, before, r.mesh.live_vertex_count(),
                (unsigned long long)r.flips, r.refused_tolerance, r.coverage->item_count(), r.reference->soup().segments.size());
    ASSERT_GT(r.applied, before / 4) << "too few collapses to test anything";
    if (flip_every > 0) {
      ASSERT_GT(r.flips, 0u) << "no flip between the collapses: nothing tested";
    }
    ASSERT_GT(r.refused_tolerance, 0u) << "the tolerance never refused: h too loose for a test";
    std::string first;
    EXPECT_EQ(invariant_violations(r, &first), 0u) << first;
    const MeshData output = r.mesh.to_mesh_data();
    const double measured = worst_label_distance(r.input, output);
    EXPECT_LE(measured, r.h) << c.family << " seed " << seed;
    std::string differences;
    EXPECT_TRUE(same_topology(compute_topology(r.input), compute_topology(output), &differences)) << differences;

    // Planted fault: push one live surface vertex 3h along its offset from the centroid.
    VertId moved = kInvalid;
    for (VertId x = 0; x < r.mesh.vertex_capacity() && moved == kInvalid; ++x)
      if (!r.mesh.is_dead_vertex(x) && r.reference->on_surface(x) && !r.mesh.is_pinned(x)) moved = x;
    ASSERT_NE(moved, kInvalid);
    glm::dvec3 centre(0.0);
    for (const auto& p : r.input.positions) centre += to_glm(p);
    centre /= static_cast<double>(r.input.positions.size());
    glm::dvec3 dir = r.mesh.positions[moved] - centre;
    dir /= glm::length(dir);
    r.mesh.positions[moved] += 3.0 * r.h * dir;
    EXPECT_GT(invariant_violations(r, nullptr), 0u) << "the invariant check missed a vertex moved by 3h";
    EXPECT_GT(worst_label_distance(r.input, r.mesh.to_mesh_data()), r.h) << "the metric missed a vertex moved by 3h";
  }
}

TEST_P(Coverage, RandomCollapsesKeepEveryOriginalPointWithinH) { check_random_collapses(GetParam(), 0); }

// Flips every 3000 attempts: the stalls of an engine's run, ten times over.
TEST_P(Coverage, FlipsBetweenTheCollapsesKeepEveryOriginalPointWithinH) { check_random_collapses(GetParam(), 3000); }

INSTANTIATE_TEST_SUITE_P(Families, Coverage,
                         testing::Values(Case{"cube-sphere", 3000, 0.01}, Case{"cube-sphere", 8000, 0.003},
                                         Case{"slab", 3000, 0.005}, Case{"polycrystal", 20000, 0.01}),
                         [](const testing::TestParamInfo<Case>& param) {
                           std::string name = param.param.family;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name + "_" + std::to_string(param.param.tets);
                         });

}  // namespace
}  // namespace topotet
