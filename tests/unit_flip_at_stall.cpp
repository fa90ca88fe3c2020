// Flips where the collapses stall (engine/flip_at_stall.h, issue #23): a run whose collapses stall
// before the target, with inverted tets holding the most of the vertices left, flips the bad tets
// the collapses made and goes on, rather than relax a limit.
// On a generated polycrystal (junction curves between pinned grain corners: most of the vertices
// left at a stall are held by inverted tets) the run with the flips reaches its target, keeps the
// topology of every substructure, stays within the tolerance it reports, and gives the same bytes
// for 1 and 2 threads; the sequential engine flips too. optimize = none flips nothing, anywhere.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "entry_points.h"
#include "mesh/mesh_model.h"
#include "topotet/generate.h"
#include "topotet/metrics/surface_distance.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

constexpr double kRatio = 0.02;

struct Simplified {
  Report report;
  MeshData output;
};

Simplified simplified(const MeshData& input, Engine engine, int threads, Optimize optimize) {
  SimplifyOptions options;
  options.engine = engine;
  options.num_threads = threads;
  options.optimize = optimize;
  options.target_vertex_ratio = kRatio;
  // The floors below the input's worst tets (which bound how far they relax by default,
  // relax_limits.h): 2% of a polycrystal needs flatter tets than its input has.
  options.min_dihedral = 0.0;
  options.min_quality = 0.0;
  MeshModel mesh = build_mesh_model(input);
  Simplified run;
  run.report = simplify(mesh, options);
  run.output = mesh.to_mesh_data();
  return run;
}

void expect_guarantees(const MeshData& input, const Simplified& run) {
  std::string differences;
  EXPECT_TRUE(same_topology(compute_topology(input), compute_topology(run.output), &differences)) << differences;
  SurfaceDistanceOptions distance_options;
  distance_options.sample_spacing_rel = 1e-3;
  const SurfaceDistance d = surface_distance(input, run.output, distance_options);
  EXPECT_LE(d.hausdorff, run.report.tolerance);
}

TEST(FlipAtStall, ThePolycrystalReachesItsTargetWithEveryGuarantee) {
  const MeshData input = generate_mesh({"polycrystal", 20000, 1});
  const Simplified plain = simplified(input, Engine::kParallel, 2, Optimize::kNone);
  EXPECT_EQ(plain.report.stall_flips, 0u);
  for (const Engine engine : {Engine::kParallel, Engine::kSequential}) {
    const Simplified run = simplified(input, engine, 2, Optimize::kLight);
    const std::uint64_t target = static_cast<std::uint64_t>(std::llround(kRatio * static_cast<double>(run.report.vertices_before)));
    std::printf("[ stall flips ] %s: %llu flips, %llu vertices (target %llu; without the flips %llu), H %.3g (%.3g), "
                "dihedral floor %.3g (%.3g)\n",
                engine == Engine::kParallel ? "parallel" : "sequential", (unsigned long long)run.report.stall_flips,
                (unsigned long long)run.report.vertices_after, (unsigned long long)target,
                (unsigned long long)plain.report.vertices_after, run.report.tolerance, plain.report.tolerance,
                run.report.min_dihedral_used, plain.report.min_dihedral_used);
    EXPECT_GT(run.report.stall_flips, 0u);
    EXPECT_GT(run.report.stall_flip_seconds, 0.0);
    ASSERT_EQ(run.report.status, Status::kOk) << run.report.message;
    EXPECT_EQ(run.report.vertices_after, target);
    expect_guarantees(input, run);
    if (engine == Engine::kParallel) {
      EXPECT_LE(run.report.vertices_after, plain.report.vertices_after);
      EXPECT_TRUE(simplified(input, engine, 1, Optimize::kLight).output == run.output) << "1 and 2 threads differ";
    }
  }
}

}  // namespace
}  // namespace topotet
