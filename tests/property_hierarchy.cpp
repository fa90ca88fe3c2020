// The collapse hierarchy (topotet/hierarchy.h): recorded the same for every thread count and both
// engines; any downward-closed selection replays legally through the kernel itself and gives the
// mesh the kernel gives; selections by error, vertex count and VOI give valid meshes with the
// input's topology (substructures included) and no inverted tet; nothing applied gives the
// input, everything the base mesh; the incremental cursor matches extraction from scratch; the
// .tth file round-trips and bad files are clear errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <tuple>

#include <glm/common.hpp>

#include "kernel/collapse.h"
#include "mesh/glm_convert.h"
#include "entry_points.h"
#include "hierarchy_levels.h"
#include "mesh/mesh_model.h"
#include "guarantees/surface_tolerance.h"
#include "topotet/error.h"
#include "topotet/features.h"
#include "topotet/generate.h"
#include "topotet/hierarchy.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

using test::expect_valid_level;
using test::random_closed;

struct Built {
  MeshData input;  // the model's own view of the input (what the records refer to)
  MeshData base;   // simplify's result
  Hierarchy hierarchy;
  Report report;
};

Built build(const std::string& family, std::uint64_t tets, Engine engine, int threads, double ratio = 0.2) {
  GenerateOptions g;
  g.family = family;
  g.target_tets = tets;
  MeshModel mesh = build_mesh_model(generate_mesh(g));
  Built b;
  b.input = mesh.to_mesh_data();
  SimplifyOptions options;
  options.engine = engine;
  options.num_threads = threads;
  options.target_vertex_ratio = ratio;
  b.report = simplify_with_hierarchy(mesh, options, b.hierarchy);
  b.base = mesh.to_mesh_data();
  return b;
}

const Built& cube_sphere() {
  static const Built b = build("cube-sphere", 4000, Engine::kParallel, 2);
  return b;
}

// A mesh with its vertices renamed to their rank in (position, fields) order, and every element
// list sorted with its vertices sorted: equal iff the meshes are the same up to numbering.
struct Canonical {
  std::vector<std::tuple<double, double, double, std::vector<double>, std::int32_t>> vertices;
  std::vector<std::pair<std::array<VertId, 4>, std::int32_t>> tets;
  std::vector<std::pair<std::array<VertId, 3>, std::int32_t>> triangles;
  std::vector<std::tuple<std::array<VertId, 2>, std::int32_t, bool>> segments;
  std::vector<VertId> corners, required;
  bool operator==(const Canonical&) const = default;
};

Canonical canonical(const MeshData& m) {
  Canonical c;
  const std::size_t n = m.positions.size();
  for (std::size_t x = 0; x < n; ++x) {
    std::vector<double> f;
    for (const VertexField& field : m.fields)
      for (int k = 0; k < field.components; ++k) f.push_back(field.values[x * field.components + k]);
    c.vertices.emplace_back(m.positions[x][0], m.positions[x][1], m.positions[x][2], f,
                            m.vertex_refs.empty() ? 0 : m.vertex_refs[x]);
  }
  std::vector<VertId> order(n);
  for (VertId x = 0; x < n; ++x) order[x] = x;
  std::sort(order.begin(), order.end(), [&](VertId a, VertId b) { return c.vertices[a] < c.vertices[b]; });
  std::vector<VertId> rank(n);
  for (VertId r = 0; r < n; ++r) rank[order[r]] = r;
  std::sort(c.vertices.begin(), c.vertices.end());
  auto renamed = [&](auto v) {
    for (VertId& x : v) x = rank[x];
    std::sort(v.begin(), v.end());
    return v;
  };
  for (std::size_t t = 0; t < m.tets.size(); ++t) c.tets.emplace_back(renamed(m.tets[t]), m.tet_material[t]);
  for (const Triangle& t : m.triangles) c.triangles.emplace_back(renamed(t.v), t.ref);
  std::vector<bool> ridge(m.segments.size(), false);
  for (std::uint32_t r : m.ridges) ridge[r] = true;
  for (std::size_t s = 0; s < m.segments.size(); ++s) c.segments.emplace_back(renamed(m.segments[s].v), m.segments[s].ref, ridge[s]);
  for (VertId x : m.corners) c.corners.push_back(rank[x]);
  for (VertId x : m.required_vertices) c.required.push_back(rank[x]);
  std::sort(c.tets.begin(), c.tets.end());
  std::sort(c.triangles.begin(), c.triangles.end());
  std::sort(c.segments.begin(), c.segments.end());
  std::sort(c.corners.begin(), c.corners.end());
  std::sort(c.required.begin(), c.required.end());
  return c;
}

TEST(Hierarchy, records_one_collapse_per_removed_vertex_with_parents_before_children) {
  const Built& b = cube_sphere();
  const Hierarchy& h = b.hierarchy;
  ASSERT_GT(h.collapse_count(), 100u);
  EXPECT_EQ(h.collapse_count(), b.report.collapses);
  EXPECT_EQ(b.input.positions.size() - h.collapse_count(), b.base.positions.size());
  EXPECT_NO_THROW(validate_hierarchy(h, "recorded"));
  for (std::size_t i = 1; i < h.error.size(); ++i) EXPECT_LE(h.error[i - 1], h.error[i]);
  for (float e : h.error_bound) EXPECT_TRUE(std::isnan(e));
  // Not a chain: the longest dependency path is much shorter than the records (collapses far
  // apart do not depend on each other, which is what lets a VOI refine only where it is).
  std::vector<std::uint32_t> depth(h.collapse_count(), 1);
  std::uint32_t longest = 0;
  for (std::size_t i = 0; i < h.collapse_count(); ++i) {
    for (std::uint32_t k = h.parent_offsets[i]; k < h.parent_offsets[i + 1]; ++k)
      depth[i] = std::max(depth[i], depth[h.parents[k]] + 1);
    longest = std::max(longest, depth[i]);
  }
  EXPECT_LT(longest, h.collapse_count() / 4) << h.collapse_count() << " collapses";
}

TEST(Hierarchy, records_are_identical_for_every_thread_count) {
  const Built& two = cube_sphere();
  for (int threads : {1, 3}) {
    const Built other = build("cube-sphere", 4000, Engine::kParallel, threads);
    const Hierarchy &a = two.hierarchy, &b = other.hierarchy;
    EXPECT_EQ(a.u, b.u);
    EXPECT_EQ(a.v, b.v);
    EXPECT_EQ(a.u_after, b.u_after);
    EXPECT_EQ(a.fields_after, b.fields_after);
    EXPECT_EQ(a.cost, b.cost);
    EXPECT_EQ(a.parent_offsets, b.parent_offsets);
    EXPECT_EQ(a.parents, b.parents);
  }
}

TEST(Hierarchy, nothing_applied_gives_the_input_and_everything_the_base_mesh) {
  for (Engine engine : {Engine::kParallel, Engine::kSequential}) {
    const Built b = engine == Engine::kParallel ? cube_sphere() : build("cube-sphere", 4000, engine, 1);
    EXPECT_EQ(extract(b.hierarchy, select_prefix(b.hierarchy, 0)), b.input);
    EXPECT_TRUE(canonical(extract(b.hierarchy, select_prefix(b.hierarchy, b.hierarchy.collapse_count()))) ==
                canonical(b.base));
  }
}

// The key fact the hierarchy rests on, checked with the kernel itself: replaying a downward
// closed set in recording order, every collapse passes may_collapse (same quality floor,
// tolerance and features as the run), and the kernel's mesh equals extract()'s.
void expect_kernel_replay(const Built& b, const std::vector<std::uint8_t>& applied, const std::string& what) {
  SCOPED_TRACE(what);
  const Hierarchy& h = b.hierarchy;
  MeshModel mesh = build_mesh_model(h.original);
  detect_features(mesh, SimplifyOptions{}.feature_angle, b.report.feature_scale);
  CollapseOptions kernel;
  kernel.quality_floor = SimplifyOptions{}.min_quality;
  const auto surfaces = SurfaceReference::from_mesh(mesh, b.report.tolerance);
  kernel.surfaces = surfaces.get();
  kernel.tolerance = b.report.tolerance;
  // The items of the original surfaces a face holds come from the collapses that made the face,
  // which a downward-closed set contains: the replay holds the same items as the run did.
  SurfaceCoverage coverage(mesh, *surfaces, b.report.tolerance);
  kernel.coverage = &coverage;
  test::replay_through_kernel(h, applied, kernel, &coverage, mesh);
  EXPECT_TRUE(canonical(mesh.to_mesh_data()) == canonical(extract(h, applied)));
}

TEST(Hierarchy, downward_closed_sets_replay_legally_through_the_kernel) {
  std::mt19937 rng(7);
  const Built slab = build("slab", 3000, Engine::kParallel, 2, 0.15);
  const Built sequential = build("cube-sphere", 4000, Engine::kSequential, 1);
  for (const Built* b : {&cube_sphere(), &slab, &sequential})
    for (double p : {0.2, 0.5, 0.8, 0.95}) expect_kernel_replay(*b, random_closed(b->hierarchy, p, rng), "p " + std::to_string(p));
  const Hierarchy& h = cube_sphere().hierarchy;
  const Voi box = parse_voi("box:0.2,0.2,0.2,0.6,0.7,0.5");
  expect_kernel_replay(cube_sphere(), select_voi(h, box, 0.0, h.error.back()), "box");
  expect_kernel_replay(cube_sphere(), select_voi(h, box, 0.0, h.error.back(), VoiClosure::kReachCoarse), "coarse box");
}

TEST(Hierarchy, uniform_and_selective_levels_keep_the_topology) {
  const Built& b = cube_sphere();
  const Hierarchy& h = b.hierarchy;
  const metrics::TopologyReport input_topology = metrics::compute_topology(b.input);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double top = h.error.back();
  for (int trial = 0; trial < 3; ++trial) {
    const std::size_t k = prefix_for_error(h, top * unit(rng) * unit(rng));
    expect_valid_level(b.input, input_topology, extract(h, select_prefix(h, k)), "prefix " + std::to_string(k));
  }
  const std::size_t k = prefix_for_vertices(h, b.input.positions.size() / 2);
  const MeshData half = extract(h, select_prefix(h, k));
  EXPECT_EQ(half.positions.size(), b.input.positions.size() / 2);
  expect_valid_level(b.input, input_topology, half, "half the vertices");
  for (int trial = 0; trial < 6; ++trial) {
    Voi voi;
    if (trial % 2 == 0) {
      voi.kind = Voi::Kind::kBox;
      const glm::dvec3 a(unit(rng), unit(rng), unit(rng)), c(unit(rng), unit(rng), unit(rng));
      voi.lo = from_glm(glm::min(a, c));
      voi.hi = from_glm(glm::max(a, c));
    } else {
      voi.kind = Voi::Kind::kSphere;
      voi.centre = {unit(rng), unit(rng), unit(rng)};
      voi.radius = 0.4 * unit(rng);
    }
    const double inside = top * 0.01 * unit(rng), outside = top * unit(rng);
    const std::vector<std::uint8_t> applied = select_voi(h, voi, inside, outside);
    expect_valid_level(b.input, input_topology, extract(h, applied), "voi trial " + std::to_string(trial));
    const std::vector<std::uint8_t> coarse = select_voi(h, voi, inside, outside, VoiClosure::kReachCoarse);
    expect_valid_level(b.input, input_topology, extract(h, coarse), "coarse voi trial " + std::to_string(trial));
    for (std::size_t i = 0; i < applied.size(); ++i) {
      const bool inside_voi = voi.contains(h.u_before[i]) || voi.contains(h.u_after[i]) || voi.contains(h.v_position[i]);
      // kKeepFine: the VOI stays fine. The contract is on the collapse's own error: h.error is
      // the running maximum, which an applied collapse inside may exceed.
      if (applied[i] && inside_voi) {
        EXPECT_LE(collapse_error(h, i), inside);
      }
      if (!inside_voi && h.error[i] <= outside) {  // kReachCoarse: the outside is coarse
        EXPECT_TRUE(coarse[i]);
      }
      if (applied[i]) {  // the closed subset lies inside the closed superset
        EXPECT_TRUE(coarse[i]);
      }
    }
  }
}

TEST(Hierarchy, every_substructure_kind_survives_random_levels) {
  // The slab has stacked interfaces with polylines on them; the cube-sphere an open patch, a
  // closed interface, a piercing polyline, boundary faces and corners.
  const Built b = build("slab", 3000, Engine::kParallel, 2, 0.15);
  const metrics::TopologyReport input_topology = metrics::compute_topology(b.input);
  std::mt19937 rng(3);
  for (double p : {0.5, 0.9})
    expect_valid_level(b.input, input_topology, extract(b.hierarchy, random_closed(b.hierarchy, p, rng)), "slab");
  EXPECT_TRUE(canonical(extract(b.hierarchy, select_prefix(b.hierarchy, b.hierarchy.collapse_count()))) ==
              canonical(b.base));
}

// With the field bounds tracked (engine/guarantees/field_bounds.h), every collapse records the bound of its
// new star, Hierarchy::error becomes their running maximum, and every level, uniform or VOI, has a
// measured field error at the original vertices no larger than the largest bound of its applied
// collapses: the levels' errors are guaranteed, not estimated.
TEST(Hierarchy, levels_by_error_bound_keep_the_measured_error_below_the_bound) {
  for (Engine engine : {Engine::kParallel, Engine::kSequential}) {
    GenerateOptions g;
    g.family = "cube-sphere";
    g.target_tets = 4000;
    MeshModel mesh = build_mesh_model(generate_mesh(g));
    const MeshData input = mesh.to_mesh_data();
    ASSERT_FALSE(input.fields.empty());
    SimplifyOptions options;
    options.engine = engine;
    options.target_vertex_ratio = 0.1;
    options.track_field_bounds = true;
    Hierarchy h;
    const Report report = simplify_with_hierarchy(mesh, options, h);
    ASSERT_TRUE(report.status == Status::kOk || report.status == Status::kStoppedEarly) << report.message;
    ASSERT_GT(h.collapse_count(), 100u);
    for (std::size_t i = 0; i < h.collapse_count(); ++i) {
      ASSERT_FALSE(std::isnan(h.error_bound[i])) << "collapse " << i;
      EXPECT_EQ(h.error[i], i == 0 ? static_cast<double>(h.error_bound[0])
                                   : std::max(h.error[i - 1], static_cast<double>(h.error_bound[i])));
    }
    const auto check = [&](const std::vector<std::uint8_t>& applied, const std::string& what) {
      double bound = 0.0;
      for (std::size_t i = 0; i < applied.size(); ++i)
        if (applied[i]) bound = std::max(bound, static_cast<double>(h.error_bound[i]));
      const FieldError error = compare_fields(input, extract(h, applied));
      for (const ComponentError& c : error.components)
        EXPECT_LE(c.original_to_simplified.max_rel, bound + 1e-6) << what << ", " << c.field;
    };
    const double top = h.error.back();
    for (double e : {top / 100.0, top / 10.0, top / 2.0, top}) {
      check(select_prefix(h, prefix_for_error(h, e)), "prefix level, error <= " + std::to_string(e));
      const std::vector<std::uint8_t> level = select_error(h, e);
      check(level, "uniform level, error <= " + std::to_string(e));
      double bound = 0.0;
      for (std::size_t i = 0; i < level.size(); ++i)
        if (level[i]) bound = std::max(bound, static_cast<double>(h.error_bound[i]));
      EXPECT_LE(bound, e);
      // It applies the prefix and more.
      const std::size_t prefix = prefix_for_error(h, e);
      EXPECT_TRUE(std::all_of(level.begin(), level.begin() + static_cast<std::ptrdiff_t>(prefix), [](std::uint8_t a) { return a != 0; }));
    }
    const Voi voi = parse_voi("sphere:0.5,0.5,0.5,0.3");
    check(select_voi(h, voi, top / 100.0, top), "VOI level");
    check(select_voi(h, voi, top / 100.0, top, VoiClosure::kReachCoarse), "coarse VOI level");
  }
}

// Everywhere under a limit, a check may accept a collapse on a cheap estimate of its bound
// (field_bounds.h). A run that records a hierarchy stores the exact maxima instead
// (FieldBounds::exact_commits): the same collapses as a run without one, every tet's bound at
// most that run's, and levels below the limit that coarsen. With the estimates stored (cube-sphere
// 20k, limit 0.05), the level at 0.01 kept every vertex where a separate run at 0.01 removes 30%
// of them; with the maxima it removes 20%.
TEST(Hierarchy, everywhere_bounds_are_recorded_exact_so_levels_below_the_limit_coarsen) {
  GenerateOptions g;
  g.family = "cube-sphere";
  g.target_tets = 8000;
  const MeshData input = generate_mesh(g);
  SimplifyOptions options;
  options.target_vertex_ratio = 0.02;
  options.track_field_bounds = true;
  options.field_bound_mode = FieldBoundMode::kEverywhere;
  options.max_field_error_rel = 0.05;
  options.optimize = Optimize::kNone;  // a hierarchy's run does not optimise: neither does the other
  MeshModel recorded = build_mesh_model(input), plain = build_mesh_model(input);
  Hierarchy h;
  const Report a = simplify_with_hierarchy(recorded, options, h);
  const Report b = simplify(plain, options);
  ASSERT_EQ(a.vertices_after, b.vertices_after);
  ASSERT_EQ(a.tet_field_bound.size(), b.tet_field_bound.size());
  std::size_t tighter = 0;
  for (std::size_t i = 0; i < a.tet_field_bound.size(); ++i) {
    EXPECT_LE(a.tet_field_bound[i], b.tet_field_bound[i]) << "tet bound " << i;
    tighter += a.tet_field_bound[i] < b.tet_field_bound[i] ? 1 : 0;
  }
  EXPECT_GT(tighter, a.tet_field_bound.size() / 10);
  for (const double e : {0.01, 0.02}) {
    const std::vector<std::uint8_t> level = select_error(h, e);
    const auto removed = static_cast<std::uint64_t>(std::count(level.begin(), level.end(), std::uint8_t{1}));
    MeshModel separate = build_mesh_model(input);
    SimplifyOptions at_e = options;
    at_e.max_field_error_rel = e;
    const Report r = simplify(separate, at_e);
    const std::uint64_t removed_separately = r.vertices_before - r.vertices_after;
    EXPECT_GE(2 * removed, removed_separately) << "level at " << e << ": " << removed << " collapses, a run at "
                                               << e << " makes " << removed_separately;
    // And the level's error stays below its bound at the original vertices.
    double bound = 0.0;
    for (std::size_t i = 0; i < level.size(); ++i)
      if (level[i]) bound = std::max(bound, static_cast<double>(h.error_bound[i]));
    EXPECT_LE(bound, e);
    for (const ComponentError& c : compare_fields(input, extract(h, level)).components)
      EXPECT_LE(c.original_to_simplified.max_rel, bound + 1e-6) << c.field;
  }
}

TEST(Hierarchy, cursor_moves_match_extraction_from_scratch) {
  const Hierarchy& h = cube_sphere().hierarchy;
  HierarchyCursor cursor(h);
  Voi voi = parse_voi("sphere:0.3,0.5,0.5,0.25");
  const double outside = h.error.back();
  std::size_t moved = 0;
  for (int step = 0; step < 4; ++step) {
    const std::vector<std::uint8_t> applied = select_voi(h, voi, 0.0, outside);
    moved += cursor.move_to(applied);
    EXPECT_EQ(cursor.mesh(), extract(h, applied)) << "step " << step;
    voi = voi.moved({voi.size() / 10, 0, 0});
  }
  EXPECT_GT(moved, 0u);
  EXPECT_THROW(cursor.move_to(std::vector<std::uint8_t>(1, 1)), InputError);  // wrong length
}

TEST(Hierarchy, selections_missing_a_parent_are_refused) {
  const Hierarchy& h = cube_sphere().hierarchy;
  std::size_t child = 0;
  while (h.parent_offsets[child] == h.parent_offsets[child + 1]) ++child;
  std::vector<std::uint8_t> applied(h.collapse_count(), 0);
  applied[child] = 1;
  EXPECT_THROW(extract(h, applied), InputError);
}

TEST(Hierarchy, voi_syntax) {
  const Voi box = parse_voi("box:0,0,0,1,2,3");
  EXPECT_TRUE(box.contains({0.5, 1.5, 2.5}));
  EXPECT_FALSE(box.contains({0.5, 2.5, 2.5}));
  const Voi ball = parse_voi("sphere:1,1,1,0.5");
  EXPECT_TRUE(ball.contains({1.2, 1.2, 1.2}));
  EXPECT_FALSE(ball.contains({1.5, 1.5, 1.5}));
  for (const char* bad : {"box:0,0,0,1,1", "cube:0,0,0,1,1,1", "sphere:0,0,0,-1", "box:0,0,0,1,x,1", "sphere"})
    EXPECT_THROW(parse_voi(bad), InputError) << bad;
}

TEST(Hierarchy, tth_file_round_trips_and_bad_files_name_the_offset) {
  const Hierarchy& h = cube_sphere().hierarchy;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "topotet_tth_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "h.tth").string();
  write_hierarchy(path, h);
  const Hierarchy back = read_hierarchy(path);
  EXPECT_EQ(back.original, h.original);
  EXPECT_EQ(back.u, h.u);
  EXPECT_EQ(back.v, h.v);
  EXPECT_EQ(back.u_before, h.u_before);
  EXPECT_EQ(back.fields_before, h.fields_before);
  EXPECT_EQ(back.cost, h.cost);
  EXPECT_EQ(back.error, h.error);
  EXPECT_EQ(back.parents, h.parents);
  EXPECT_EQ(back.parent_offsets, h.parent_offsets);
  EXPECT_EQ(back.error_bound.size(), h.error_bound.size());

  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  auto expect_error = [&](const std::string& content, const std::string& needle) {
    const std::string bad = (dir / "bad.tth").string();
    std::ofstream(bad, std::ios::binary) << content;
    try {
      read_hierarchy(bad);
      ADD_FAILURE() << "no error for " << needle;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("bad.tth"), std::string::npos) << what;
      EXPECT_NE(what.find(needle), std::string::npos) << what;
    }
  };
  expect_error(bytes.substr(0, bytes.size() / 2), "truncated");
  expect_error(bytes.substr(0, 30), "byte ");
  expect_error("NOTATTH!" + bytes.substr(8), "magic");
  std::string version = bytes;
  version[8] = 9;
  expect_error(version, "version 9");
  expect_error(bytes + "x", "after the end marker");
  // A NaN coordinate (the first vertex's x, after the magic, version, flags and vertex count) is
  // refused as every mesh reader refuses it, naming the vertex.
  std::string nan_position = bytes;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  nan_position.replace(24, sizeof nan, reinterpret_cast<const char*>(&nan), sizeof nan);
  expect_error(nan_position, "vertex 1: non-finite");
  // An offset past the parents followed by a smaller one: refused before any parent is read.
  Hierarchy jumbled = h;
  ASSERT_GE(jumbled.parent_offsets.size(), 3u);
  jumbled.parent_offsets[1] = static_cast<std::uint32_t>(jumbled.parents.size() + 5);
  try {
    validate_hierarchy(jumbled, "jumbled");
    ADD_FAILURE() << "no error for decreasing parent offsets";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("parent offsets decrease"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace topotet
