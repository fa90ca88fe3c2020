// The hierarchy file out of core (OutOfCoreOptions::hierarchy_path, `simplify --memory-limit
// --hierarchy`): every piece's collapses are recorded with their parents, continuing across pieces
// and levels (outofcore/hierarchy_spool.h). Checked here on meshes whose substructures cross many
// piece borders (the cube-sphere's sphere, a polyline straight through every piece) or lie inside
// one (a disc in the first cut plane):
//   - the file reads back and validates; its original is the input as read; nothing applied gives
//     the input, everything applied gives the run's output;
//   - levels the file offers (random downward-closed sets, prefixes, by error, fine in a volume of
//     interest) have the input's topology by the independent checker (metrics/), substructures
//     included, and no inverted tet; replayed through the kernel on the WHOLE original, every
//     collapse of such a set passes the link conditions (the pieces' runs never saw the whole);
//   - collapses of the merge levels depend on collapses of the levels before (the seeds work);
//   - with fields, each collapse's bound holds: a level by error e has its measured error <= e;
//   - 1 and 2 threads write the same bytes; the memory budget counts the records; a vertex map
//     and a hierarchy together are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "hierarchy_levels.h"
#include "io_test_files.h"
#include "engines.h"
#include "hierarchy/hierarchy_log.h"
#include "kernel/collapse.h"
#include "mesh/glm_convert.h"
#include "mesh/mesh_model.h"
#include "out_of_core_test_meshes.h"
#include "outofcore/cut.h"
#include "outofcore/memory_budget.h"
#include "topotet/error.h"
#include "topotet/hierarchy.h"
#include "topotet/io.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/topology.h"
#include "topotet/out_of_core.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

using test::expect_valid_level;
using test::random_closed;


struct Recorded {
  OutOfCoreReport report;
  MeshData input;   // as written to the input file and read back
  MeshData output;
  Hierarchy hierarchy;
  std::string bytes;  // the .tth
};

Recorded run_recorded(const MeshData& input, const test::TempDir& folder, std::uint32_t pieces, int threads,
                      bool field_bounds = false) {
  const std::string in = folder.file("in.mesh"), out = folder.file("out.mesh"), tth = folder.file("h.tth");
  write_mesh(in, input);
  SimplifyOptions options;
  options.target_vertex_ratio = 0.15;
  options.num_threads = threads;
  options.track_field_bounds = field_bounds;
  OutOfCoreOptions ooc;
  ooc.pieces = pieces;
  ooc.hierarchy_path = tth;
  Recorded r;
  r.report = simplify_out_of_core(in, out, options, ooc);
  r.input = read_mesh(in);
  r.output = read_mesh(out);
  r.hierarchy = read_hierarchy(tth);
  r.bytes = test::read_text(tth);
  return r;
}

const Recorded& cube_sphere_16() {
  static const test::TempDir folder;
  static const Recorded r = run_recorded(test::planted_cube_sphere(16000), folder, 16, 2);
  return r;
}

// Positions of a mesh's vertices, sorted: two meshes with the same vertices in another order agree.
std::vector<std::array<double, 3>> sorted_positions(const MeshData& m) {
  std::vector<std::array<double, 3>> p = m.positions;
  std::sort(p.begin(), p.end());
  return p;
}

TEST(OutOfCoreHierarchy, TheFileHoldsTheInputAndEveryCollapseUpToTheOutput) {
  const Recorded& r = cube_sphere_16();
  const Hierarchy& h = r.hierarchy;
  EXPECT_EQ(r.report.pieces, 16u);
  EXPECT_EQ(r.report.output_pieces, 1u);
  EXPECT_EQ(r.report.hierarchy_collapses, h.collapse_count());
  EXPECT_EQ(h.collapse_count(), r.report.report.collapses);
  EXPECT_EQ(h.collapse_count(), r.input.vertex_count() - r.output.vertex_count());
  EXPECT_EQ(r.report.hierarchy_bytes, r.bytes.size());
  // The original is the input as read, in its numbering.
  EXPECT_EQ(h.original.positions, r.input.positions);
  EXPECT_EQ(h.original.tets, r.input.tets);
  EXPECT_EQ(h.original.tet_material, r.input.tet_material);
  EXPECT_EQ(h.original.triangles.size(), r.input.triangles.size());
  EXPECT_EQ(h.original.segments.size(), r.input.segments.size());
  EXPECT_EQ(h.original.fields.size(), r.input.fields.size());
  // Nothing applied: the input; everything: the output (up to the vertices' order).
  const MeshData none = extract(h, select_prefix(h, 0));
  EXPECT_EQ(none.positions, r.input.positions);
  EXPECT_EQ(none.tets, r.input.tets);
  const MeshData all = extract(h, select_prefix(h, h.collapse_count()));
  EXPECT_EQ(sorted_positions(all), sorted_positions(r.output));
  EXPECT_EQ(all.tets.size(), r.output.tets.size());
  EXPECT_EQ(all.triangles.size(), r.output.triangles.size());
  EXPECT_EQ(all.segments.size(), r.output.segments.size());
}

TEST(OutOfCoreHierarchy, MergeLevelsDependOnTheLevelsBefore) {
  const Recorded& r = cube_sphere_16();
  const Hierarchy& h = r.hierarchy;
  ASSERT_GE(r.report.levels.size(), 3u);
  const std::uint64_t level0 = r.report.levels[0].collapses;
  ASSERT_GT(level0, 0u);
  ASSERT_LT(level0, h.collapse_count());
  std::uint64_t crossing = 0;  // collapses of a merge level with a parent in level 0
  for (std::size_t i = level0; i < h.collapse_count(); ++i)
    for (std::uint32_t k = h.parent_offsets[i]; k < h.parent_offsets[i + 1]; ++k) crossing += h.parents[k] < level0;
  EXPECT_GT(crossing, 0u);
}

TEST(OutOfCoreHierarchy, EveryLevelItOffersKeepsTheTopologyOfTheMeshAndItsSubstructures) {
  const Recorded& r = cube_sphere_16();
  const Hierarchy& h = r.hierarchy;
  const metrics::TopologyReport input_topology = metrics::compute_topology(r.input);
  ASSERT_GE(input_topology.surfaces.size() + input_topology.interfaces.size(), 2u);  // the sphere, the disc
  ASSERT_GE(input_topology.polylines.size(), 1u);                                     // the line
  std::mt19937 rng(5);
  for (double p : {0.3, 0.7, 0.95}) expect_valid_level(r.input, input_topology, extract(h, random_closed(h, p, rng)), "p " + std::to_string(p));
  for (double f : {0.25, 0.5, 0.9}) {
    const auto k = static_cast<std::size_t>(f * static_cast<double>(h.collapse_count()));
    expect_valid_level(r.input, input_topology, extract(h, select_prefix(h, k)), "prefix " + std::to_string(k));
  }
  const double top = h.error.back();
  expect_valid_level(r.input, input_topology, extract(h, select_error(h, 0.3 * top)), "by error");
  const Voi voi = parse_voi("sphere:0.5,0.5,0.5,0.3");
  expect_valid_level(r.input, input_topology, extract(h, select_voi(h, voi, 0.0, top)), "fine voi");
  expect_valid_level(r.input, input_topology, extract(h, select_voi(h, voi, 0.0, top, VoiClosure::kReachCoarse)), "coarse voi");
}

// The pieces' runs checked each collapse on their piece; the hierarchy promises it is legal on the
// whole mesh, in any closed set: replayed on the whole original, every applied collapse passes
// the kernel's link conditions and orientation check, and the kernel's mesh is extract()'s.
TEST(OutOfCoreHierarchy, ClosedSetsReplayLegallyThroughTheKernelOnTheWholeMesh) {
  const Recorded& r = cube_sphere_16();
  const Hierarchy& h = r.hierarchy;
  std::mt19937 rng(9);
  for (double p : {0.5, 0.9, 1.0}) {
    SCOPED_TRACE("p " + std::to_string(p));
    const std::vector<std::uint8_t> applied = random_closed(h, p, rng);
    MeshModel mesh = build_mesh_model(h.original);
    const CollapseOptions kernel;  // topology and orientation: the tolerance and floors were the levels' own
    test::replay_through_kernel(h, applied, kernel, nullptr, mesh);
    const MeshData replayed = mesh.to_mesh_data();
    const MeshData extracted = extract(h, applied);
    EXPECT_EQ(sorted_positions(replayed), sorted_positions(extracted));
    EXPECT_EQ(replayed.tets.size(), extracted.tets.size());
  }
}

TEST(OutOfCoreHierarchy, SameBytesForOneAndTwoThreads) {
  const MeshData input = test::planted_cube_sphere(8000);
  test::TempDir a, b;
  const Recorded one = run_recorded(input, a, 8, 1);
  const Recorded two = run_recorded(input, b, 8, 2);
  EXPECT_EQ(one.bytes, two.bytes);
  EXPECT_GT(one.hierarchy.collapse_count(), 0u);
}

// With fields, each collapse records its bound: a level by error e (relative to the range) has
// every input vertex's error within e, measured by metrics/ against the input.
TEST(OutOfCoreHierarchy, LevelsByErrorHoldTheirFieldBound) {
  const MeshData input = test::planted_cube_sphere(8000);
  ASSERT_FALSE(input.fields.empty());
  test::TempDir folder;
  const Recorded r = run_recorded(input, folder, 8, 2, true);
  const Hierarchy& h = r.hierarchy;
  ASSERT_GT(h.collapse_count(), 0u);
  EXPECT_TRUE(std::none_of(h.error_bound.begin(), h.error_bound.end(), [](float b) { return std::isnan(b); }));
  for (double e : {0.01, 0.05}) {
    const MeshData level = extract(h, select_error(h, e));
    EXPECT_LT(level.vertex_count(), r.input.vertex_count());
    EXPECT_LE(compare_fields(r.input, level).worst_max_rel_at_original(), e * (1 + 1e-6)) << "e " << e;
  }
}

// A piece's log hands its records to the spool every kHierarchyBatch collapses (pieces here are too
// small to reach it): with a sink every 7 collapses, from a seeded id, the records handed over are
// the ones a log that keeps them all holds, ids and parents included.
TEST(OutOfCoreHierarchy, ALogHandsOverItsRecordsInBatchesAsOneLogHoldsThem) {
  SimplifyOptions options;
  options.target_vertex_ratio = 0.3;
  options.num_threads = 2;
  const MeshData input = test::generated("cube-sphere", 3000);
  MeshModel whole = build_mesh_model(input);
  detail::CollapseLog kept(whole.tet_capacity(), whole.field_stride(), 1000);
  std::vector<VertId> new2old;
  ASSERT_EQ(detail::simplify_recorded(whole, options, kept, new2old).status, Status::kOk);
  MeshModel batched_mesh = build_mesh_model(input);
  detail::CollapseLog batched(batched_mesh.tet_capacity(), batched_mesh.field_stride(), 1000);
  std::vector<VertId> u, v;
  std::vector<std::uint32_t> parents, offsets{0};
  int handovers = 0;
  batched.set_sink(
      [&](const detail::CollapseLog& r) {
        ++handovers;
        u.insert(u.end(), r.u.begin(), r.u.end());
        v.insert(v.end(), r.v.begin(), r.v.end());
        for (std::size_t i = 1; i < r.parent_offsets.size(); ++i) offsets.push_back(static_cast<std::uint32_t>(parents.size()) + r.parent_offsets[i]);
        parents.insert(parents.end(), r.parents.begin(), r.parents.end());
      },
      7);
  ASSERT_EQ(detail::simplify_recorded(batched_mesh, options, batched, new2old).status, Status::kOk);
  batched.flush();
  EXPECT_GT(handovers, 10);
  EXPECT_TRUE(batched.u.empty());
  EXPECT_EQ(u, kept.u);
  EXPECT_EQ(v, kept.v);
  EXPECT_EQ(parents, kept.parents);
  EXPECT_EQ(offsets, kept.parent_offsets);
  EXPECT_TRUE(std::all_of(parents.begin(), parents.end(), [](std::uint32_t p) { return p >= 1000; }));
}

TEST(OutOfCoreHierarchy, TheBudgetCountsTheRecordsAndAVertexMapIsRefused) {
  ooc::InputCounts counts;
  counts.vertices = 2'000'000;
  counts.tets = 12'000'000;
  counts.vertex_stride = 1;
  ooc::MemoryBudget budget;
  budget.limit = 1ull << 30;
  budget.baseline = 64ull << 20;
  const std::uint64_t without = budget.piece_tets(counts);
  budget.hierarchy = true;
  const std::uint64_t with = budget.piece_tets(counts);
  EXPECT_LT(with, without);
  EXPECT_GT(ooc::hierarchy_batch_bytes(counts), ooc::hierarchy_batch_bytes(ooc::InputCounts{}));

  test::TempDir folder;
  const std::string in = folder.file("in.mesh");
  write_mesh(in, test::generated("cube-sphere", 3000));
  OutOfCoreOptions ooc;
  ooc.pieces = 2;
  ooc.hierarchy_path = folder.file("h.tth");
  ooc.vertex_map_path = folder.file("map.npy");
  EXPECT_THROW(simplify_out_of_core(in, folder.file("out.mesh"), SimplifyOptions{}, ooc), InputError);
  for (const std::string& e : folder.entries()) EXPECT_TRUE(e == "in.mesh" || e == "in.sol" || e == "in.sol.fields.txt") << e;
}

}  // namespace
}  // namespace topotet
