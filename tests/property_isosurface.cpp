// Isosurfaces as embedded structures (topotet/isosurface.h, issue #24).
//
// Property (random scalar fields on small jittered grids, real-valued and integer-valued so that
// levels fall exactly on vertices, edges and faces, one to three levels): after embedding no tet
// has vertices strictly on both sides of a level, no tet is inverted or flat, every vertex of a
// level's triangles has the level's value exactly, and the level's triangles have the Betti
// numbers of a marching-tets extraction of the field on the input mesh (written here,
// independently of the engine). After simplification to 30% the independent checker finds every
// complex unchanged (the isosurfaces among them) and every isosurface vertex still has exactly
// the level; the output is the same for 1 and 2 threads.
// Unit: crossing a material interface and a listed surface (both survive), a listed segment is
// split, a crossing near a vertex snaps, the option parser.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "mesh/mesh_model.h"
#include "mesh/orient.h"
#include "test_meshes.h"
#include "topotet/error.h"
#include "topotet/isosurface.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"
#include "topotet/threads.h"

namespace topotet {
namespace {

using testing::Grid;
using testing::make_grid;
using testing::splitmix64;

double field_at(const MeshData& d, const std::string& name, int component, VertId v) {
  for (const VertexField& f : d.fields)
    if (f.name == name) return f.values[static_cast<std::size_t>(v) * f.components + component];
  ADD_FAILURE() << "no field " << name;
  return 0.0;
}

// A field of random values in [0, 1) (integer_levels > 0: random integers in [0, integer_levels)).
void add_random_field(MeshData& d, const std::string& name, std::uint64_t seed, int integer_levels) {
  VertexField f{name, 1, {}};
  for (std::size_t v = 0; v < d.positions.size(); ++v) {
    const double r = static_cast<double>(splitmix64(seed * 7919 + v) >> 11) * 0x1.0p-53;
    f.values.push_back(integer_levels > 0 ? std::floor(r * integer_levels) : r);
  }
  d.fields.push_back(f);
}

// Marching tets on the input mesh, written apart from the engine: the boundary of {f < c}. Points
// are the vertices on the level (their own ids) and one per crossed edge (ids from nv up, by a
// map); a quad is cut along either diagonal (the topology does not care which).
MeshData marching_tets(const MeshData& in, const std::vector<double>& f, double c) {
  MeshData out;
  out.positions = in.positions;
  std::map<std::pair<VertId, VertId>, VertId> crossing;
  auto point = [&](VertId a, VertId b) {
    const auto key = std::minmax(a, b);
    auto [it, inserted] = crossing.try_emplace({key.first, key.second}, static_cast<VertId>(out.positions.size()));
    if (inserted) {
      const double t = (c - f[a]) / (f[b] - f[a]);
      std::array<double, 3> p{};
      for (int k = 0; k < 3; ++k) p[k] = in.positions[a][k] + t * (in.positions[b][k] - in.positions[a][k]);
      out.positions.push_back(p);
    }
    return it->second;
  };
  std::map<std::array<VertId, 3>, int> level_faces;  // face in the level -> tets below it
  for (const auto& tet : in.tets) {
    std::vector<VertId> below, above, on;
    for (VertId v : tet) (f[v] < c ? below : f[v] > c ? above : on).push_back(v);
    if (below.empty() || above.empty()) {
      if (on.size() == 3) {
        std::array<VertId, 3> key = {on[0], on[1], on[2]};
        std::sort(key.begin(), key.end());
        level_faces[key] += below.empty() ? 0 : 1;
      }
      continue;
    }
    std::vector<VertId> poly = on;
    for (VertId a : below)
      for (VertId b : above) poly.push_back(point(a, b));
    if (poly.size() == 3) {
      out.triangles.push_back({{poly[0], poly[1], poly[2]}, 1});
    } else {  // 2-2: crossings (b0,a0) (b0,a1) (b1,a0) (b1,a1); in cyclic order 0, 1, 3, 2
      out.triangles.push_back({{poly[0], poly[1], poly[3]}, 1});
      out.triangles.push_back({{poly[0], poly[3], poly[2]}, 1});
    }
  }
  for (const auto& [face, below] : level_faces)
    if (below == 1) out.triangles.push_back({face, 1});
  return out;
}

ComplexTopology surface_topology(const MeshData& d, std::int32_t ref) {
  const TopologyReport r = compute_topology(d);
  const auto it = r.surfaces.find(ref);
  return it == r.surfaces.end() ? ComplexTopology{} : it->second;
}

// Every vertex of every level's triangles has exactly the level.
void expect_levels_exact(const MeshData& d, const std::vector<IsoLevel>& levels) {
  for (const IsoLevel& l : levels)
    for (const Triangle& t : d.triangles) {
      if (t.ref != l.ref) continue;
      for (VertId v : t.v) ASSERT_EQ(field_at(d, l.field, l.component, v), l.value) << "vertex " << v << " of " << l.ref;
    }
}

void expect_no_bad_tets(const MeshData& d) {
  for (std::size_t t = 0; t < d.tets.size(); ++t) {
    const auto p = [&](int i) { return to_glm(d.positions[d.tets[t][i]]); };
    ASSERT_GT(orient3d_sign(p(0), p(1), p(2), p(3)), 0) << "tet " << t;
  }
}

void expect_no_tet_crosses(const MeshData& d, const IsoLevel& l) {
  for (const auto& tet : d.tets) {
    bool below = false, above = false;
    for (VertId v : tet) {
      const double x = field_at(d, l.field, l.component, v);
      below = below || x < l.value;
      above = above || x > l.value;
    }
    ASSERT_FALSE(below && above);
  }
}

MeshData simplify_to(const MeshData& in, const std::vector<IsoLevel>& levels, double ratio, int threads,
                     Engine engine = Engine::kParallel) {
  TetMesh mesh = build_tet_mesh(in);
  SimplifyOptions options;
  options.target_vertex_ratio = ratio;
  options.isosurfaces = levels;
  options.num_threads = threads;
  options.engine = engine;
  const Report r = simplify(mesh, options);
  EXPECT_TRUE(r.status == Status::kOk || r.status == Status::kStoppedEarly) << r.message;
  return mesh.to_mesh_data();
}

class IsosurfaceRandom : public ::testing::TestWithParam<std::tuple<int, std::uint64_t>> {};

TEST_P(IsosurfaceRandom, EmbedsExactlyAndSimplificationKeepsTopologyAndValues) {
  const auto [integer_levels, seed] = GetParam();
  Grid g = make_grid(5, 5, 5, [](int, int, int) { return 1; }, 0.12, seed);
  add_random_field(g.data, "u", seed, integer_levels);
  add_random_field(g.data, "w", seed + 101, 0);
  const MeshData input = g.data;
  const std::size_t nv = input.positions.size();
  // Real fields: two levels of u (one exactly the value of a vertex) and one of w. Integer fields:
  // levels on the values themselves (vertices, edges, faces and whole tets on the level).
  std::vector<IsoLevel> levels;
  if (integer_levels > 0) {
    levels = {{"u", 0, 1.0}, {"u", 0, 2.0}, {"w", 0, 0.5}};
  } else {
    levels = {{"u", 0, 0.35}, {"u", 0, input.fields[0].values[nv / 2]}, {"w", 0, 0.6}};
  }

  MeshData embedded = input;
  IsoEmbedOptions embed_options;
  embed_options.snap = 0.0;  // exact crossings: the extraction below sees the same field
  const IsoEmbedReport report = embed_isosurfaces(embedded, levels, embed_options);
  ASSERT_EQ(report.levels.size(), levels.size());
  expect_no_bad_tets(embedded);
  expect_levels_exact(embedded, report.levels);
  ASSERT_EQ(embedded.tet_material.size(), embedded.tets.size());
  for (const IsoLevel& l : report.levels) {
    expect_no_tet_crosses(embedded, l);
    // The extraction from the input field of the same component (the input's vertices keep their
    // values: no snap).
    std::vector<double> f(nv);
    for (std::size_t v = 0; v < nv; ++v) f[v] = field_at(input, l.field, l.component, static_cast<VertId>(v));
    const ComplexTopology expected = surface_topology(marching_tets(input, f, l.value), 1);
    const ComplexTopology got = surface_topology(embedded, l.ref);
    EXPECT_EQ(got.betti, expected.betti) << l.field << "=" << l.value;
    EXPECT_EQ(got.euler_characteristic, expected.euler_characteristic);
    EXPECT_GT(got.simplex_count[2], 0);
  }
  // The pieces fit together (neighbours split shared faces alike): otherwise the mesh would have
  // faces of one tet inside it, and its boundary would change.
  const TopologyReport input_topology = compute_topology(input), embedded_topology = compute_topology(embedded);
  EXPECT_EQ(embedded_topology.boundary.betti, input_topology.boundary.betti);
  EXPECT_EQ(embedded_topology.mesh.betti, input_topology.mesh.betti);
  EXPECT_EQ(embedded_topology.boundary.euler_characteristic, input_topology.boundary.euler_characteristic);
  EXPECT_EQ(embedded_topology.nonmanifold_face_count, 0u);
  // Every tet of the input is covered: the volume is unchanged.
  const auto volume = [](const MeshData& d) {
    double s = 0.0;
    for (const auto& t : d.tets)
      s += signed_volume6(to_glm(d.positions[t[0]]), to_glm(d.positions[t[1]]), to_glm(d.positions[t[2]]),
                          to_glm(d.positions[t[3]]));
    return s;
  };
  EXPECT_NEAR(volume(embedded), volume(input), 1e-9 * volume(input));
  // The new vertices' values of the first level (its vertices came first).
  for (std::size_t v = nv; v < nv + report.stats[0].vertices_added; ++v)
    ASSERT_EQ(field_at(embedded, "u", 0, static_cast<VertId>(v)), levels[0].value);

  // Deterministic for any thread count (the embedding runs in the caller's arena).
  MeshData embedded1 = input;
  run_with_thread_limit(1, [&] { embed_isosurfaces(embedded1, levels, embed_options); });
  EXPECT_TRUE(embedded1 == embedded);

  const TopologyReport before = compute_topology(embedded);
  const MeshData out = simplify_to(embedded, report.levels, 0.3, 2);
  std::string why;
  EXPECT_TRUE(same_topology(before, compute_topology(out), &why)) << why;
  expect_levels_exact(out, report.levels);
  EXPECT_LT(out.positions.size(), embedded.positions.size());
  if (seed == 1) {
    EXPECT_TRUE(simplify_to(embedded, report.levels, 0.3, 1) == out) << "1 vs 2 threads differ";
  }
}

INSTANTIATE_TEST_SUITE_P(Fields, IsosurfaceRandom,
                         ::testing::Combine(::testing::Values(0, 3), ::testing::Values(1u, 2u)));

TEST(Isosurface, SequentialEngineKeepsTheLevelsToo) {
  Grid g = make_grid(6, 6, 6, [](int, int, int) { return 1; }, 0.12, 9);
  add_random_field(g.data, "u", 9, 0);
  const std::vector<IsoLevel> levels = {{"u", 0, 0.5}};
  const IsoEmbedReport report = embed_isosurfaces(g.data, levels);
  const TopologyReport before = compute_topology(g.data);
  const MeshData out = simplify_to(g.data, report.levels, 0.3, 2, Engine::kSequential);
  std::string why;
  EXPECT_TRUE(same_topology(before, compute_topology(out), &why)) << why;
  expect_levels_exact(out, report.levels);
}

// Cell arrays stay aligned with the tets through the embedding: each piece of a split tet takes
// its tet's value, and an extensive array's amount is shared out by volume (its sum is kept).
TEST(Isosurface, CellArraysFollowTheSplitTets) {
  Grid g = make_grid(5, 5, 5, [](int, int, int) { return 1; }, 0.12, 3);
  add_random_field(g.data, "u", 3, 0);
  const std::size_t nt = g.data.tets.size();
  CellField id{"id", 1, CellFieldKind::kCategorical, {}}, mass{"mass", 2, CellFieldKind::kExtensive, {}};
  for (std::size_t t = 0; t < nt; ++t) {
    id.values.push_back(static_cast<double>(t));
    mass.values.push_back(1.0 + static_cast<double>(t % 7));
    mass.values.push_back(-2.0);
  }
  g.data.cell_fields = {id, mass};
  const MeshData before = g.data;
  const IsoEmbedReport report = embed_isosurfaces(g.data, {{"u", 0, 0.5}});
  ASSERT_GT(report.stats[0].tets_added, 0u);
  const std::size_t n = g.data.tets.size();
  ASSERT_EQ(g.data.cell_fields[0].values.size(), n);
  ASSERT_EQ(g.data.cell_fields[1].values.size(), 2 * n);
  // Every piece lies inside the tet whose id it carries: its centroid has non-negative barycentric
  // coordinates there (up to rounding).
  const auto& P = g.data.positions;
  const auto& Q = before.positions;
  for (std::size_t t = 0; t < n; ++t) {
    const auto parent = before.tets[static_cast<std::size_t>(g.data.cell_fields[0].values[t])];
    std::array<double, 3> c{0, 0, 0};
    for (VertId x : g.data.tets[t])
      for (int k = 0; k < 3; ++k) c[k] += 0.25 * P[x][k];
    const auto vol = [](const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& d,
                        const std::array<double, 3>& e) {
      const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]},
                   w[3] = {e[0] - a[0], e[1] - a[1], e[2] - a[2]};
      return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
    };
    const double whole = vol(Q[parent[0]], Q[parent[1]], Q[parent[2]], Q[parent[3]]);
    for (int k = 0; k < 4; ++k) {
      auto corners = std::array<std::array<double, 3>, 4>{Q[parent[0]], Q[parent[1]], Q[parent[2]], Q[parent[3]]};
      corners[static_cast<std::size_t>(k)] = c;
      EXPECT_GE(vol(corners[0], corners[1], corners[2], corners[3]) / whole, -1e-9) << "tet " << t;
    }
  }
  double sum_before[2] = {0, 0}, sum_after[2] = {0, 0};
  for (std::size_t t = 0; t < nt; ++t)
    for (int j = 0; j < 2; ++j) sum_before[j] += before.cell_fields[1].values[2 * t + j];
  for (std::size_t t = 0; t < n; ++t)
    for (int j = 0; j < 2; ++j) sum_after[j] += g.data.cell_fields[1].values[2 * t + j];
  for (int j = 0; j < 2; ++j) EXPECT_NEAR(sum_after[j], sum_before[j], 1e-9 * std::fabs(sum_before[j]));
}

// A smooth field (distance to a point) whose level sphere crosses a material interface, a listed
// surface (the plane z = 3) and a listed polyline (the line x = y = 3): all survive embedding and
// simplification with their topology.
TEST(Isosurface, CrossesMaterialInterfaceListedSurfaceAndPolyline) {
  Grid g = make_grid(6, 6, 6, [](int i, int, int) { return i < 3 ? 1 : 2; }, 0.1, 4);
  testing::add_patch(g, 2, 3, [](int, int) { return true; }, 7);
  testing::add_polyline(g, testing::grid_line({3, 3, 0}, {3, 3, 6}), 5);
  VertexField f{"d", 1, {}};
  for (const auto& p : g.data.positions)
    f.values.push_back(std::sqrt((p[0] - 3.1) * (p[0] - 3.1) + (p[1] - 2.9) * (p[1] - 2.9) + (p[2] - 3.05) * (p[2] - 3.05)));
  g.data.fields.push_back(f);
  const std::size_t listed_before = g.data.triangles.size(), segments_before = g.data.segments.size();
  const IsoEmbedReport report = embed_isosurfaces(g.data, {{"d", 0, 2.0}});
  const IsoLevelStats& s = report.stats[0];
  EXPECT_GT(s.triangles_split, 0u);
  EXPECT_EQ(s.segments_split, 2u);  // the sphere meets the line twice
  EXPECT_EQ(g.data.segments.size(), segments_before + 2);
  EXPECT_GT(g.data.triangles.size(), listed_before + s.triangles);
  expect_no_bad_tets(g.data);
  const TopologyReport before = compute_topology(g.data);
  EXPECT_EQ(before.detached_triangle_count, 0u);
  EXPECT_EQ(before.detached_segment_count, 0u);
  const ComplexTopology sphere = before.surfaces.at(report.levels[0].ref);
  EXPECT_EQ(sphere.betti, (std::array<std::int64_t, 4>{1, 0, 1, 0}));
  EXPECT_EQ(before.surfaces.at(7).betti, (std::array<std::int64_t, 4>{1, 0, 0, 0}));
  EXPECT_EQ(before.interfaces.size(), 1u);
  const MeshData out = simplify_to(g.data, report.levels, 0.3, 2);
  const TopologyReport after = compute_topology(out);
  std::string why;
  EXPECT_TRUE(same_topology(before, after, &why)) << why;
  expect_levels_exact(out, report.levels);
  EXPECT_TRUE(std::binary_search(out.group_names.begin(), out.group_names.end(),
                                 GroupName{2, report.levels[0].ref, "iso:d=2"}));
}

// Every way a level can cut one tet (sides -, 0, + at its four vertices, with both - and +): the
// pieces are positively oriented, fill the tet, and their number and the cap's are those of the
// case (1-3: tet + prism = 4 tets; 2-2: two prisms = 6; one vertex on the level: tet + pyramid = 3;
// two on it: 2), and nothing crosses the level afterwards.
TEST(Isosurface, EveryCutPatternOfOneTet) {
  for (int pattern = 0; pattern < 81; ++pattern) {
    int side[4], below = 0, above = 0;
    for (int k = 0, p = pattern; k < 4; ++k, p /= 3) {
      side[k] = p % 3 - 1;
      below += side[k] < 0;
      above += side[k] > 0;
    }
    if (below == 0 || above == 0) continue;
    MeshData d;
    d.positions = {{0, 0, 0}, {1, 0.1, 0}, {0.2, 1, 0}, {0.3, 0.2, 1}};
    d.tets = {{0, 1, 2, 3}};
    d.tet_material = {1};
    VertexField f{"u", 1, {}};
    for (int k = 0; k < 4; ++k) f.values.push_back(side[k] * (1.0 + 0.3 * k));
    d.fields.push_back(f);
    const MeshData input = d;
    const IsoEmbedReport r = embed_isosurfaces(d, {{"u", 0, 0.0}});
    const int zeros = 4 - below - above;
    const std::size_t want_tets = zeros == 2 ? 2 : zeros == 1 ? 3 : below == 2 ? 6 : 4;
    const std::uint64_t want_caps = below == 2 && above == 2 ? 2 : 1;
    SCOPED_TRACE("pattern " + std::to_string(pattern));
    EXPECT_EQ(d.tets.size(), want_tets);
    EXPECT_EQ(r.stats[0].triangles, want_caps);
    EXPECT_EQ(r.stats[0].vertices_added, static_cast<std::uint64_t>(below * above));
    expect_no_bad_tets(d);
    expect_no_tet_crosses(d, r.levels[0]);
    double volume = 0.0;
    for (const auto& t : d.tets)
      volume += signed_volume6(to_glm(d.positions[t[0]]), to_glm(d.positions[t[1]]), to_glm(d.positions[t[2]]),
                               to_glm(d.positions[t[3]]));
    const auto& p = input.positions;
    EXPECT_NEAR(volume, signed_volume6(to_glm(p[0]), to_glm(p[1]), to_glm(p[2]), to_glm(p[3])), 1e-12);
    EXPECT_NO_THROW(build_tet_mesh(d));
  }
}

// A mesh with every tet negatively oriented (build_tet_mesh flips such input as a whole): the
// pieces keep their parent's orientation, and the level set is the same.
TEST(Isosurface, KeepsTheOrientationOfAMirroredMesh) {
  Grid g = make_grid(4, 4, 4, [](int, int, int) { return 1; }, 0.12, 5);
  add_random_field(g.data, "u", 5, 0);
  MeshData mirrored = g.data;
  for (auto& t : mirrored.tets) std::swap(t[0], t[1]);
  const IsoEmbedReport straight = embed_isosurfaces(g.data, {{"u", 0, 0.5}});
  const IsoEmbedReport mirror = embed_isosurfaces(mirrored, {{"u", 0, 0.5}});
  ASSERT_EQ(mirrored.tets.size(), g.data.tets.size());
  for (const auto& t : mirrored.tets) {
    const auto p = [&](int i) { return to_glm(mirrored.positions[t[i]]); };
    ASSERT_LT(orient3d_sign(p(0), p(1), p(2), p(3)), 0);
  }
  EXPECT_EQ(surface_topology(mirrored, mirror.levels[0].ref), surface_topology(g.data, straight.levels[0].ref));
  EXPECT_NO_THROW(build_tet_mesh(mirrored));
}

// The isosurfaces are not searched for sharp features (features/features.h): a faceted sphere of a
// distance field adds no feature edge, while the same triangles listed as an ordinary surface do.
TEST(Isosurface, IsNotSearchedForFeatures) {
  Grid g = make_grid(6, 6, 6, [](int, int, int) { return 1; }, 0.0);
  VertexField f{"d", 1, {}};
  for (const auto& p : g.data.positions)
    f.values.push_back(std::sqrt((p[0] - 3.1) * (p[0] - 3.1) + (p[1] - 2.9) * (p[1] - 2.9) + (p[2] - 3.05) * (p[2] - 3.05)));
  g.data.fields.push_back(f);
  const auto feature_edges = [](const MeshData& d, const std::vector<IsoLevel>& levels) {
    TetMesh mesh = build_tet_mesh(d);
    SimplifyOptions options;
    options.target_vertex_ratio = 1.0;
    options.feature_angle = 10.0;
    options.tolerance_rel = 1e-5;  // creases count at any height
    options.isosurfaces = levels;
    return simplify(mesh, options).feature_edges;
  };
  const std::uint64_t box = feature_edges(g.data, {});
  const IsoEmbedReport report = embed_isosurfaces(g.data, {{"d", 0, 2.2}});
  EXPECT_GT(feature_edges(g.data, {}), box);  // the sphere's facets, as a plain listed surface
  EXPECT_EQ(feature_edges(g.data, report.levels), box);
}

TEST(Isosurface, NearVertexCrossingSnapsToTheVertex) {
  Grid g = make_grid(2, 2, 2, [](int, int, int) { return 1; }, 0.0);
  VertexField f{"u", 1, std::vector<double>(g.data.positions.size(), 1.0)};
  const VertId centre = g.vid(1, 1, 1);
  f.values[centre] = 0.5 - 1e-9;  // every crossing is within 2e-9 of the centre (edge parameter)
  g.data.fields.push_back(f);
  MeshData exact = g.data;
  const IsoEmbedReport snapped = embed_isosurfaces(g.data, {{"u", 0, 0.5}});
  EXPECT_EQ(snapped.stats[0].vertices_snapped, 1u);
  EXPECT_EQ(field_at(g.data, "u", 0, centre), 0.5);
  EXPECT_EQ(snapped.stats[0].tets_split, 0u);  // the level now touches the centre vertex only...
  EXPECT_EQ(snapped.stats[0].triangles, 0u);   // ...and bounds nothing: {u < 0.5} is empty
  expect_no_bad_tets(g.data);
  // Without the snap the pieces at the centre are too thin for a certified orientation: a clear
  // error, never a flat tet in the output.
  IsoEmbedOptions no_snap;
  no_snap.snap = 0.0;
  EXPECT_THROW(embed_isosurfaces(exact, {{"u", 0, 0.5}}, no_snap), InputError);
}

TEST(Isosurface, RejectsUnknownFieldsAndParsesSpecs) {
  Grid g = make_grid(1, 1, 1, [](int, int, int) { return 1; }, 0.0);
  add_random_field(g.data, "u", 1, 0);
  EXPECT_THROW(embed_isosurfaces(g.data, {{"nope", 0, 0.5}}), InputError);
  EXPECT_THROW(embed_isosurfaces(g.data, {{"u", 1, 0.5}}), InputError);
  EXPECT_THROW(embed_isosurfaces(g.data, {{"u", 0, 0.5}, {"u", 0, 0.5}}), InputError);
  std::vector<IsoLevel> levels;
  EXPECT_EQ(parse_isosurface_spec("rho=0.5,0.25", levels), "");
  EXPECT_EQ(parse_isosurface_spec("v:2=-1e-3", levels), "");
  ASSERT_EQ(levels.size(), 3u);
  EXPECT_EQ(levels[1], (IsoLevel{"rho", 0, 0.25, 0}));
  EXPECT_EQ(levels[2], (IsoLevel{"v", 2, -1e-3, 0}));
  EXPECT_NE(parse_isosurface_spec("rho", levels), "");
  EXPECT_NE(parse_isosurface_spec("rho=0.5,", levels), "");
  EXPECT_NE(parse_isosurface_spec("rho:x=1", levels), "");
  // simplify() refuses levels whose vertices do not have the level's value.
  IsoLevel level{"u", 0, 0.5, 0};
  const IsoEmbedReport report = embed_isosurfaces(g.data, {level});
  TetMesh mesh = build_tet_mesh(g.data);
  SimplifyOptions options;
  options.isosurfaces = report.levels;
  options.isosurfaces[0].value = 0.25;
  if (report.stats[0].triangles > 0) {
    EXPECT_EQ(simplify(mesh, options).status, Status::kInvalidInput);
  }
}

}  // namespace
}  // namespace topotet
