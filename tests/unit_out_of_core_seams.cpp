// Seams (outofcore/seams.h): when the memory limit keeps neighbouring pieces apart at the last
// level, a band on each side of their common border becomes a piece of its own in which that
// border is simplified. Checked on the cube-sphere with a disc in the first cut plane (inside a
// border) and a polyline through every piece, cut into 16 pieces with a limit that leaves four
// apart at the last level (every pair of them neighbours, several seams cut out of one piece):
//   - the run reaches its target (the borders' vertices were left over before), with the topology
//     of the mesh and of every substructure (metrics/ independent checker), no inverted tet, the
//     surfaces within the tolerance, the same bytes for 1 and 2 threads;
//   - with field error bounds and a hierarchy file: the bound holds at every input vertex, the
//     hierarchy's coarsest level is the output and its levels keep the topology;
//   - a piece cut into a band and the rest, merged back, is the piece again (sub_piece, band_tets).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "hierarchy_levels.h"
#include "io_test_files.h"
#include "out_of_core_test_meshes.h"
#include "outofcore/piece.h"
#include "topotet/hierarchy.h"
#include "topotet/io.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/surface_distance.h"
#include "topotet/metrics/topology.h"
#include "topotet/out_of_core.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

struct Seamed {
  OutOfCoreReport report;
  MeshData input, output;
  std::string bytes;
  std::string hierarchy_path;
};

// `pieces` pieces of at most `fraction` of the input's tets (forced: OutOfCoreOptions::piece_tets),
// so that at the asked ratio the pieces of the last level no longer fit two together.
Seamed run_seamed(const MeshData& input, const test::TempDir& folder, int threads, std::uint32_t pieces, double fraction,
                  double ratio, bool bounds_and_hierarchy) {
  const std::string in = folder.file("in.mesh"), out = folder.file("out.mesh");
  write_mesh(in, input);
  SimplifyOptions options;
  options.target_vertex_ratio = ratio;
  options.num_threads = threads;
  OutOfCoreOptions ooc;
  ooc.pieces = pieces;
  ooc.piece_tets = static_cast<std::uint64_t>(fraction * static_cast<double>(input.tet_count()));
  if (bounds_and_hierarchy) {
    options.max_field_error_rel = 0.02;
    ooc.hierarchy_path = folder.file("h.tth");
  }
  Seamed r;
  r.report = simplify_out_of_core(in, out, options, ooc);
  r.input = read_mesh(in);
  r.output = read_mesh(out);
  r.bytes = test::read_text(out);
  r.hierarchy_path = ooc.hierarchy_path;
  return r;
}

void expect_same_topology(const MeshData& input, const MeshData& output) {
  const auto after = metrics::compute_topology(output);
  std::string differences;
  EXPECT_TRUE(metrics::same_topology(metrics::compute_topology(input), after, &differences)) << differences;
  EXPECT_EQ(after.inverted_tet_count, 0u);
  EXPECT_EQ(after.degenerate_tet_count, 0u);
}

void expect_no_litter(const test::TempDir& folder) {
  for (const std::string& e : folder.entries()) {
    EXPECT_EQ(e.find(".topotet-scratch"), std::string::npos) << e;
    EXPECT_EQ(e.find(".tmp-"), std::string::npos) << e;
  }
}

// Two halves that no longer fit together at 30%: one seam along the first cut plane, where the
// disc lies, and the run gets its target (the halves' common border, frozen until then, left
// more vertices than asked).
TEST(OutOfCoreSeams, TwoHalvesTheLimitKeepsApartReachTheTargetWithTheirTopology) {
  const MeshData input = test::planted_cube_sphere(40000);
  test::TempDir two_folder, one_folder;
  const Seamed two = run_seamed(input, two_folder, 2, 2, 0.3, 0.3, false);
  ASSERT_EQ(two.report.levels.size(), 2u);
  EXPECT_EQ(two.report.levels.back().unmerged, 1u);
  EXPECT_EQ(two.report.levels.back().seams, 1u);
  EXPECT_GT(two.report.output_pieces, 2u);  // the halves' rests and the seam
  const double target = std::round(0.3 * static_cast<double>(input.vertex_count()));
  EXPECT_NEAR(static_cast<double>(two.output.vertex_count()), target, 0.02 * target);
  EXPECT_EQ(two.output.vertex_count(), two.report.report.vertices_after);
  expect_same_topology(two.input, two.output);
  const SurfaceDistance d = surface_distance(two.input, two.output);
  EXPECT_EQ(d.unmatched_labels, 0u);
  EXPECT_LE(d.hausdorff, two.report.report.tolerance * (1 + 1e-9) + d.sampling_error);
  const Seamed one = run_seamed(input, one_folder, 1, 2, 0.3, 0.3, false);
  EXPECT_EQ(one.bytes, two.bytes);
  expect_no_litter(two_folder);
  expect_no_litter(one_folder);
}

// Four quarters apart: seams between every two neighbours, and between seams and the pieces
// whose other borders their bands took part of; with field error bounds (the samples go with
// their tets into the bands) and a hierarchy file (so do the tets' last collapses).
TEST(OutOfCoreSeams, FourQuartersWithFieldBoundsAndAHierarchy) {
  const MeshData input = test::planted_cube_sphere(100000);
  test::TempDir folder;
  const Seamed r = run_seamed(input, folder, 2, 4, 0.15, 0.1, true);
  ASSERT_FALSE(r.report.levels.empty());
  EXPECT_GE(r.report.levels.back().seams, 2u);
  expect_same_topology(r.input, r.output);
  ASSERT_TRUE(r.report.report.field_bounds);
  EXPECT_LE(r.report.report.field_bound_rel, 0.02 * (1 + 1e-9));
  EXPECT_LE(compare_fields(r.input, r.output).worst_max_rel_at_original(), r.report.report.field_bound_rel * (1 + 1e-6));
  // The coarsest level is the output; levels between keep the topology; every collapse replays
  // legally through the kernel on the whole input (a seam's depend on both pieces' earlier ones).
  const Hierarchy h = read_hierarchy(r.hierarchy_path);
  const MeshData all = extract(h, select_prefix(h, h.collapse_count()));
  EXPECT_EQ(all.vertex_count(), r.output.vertex_count());
  EXPECT_EQ(all.tet_count(), r.output.tet_count());
  const auto input_topology = metrics::compute_topology(r.input);
  std::mt19937 rng(5);
  for (double p : {0.5, 0.9})
    test::expect_valid_level(r.input, input_topology, extract(h, test::random_closed(h, p, rng)), "p " + std::to_string(p));
  MeshModel whole = build_mesh_model(h.original);
  test::replay_through_kernel(h, std::vector<std::uint8_t>(h.collapse_count(), 1), CollapseOptions{}, nullptr, whole);
  expect_no_litter(folder);
}

// Structure: a band around some vertices and the rest of a piece, merged back, give the piece's
// tets (by global ids), listed triangles and edges, corners and samples; the band holds every tet
// at the seeds, and the vertices both parts use are exactly the rest's vertices the band uses.
TEST(OutOfCoreSeams, ABandAndTheRestMergeBackIntoThePiece) {
  MeshData m = test::planted_cube_sphere(6000);
  m.corners = {0, 5};
  ooc::Piece piece;
  piece.mesh = m;
  for (VertId v = 0; v < m.vertex_count(); ++v) piece.global_ids.push_back(v);
  for (std::uint32_t t = 0; t < m.tet_count(); ++t) piece.last_collapse.push_back(t % 7 == 0 ? kInvalid : t);
  std::vector<ooc::GlobalId> seeds;
  for (const Segment& s : m.segments) seeds.push_back(s.v[0]);  // along the polyline
  std::sort(seeds.begin(), seeds.end());
  seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  const std::vector<std::uint32_t> band = ooc::band_tets(piece, seeds, m.tet_count() / 3, 1000);
  ASSERT_GT(band.size(), 0u);
  EXPECT_LE(band.size(), m.tet_count() / 3);
  for (std::uint32_t t = 0; t < m.tet_count(); ++t)
    for (VertId v : m.tets[t])
      if (std::binary_search(seeds.begin(), seeds.end(), v)) {
        EXPECT_TRUE(std::binary_search(band.begin(), band.end(), t)) << "tet " << t;
      }
  std::vector<std::uint32_t> rest;
  for (std::uint32_t t = 0; t < m.tet_count(); ++t)
    if (!std::binary_search(band.begin(), band.end(), t)) rest.push_back(t);
  const ooc::Piece a = ooc::sub_piece(piece, band), b = ooc::sub_piece(piece, rest);
  EXPECT_EQ(a.mesh.tet_count() + b.mesh.tet_count(), m.tet_count());
  const ooc::Piece merged = ooc::merge_pieces(a, b);
  // As sets over global ids (the merge orders vertices and tets its own way).
  const auto tets_of = [](const ooc::Piece& p) {
    std::vector<std::array<ooc::GlobalId, 5>> out;
    for (std::size_t t = 0; t < p.mesh.tet_count(); ++t) {
      std::array<ooc::GlobalId, 5> k;
      for (int i = 0; i < 4; ++i) k[i] = p.global_ids[p.mesh.tets[t][i]];
      k[4] = p.last_collapse[t];
      out.push_back(k);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(tets_of(merged), tets_of(piece));
  const auto triangles_of = [](const ooc::Piece& p) {
    std::vector<std::array<std::int64_t, 4>> out;
    for (const Triangle& t : p.mesh.triangles) {
      std::array<std::int64_t, 4> k = {p.global_ids[t.v[0]], p.global_ids[t.v[1]], p.global_ids[t.v[2]], 0};
      std::sort(k.begin(), k.begin() + 3);
      k[3] = t.ref;
      out.push_back(k);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(triangles_of(merged), triangles_of(piece));
  EXPECT_EQ(merged.mesh.segments.size(), m.segments.size());
  EXPECT_EQ(merged.mesh.corners.size(), m.corners.size());
  EXPECT_EQ(merged.mesh.positions.size(), m.positions.size());
  ASSERT_EQ(merged.mesh.fields.size(), m.fields.size());
  for (VertId v = 0; v < merged.mesh.vertex_count(); ++v) {
    const VertId g = merged.global_ids[v];
    EXPECT_EQ(merged.mesh.positions[v], m.positions[g]);
    EXPECT_EQ(merged.mesh.fields[0].values[v], m.fields[0].values[g]);
  }
}

}  // namespace
}  // namespace topotet
