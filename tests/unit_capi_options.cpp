// The C API's options are the library's (issue #27, item 5): topotet_options_init gives exactly
// topotet::SimplifyOptions{}'s defaults, field by field, and every SimplifyOptions field is either
// in topotet_options or listed here as deliberately not (with why). A field added to
// SimplifyOptions fails FieldCountIsKnown until this test, the C struct and the Fortran type are
// updated (tests/fortran_cell_fields_test.f90 checks the Fortran type against the C one).
#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstring>
#include <vector>

#include "topotet/simplify.h"
#include "topotet/topotet_c.h"

namespace {

// Aggregate field counting: the largest n for which T{any x n} compiles (C++20 aggregates).
struct Any {
  template <class T>
  operator T() const;  // never called: only in unevaluated contexts
};
template <class T, class... A>
constexpr std::size_t field_count() {
  if constexpr (requires { T{A{}..., Any{}}; })
    return field_count<T, A..., Any>();
  else
    return sizeof...(A);
}

TEST(CapiOptions, DefaultsAreTheLibrarys) {
  const topotet::SimplifyOptions d;
  topotet_options c;
  std::memset(&c, 0xAB, sizeof c);  // every field must be written
  topotet_options_init(&c);
  EXPECT_EQ(c.target_vertex_ratio, d.target_vertex_ratio);
  EXPECT_EQ(c.target_vertices, static_cast<std::int64_t>(d.target_vertices));
  EXPECT_EQ(c.max_cost, d.max_cost);
  EXPECT_EQ(c.min_quality, d.min_quality);
  EXPECT_EQ(c.min_dihedral, d.min_dihedral);
  EXPECT_EQ(c.boundary_weight, d.boundary_weight);
  EXPECT_EQ(c.polyline_weight, d.polyline_weight);
  EXPECT_EQ(c.tolerance, d.tolerance);
  EXPECT_EQ(c.tolerance_rel, d.tolerance_rel);
  EXPECT_EQ(c.engine, static_cast<int>(d.engine));
  EXPECT_EQ(c.num_threads, d.num_threads);
  EXPECT_EQ(c.round_fraction, d.round_fraction);
  EXPECT_EQ(c.feature_angle, d.feature_angle);
  EXPECT_EQ(c.max_field_error, d.max_field_error);
  EXPECT_EQ(c.field_bound_mode, static_cast<int>(d.field_bound_mode));
  EXPECT_EQ(c.max_field_error_rel, d.max_field_error_rel);
  EXPECT_EQ(c.field_weight_count, static_cast<int>(d.field_weights.size()));
  EXPECT_EQ(c.field_weight_names, nullptr);
  EXPECT_EQ(c.field_weights, nullptr);
  EXPECT_EQ(c.optimize, static_cast<int>(d.optimize));
  EXPECT_EQ(c.track_field_bounds != 0, d.track_field_bounds);
  EXPECT_EQ(c.progress == nullptr, !d.on_progress);
  EXPECT_EQ(c.progress_user_data, nullptr);
  EXPECT_EQ(c.size_weight, d.size_weight);
  EXPECT_EQ(c.relax_tolerance != 0, d.relax_tolerance);
  EXPECT_EQ(c.relax_quality != 0, d.relax_quality);
  EXPECT_EQ(c.relax_features != 0, d.relax_features);
  // The enums' values are the library's.
  EXPECT_EQ(static_cast<int>(topotet::Engine::kSequential), 1);
  EXPECT_EQ(static_cast<int>(topotet::Optimize::kFull), 2);
  EXPECT_EQ(static_cast<int>(topotet::CellFieldKind::kCategorical), TOPOTET_CELL_CATEGORICAL);
  EXPECT_EQ(static_cast<int>(topotet::CellFieldKind::kExtensive), TOPOTET_CELL_EXTENSIVE);
}

// SimplifyOptions' 29 fields: 24 reach C, 22 as options of their own and three as pairs or
// triples (field_weights: field_weight_count, _names, _weights; on_progress: progress,
// progress_user_data), isosurfaces through topotet_mesh_embed_isosurfaces (the handle remembers
// them); 5 are the C++ engine's own:
//   round_log    - per-round diagnostics for bench_simplify and `topotet simplify -vv`
//   cost_units   - the shared cost units of runs in parts (topotet::mpi, out of core)
//   quadrics_in, quadrics_out - the quadrics carried between the levels of an out-of-core run
//   field_samples - the field error bounds' samples carried likewise (C reaches them through
//                   topotet_simplify_out_of_core)
TEST(CapiOptions, FieldCountIsKnown) {
  constexpr std::size_t in_c = 25;        // every other field
  constexpr std::size_t engine_only = 5;  // round_log, cost_units, quadrics_in, quadrics_out, field_samples
  EXPECT_EQ(field_count<topotet::SimplifyOptions>(), in_c + engine_only)
      << "SimplifyOptions changed: add the field to topotet_options (capi/include/topotet/topotet_c.h, at the end), "
         "topotet_options_init, topotet_simplify, the Fortran type (fortran/topotet.f90) and this test";
}

// The options added for parity with the CLI reach the library: track_field_bounds (`--field-bounds`)
// keeps the bounds and reports them; progress (`--progress`) is called and may cancel.
TEST(CapiOptions, FieldBoundsAndProgressReachTheLibrary) {
  constexpr int n = 4, nv = (n + 1) * (n + 1) * (n + 1);
  std::vector<double> xyz, f;
  std::vector<std::int32_t> tets;
  for (int v = 0; v < nv; ++v) {
    const double x = v % (n + 1), y = v / (n + 1) % (n + 1), z = v / ((n + 1) * (n + 1));
    xyz.insert(xyz.end(), {x, y, z});
    f.push_back(x * x + y - z);
  }
  const auto vid = [](std::array<int, 3> c) { return c[0] + (n + 1) * (c[1] + (n + 1) * c[2]); };
  constexpr int order[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {1, 0, 2}, {2, 1, 0}};
  for (int cube = 0; cube < n * n * n; ++cube)
    for (int p = 0; p < 6; ++p) {
      std::array<int, 3> c = {cube % n, cube / n % n, cube / (n * n)};
      std::array<std::int32_t, 4> t{vid(c)};
      for (int s = 0; s < 3; ++s) {
        ++c[order[p][s]];
        t[s + 1] = vid(c);
      }
      if (p >= 3) std::swap(t[2], t[3]);
      tets.insert(tets.end(), t.begin(), t.end());
    }
  const topotet_field_view field = {"f", 1, {f.data(), TOPOTET_FLOAT64, 0}};
  topotet_mesh_arrays in;
  topotet_mesh_arrays_init(&in);
  in.vertex_count = nv;
  in.positions = {xyz.data(), TOPOTET_FLOAT64, 0};
  in.tet_count = static_cast<std::int64_t>(tets.size() / 4);
  in.tets = {tets.data(), TOPOTET_INT32, 0};
  in.field_count = 1;
  in.fields = &field;
  topotet_mesh* mesh = nullptr;
  ASSERT_EQ(topotet_mesh_build(&in, 1, &mesh), TOPOTET_OK);
  topotet_options options;
  topotet_options_init(&options);
  options.num_threads = 1;
  topotet_report report;
  ASSERT_LE(topotet_simplify(mesh, &options, &report), TOPOTET_STOPPED_EARLY);
  EXPECT_EQ(report.field_bounds, 0);
  EXPECT_EQ(topotet_mesh_field_bounds(mesh), nullptr);
  topotet_mesh_free(mesh);

  ASSERT_EQ(topotet_mesh_build(&in, 1, &mesh), TOPOTET_OK);
  options.track_field_bounds = 1;
  int calls = 0;
  options.progress = [](double done, void* user) {
    EXPECT_GE(done, 0.0);
    EXPECT_LE(done, 1.0);
    ++*static_cast<int*>(user);
    return 1;
  };
  options.progress_user_data = &calls;
  ASSERT_LE(topotet_simplify(mesh, &options, &report), TOPOTET_STOPPED_EARLY);
  EXPECT_GT(calls, 0);
  EXPECT_EQ(report.field_bounds, 1);
  const double* bounds = topotet_mesh_field_bounds(mesh);
  ASSERT_NE(bounds, nullptr);
  EXPECT_GT(bounds[0], 0.0);  // the collapses moved the quadratic field
  EXPECT_GT(report.field_bound_rel, 0.0);
  EXPECT_LE(report.field_bound_rel, 1.0);
  topotet_mesh_free(mesh);
}

}  // namespace
