// Report::stop (issue #23): a run that stops before its target names what holds the vertices left
// and suggests the option that relaxes it. Each case is built so that one reason alone stops it:
// the tolerance, the quality floor, pinned vertices, the topology.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <numeric>
#include <string>

#include "engines.h"
#include "entry_points.h"
#include "guarantees/surface_coverage.h"
#include "guarantees/surface_tolerance.h"
#include "mesh/mesh_model.h"
#include "stop_diagnosis.h"
#include "test_meshes.h"
#include "topotet/generate.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

std::uint64_t share_sum(const StopDiagnosis& d) {
  return d.topology + d.pinned + d.inversion + d.quality + d.tolerance + d.field_error + d.collapsible;
}

// The common facts of every stopped run: filled, one count per vertex left, the dominant reason
// is the largest count and is named in the suggestion.
void expect_consistent(const Report& r, const char* dominant) {
  ASSERT_EQ(r.status, Status::kStoppedEarly) << r.message;
  const StopDiagnosis& d = r.stop;
  ASSERT_TRUE(d.is_filled);
  EXPECT_EQ(d.vertices, r.vertices_after);
  EXPECT_EQ(share_sum(d), d.vertices);
  EXPECT_STREQ(d.dominant, dominant);
  EXPECT_GT(d.dominant_share, 0.5) << d.suggestion;
  EXPECT_FALSE(d.suggestion.empty());
}

MeshData small_cube_sphere() { return generate_mesh({"cube-sphere", 8000, 1}); }

// The kernel of a run with tolerance H (the surfaces' reference and coverage, the floors of
// `options`), made by hand so that a test can take the census at each stall itself.
struct ToleranceKernel {
  std::unique_ptr<SurfaceReference> surfaces;
  std::unique_ptr<SurfaceCoverage> coverage;
  CollapseOptions kernel;
  ToleranceKernel(const MeshModel& mesh, const SimplifyOptions& options, double h)
      : surfaces(SurfaceReference::from_mesh(mesh, h)), coverage(std::make_unique<SurfaceCoverage>(mesh, *surfaces, h)) {
    kernel.quality_floor = options.min_quality;
    kernel.dihedral_floor = DihedralFloor::degrees(options.min_dihedral);
    kernel.surfaces = surfaces.get();
    kernel.coverage = coverage.get();
    kernel.tolerance = h;
  }
  void double_tolerance() {  // as relax_limits' plain step does
    kernel.tolerance *= 2.0;
    coverage->raise_tolerance(kernel.tolerance);
  }
};

// The polycrystal 20k run to 10% under the default tolerance (no features), stalled twice: `at`
// is called at each stall (0, then 1) with the mesh as the engine left it; the tolerance doubles
// between them. Returns the number of stalls.
using AtStall = std::function<void(const MeshModel&, const SimplifyOptions&, const CollapseOptions&, CostModel&,
                                   std::uint64_t target, int stall)>;
int polycrystal_stalls(const AtStall& at) {
  MeshModel mesh = build_mesh_model(generate_mesh({"polycrystal", 20000, 1}));
  SimplifyOptions options;
  options.feature_angle = 180.0;
  ToleranceKernel tk(mesh, options, options.tolerance_rel * bounding_box_diagonal(mesh));
  const std::uint64_t target = mesh.live_vertex_count() / 10;
  int stalls = 0;
  const detail::RelaxStep relax = [&](CostModel& cost) {
    at(mesh, options, tk.kernel, cost, target, stalls);
    if (++stalls == 2) return false;
    tk.double_tolerance();
    return true;
  };
  Report report;
  detail::simplify_parallel(mesh, options, tk.kernel, nullptr, target, report, nullptr, {}, relax);
  return stalls;
}

TEST(StopDiagnosis, NotFilledWhenTheTargetIsReached) {
  MeshModel mesh = build_mesh_model(small_cube_sphere());
  SimplifyOptions options;
  options.target_vertex_ratio = 0.5;
  const Report r = simplify(mesh, options);
  EXPECT_EQ(r.status, Status::kOk);
  EXPECT_FALSE(r.stop.is_filled);
  EXPECT_TRUE(r.stop.suggestion.empty());
}

// A tolerance far below the surfaces' jitter: nothing on a surface can move; the interior empties.
TEST(StopDiagnosis, OnlyTheToleranceStopsIt) {
  MeshModel mesh = build_mesh_model(small_cube_sphere());
  SimplifyOptions options;
  options.tolerance_rel = 1e-5;
  options.relax_tolerance = false;  // a hard limit: the run stops where the tolerance holds it
  options.feature_angle = 180.0;
  options.target_vertex_ratio = 0.02;
  const Report r = simplify(mesh, options);
  expect_consistent(r, "tolerance");
  EXPECT_FALSE(r.stop.beyond_reach);  // an option frees them
  EXPECT_NE(r.stop.suggestion.find("--tolerance-rel 2e-05"), std::string::npos) << r.stop.suggestion;
  EXPECT_NE(r.stop.suggestion.find("the tolerance held"), std::string::npos) << r.stop.suggestion;
}

// No tolerance, no features, a quality floor no collapse of this mesh can keep.
TEST(StopDiagnosis, OnlyTheQualityFloorStopsIt) {
  MeshModel mesh = build_mesh_model(small_cube_sphere());
  SimplifyOptions options;
  options.tolerance_rel = 0.0;
  options.feature_angle = 180.0;
  options.min_quality = 0.9;
  options.relax_quality = false;  // a hard limit
  options.target_vertex_ratio = 0.02;
  const Report r = simplify(mesh, options);
  expect_consistent(r, "quality");
  EXPECT_EQ(r.stop.tolerance, 0u);
  EXPECT_NE(r.stop.suggestion.find("--min-quality 0.45"), std::string::npos) << r.stop.suggestion;
}

// The dihedral floor alone (no mean ratio floor): the reason is quality, and the suggestion halves
// the dihedral floor.
TEST(StopDiagnosis, OnlyTheDihedralFloorStopsIt) {
  MeshModel mesh = build_mesh_model(small_cube_sphere());
  SimplifyOptions options;
  options.tolerance_rel = 0.0;
  options.feature_angle = 180.0;
  options.min_quality = 0.0;
  options.min_dihedral = 50.0;
  options.relax_quality = false;  // a hard limit
  options.target_vertex_ratio = 0.02;
  const Report r = simplify(mesh, options);
  expect_consistent(r, "quality");
  EXPECT_GT(r.rejected_by(RejectReason::kQuality), 0u);
  EXPECT_NE(r.stop.suggestion.find("--min-dihedral 25"), std::string::npos) << r.stop.suggestion;
}

// Every vertex listed as a corner (or required): nothing moves, and no option changes that.
TEST(StopDiagnosis, OnlyPinnedVerticesStopIt) {
  for (const bool required : {false, true}) {
    testing::Grid grid = testing::make_grid(4, 3, 3, [](int, int, int) { return 1; });
    std::vector<VertId> all(grid.data.positions.size());
    std::iota(all.begin(), all.end(), VertId{0});
    (required ? grid.data.required_vertices : grid.data.corners) = all;
    MeshModel mesh = build_mesh_model(grid.data);
    SimplifyOptions options;
    options.target_vertex_ratio = 0.2;
    const Report r = simplify(mesh, options);
    expect_consistent(r, "pinned");
    EXPECT_EQ(r.collapses, 0u);
    EXPECT_EQ(r.stop.pinned, all.size());
    EXPECT_EQ(required ? r.stop.pinned_required : r.stop.pinned_corners, all.size());
    EXPECT_EQ(r.stop.pinned_features, 0u);
    EXPECT_NE(r.stop.suggestion.find("no option moves them"), std::string::npos) << r.stop.suggestion;
    EXPECT_EQ(r.stop.suggestion.find("--"), std::string::npos) << r.stop.suggestion;  // nothing to try
  }
}

// Every cube of the grid its own material: every vertex but the box's corners is a junction of
// interface curves (order 3), so once the corners are gone no vertex can go without changing the
// topology of a substructure.
TEST(StopDiagnosis, OnlyTheTopologyStopsIt) {
  const testing::Grid grid = testing::make_grid(3, 3, 2, [](int i, int j, int k) { return 1 + i + 3 * j + 9 * k; });
  MeshModel mesh = build_mesh_model(grid.data);
  SimplifyOptions options;
  options.target_vertex_ratio = 0.2;
  // The topology alone: no features (the box's edges would pin its corners), no tolerance (the
  // box corners, inside one cube each, are plain surface points and may go).
  options.feature_angle = 180.0;
  options.tolerance_rel = 0.0;
  const Report r = simplify(mesh, options);
  expect_consistent(r, "topology");
  EXPECT_EQ(r.stop.topology, r.vertices_after);
  EXPECT_EQ(r.stop.pinned, 0u);
  EXPECT_NE(r.stop.suggestion.find("the topology held 100%"), std::string::npos) << r.stop.suggestion;
  EXPECT_EQ(r.stop.suggestion.find("--"), std::string::npos) << r.stop.suggestion;
  // More vertices than the target are held where no option reaches: said, with the numbers.
  EXPECT_TRUE(r.stop.beyond_reach);
  EXPECT_NE(r.stop.suggestion.find("alone hold " + std::to_string(r.vertices_after) + " vertices"), std::string::npos)
      << r.stop.suggestion;
  EXPECT_NE(r.stop.suggestion.find("no option reaches it"), std::string::npos) << r.stop.suggestion;
}

// Feature corners that hold a run are named with the feature angle to raise.
TEST(StopDiagnosis, PinnedFeatureCornersSuggestTheFeatureAngle) {
  // Pinned as detect_features pins its corners (every vertex, so that they alone stop the run).
  testing::Grid grid = testing::make_grid(2, 2, 2, [](int, int, int) { return 1; });
  MeshModel mesh = build_mesh_model(grid.data);
  for (VertId v = 0; v < mesh.vertex_capacity(); ++v)
    mesh.vertex_states[v] |= vertex_state::kPinned | vertex_state::kFeatureCorner;
  SimplifyOptions options;
  options.target_vertex_ratio = 0.2;
  const Report r = simplify(mesh, options);
  expect_consistent(r, "pinned");
  EXPECT_EQ(r.stop.pinned_features, r.vertices_after);
  EXPECT_NE(r.stop.suggestion.find("--feature-angle 75"), std::string::npos) << r.stop.suggestion;
}

// At a stall the census counts a placement the engine refused for the tolerance without proving it
// again (diagnose_stop's every_edge_refused): its counts must be the full census's, at every stall
// of runs whose tolerance doubles at each one (as relax_limits does), with both engines, on
// interfaces of many materials and on a curved one.
TEST(StopDiagnosis, TheEnginesRefusalsGiveTheFullCensus) {
  for (const char* family : {"polycrystal", "cube-sphere"})
    for (const Engine engine : {Engine::kParallel, Engine::kSequential}) {
      SCOPED_TRACE(std::string(family) + (engine == Engine::kParallel ? ", parallel" : ", sequential"));
      MeshModel mesh = build_mesh_model(generate_mesh({family, std::strcmp(family, "polycrystal") == 0 ? 20000u : 8000u, 1}));
      SimplifyOptions options;
      options.engine = engine;
      options.feature_angle = 180.0;
      ToleranceKernel tk(mesh, options, 1e-4 * bounding_box_diagonal(mesh));
      CollapseOptions& kernel = tk.kernel;
      const std::uint64_t target = mesh.live_vertex_count() / 20;
      int stalls = 0;
      std::uint64_t held_by_tolerance = 0;
      const detail::RelaxStep relax = [&](CostModel& cost) {
        Report full, taken;
        detail::diagnose_stop(mesh, options, kernel, cost, target, full, false);
        detail::diagnose_stop(mesh, options, kernel, cost, target, taken, true);
        const StopDiagnosis &a = full.stop, &b = taken.stop;
        EXPECT_EQ(a.topology, b.topology);
        EXPECT_EQ(a.pinned, b.pinned);
        EXPECT_EQ(a.inversion, b.inversion);
        EXPECT_EQ(a.quality, b.quality);
        EXPECT_EQ(a.tolerance, b.tolerance);
        EXPECT_EQ(a.field_error, b.field_error);
        EXPECT_EQ(a.collapsible, b.collapsible);
        EXPECT_EQ(a.suggestion, b.suggestion);
        held_by_tolerance += b.tolerance;
        if (++stalls == 3) return false;
        tk.double_tolerance();
        return true;
      };
      Report report;
      if (engine == Engine::kParallel)
        detail::simplify_parallel(mesh, options, kernel, nullptr, target, report, nullptr, {}, relax);
      else
        detail::simplify_sequential(mesh, options, kernel, nullptr, target, report, nullptr, {}, relax);
      EXPECT_GE(stalls, 2);
      EXPECT_GT(held_by_tolerance, 0u);  // the shortcut was taken
    }
}

// relax_limits' look-ahead (tolerance_frees): at each stall of the polycrystal, how many of the
// vertices the tolerance holds a larger H would free. Asked of every one of them (a sample at
// least as large as they are), the count is exact: the vertices held at H that the census under the
// larger H (without the coverage, as tolerance_frees asks) no longer finds held. Asked of a sample
// of 128, it answers as the full count wherever that is not within a factor of 2 of the question.
TEST(StopDiagnosis, TheToleranceLookAheadCountsWhatALargerToleranceFrees) {
  int clear_answers = 0, few_freed = 0;
  const AtStall at = [&](const MeshModel& mesh, const SimplifyOptions& options, const CollapseOptions& kernel,
                         CostModel& cost, std::uint64_t target, int stall) {
    Report census;
    std::vector<std::uint8_t> held;
    detail::diagnose_stop(mesh, options, kernel, cost, target, census, true, &held);
    const std::uint64_t held_count = std::accumulate(held.begin(), held.end(), std::uint64_t{0});
    EXPECT_EQ(held_count, census.stop.tolerance);
    const std::size_t all = held.size();
    for (const int step : {1, 2}) {
      SCOPED_TRACE("stall " + std::to_string(stall) + ", H x " + std::to_string(1 << step));
      CollapseOptions larger = kernel;
      larger.tolerance = std::ldexp(kernel.tolerance, step);
      larger.coverage = nullptr;
      Report after;
      std::vector<std::uint8_t> still;
      detail::diagnose_stop(mesh, options, larger, cost, target, after, false, &still);
      std::uint64_t freed = 0;
      for (std::size_t v = 0; v < held.size(); ++v) freed += held[v] != 0 && still[v] == 0;
      EXPECT_TRUE(detail::tolerance_frees(mesh, kernel, cost, larger.tolerance, held, freed, all));
      EXPECT_FALSE(detail::tolerance_frees(mesh, kernel, cost, larger.tolerance, held, freed + 1, all));
      EXPECT_TRUE(detail::tolerance_frees(mesh, kernel, cost, larger.tolerance, held, 0, 128));
      const std::uint64_t wanted = (mesh.live_vertex_count() - target + 7) / 8;
      const bool sampled = detail::tolerance_frees(mesh, kernel, cost, larger.tolerance, held, wanted, 128);
      if (freed >= 2 * wanted) {
        EXPECT_TRUE(sampled) << freed << " freed, " << wanted << " wanted";
        ++clear_answers;
      }
      if (2 * freed < wanted) {
        EXPECT_FALSE(sampled) << freed << " freed, " << wanted << " wanted";
        ++clear_answers;
      }
      few_freed += freed < wanted;
    }
  };
  EXPECT_EQ(polycrystal_stalls(at), 2);
  EXPECT_GE(clear_answers, 3);  // the sample was asked both ways
  EXPECT_GE(few_freed, 1);      // a doubling that frees too few: the case the look-ahead is for
}

// relax_limits chooses its steps on a sampled census where many vertices are left (diagnose_stop's
// stride). Each vertex it asks gets the full census's verdict (the flags of the vertices the
// tolerance holds are the full census's on the sampled slots, nothing elsewhere); the pinned
// vertices are counted exactly; the other counts, scaled, stay within five standard deviations of
// the full census's (a share p of n vertices asked: sqrt(n p (1 - p)) each), at every stall.
TEST(StopDiagnosis, ASampledCensusAsksEveryVertexItSamplesAsTheFullOne) {
  const AtStall at = [&](const MeshModel& mesh, const SimplifyOptions& options, const CollapseOptions& kernel,
                         CostModel& cost, std::uint64_t target, int stall) {
    Report full;
    std::vector<std::uint8_t> held_full;
    EXPECT_EQ(detail::diagnose_stop(mesh, options, kernel, cost, target, full, true, &held_full), 1.0);
    for (const std::size_t stride : {3u, 8u}) {
      SCOPED_TRACE("stall " + std::to_string(stall) + ", stride " + std::to_string(stride));
      Report sampled;
      std::vector<std::uint8_t> held;
      const double scale = detail::diagnose_stop(mesh, options, kernel, cost, target, sampled, true, &held, stride);
      EXPECT_GT(scale, 0.5 * static_cast<double>(stride));
      EXPECT_LT(scale, 2.0 * static_cast<double>(stride));
      EXPECT_EQ(held.size(), held_full.size());
      std::size_t differ = 0;
      for (std::size_t v = 0; v < std::min(held.size(), held_full.size()); ++v)
        differ += held[v] != (v % stride == 0 ? held_full[v] : 0);
      EXPECT_EQ(differ, 0u);
      const StopDiagnosis &a = full.stop, &b = sampled.stop;
      EXPECT_EQ(b.pinned, a.pinned);
      EXPECT_EQ(b.pinned_features, a.pinned_features);
      const double unpinned = static_cast<double>(a.vertices - a.pinned);
      EXPECT_NEAR(static_cast<double>(b.vertices - b.pinned), unpinned, 4.0);  // rounding of each count
      const double asked = unpinned / scale;
      const std::pair<std::uint64_t, std::uint64_t> counts[] = {{a.topology, b.topology},   {a.inversion, b.inversion},
                                                                {a.quality, b.quality},     {a.tolerance, b.tolerance},
                                                                {a.collapsible, b.collapsible}};
      for (const auto& [exact, estimate] : counts) {
        const double p = static_cast<double>(exact) / unpinned;
        EXPECT_NEAR(static_cast<double>(estimate), static_cast<double>(exact),
                    5.0 * scale * std::sqrt(asked * p * (1.0 - p)) + scale)
            << "exact " << exact;
      }
      EXPECT_GT(b.tolerance, 0u);
    }
  };
  EXPECT_EQ(polycrystal_stalls(at), 2);
}

}  // namespace
}  // namespace topotet
