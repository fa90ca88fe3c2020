// SimplifyOptions::relax_tolerance, relax_quality and relax_features (issue #23): where the
// tolerance, the quality floors or feature corners would stop a run before its target, they relax
// (H doubled, floors halved, features lower than H dropped) and the run reaches its target; the
// output holds its guarantees with the values the Report gives, the topology is never relaxed,
// and the output is the same for every thread count. With relaxing off the same runs stop early
// (unit_stop_diagnosis.cpp names why).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "entry_points.h"
#include "relax_limits.h"
#include "mesh/mesh_model.h"
#include "test_meshes.h"
#include "topotet/generate.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/surface_distance.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

MeshData cube_sphere() { return generate_mesh({"cube-sphere", 8000, 1}); }

std::uint64_t target_of(const Report& r, double ratio) {
  return static_cast<std::uint64_t>(std::llround(ratio * static_cast<double>(r.vertices_before)));
}

std::size_t relaxations_of(const Report& r, const char* limit) {
  std::size_t n = 0;
  for (const Relaxation& x : r.relaxations) n += std::strcmp(x.limit, limit) == 0;
  return n;
}

void expect_same_topology(const MeshData& in, const MeshData& out) {
  std::string differences;
  EXPECT_TRUE(same_topology(compute_topology(in), compute_topology(out), &differences)) << differences;
}

// Every tolerance step goes from the H before it to 2, 4 or 8 times it (relax_limits.cpp), in a
// chain from the asked H to the one the run ended with.
void expect_tolerance_steps(const Report& r) {
  double h = r.tolerance_asked;
  for (const Relaxation& x : r.relaxations) {
    if (std::strcmp(x.limit, "tolerance") != 0) continue;
    EXPECT_EQ(x.from, h);
    EXPECT_TRUE(x.to == 2.0 * h || x.to == 4.0 * h || x.to == 8.0 * h) << x.to / h;
    h = x.to;
  }
  EXPECT_EQ(h, r.tolerance);
}

// A tolerance far below the surfaces' jitter holds every surface vertex (StopDiagnosis.
// OnlyTheToleranceStopsIt); relaxed, H doubles until the run gets to its target, and the measured
// Hausdorff distance stays within the last H, which is the asked one times a power of two.
void expect_tolerance_relaxes(Engine engine) {
  const MeshData input = cube_sphere();
  SimplifyOptions options;
  options.engine = engine;
  options.tolerance_rel = 1e-4;
  options.feature_angle = 180.0;
  options.target_vertex_ratio = 0.05;
  MeshModel hard = build_mesh_model(input);
  options.relax_tolerance = options.relax_quality = false;
  const Report stopped = simplify(hard, options);
  ASSERT_EQ(stopped.status, Status::kStoppedEarly);
  EXPECT_GT(stopped.vertices_after, 2 * target_of(stopped, 0.05));
  EXPECT_TRUE(stopped.relaxations.empty());
  EXPECT_EQ(stopped.tolerance, stopped.tolerance_asked);

  MeshModel mesh = build_mesh_model(input);
  options.relax_tolerance = options.relax_quality = true;
  const Report r = simplify(mesh, options);
  ASSERT_EQ(r.status, Status::kOk) << r.message;
  EXPECT_EQ(r.vertices_after, target_of(r, 0.05));
  const std::size_t steps = relaxations_of(r, "tolerance");
  ASSERT_GE(steps, 1u);
  expect_tolerance_steps(r);
  EXPECT_EQ(r.relaxations.front().from, r.tolerance_asked);
  EXPECT_EQ(r.relaxations.back().to, r.tolerance);
  EXPECT_FALSE(r.stop.is_filled);
  const MeshData output = mesh.to_mesh_data();
  expect_same_topology(input, output);
  SurfaceDistanceOptions distance_options;
  distance_options.sample_spacing_rel = 5e-4;
  const SurfaceDistance d = surface_distance(input, output, distance_options);
  EXPECT_LE(d.hausdorff, r.tolerance);
  // Relaxed only as far as needed: the H before the last step was not enough.
  EXPECT_GT(d.hausdorff, 0.5 * r.relaxations.back().from);
}

TEST(RelaxLimits, TheToleranceDoublesUntilTheTargetParallel) { expect_tolerance_relaxes(Engine::kParallel); }
TEST(RelaxLimits, TheToleranceDoublesUntilTheTargetSequential) { expect_tolerance_relaxes(Engine::kSequential); }

// A mean-ratio floor no collapse of this mesh keeps (StopDiagnosis.OnlyTheQualityFloorStopsIt):
// relaxed, both floors halve, but never below the input's own worst tet (issue #50: an output of
// slivers is of no use to a solver); the run stops there, says the floors hold it, and no new tet
// is below the last floor.
TEST(RelaxLimits, TheQualityFloorsHalveDownToTheInputsWorst) {
  const MeshData input = cube_sphere();
  const QualityStats q_in = compute_quality(input);
  MeshModel mesh = build_mesh_model(input);
  SimplifyOptions options;
  options.tolerance_rel = 0.0;
  options.feature_angle = 180.0;
  options.min_quality = 0.9;
  options.optimize = Optimize::kNone;
  options.target_vertex_ratio = 0.05;
  const Report r = simplify(mesh, options);
  // The lowest floors: the input's worst mean ratio, and its worst dihedral angle as the floor
  // measures it (by its sine: an angle near 180 degrees is as flat as one near 0).
  const double worst_dihedral = std::min(q_in.dihedral_deg.min, 180.0 - q_in.dihedral_deg.max);
  EXPECT_NEAR(r.min_quality_lowest, std::min(0.9, q_in.mean_ratio.min), 1e-9);
  EXPECT_NEAR(r.min_dihedral_lowest, std::min(options.min_dihedral, worst_dihedral), 1e-6);
  const std::size_t steps = relaxations_of(r, "min_quality");
  ASSERT_GE(steps, 1u);
  EXPECT_EQ(relaxations_of(r, "tolerance"), 0u);
  EXPECT_GE(r.min_quality_used, r.min_quality_lowest);
  EXPECT_GE(r.min_dihedral_used, r.min_dihedral_lowest);
  EXPECT_EQ(relaxations_of(r, "min_dihedral") > 0, options.min_dihedral > r.min_dihedral_lowest);
  if (r.status != Status::kOk) {
    // Stopped with the floors at their lowest, and the census says they hold it.
    EXPECT_EQ(r.min_quality_used, r.min_quality_lowest);
    EXPECT_STREQ(r.stop.dominant, "quality");
    EXPECT_GT(r.vertices_after, target_of(r, 0.05));
  }
  const MeshData output = mesh.to_mesh_data();
  expect_same_topology(input, output);
  const QualityStats q = compute_quality(output);
  EXPECT_EQ(q.inverted, 0u);
  EXPECT_GE(q.mean_ratio.min, std::min(r.min_quality_used, q_in.mean_ratio.min) * (1.0 - 1e-9));

  // Without relax_quality the floors hold as asked.
  MeshModel held = build_mesh_model(input);
  options.relax_quality = false;
  const Report h = simplify(held, options);
  EXPECT_EQ(relaxations_of(h, "min_quality"), 0u);
  EXPECT_EQ(h.min_quality_lowest, 0.9);
}

// With floors the input is above everywhere (the default 5 degrees on the generated cube-sphere),
// a target beyond their reach never halves them into slivers: the tolerance relaxes instead (the
// floors relax last), or the run stops and says what holds it.
TEST(RelaxLimits, DefaultFloorsAboveTheInputsWorstNeverRelax) {
  const MeshData input = cube_sphere();
  const QualityStats q_in = compute_quality(input);
  ASSERT_GT(std::min(q_in.dihedral_deg.min, 180.0 - q_in.dihedral_deg.max), 5.0);
  ASSERT_GT(q_in.mean_ratio.min, 0.05);
  MeshModel mesh = build_mesh_model(input);
  SimplifyOptions options;
  options.target_vertex_ratio = 0.01;
  const Report r = simplify(mesh, options);
  EXPECT_EQ(relaxations_of(r, "min_quality") + relaxations_of(r, "min_dihedral"), 0u);
  EXPECT_EQ(r.min_dihedral_used, 5.0);
  EXPECT_EQ(r.min_quality_used, options.min_quality);
  const QualityStats q = compute_quality(mesh.to_mesh_data());
  EXPECT_GE(std::min(q.dihedral_deg.min, 180.0 - q.dihedral_deg.max), 5.0 * (1.0 - 1e-9));
  if (r.status != Status::kOk) {
    EXPECT_FALSE(r.stop.suggestion.empty());
  }
}

// The floors relax last: at their lowest, what they hold no longer keeps the tolerance (or the
// flips) from relaxing for the vertices it holds; floors the user set keep counting.
TEST(RelaxLimits, TheFloorsAtTheirLowestNoLongerHoldTheOthersBack) {
  StopDiagnosis census;
  census.vertices = 1000;
  census.quality = 600;
  census.tolerance = 300;
  census.inversion = 100;
  Report report;
  report.min_quality_used = report.min_quality_lowest = 0.05;
  report.min_dihedral_used = report.min_dihedral_lowest = 5.0;
  ASSERT_FALSE(report.floors_may_relax());
  const std::uint64_t live = 1000, target = 200;
  // As the user's hard floors: the floors hold the most, and nothing relaxes for the tolerance.
  const StopDiagnosis hard = detail::floors_at_lowest(census, false, report);
  EXPECT_EQ(detail::choose_relaxation(hard, live, target, true, false, false), detail::RelaxChoice::kNone);
  // Default floors at their lowest: the tolerance relaxes; with no tolerance to relax, the flips go first.
  const StopDiagnosis last = detail::floors_at_lowest(census, true, report);
  EXPECT_EQ(last.quality, 0u);
  EXPECT_EQ(detail::choose_relaxation(last, live, target, true, false, false), detail::RelaxChoice::kTolerance);
  census.tolerance = 0;
  EXPECT_TRUE(detail::inversion_holds_most(detail::floors_at_lowest(census, true, report), live, target));
  EXPECT_FALSE(detail::inversion_holds_most(detail::floors_at_lowest(census, false, report), live, target));
  // Above their lowest they still relax first when they hold the most.
  report.min_dihedral_used = 10.0;
  census.tolerance = 300;
  EXPECT_EQ(detail::choose_relaxation(detail::floors_at_lowest(census, true, report), live, target, true, true, false),
            detail::RelaxChoice::kFloors);
}

// Feature corners that hold the run (the generated tori's staircase creases, features at the
// asked H): H doubles and the curves are judged again at it; those lower than H go, the run reaches
// its target, and the surfaces stay within the H reported. Without relax_features they hold it.
TEST(RelaxLimits, FeaturesLowerThanTheRelaxedToleranceGo) {
  const MeshData input = generate_mesh({"linked-tori", 40000, 1});
  SimplifyOptions options;
  options.target_vertex_ratio = 0.05;
  MeshModel held_mesh = build_mesh_model(input);
  options.relax_features = false;
  const Report held = simplify(held_mesh, options);
  ASSERT_EQ(held.status, Status::kStoppedEarly);
  EXPECT_STREQ(held.stop.dominant, "pinned");
  EXPECT_GT(held.stop.pinned_features, held.stop.vertices / 2);
  EXPECT_EQ(held.features_dropped, 0u);

  MeshModel mesh = build_mesh_model(input);
  options.relax_features = true;
  const Report r = simplify(mesh, options);
  ASSERT_EQ(r.status, Status::kOk) << r.message;
  EXPECT_EQ(r.vertices_after, target_of(r, 0.05));
  ASSERT_GE(relaxations_of(r, "features"), 1u);
  EXPECT_GT(r.features_dropped, 0u);
  EXPECT_LT(r.features_dropped, r.feature_edges);  // not all: the rest are features at the last H
  EXPECT_GT(r.tolerance, r.tolerance_asked);
  const MeshData output = mesh.to_mesh_data();
  expect_same_topology(input, output);
  SurfaceDistanceOptions distance_options;
  distance_options.sample_spacing_rel = 1e-3;
  EXPECT_LE(surface_distance(input, output, distance_options).hausdorff, r.tolerance);
}

// The topology is never relaxed: a run it stops still stops, with no relaxation, and says so.
TEST(RelaxLimits, TheTopologyIsNeverRelaxed) {
  const testing::Grid grid = testing::make_grid(3, 3, 2, [](int i, int j, int k) { return 1 + i + 3 * j + 9 * k; });
  MeshModel mesh = build_mesh_model(grid.data);
  SimplifyOptions options;
  options.target_vertex_ratio = 0.2;
  options.feature_angle = 180.0;
  const Report r = simplify(mesh, options);
  ASSERT_EQ(r.status, Status::kStoppedEarly);
  EXPECT_STREQ(r.stop.dominant, "topology");
  EXPECT_GE(4 * r.stop.topology, 3 * r.vertices_after);
  // What the tolerance still holds is too little to relax it for (relax_limits.cpp); the floors never
  // held the run.
  EXPECT_EQ(relaxations_of(r, "min_quality") + relaxations_of(r, "min_dihedral"), 0u);
  EXPECT_EQ(relaxations_of(r, "tolerance"), r.relaxations.size());
  EXPECT_LT(4 * r.stop.tolerance, r.stop.vertices);
}

// The polycrystal's interfaces at the default tolerance: at the first stall, 2H would free only a
// few of the vertices the tolerance holds (polycrystal 30k: 50 of 1,267), 4H most of them; the
// step skips the doubling that would stall again after a few collapses (relax_limits.cpp), and the
// step it takes lets at least an eighth of the excess go before the next stall. The guarantees
// hold with the H it ends with, and the output is the same for every thread count.
TEST(RelaxLimits, TheToleranceSkipsADoublingThatFreesTooFew) {
  const MeshData input = generate_mesh({"polycrystal", 20000, 1});
  MeshData reference;
  for (int threads : {1, 2}) {
    MeshModel mesh = build_mesh_model(input);
    SimplifyOptions options;
    options.num_threads = threads;
    options.target_vertex_ratio = 0.1;
    options.optimize = Optimize::kNone;
    const Report r = simplify(mesh, options);
    ASSERT_EQ(r.status, Status::kOk) << r.message;
    const std::uint64_t target = target_of(r, 0.1);
    EXPECT_EQ(r.vertices_after, target);
    ASSERT_GE(relaxations_of(r, "tolerance"), 2u);
    expect_tolerance_steps(r);
    const Relaxation& first = r.relaxations[0];
    EXPECT_STREQ(first.limit, "tolerance");
    EXPECT_EQ(first.to, 4.0 * first.from);
    const std::uint64_t eighth = (first.vertices_left - target + 7) / 8;
    EXPECT_LE(r.relaxations[1].vertices_left + eighth, first.vertices_left);
    const MeshData output = mesh.to_mesh_data();
    if (threads == 1) {
      expect_same_topology(input, output);
      const SurfaceDistance d = surface_distance(input, output, SurfaceDistanceOptions{});
      EXPECT_LE(d.hausdorff, r.tolerance);
      reference = output;
    } else {
      EXPECT_TRUE(output == reference);
    }
  }
}

// Relaxing happens at the same points of the run for every thread count: the same output.
TEST(RelaxLimits, SameOutputForEveryThreadCount) {
  const MeshData input = cube_sphere();
  MeshData reference;
  Report first;
  for (int threads : {1, 2}) {
    MeshModel mesh = build_mesh_model(input);
    SimplifyOptions options;
    options.num_threads = threads;
    options.tolerance_rel = 2e-4;
    options.feature_angle = 180.0;
    options.target_vertex_ratio = 0.05;
    const Report r = simplify(mesh, options);
    ASSERT_EQ(r.status, Status::kOk) << r.message;
    ASSERT_FALSE(r.relaxations.empty());
    const MeshData out = mesh.to_mesh_data();
    if (threads == 1) {
      reference = out;
      first = r;
      continue;
    }
    EXPECT_TRUE(out == reference) << "threads = " << threads;
    EXPECT_EQ(r.tolerance, first.tolerance);
    EXPECT_EQ(r.min_dihedral_used, first.min_dihedral_used);
    EXPECT_EQ(r.relaxations.size(), first.relaxations.size());
  }
}

}  // namespace
}  // namespace topotet
