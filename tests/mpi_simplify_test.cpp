// topotet::mpi::simplify under mpirun (registered for 1, 2, 3 and 4 ranks): the gathered result
// keeps the topology of the input (mesh, materials, interfaces, listed surfaces, polylines, pins,
// all crossing the partition borders), the global vertex map names real merges, and the output
// does not depend on the run or on the thread count per rank. Every test is collective; rank 0
// checks what it gathered.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <unordered_map>
#include <utility>

#include "topotet/generate.h"
#include "topotet/metrics/surface_distance.h"
#include "topotet/metrics/topology.h"
#include "topotet/mpi.h"

namespace topotet::mpi {
namespace {

int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int ranks() {
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

MeshData generated(const std::string& family, std::uint64_t tets) {
  GenerateOptions g;
  g.family = family;
  g.target_tets = tets;
  return generate_mesh(g);
}

// This rank's part of `whole` when a code already holds it spread: the tets whose centroid
// falls in its slab along y (another cut than METIS would make), with what lies on them.
DistributedMesh slab_part(const MeshData& whole) {
  DistributedMesh part;
  MeshData& d = part.local;
  std::unordered_map<VertId, VertId> local_of;
  auto local = [&](VertId g) {
    auto [it, added] = local_of.emplace(g, static_cast<VertId>(d.positions.size()));
    if (added) {
      d.positions.push_back(whole.positions[g]);
      part.global_ids.push_back(g);
    }
    return it->second;
  };
  double lo = 1e300, hi = -1e300;
  for (const auto& p : whole.positions) {
    lo = std::min(lo, p[1]);
    hi = std::max(hi, p[1]);
  }
  for (std::size_t t = 0; t < whole.tet_count(); ++t) {
    const auto& v = whole.tets[t];
    double y = 0;
    for (VertId x : v) y += 0.25 * whole.positions[x][1];
    if (std::min(ranks() - 1, static_cast<int>((y - lo) / (hi - lo) * ranks())) != rank()) continue;
    d.tets.push_back({local(v[0]), local(v[1]), local(v[2]), local(v[3])});
    d.tet_material.push_back(whole.tet_material[t]);
  }
  auto here = [&](VertId g) { return local_of.count(g) != 0; };
  // Listed triangles and segments with all vertices here, as a code that knows no better would
  // list them: those that are no face / edge of a local tet are ignored by the library.
  for (const auto& tri : whole.triangles)
    if (here(tri.v[0]) && here(tri.v[1]) && here(tri.v[2]))
      d.triangles.push_back({{local_of[tri.v[0]], local_of[tri.v[1]], local_of[tri.v[2]]}, tri.ref});
  for (const auto& seg : whole.segments)
    if (here(seg.v[0]) && here(seg.v[1])) d.segments.push_back({{local_of[seg.v[0]], local_of[seg.v[1]]}, seg.ref});
  for (VertId c : whole.corners)
    if (here(c)) d.corners.push_back(local_of[c]);
  for (const auto& f : whole.fields) {
    VertexField lf{f.name, f.components, {}};
    for (GlobalId g : part.global_ids)
      for (int c = 0; c < f.components; ++c) lf.values.push_back(f.values[g * f.components + c]);
    d.fields.push_back(lf);
  }
  return part;
}

struct Simplified {
  MeshData output;                  // rank 0
  std::vector<GlobalId> output_ids;  // rank 0: global id of each output vertex
  Result result;
};

Simplified run(DistributedMesh part, double ratio, int threads, Optimize optimize = SimplifyOptions{}.optimize) {
  Options options;
  options.simplify.target_vertex_ratio = ratio;
  options.simplify.num_threads = threads;
  options.simplify.optimize = optimize;
  Simplified r;
  r.result = simplify(MPI_COMM_WORLD, part, options);
  r.output = gather(MPI_COMM_WORLD, part, 0, &r.output_ids);
  return r;
}

Simplified run_from_rank0(const MeshData& whole, double ratio, int threads) {
  DistributedMesh part = rank() == 0 ? from_whole(whole) : DistributedMesh{};
  distribute(MPI_COMM_WORLD, part);
  return run(std::move(part), ratio, threads);
}

void expect_same_topology(const MeshData& input, const Simplified& r) {
  if (rank() != 0) return;
  const auto before = compute_topology(input);
  const auto after = compute_topology(r.output);
  std::string differences;
  EXPECT_TRUE(same_topology(before, after, &differences)) << differences;
  EXPECT_EQ(after.inverted_tet_count, 0u);
  EXPECT_EQ(after.degenerate_tet_count, 0u);
}

class MpiSimplify : public ::testing::TestWithParam<std::string> {};

TEST_P(MpiSimplify, GatheredResultKeepsTheTopology) {
  const MeshData input = generated(GetParam(), 3000);
  const Simplified r = run_from_rank0(input, 0.3, 1);
  EXPECT_EQ(r.result.report.vertices_before, input.vertex_count());
  EXPECT_LE(r.result.report.vertices_after, static_cast<std::uint64_t>(0.35 * input.vertex_count()));
  if (rank() == 0) {
    EXPECT_EQ(r.output.vertex_count(), r.result.report.vertices_after);
  }
  if (ranks() > 1) {
    EXPECT_GT(r.result.passes.front().frozen_vertices, 0u);
  }
  expect_same_topology(input, r);
}

INSTANTIATE_TEST_SUITE_P(Families, MpiSimplify, ::testing::Values("cube-sphere", "slab"),
                         [](const auto& p) { return p.param == "cube-sphere" ? std::string("cube_sphere") : p.param; });

TEST(MpiSimplifyDistributed, AlreadySpreadMeshKeepsTheTopologyAndMapsEveryVertex) {
  const MeshData input = generated("cube-sphere", 3000);
  DistributedMesh part = slab_part(input);
  const std::vector<GlobalId> my_ids = part.global_ids;
  // Without the flips of the optimisation, which make tets that are no input tet renamed.
  const Simplified r = run(std::move(part), 0.3, 1, Optimize::kNone);
  expect_same_topology(input, r);
  // The map: gather (input id, final id) pairs; every input tet renamed through it is an output
  // tet, or has collapsed (two corners with one image).
  ASSERT_EQ(r.result.vertex_map.size(), my_ids.size());
  std::vector<GlobalId> pairs;
  for (std::size_t i = 0; i < my_ids.size(); ++i) {
    pairs.push_back(my_ids[i]);
    pairs.push_back(r.result.vertex_map[i]);
  }
  int count = static_cast<int>(pairs.size()), n = ranks();
  std::vector<int> counts(n), displs(n);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  int total = 0;
  for (int k = 0; k < n; ++k) {
    displs[k] = total;
    total += counts[k];
  }
  std::vector<GlobalId> all(rank() == 0 ? total : 0);
  MPI_Gatherv(pairs.data(), count, MPI_UINT64_T, all.data(), counts.data(), displs.data(), MPI_UINT64_T, 0,
              MPI_COMM_WORLD);
  if (rank() != 0) return;
  std::vector<GlobalId> image(input.vertex_count(), ~GlobalId{0});
  for (std::size_t k = 0; k < all.size(); k += 2) {
    if (image[all[k]] != ~GlobalId{0}) {
      EXPECT_EQ(image[all[k]], all[k + 1]) << "ranks disagree on vertex " << all[k];
    }
    image[all[k]] = all[k + 1];
  }
  std::unordered_map<GlobalId, VertId> output_of;
  for (VertId o = 0; o < r.output_ids.size(); ++o) output_of[r.output_ids[o]] = o;
  using Key = std::pair<std::array<VertId, 4>, std::int32_t>;
  std::vector<Key> renamed, output;
  for (std::size_t t = 0; t < input.tet_count(); ++t) {
    std::array<VertId, 4> v;
    for (int k = 0; k < 4; ++k) {
      const auto it = output_of.find(image[input.tets[t][k]]);
      ASSERT_NE(it, output_of.end()) << "input vertex " << input.tets[t][k] << " maps to no output vertex";
      v[k] = it->second;
    }
    std::sort(v.begin(), v.end());
    if (std::adjacent_find(v.begin(), v.end()) == v.end()) renamed.emplace_back(v, input.tet_material[t]);
  }
  for (std::size_t t = 0; t < r.output.tet_count(); ++t) {
    std::array<VertId, 4> v = r.output.tets[t];
    std::sort(v.begin(), v.end());
    output.emplace_back(v, r.output.tet_material[t]);
  }
  std::sort(renamed.begin(), renamed.end());
  std::sort(output.begin(), output.end());
  EXPECT_TRUE(renamed == output);
}

// The limits relax over MPI as in core (relax_limits.h), for every rank alike: a tolerance far
// below the surfaces' jitter (as RelaxLimits.TheToleranceDoublesUntilTheTarget*) stops a run held
// to it before its target; relaxed, H doubles at each global stall until the run reaches the
// target, the report gives the H that holds, and the surfaces stay within it.
TEST(MpiSimplifyRelax, TheToleranceRelaxesForEveryRankAlike) {
  const MeshData input = generated("cube-sphere", 8000);
  const auto run_with = [&](bool relax, int threads = 1) {
    Options options;
    options.simplify.target_vertex_ratio = 0.05;
    options.simplify.tolerance_rel = 1e-4;
    options.simplify.feature_angle = 180.0;
    options.simplify.num_threads = threads;
    options.simplify.relax_tolerance = options.simplify.relax_quality = relax;
    DistributedMesh part = rank() == 0 ? from_whole(input) : DistributedMesh{};
    distribute(MPI_COMM_WORLD, part);
    Simplified r;
    r.result = simplify(MPI_COMM_WORLD, part, options);
    r.output = gather(MPI_COMM_WORLD, part, 0, &r.output_ids);
    return r;
  };
  const std::uint64_t target = static_cast<std::uint64_t>(std::llround(0.05 * static_cast<double>(input.vertex_count())));
  const Simplified held = run_with(false);
  EXPECT_EQ(held.result.report.status, Status::kStoppedEarly);
  EXPECT_GT(held.result.report.vertices_after, 2 * target);
  EXPECT_TRUE(held.result.report.relaxations.empty());

  const Simplified relaxed = run_with(true);
  const Report& r = relaxed.result.report;
  std::string relaxations;
  for (const Relaxation& x : r.relaxations)
    relaxations += std::string(x.limit) + " " + std::to_string(x.from) + " -> " + std::to_string(x.to) + " at " +
                   std::to_string(x.vertices_left) + "; ";
  ASSERT_EQ(r.status, Status::kOk) << r.message << "; relaxed: " << relaxations;
  EXPECT_LE(r.vertices_after, target);
  std::size_t steps = 0;
  for (const Relaxation& x : r.relaxations)
    if (std::strcmp(x.limit, "tolerance") == 0) {
      EXPECT_EQ(x.to, 2.0 * x.from);
      ++steps;
    }
  ASSERT_GE(steps, 1u);
  EXPECT_EQ(r.tolerance, std::ldexp(r.tolerance_asked, static_cast<int>(steps)));
  expect_same_topology(input, relaxed);
  if (rank() == 0) {
    SurfaceDistanceOptions distance_options;
    distance_options.sample_spacing_rel = 5e-4;
    // Each pass checks H against its own input (docs/mpi.md, Limits): H per pass at most.
    EXPECT_LE(surface_distance(input, relaxed.output, distance_options).hausdorff,
              r.tolerance * static_cast<double>(relaxed.result.passes.size()));
  }
  // The same relaxations and output for another thread count per rank.
  const Simplified two_threads = run_with(true, 2);
  EXPECT_EQ(two_threads.result.report.relaxations.size(), r.relaxations.size());
  EXPECT_EQ(two_threads.result.report.tolerance, r.tolerance);
  EXPECT_TRUE(two_threads.output == relaxed.output);
  EXPECT_TRUE(two_threads.output_ids == relaxed.output_ids);
}

TEST(MpiSimplifyDeterminism, SameOutputForEveryRunAndThreadCount) {
  const MeshData input = generated("slab", 2000);
  const Simplified first = run_from_rank0(input, 0.3, 1);
  const Simplified again = run_from_rank0(input, 0.3, 1);
  const Simplified threads = run_from_rank0(input, 0.3, 2);
  if (rank() != 0) return;
  EXPECT_TRUE(first.output == again.output);
  EXPECT_TRUE(first.output == threads.output);
  EXPECT_TRUE(first.output_ids == threads.output_ids);
}

}  // namespace
}  // namespace topotet::mpi

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  // Only rank 0 prints; every rank runs every (collective) test.
  if (topotet::mpi::rank() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int failed = RUN_ALL_TESTS();
  int any = 0;
  MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return any;
}
