// Field error bounds out of core (SimplifyOptions::max_field_error(_rel), track_field_bounds):
// every input vertex is a sample of one piece and travels with its tet through the levels
// (SimplifyOptions::field_samples), so the bound the report gives holds at every input vertex of
// the output, measured here by metrics/ (compare_fields, independent of the engine), across
// pieces, merges and frozen borders; the limit is met and binding; 1 and 2 threads write the same
// bytes; the memory budget counts the samples and refuses a limit too small for them by name.
// In core, the carried samples make two runs bound the error against the first run's input.
#include <gtest/gtest.h>

#include <cmath>

#include "io_test_files.h"
#include "outofcore/cut.h"
#include "outofcore/memory_budget.h"
#include "topotet/error.h"
#include "topotet/generate.h"
#include "topotet/io.h"
#include "topotet/metrics/field_error.h"
#include "topotet/out_of_core.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

// The generated cube-sphere's field, and a vector field that varies otherwise
// (so that the bounds are kept per component, not for one scalar).
MeshData input_with_two_fields(std::uint64_t tets) {
  GenerateOptions g;
  g.family = "cube-sphere";
  g.target_tets = tets;
  MeshData m = generate_mesh(g);
  VertexField wave{"wave", 3, {}};
  for (const auto& p : m.positions) {
    wave.values.push_back(std::sin(4.0 * p[0]) * std::cos(3.0 * p[1]));
    wave.values.push_back(p[2] * p[2] + 0.5 * p[0]);
    wave.values.push_back(-2.0 * p[1]);
  }
  m.fields.push_back(std::move(wave));
  return m;
}

struct Outcome {
  OutOfCoreReport report;
  MeshData output;
  std::string bytes;
};

Outcome run_out_of_core(const MeshData& input, const test::TempDir& folder, const SimplifyOptions& options,
                        std::uint32_t pieces) {
  const std::string in = folder.file("in.mesh"), out = folder.file("out.mesh");
  write_mesh(in, input);
  OutOfCoreOptions ooc;
  ooc.pieces = pieces;
  Outcome r;
  r.report = simplify_out_of_core(in, out, options, ooc);
  r.output = read_mesh(out);
  r.bytes = test::read_text(out);
  return r;
}

// The measured error at every input vertex, per component, is within the reported bound.
void expect_bounded(const MeshData& input, const MeshData& output, const Report& report) {
  const FieldError measured = compare_fields(input, output);
  ASSERT_TRUE(report.field_bounds);
  ASSERT_EQ(measured.components.size(), report.field_bound.size());
  for (std::size_t c = 0; c < measured.components.size(); ++c) {
    const DirectionalError& at_input = measured.components[c].original_to_simplified;
    EXPECT_EQ(at_input.samples, input.vertex_count());
    EXPECT_LE(at_input.max_abs, report.field_bound[c]) << measured.components[c].field << ":" << measured.components[c].component;
  }
  EXPECT_LE(measured.worst_max_rel_at_original(), report.field_bound_rel * (1 + 1e-12));
}

TEST(OutOfCoreFieldBounds, TheLimitHoldsAtEveryInputVertexThroughPiecesAndMerges) {
  const MeshData input = input_with_two_fields(12000);
  SimplifyOptions options;
  options.target_vertex_ratio = 0.1;
  options.max_field_error_rel = 0.01;
  test::TempDir a, b;
  options.num_threads = 2;
  const Outcome two = run_out_of_core(input, a, options, 8);
  options.num_threads = 1;
  const Outcome one = run_out_of_core(input, b, options, 8);
  EXPECT_EQ(one.bytes, two.bytes);
  EXPECT_EQ(two.report.pieces, 8u);
  EXPECT_EQ(two.report.levels.size(), 4u);
  expect_bounded(input, two.output, two.report.report);
  EXPECT_LE(two.report.report.field_bound_rel, 0.01);
  // Binding: the limit refused collapses and the error reached it (the levels add up their errors
  // against the input, not each against its own already simplified piece).
  EXPECT_GT(two.report.report.rejected_by(RejectReason::kFieldError), 0u);
  const double measured = compare_fields(input, two.output).worst_max_rel_at_original();
  EXPECT_GT(measured, 0.005);
  std::printf("8 pieces, limit 0.01: %zu vertices, bound %.5f, measured %.5f at the input's vertices\n",
              two.output.vertex_count(), two.report.report.field_bound_rel, measured);
}

TEST(OutOfCoreFieldBounds, TrackedWithoutALimitTheyStillBoundEveryInputVertex) {
  const MeshData input = input_with_two_fields(12000);
  SimplifyOptions options;
  options.target_vertex_ratio = 0.15;
  options.track_field_bounds = true;
  test::TempDir folder;
  const Outcome r = run_out_of_core(input, folder, options, 4);
  expect_bounded(input, r.output, r.report.report);
  EXPECT_GT(r.report.report.field_bound_rel, 0.0);
  EXPECT_EQ(r.report.report.rejected_by(RejectReason::kFieldError), 0u);
}

TEST(OutOfCoreFieldBounds, TheBudgetCountsTheSamplesAndNamesThemWhenTheLimitIsTooSmall) {
  ooc::InputCounts counts;
  counts.vertices = 3'000'000;
  counts.tets = 18'000'000;
  counts.vertex_stride = 3;
  ooc::MemoryBudget budget;
  budget.baseline = ooc::kBaselineStep;
  budget.limit = 256ull << 20;
  const std::uint64_t without = budget.piece_tets(counts);
  budget.field_samples = true;
  // 3M samples of 3 components: 76 bytes each (memory_budget.h), 228 MB: more than 256M leaves.
  try {
    budget.piece_tets(counts);
    FAIL() << "field samples of 2M vertices fit in 256M";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field error bounds"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("at least"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ooc::bytes_per_field_sample(counts), 28u + 24u + 24u);
  budget.limit = 1ull << 30;
  const std::uint64_t with = budget.piece_tets(counts);
  budget.field_samples = false;
  EXPECT_LT(with, budget.piece_tets(counts));
  EXPECT_GT(without, 0u);
  // Without fields there is nothing to sample: the flag costs nothing.
  counts.vertex_stride = 0;
  const std::uint64_t plain = budget.piece_tets(counts);
  budget.field_samples = true;
  EXPECT_EQ(budget.piece_tets(counts), plain);
}

// A memory limit (not a piece count) that leaves room for the samples and pieces of about 22,000
// tets: several pieces, the samples counted, the bound still holds at every input vertex.
TEST(OutOfCoreFieldBounds, UnderAMemoryLimitTheSamplesAreCountedAndTheBoundHolds) {
  const MeshData input = input_with_two_fields(70000);
  test::TempDir folder;
  const std::string in = folder.file("in.mesh"), out = folder.file("out.mesh");
  write_mesh(in, input);
  ooc::InputCounts counts;
  counts.vertices = input.vertex_count();
  counts.vertex_stride = 4;
  const double per_tet = static_cast<double>(ooc::bytes_per_piece_tet(counts) + 4 + 12 * 4);
  const double samples = static_cast<double>(counts.vertices * (ooc::bytes_per_field_sample(counts) + ooc::kLevelBytesPerVertex));
  OutOfCoreOptions ooc;
  ooc.memory_limit_bytes = static_cast<std::uint64_t>(
      (static_cast<double>(ooc::budget_baseline(ooc::resident_bytes())) + samples + 22000.0 * per_tet) / (1.0 - ooc::kHeadroom));
  SimplifyOptions options;
  options.target_vertex_ratio = 0.2;
  options.track_field_bounds = true;
  const OutOfCoreReport r = simplify_out_of_core(in, out, options, ooc);
  EXPECT_GE(r.pieces, 4u);
  EXPECT_LE(r.piece_tet_limit, 26000u);
  expect_bounded(input, read_mesh(out), r.report);
}

// In core, through the public options: a second run that carries the first run's samples bounds
// the error against the first run's input; one that does not bounds it against its own input only.
TEST(CarriedFieldBounds, TwoRunsBoundTheErrorAgainstTheFirstInput) {
  const MeshData input = input_with_two_fields(12000);
  TetMesh first_mesh = build_tet_mesh(input);
  SimplifyOptions first;
  first.target_vertex_ratio = 0.4;
  first.track_field_bounds = true;
  FieldBoundSamples samples;
  first.field_samples = &samples;
  const Report r1 = simplify(first_mesh, first);
  ASSERT_TRUE(r1.field_bounds);
  const MeshData middle = first_mesh.to_mesh_data();
  EXPECT_EQ(samples.size(), input.vertex_count());  // every vertex is used by a tet
  EXPECT_EQ(samples.bounds.size(), middle.tet_count() * 4);
  expect_bounded(input, middle, r1);

  TetMesh second_mesh = build_tet_mesh(middle);
  SimplifyOptions second = first;
  second.target_vertex_ratio = 0.3;
  const Report r2 = simplify(second_mesh, second);
  ASSERT_EQ(r2.status, Status::kOk) << r2.message;
  const MeshData last = second_mesh.to_mesh_data();
  expect_bounded(input, last, r2);
  EXPECT_EQ(samples.size(), input.vertex_count());
  EXPECT_GE(r2.field_bound_rel, r1.field_bound_rel * 0.5);

  // Samples that do not fit the mesh are refused, the mesh untouched.
  FieldBoundSamples wrong = samples;
  wrong.tet[0] = static_cast<std::uint32_t>(last.tet_count() + 5);
  TetMesh again = build_tet_mesh(last);
  SimplifyOptions third = first;
  third.field_samples = &wrong;
  const Report r3 = simplify(again, third);
  EXPECT_EQ(r3.status, Status::kInvalidInput);
  EXPECT_NE(r3.message.find("field_samples"), std::string::npos) << r3.message;
  wrong = samples;
  wrong.components = 1;
  EXPECT_EQ(simplify(again, third).status, Status::kInvalidInput);
}

}  // namespace
}  // namespace topotet
