// The optimisation after the collapses (SimplifyOptions::optimize; engine/optimize/): smoothing of
// free vertices, 2-3 flips and edge removals.
//
// Property (every planted mesh, several jitter seeds, two targets, light and full): the run with
// the optimisation keeps the Betti numbers of the mesh and of every substructure (the independent
// checker of metrics/), inverts no tet, never has a worse worst tet than the same run without it,
// moves only free vertices (interior of one material, on no substructure) and vertices inside a
// flat sheet in an axis plane (in that plane, to the last bit), keeps every other vertex, its field
// values, every listed triangle and segment exactly, and the area of every surface label (boundary,
// each listed ref, each material interface: an in-plane move re-shapes a sheet's triangles but not
// the sheet); and it gives the same mesh for 1 and 2 threads.
// Unit: a planted sliver is improved, not kept; a 2-3 flip and a 3-2 edge removal happen where they lift the
// worst tet, and not across a listed face or between two materials; a flip that makes the field
// worse at an input vertex the collapses removed is refused, and the guard's errors are the
// squared errors at the recorded vertices inside the region.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <tuple>

#include "entry_points.h"
#include "mesh/mesh_model.h"
#include "optimize/input_samples.h"
#include "optimize/smooth.h"
#include "optimize/swap.h"
#include "test_meshes.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

// The model of `in` with every vertex marked as the collapses would mark a survivor
// (vertex_state::kReshaped): the optimisation works on the tets the collapses made or moved only,
// so a test of it on an input without collapses makes the whole input count as such.
MeshModel reshaped_model(const MeshData& in) {
  MeshModel mesh = build_mesh_model(in);
  for (auto& state : mesh.vertex_states) state |= vertex_state::kReshaped;
  return mesh;
}

MeshData simplified(const MeshData& in, double ratio, Optimize optimize, int threads, Report* report = nullptr,
                    bool all_reshaped = false) {
  MeshModel mesh = all_reshaped ? reshaped_model(in) : build_mesh_model(in);
  SimplifyOptions options;
  options.target_vertex_ratio = ratio;
  options.optimize = optimize;
  options.num_threads = threads;
  const Report r = simplify(mesh, options);
  EXPECT_TRUE(r.status == Status::kOk || r.status == Status::kStoppedEarly) << r.message;
  if (report != nullptr) *report = r;
  return mesh.to_mesh_data();
}

// Listed triangles or segments as a set: each with its vertices sorted, then sorted.
template <class T>
std::vector<T> sorted(std::vector<T> v) {
  for (T& x : v) std::sort(x.v.begin(), x.v.end());
  std::sort(v.begin(), v.end(), [](const T& a, const T& b) { return std::tie(a.v, a.ref) < std::tie(b.v, b.ref); });
  return v;
}

// Surface area by label: boundary faces (by listed ref, or unlisted), listed triangles inside the
// domain (by ref) and material interfaces (by the pair of materials), computed from the tets.
std::map<std::tuple<int, std::int64_t, std::int64_t>, double> area_by_label(const MeshData& m) {
  std::map<std::array<VertId, 3>, std::vector<std::size_t>> faces;
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      std::array<VertId, 3> key{};
      for (int j = 0, k = 0; j < 4; ++j)
        if (j != f) key[k++] = m.tets[t][j];
      std::sort(key.begin(), key.end());
      faces[key].push_back(t);
    }
  std::map<std::array<VertId, 3>, std::int32_t> listed;
  for (const Triangle& tr : m.triangles) {
    std::array<VertId, 3> key = tr.v;
    std::sort(key.begin(), key.end());
    listed[key] = tr.ref;
  }
  std::map<std::tuple<int, std::int64_t, std::int64_t>, double> area;
  for (const auto& [key, ts] : faces) {
    const auto p = [&](int i) { const auto& x = m.positions[key[i]]; return std::array<double, 3>{x[0], x[1], x[2]}; };
    const auto a = p(0), b = p(1), c = p(2);
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    const double face_area = 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const auto it = listed.find(key);
    const std::int64_t ref = it == listed.end() ? std::int64_t{1} << 40 : it->second;
    if (ts.size() == 1) {
      area[{0, ref, 0}] += face_area;
    } else if (it != listed.end()) {
      area[{1, ref, 0}] += face_area;
    } else if (m.tet_material[ts[0]] != m.tet_material[ts[1]]) {
      const std::int64_t lo = std::min(m.tet_material[ts[0]], m.tet_material[ts[1]]);
      const std::int64_t hi = std::max(m.tet_material[ts[0]], m.tet_material[ts[1]]);
      area[{2, lo, hi}] += face_area;
    }
  }
  return area;
}

struct OptimizeCase {
  std::size_t planted;
  std::uint64_t seed;
  double ratio;
  Optimize optimize;
};

class OptimizePlanted : public ::testing::TestWithParam<std::tuple<std::size_t, std::uint64_t, double, Optimize>> {};

TEST_P(OptimizePlanted, KeepsEveryGuaranteeAndNeverWorsensTheWorstTet) {
  const auto [index, seed, ratio, optimize] = GetParam();
  const std::vector<testing::PlantedMesh> meshes = testing::planted_meshes();
  const testing::PlantedMesh& planted = meshes[index];
  testing::Grid g = planted.make();
  // Another jitter of the same grid: interior vertices in 3D, boundary ones tangentially.
  if (seed != 1) {
    testing::Grid h = testing::make_grid(g.nx, g.ny, g.nz, [](int, int, int) { return 1; }, 0.12, seed);
    g.data.positions = h.data.positions;
  }
  const MeshData& in = g.data;
  const auto before = compute_topology(in);
  Report plain_report, report;
  const MeshData plain = simplified(in, ratio, Optimize::kNone, 1, &plain_report);
  const MeshData out = simplified(in, ratio, optimize, 1, &report);

  std::string differences;
  EXPECT_TRUE(same_topology(before, compute_topology(out), &differences)) << planted.name << ": " << differences;
  const QualityStats q = compute_quality(out), q_plain = compute_quality(plain);
  EXPECT_EQ(q.inverted, 0u);
  // Where the collapses stalled before the target, the optimised run flipped there and went on
  // (engine/flip_at_stall.h): its collapses differ from the plain run's from that point, so only
  // what holds for any run is compared (below: the same collapses otherwise).
  const bool same_collapses = report.stall_flips == 0;
  EXPECT_EQ(plain_report.stall_flips, 0u);
  if (same_collapses) {
    EXPECT_GE(q.mean_ratio.min, q_plain.mean_ratio.min * (1.0 - 1e-9)) << planted.name;
  }
  // The dihedral floor (SimplifyOptions::min_dihedral, as the run used it: relaxed where it would
  // have stopped the run short) holds through the collapses and the optimisation: every angle
  // within [f, 180 - f], f = min(floor, the input's worst, either way).
  const QualityStats q_in = compute_quality(in);
  if (same_collapses) {
    EXPECT_EQ(report.min_dihedral_used, plain_report.min_dihedral_used);
  }
  EXPECT_LE(report.min_dihedral_used, SimplifyOptions{}.min_dihedral);
  for (const auto& [s, used] : {std::pair{&q_plain, plain_report.min_dihedral_used}, std::pair{&q, report.min_dihedral_used}}) {
    const double floor = std::min({used, q_in.dihedral_deg.min, 180.0 - q_in.dihedral_deg.max});
    EXPECT_GE(s->dihedral_deg.min, floor - 1e-6) << planted.name << (s == &q ? " optimised" : " collapsed");
    EXPECT_LE(s->dihedral_deg.max, 180.0 - floor + 1e-6) << planted.name << (s == &q ? " optimised" : " collapsed");
  }
  // Determinism.
  EXPECT_TRUE(simplified(in, ratio, optimize, 2) == out) << planted.name << ": 1 and 2 threads differ";
  if (!same_collapses) {
    std::printf("[ optimize ] %-45s seed %llu ratio %.2f %s: %llu flips where the collapses stalled, %zu vertices (plain "
                "run %zu), min mean ratio %.3f (plain run %.3f)\n",
                planted.name, static_cast<unsigned long long>(seed), ratio, to_string(optimize),
                static_cast<unsigned long long>(report.stall_flips), out.positions.size(), plain.positions.size(),
                q.mean_ratio.min, q_plain.mean_ratio.min);
    return;
  }

  // Same collapses, then only free vertices move; everything on a substructure stays exactly.
  ASSERT_EQ(out.positions.size(), plain.positions.size());
  EXPECT_EQ(report.collapses, plain_report.collapses);
  EXPECT_EQ(sorted(out.triangles), sorted(plain.triangles));
  EXPECT_EQ(sorted(out.segments), sorted(plain.segments));
  EXPECT_EQ(out.corners, plain.corners);
  const MeshModel model = build_mesh_model(out);
  std::uint64_t moved = 0;
  for (VertId v = 0; v < out.positions.size(); ++v) {
    if (out.positions[v] == plain.positions[v]) {
      for (const VertexField& f : out.fields)
        for (int c = 0; c < f.components; ++c) {
          const std::size_t i = static_cast<std::size_t>(v) * f.components + c;
          ASSERT_EQ(f.values[i], plain.fields[&f - out.fields.data()].values[i]) << "vertex " << v << " did not move";
        }
      continue;
    }
    ++moved;
    const int axis = flat_sheet_axis(model, v);
    EXPECT_TRUE(is_free_vertex(model, v) || axis >= 0)
        << planted.name << ": vertex " << v << " is on a substructure that is not a flat sheet, and moved";
    if (axis >= 0) {
      EXPECT_EQ(out.positions[v][axis], plain.positions[v][axis]) << "vertex " << v << " left its plane";
    }
  }
  EXPECT_EQ(moved <= report.optimize_moves, true);
  const auto area = area_by_label(out), plain_area = area_by_label(plain);
  ASSERT_EQ(area.size(), plain_area.size());
  for (const auto& [label, a] : plain_area)
    EXPECT_NEAR(area.at(label), a, 1e-9 * a) << planted.name << ": a surface label's area changed";

  std::printf("[ optimize ] %-45s seed %llu ratio %.2f %s: min mean ratio %.3f -> %.3f, %llu moves, %llu flips\n",
              planted.name, static_cast<unsigned long long>(seed), ratio, to_string(optimize), q_plain.mean_ratio.min,
              q.mean_ratio.min, static_cast<unsigned long long>(report.optimize_moves),
              static_cast<unsigned long long>(report.optimize_flips));
}

INSTANTIATE_TEST_SUITE_P(
    Planted, OptimizePlanted,
    ::testing::Combine(::testing::Range<std::size_t>(0, testing::planted_meshes().size()), ::testing::Values(1u, 7u),
                       ::testing::Values(0.5, 0.15), ::testing::Values(Optimize::kLight, Optimize::kFull)),
    [](const ::testing::TestParamInfo<std::tuple<std::size_t, std::uint64_t, double, Optimize>>& p) {
      return std::string(testing::planted_meshes()[std::get<0>(p.param)].name) + "_seed" +
             std::to_string(std::get<1>(p.param)) + (std::get<2>(p.param) > 0.3 ? "_half" : "_small") + "_" +
             to_string(std::get<3>(p.param));
    });

// A grid with one interior vertex pushed almost onto a face of its star: slivers.
MeshData planted_sliver() {
  testing::Grid g = testing::make_grid(4, 4, 4, [](int, int, int) { return 1; }, 0.0);
  auto& p = g.data.positions[g.vid(2, 2, 2)];
  p[0] += 0.9;  // worst mean ratio 0.11 (the grid's tets have 0.71)
  p[1] += 0.9;
  return g.data;
}

TEST(OptimizeSliver, APlantedSliverIsImprovedNotKept) {
  const MeshData in = planted_sliver();
  const double worst_in = compute_quality(in).mean_ratio.min;
  ASSERT_LT(worst_in, 0.2);
  // Ratio 1: no collapse, only the optimisation.
  const MeshData kept = simplified(in, 1.0, Optimize::kNone, 1);
  EXPECT_DOUBLE_EQ(compute_quality(kept).mean_ratio.min, worst_in);
  Report report;
  const MeshData out = simplified(in, 1.0, Optimize::kLight, 1, &report, /*all_reshaped=*/true);
  EXPECT_GT(compute_quality(out).mean_ratio.min, 2.0 * worst_in);
  EXPECT_GE(report.optimize_moves, 1u);
  EXPECT_TRUE(same_topology(compute_topology(in), compute_topology(out)));
}

// The same sliver with no collapse anywhere near it: an input tet the collapses left alone stays
// as the input had it (smooth.h, swap.h), and so does the whole mesh here.
TEST(OptimizeSliver, AnInputSliverNoCollapseTouchedIsKept) {
  const MeshData in = planted_sliver();
  Report report;
  const MeshData out = simplified(in, 1.0, Optimize::kFull, 1, &report);
  EXPECT_EQ(report.optimize_moves, 0u);
  EXPECT_EQ(report.optimize_flips, 0u);
  EXPECT_TRUE(out == simplified(in, 1.0, Optimize::kNone, 1));
}

// A vertex inside the bottom face of a box (z = 0), pushed in that face almost onto a neighbour,
// then the same inside a listed sheet in the interior (z = 2), and inside a material interface:
// vertices of the sheet move in its plane (z kept to the last bit), the worst tet is lifted, and
// every surface label keeps its area.
TEST(OptimizeSliver, AVertexOfAFlatSheetMovesInItsPlane) {
  for (int kind = 0; kind < 3; ++kind) {
    const int z = kind == 0 ? 0 : 2;
    testing::Grid g = testing::make_grid(4, 4, 4, [](int, int, int k) { return k < 2 ? 1 : 2; }, 0.0);
    if (kind != 2) std::fill(g.data.tet_material.begin(), g.data.tet_material.end(), 1);
    if (kind == 1) {  // the plane z = 2 listed as a sheet inside one material
      for (std::size_t t = 0; t < g.data.tets.size(); ++t)
        for (int f = 0; f < 4; ++f) {
          std::array<VertId, 3> tri{};
          bool flat = true;
          for (int j = 0, k = 0; j < 4; ++j)
            if (j != f) {
              tri[k++] = g.data.tets[t][j];
              flat = flat && g.data.positions[g.data.tets[t][j]][2] == 2.0;
            }
          if (flat) g.data.triangles.push_back({tri, 7});
        }
      // Each face once (the two tets on either side list it twice).
      for (Triangle& tr : g.data.triangles) std::sort(tr.v.begin(), tr.v.end());
      std::sort(g.data.triangles.begin(), g.data.triangles.end(), [](const Triangle& a, const Triangle& b) { return a.v < b.v; });
      g.data.triangles.erase(std::unique(g.data.triangles.begin(), g.data.triangles.end()), g.data.triangles.end());
    }
    const VertId v = g.vid(2, 2, z);
    g.data.positions[v][0] += 0.95;
    g.data.positions[v][1] += 0.95;
    const MeshData& in = g.data;
    const double worst_in = compute_quality(in).mean_ratio.min;
    ASSERT_LT(worst_in, 0.2);
    ASSERT_EQ(compute_quality(in).inverted, 0u);
    Report report;
    const MeshData out = simplified(in, 1.0, Optimize::kLight, 1, &report, /*all_reshaped=*/true);
    EXPECT_GT(compute_quality(out).mean_ratio.min, 2.0 * worst_in) << "kind " << kind;
    // The output is renumbered: find the moved vertices by their positions.
    const std::set<std::array<double, 3>> before(in.positions.begin(), in.positions.end());
    int moved_in_sheet = 0;
    for (const auto& p : out.positions)
      if (before.count(p) == 0 && std::abs(p[2] - z) < 0.5) {
        EXPECT_EQ(p[2], static_cast<double>(z)) << "kind " << kind << ": a vertex left the sheet's plane";
        ++moved_in_sheet;
      }
    EXPECT_GE(moved_in_sheet, 1) << "kind " << kind;
    EXPECT_TRUE(same_topology(compute_topology(in), compute_topology(out))) << "kind " << kind;
    const auto area = area_by_label(out), area_in = area_by_label(in);
    ASSERT_EQ(area.size(), area_in.size());
    for (const auto& [label, a] : area_in) EXPECT_NEAR(area.at(label), a, 1e-9 * a) << "kind " << kind;
  }
}

// Two tets on an equilateral triangle (side 1) with their apexes at +-h over its centroid.
MeshData bipyramid(double h, bool three) {
  MeshData m;
  const double s = std::sqrt(3.0) / 2.0;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, s, 0}, {0.5, s / 3.0, h}, {0.5, s / 3.0, -h}};
  if (three) {
    m.tets = {{3, 4, 0, 1}, {3, 4, 1, 2}, {3, 4, 2, 0}};
  } else {
    m.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  }
  m.tet_material.assign(m.tets.size(), 1);
  return m;  // build_mesh_model orients the tets
}

// One flip pass on the bipyramid: the flips made, the tets left, and the worst tet lifted, nothing
// inverted, the topology kept.
void expect_one_flip(double h, bool three, std::uint64_t SwapStats::*kind, std::size_t tets_after) {
  const MeshData in = bipyramid(h, three);
  MeshModel m = reshaped_model(in);
  const double before = compute_quality(m.to_mesh_data()).mean_ratio.min;
  const SwapStats stats = swap_bad_tets(m, SwapOptions{});
  compact(m);
  EXPECT_EQ(stats.*kind, 1u);
  EXPECT_EQ(stats.flips_23 + stats.edge_removals, 1u);
  EXPECT_EQ(m.live_tet_count(), tets_after);
  const MeshData out = m.to_mesh_data();
  EXPECT_GT(compute_quality(out).mean_ratio.min, before);
  EXPECT_EQ(compute_quality(out).inverted, 0u);
  EXPECT_TRUE(same_topology(compute_topology(in), compute_topology(out)));
}

// h = 0.05: two flat tets (mean ratio ~0.2); the three around the axis are better.
TEST(OptimizeSwap, TwoThreeFlipWhereItLiftsTheWorstTet) { expect_one_flip(0.05, false, &SwapStats::flips_23, 3); }

// h = 2: three needles around a long axis (0.24); the two tets on the triangle are better (0.68).
TEST(OptimizeSwap, ThreeTwoFlipWhereItLiftsTheWorstTet) { expect_one_flip(2.0, true, &SwapStats::edge_removals, 2); }

TEST(OptimizeSwap, NoFlipAcrossAListedFaceOrBetweenMaterials) {
  MeshData listed = bipyramid(0.05, false);
  listed.triangles.push_back({{0, 1, 2}, 5});
  MeshModel a = reshaped_model(listed);
  EXPECT_EQ(swap_bad_tets(a, SwapOptions{}).flips_23, 0u);
  MeshData two = bipyramid(0.05, false);
  two.tet_material = {1, 2};
  MeshModel b = reshaped_model(two);
  EXPECT_EQ(swap_bad_tets(b, SwapOptions{}).flips_23, 0u);
  MeshData edge = bipyramid(2.0, true);
  edge.segments.push_back({{3, 4}, 9});  // the axis is a polyline: the edge removal would remove it
  MeshModel c = reshaped_model(edge);
  EXPECT_EQ(swap_bad_tets(c, SwapOptions{}).edge_removals, 0u);
}

TEST(OptimizeSwap, FlipsKeepTheFlagsOfTheFacesTheyKeep) {
  // The outer faces of the bipyramid listed: after the 2-3 flip all six are still listed.
  MeshData m = bipyramid(0.05, false);
  m.triangles = {{{0, 1, 3}, 1}, {{1, 2, 3}, 1}, {{2, 0, 3}, 1}, {{0, 1, 4}, 2}, {{1, 2, 4}, 2}, {{2, 0, 4}, 2}};
  MeshModel model = reshaped_model(m);
  ASSERT_EQ(swap_bad_tets(model, SwapOptions{}).flips_23, 1u);
  compact(model);
  const MeshData out = model.to_mesh_data();
  EXPECT_EQ(sorted(out.triangles), sorted(build_mesh_model(m).to_mesh_data().triangles));
}

// The flips' field guard at the input's vertices (optimize/input_samples.h). The bipyramid's 2-3
// flip makes the axis 3-4, which crosses the shared face at its centroid; an input vertex the
// collapses removed sits there. The field is 0 on the face's corners and 1 at the apexes, so the
// old tets give 0 at the centroid and the new ones 1: the flip is refused where the input said 0
// there, and made where it said 1 (it then removes the error). The pointwise bound is lifted so
// that only the samples decide.
TEST(OptimizeFieldGuard, AFlipMustNotMakeTheFieldWorseAtTheInputsVertices) {
  const auto flips = [](double truth, bool with_samples) {
    MeshData in = bipyramid(0.05, false);
    const double s = std::sqrt(3.0) / 2.0;
    in.positions.push_back({0.5, s / 3.0, 0.0});  // 5: the face's centroid, removed by a collapse
    in.fields.push_back({"f", 1, {0.0, 0.0, 0.0, 1.0, 1.0, truth}});
    MeshModel m = reshaped_model(in);
    m.vertex_states[5] &= static_cast<std::uint8_t>(~vertex_state::kDead);  // as before the collapses (a tet's vertex)
    InputSamples samples(m);
    m.vertex_states[5] |= vertex_state::kDead;
    samples.index(m);
    SwapOptions options;
    options.max_field_change = 1e9;
    return swap_bad_tets(m, options, with_samples ? &samples : nullptr).flips_23;
  };
  EXPECT_EQ(flips(0.0, true), 0u);
  EXPECT_EQ(flips(1.0, true), 1u);
  EXPECT_EQ(flips(0.0, false), 1u);  // without the samples only the geometry decides
  // The growth allowed: the old tets err by 0.5 there (truth 0.5), the new ones by 0.5 too.
  EXPECT_EQ(flips(0.5, true), 1u);
}

// inside / errors_after: squared errors in units of the range, at the recorded vertices inside the region
// only, none at a live vertex still at its input place (both fields take its value there).
TEST(OptimizeFieldGuard, RegionErrorsAreTheSquaredErrorsAtTheRecordedVerticesInside) {
  MeshData in;
  in.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.25, 0.25, 0.25}, {1, 1, 1}, {-1, -1, -1}};
  in.tets = {{0, 1, 2, 3}, {1, 2, 3, 5}, {0, 2, 1, 6}};
  in.tet_material.assign(3, 1);
  // f = 2x on the corners (range 0..2 over the recorded vertices: -2 at vertex 6, 2 at 5: 4).
  in.fields.push_back({"f", 1, {0.0, 2.0, 0.0, 0.0, 0.9, 2.0, -2.0}});
  MeshModel m = build_mesh_model(in);
  m.vertex_states[4] &= static_cast<std::uint8_t>(~vertex_state::kDead);  // as before the collapses
  InputSamples samples(m);
  m.vertex_states[4] |= vertex_state::kDead;  // inside tet 0: its input value 0.9, the tet's 0.5
  samples.index(m);
  FieldTet before;
  for (int j = 0; j < 4; ++j) {
    before.p[static_cast<std::size_t>(j)] = m.positions[in.tets[0][static_cast<std::size_t>(j)]];
    before.f[static_cast<std::size_t>(j)] = &m.field_values[in.tets[0][static_cast<std::size_t>(j)]];
  }
  FieldTet after = before;
  const double three = 3.0;
  after.f[1] = &three;  // corner (1, 0, 0) now 3: 0.75 at the sample
  InputSamples::Inside inside;
  samples.inside(m, std::span(&before, 1), kInvalid, inside);
  EXPECT_EQ(inside.vertices, std::vector<VertId>{4});
  EXPECT_NEAR(inside.error, (0.4 / 4.0) * (0.4 / 4.0), 1e-15);
  EXPECT_NEAR(samples.errors_after(m, std::span(&after, 1), inside), (0.15 / 4.0) * (0.15 / 4.0), 1e-15);
  // The corners are live and unmoved: skipped, though corner 1's value changed in `after`; once
  // it is the moving vertex, it counts (1 away from 3 at its own place).
  samples.inside(m, std::span(&before, 1), in.tets[0][1], inside);
  EXPECT_EQ(inside.vertices.size(), 2u);
  EXPECT_NEAR(samples.errors_after(m, std::span(&after, 1), inside), (0.15 / 4.0) * (0.15 / 4.0) + (1.0 / 4.0) * (1.0 / 4.0), 1e-15);
}

}  // namespace
}  // namespace topotet
