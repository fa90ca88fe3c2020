// Cell data through simplification (topotet/cell_fields.h): the overlap volume of two tets, then
// the remap's documented properties on a generated mesh simplified to a fifth of its vertices.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "cell_data/tet_overlap.h"
#include "topotet/cell_fields.h"
#include "topotet/error.h"
#include "topotet/generate.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"
#include "topotet/threads.h"

namespace topotet {
namespace {

using cell_data::Tet;
using cell_data::tet_overlap_volume;
using cell_data::tet_volume;

double volume(const Tet& t) { return tet_volume(t[0], t[1], t[2], t[3]); }

// The 6 tets of the unit cube around its diagonal (0,0,0)-(1,1,1): they tile it.
std::vector<std::array<glm::dvec3, 4>> kuhn_cube() {
  const glm::dvec3 o(0), d(1);
  const glm::dvec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  std::vector<std::array<glm::dvec3, 4>> tets;
  for (const auto& p : perms) tets.push_back({o, e[p[0]], e[p[0]] + e[p[1]], d});
  return tets;
}

void copy(const std::array<glm::dvec3, 4>& from, Tet& to) {
  for (int k = 0; k < 4; ++k) to[k] = from[static_cast<std::size_t>(k)];
}

TEST(TetOverlap, tet_with_itself_is_its_volume) {
  const Tet a = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
  EXPECT_NEAR(tet_overlap_volume(a, a), 1.0, 1e-14);
  const Tet flipped = {a[1], a[0], a[2], a[3]};  // orientation does not matter
  EXPECT_NEAR(tet_overlap_volume(a, flipped), 1.0, 1e-14);
}

TEST(TetOverlap, disjoint_tets_overlap_zero) {
  const Tet a = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const Tet b = {{2, 0, 0}, {3, 0, 0}, {2, 1, 0}, {2, 0, 1}};
  EXPECT_EQ(tet_overlap_volume(a, b), 0.0);
  // Boxes that meet, tets that do not (b across a's slanted face).
  const Tet c = {{1, 1, 1}, {0.4, 1, 1}, {1, 0.4, 1}, {1, 1, 0.4}};
  EXPECT_EQ(tet_overlap_volume(a, c), 0.0);
}

TEST(TetOverlap, the_halves_of_a_cube_split_a_tet_inside_it) {
  // Cut by the plane x = y, the cube's six tets fall into two halves of three; any tet in the
  // cube is the sum of its overlaps with the six.
  const auto cube = kuhn_cube();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    Tet a;
    for (auto& p : a) p = {u(rng), u(rng), u(rng)};
    double sum = 0, half = 0;
    for (std::size_t k = 0; k < cube.size(); ++k) {
      Tet b;
      copy(cube[k], b);
      const double v = tet_overlap_volume(a, b);
      sum += v;
      if (cube[k][1].x == 1) half += v;  // the half x >= y: the tets whose first edge runs along x
    }
    ASSERT_NEAR(sum, volume(a), 1e-14) << "trial " << trial;
    EXPECT_LE(half, volume(a) + 1e-15);
  }
}

TEST(TetOverlap, affine_maps_scale_the_overlap_by_the_determinant) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto cube = kuhn_cube();
  for (int trial = 0; trial < 100; ++trial) {
    glm::dmat3 m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[i][j] = (i == j ? 1.5 : 0.0) + 0.5 * u(rng);
    const glm::dvec3 shift(u(rng), u(rng), u(rng));
    const double det = std::abs(glm::determinant(m));
    Tet a, ma;
    for (int k = 0; k < 4; ++k) {
      a[k] = glm::dvec3(0.5 + 0.6 * u(rng), 0.5 + 0.6 * u(rng), 0.5 + 0.6 * u(rng));
      ma[k] = m * a[k] + shift;
    }
    double sum = 0, direct = 0;
    for (const auto& c : cube) {
      Tet b, mb;
      copy(c, b);
      for (int k = 0; k < 4; ++k) mb[k] = m * b[k] + shift;
      sum += tet_overlap_volume(ma, mb);
      direct += tet_overlap_volume(a, b);
    }
    ASSERT_NEAR(sum, det * direct, 1e-12 * std::max(1.0, det)) << "trial " << trial;
  }
}

// ---- the remap on a simplified mesh ----

struct Simplified {
  MeshData input, output;
};

double volume_of(const MeshData& m, std::size_t t) {
  Tet x;
  for (int k = 0; k < 4; ++k) {
    const auto& p = m.positions[m.tets[t][static_cast<std::size_t>(k)]];
    x[k] = {p[0], p[1], p[2]};
  }
  return volume(x);
}

glm::dvec3 centroid_of(const MeshData& m, std::size_t t) {
  glm::dvec3 c(0);
  for (VertId v : m.tets[t]) c += glm::dvec3(m.positions[v][0], m.positions[v][1], m.positions[v][2]);
  return c * 0.25;
}

// cube-sphere (two materials, a moved interface) with four arrays: a constant, a linear function
// of the centroid, the material as a label, and a mass (density x volume).
const Simplified& simplified_cube_sphere() {
  static const Simplified s = [] {
    Simplified r;
    GenerateOptions g;
    g.target_tets = 20000;
    r.input = generate_mesh(g);
    const std::size_t n = r.input.tets.size();
    CellField constant{"constant", 1, CellFieldKind::kIntensive, std::vector<double>(n, 3.7)};
    CellField linear{"linear", 1, CellFieldKind::kIntensive, {}};
    CellField region{"region", 1, CellFieldKind::kCategorical, {}};
    CellField mass{"mass", 1, CellFieldKind::kIntensive, {}};  // extensive by option
    for (std::size_t t = 0; t < n; ++t) {
      const glm::dvec3 c = centroid_of(r.input, t);
      linear.values.push_back(1.0 + 2.0 * c.x - 3.0 * c.y + 0.5 * c.z);
      region.values.push_back(r.input.tet_material[t]);
      mass.values.push_back((1.0 + c.x * c.x) * volume_of(r.input, t));
    }
    r.input.cell_fields = {constant, linear, region, mass};
    TetMesh mesh = build_tet_mesh(r.input);
    SimplifyOptions options;
    options.target_vertex_ratio = 0.2;
    const Report report = simplify(mesh, options);
    EXPECT_NE(report.status, Status::kInvalidInput) << report.message;
    r.output = mesh.to_mesh_data();
    return r;
  }();
  return s;
}

CellRemapOptions mass_is_extensive() {
  CellRemapOptions o;
  o.extensive = {"mass"};
  return o;
}

TEST(RemapCellFields, every_array_reaches_the_output_with_its_kind) {
  Simplified s = simplified_cube_sphere();
  ASSERT_LT(s.output.tets.size(), s.input.tets.size() / 2);
  const CellRemapReport report = remap_cell_fields(s.input, s.output, mass_is_extensive());
  ASSERT_EQ(s.output.cell_fields.size(), 4u);
  const char* names[4] = {"constant", "linear", "region", "mass"};
  const CellFieldKind kinds[4] = {CellFieldKind::kIntensive, CellFieldKind::kIntensive, CellFieldKind::kCategorical,
                                  CellFieldKind::kExtensive};
  for (std::size_t f = 0; f < 4; ++f) {
    EXPECT_EQ(s.output.cell_fields[f].name, names[f]);
    EXPECT_EQ(s.output.cell_fields[f].kind, kinds[f]);
    EXPECT_EQ(s.output.cell_fields[f].values.size(), s.output.tets.size());
  }
  EXPECT_GT(report.overlap_pairs, s.output.tets.size());
  EXPECT_GT(report.covered_volume_fraction, 0.99);
  EXPECT_LE(report.covered_volume_fraction, 1.0 + 1e-12);
}

TEST(RemapCellFields, a_constant_stays_constant) {
  Simplified s = simplified_cube_sphere();
  remap_cell_fields(s.input, s.output);
  for (double v : s.output.cell_fields[0].values) ASSERT_NEAR(v, 3.7, 1e-12);
}

TEST(RemapCellFields, a_linear_fields_integral_is_kept_within_the_moved_volume) {
  // Over the covered part the average conserves the integral exactly: the output's integral
  // differs from the input's only by the value on the volume that moved (new tets outside the old
  // ones of their material, and old volume no new tet of the material covers). Bound: max|f|
  // times that volume, |V_out - C| + |V_in - C|, C the covered volume.
  Simplified s = simplified_cube_sphere();
  const CellRemapReport report = remap_cell_fields(s.input, s.output);
  double in = 0, out = 0, v_in = 0, v_out = 0, max_abs = 0;
  for (std::size_t t = 0; t < s.input.tets.size(); ++t) {
    in += volume_of(s.input, t) * s.input.cell_fields[1].values[t];
    v_in += volume_of(s.input, t);
    max_abs = std::max(max_abs, std::abs(s.input.cell_fields[1].values[t]));
  }
  for (std::size_t t = 0; t < s.output.tets.size(); ++t) {
    out += volume_of(s.output, t) * s.output.cell_fields[1].values[t];
    v_out += volume_of(s.output, t);
  }
  const double covered = report.covered_volume_fraction * v_in;
  const double bound = max_abs * (std::abs(v_out - covered) + std::abs(v_in - covered)) + 1e-12 * std::abs(in);
  EXPECT_LE(std::abs(out - in), bound) << "integral in " << in << " out " << out;
  EXPECT_LE(std::abs(out - in), 1e-2 * std::abs(in));  // and it is small: the surfaces move little
}

TEST(RemapCellFields, a_label_equal_to_the_material_is_the_output_material) {
  Simplified s = simplified_cube_sphere();
  remap_cell_fields(s.input, s.output);
  for (std::size_t t = 0; t < s.output.tets.size(); ++t)
    ASSERT_EQ(s.output.cell_fields[2].values[t], s.output.tet_material[t]) << "tet " << t;
}

TEST(RemapCellFields, extensive_sums_are_conserved) {
  Simplified s = simplified_cube_sphere();
  remap_cell_fields(s.input, s.output, mass_is_extensive());
  double in = 0, out = 0;
  for (double v : s.input.cell_fields[3].values) in += v;
  for (double v : s.output.cell_fields[3].values) out += v;
  EXPECT_NEAR(out, in, 1e-9 * std::abs(in));
}

TEST(RemapCellFields, output_is_identical_for_one_and_two_threads) {
  const Simplified& s = simplified_cube_sphere();
  MeshData one = s.output, two = s.output;
  run_with_thread_limit(1, [&] { remap_cell_fields(s.input, one, mass_is_extensive()); });
  run_with_thread_limit(2, [&] { remap_cell_fields(s.input, two, mass_is_extensive()); });
  EXPECT_TRUE(one.cell_fields == two.cell_fields);
}

TEST(RemapCellFields, the_same_mesh_gives_the_same_values) {
  // Every tet overlaps itself only (its neighbours share faces, no volume).
  MeshData input = simplified_cube_sphere().input, same = input;
  remap_cell_fields(input, same, mass_is_extensive());
  for (std::size_t f = 0; f < input.cell_fields.size(); ++f)
    for (std::size_t t = 0; t < input.tets.size(); ++t)
      ASSERT_NEAR(same.cell_fields[f].values[t], input.cell_fields[f].values[t], 1e-9 * (1 + std::abs(input.cell_fields[f].values[t])));
}

TEST(RemapCellFields, tets_without_overlap_take_the_nearest_ones) {
  // Input: tet T0 at the origin (value 1, mass 10) and T1 at x = 10 (value 2, mass 5). Output: T0
  // again, a tet at x = 7 that overlaps nothing, and one of a material the input lacks.
  MeshData input;
  input.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {10, 0, 0}, {11, 0, 0}, {10, 1, 0}, {10, 0, 1}};
  input.tets = {{0, 1, 2, 3}, {4, 5, 6, 7}};
  input.tet_material = {1, 1};
  input.cell_fields = {{"value", 1, CellFieldKind::kIntensive, {1, 2}}, {"mass", 1, CellFieldKind::kExtensive, {10, 5}}};
  MeshData output;
  output.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {7, 0, 0}, {8, 0, 0}, {7, 1, 0}, {7, 0, 1},
                      {-3, 0, 0}, {-2, 0, 0}, {-3, 1, 0}, {-3, 0, 1}};
  output.tets = {{0, 1, 2, 3}, {4, 5, 6, 7}, {8, 9, 10, 11}};
  output.tet_material = {1, 1, 9};
  const CellRemapReport report = remap_cell_fields(input, output);
  EXPECT_EQ(report.nearest_new_tets, 2u);
  EXPECT_EQ(report.nearest_original_tets, 1u);
  EXPECT_EQ(output.cell_fields[0].values, (std::vector<double>{1, 2, 1}));  // T0 itself; T1 nearest; any material: T0
  EXPECT_EQ(output.cell_fields[1].values, (std::vector<double>{10, 5, 0}));  // T1's mass to its nearest output tet
}

TEST(RemapCellFields, bad_arrays_and_unknown_names_are_errors) {
  Simplified s = simplified_cube_sphere();
  CellRemapOptions unknown;
  unknown.extensive = {"nope"};
  EXPECT_THROW(remap_cell_fields(s.input, s.output, unknown), InputError);
  s.input.cell_fields[0].values.pop_back();
  try {
    remap_cell_fields(s.input, s.output);
    FAIL() << "a short array was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("constant"), std::string::npos) << e.what();
  }
}

TEST(RemapCellFields, no_cell_fields_costs_nothing) {
  Simplified s = simplified_cube_sphere();
  s.input.cell_fields.clear();
  const CellRemapReport report = remap_cell_fields(s.input, s.output);
  EXPECT_TRUE(s.output.cell_fields.empty());
  EXPECT_EQ(report.overlap_pairs, 0u);
}

}  // namespace
}  // namespace topotet
