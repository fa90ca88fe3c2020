// Out-of-core simplification (topotet/out_of_core.h): small meshes cut into many pieces (forced
// with OutOfCoreOptions::pieces, or by a tiny memory limit) come out with the topology of the
// input and of every substructure (surfaces, interfaces, polylines crossing many piece borders,
// and a surface and a polyline lying in a grid plane that piece borders follow), within the
// tolerance, identical for 1 and 2 threads; bad input and limits that cannot work are clear
// errors, and the scratch folder never outlives the run.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "io_test_files.h"
#include "out_of_core_test_meshes.h"
#include "outofcore/cut.h"
#include "outofcore/memory_budget.h"
#include "topotet/error.h"
#include "topotet/generate.h"
#include "topotet/io.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/surface_distance.h"
#include "topotet/metrics/topology.h"
#include "topotet/out_of_core.h"
#include "topotet/simplify.h"
#include "topotet/threads.h"

namespace topotet {
namespace {

namespace fs = std::filesystem;
using test::generated;
using test::plant_in_mid_plane;

struct Outcome {
  OutOfCoreReport report;
  MeshData output;
  std::string bytes;
};

Outcome run(const MeshData& input, const test::TempDir& folder, std::uint32_t pieces, double ratio, int threads,
        std::uint64_t limit = 0) {
  const std::string in = folder.file("in.mesh"), out = folder.file("out.mesh");
  write_mesh(in, input);
  SimplifyOptions options;
  options.target_vertex_ratio = ratio;
  options.num_threads = threads;
  OutOfCoreOptions ooc;
  ooc.pieces = pieces;
  ooc.memory_limit_bytes = limit;
  Outcome r;
  r.report = simplify_out_of_core(in, out, options, ooc);
  r.output = read_mesh(out);
  r.bytes = test::read_text(out);
  return r;
}

void expect_same_topology(const MeshData& input, const MeshData& output) {
  const auto before = compute_topology(input);
  const auto after = compute_topology(output);
  std::string differences;
  EXPECT_TRUE(same_topology(before, after, &differences)) << differences;
  EXPECT_EQ(after.inverted_tet_count, 0u);
  EXPECT_EQ(after.degenerate_tet_count, 0u);
}

class OutOfCore : public ::testing::TestWithParam<std::string> {};

TEST_P(OutOfCore, ManyPiecesKeepTheTopologyAndTheTolerance) {
  MeshData input = generated(GetParam(), 24000);
  plant_in_mid_plane(input);
  test::TempDir folder;
  const Outcome r = run(input, folder, 16, 0.2, 2);
  EXPECT_EQ(r.report.pieces, 16u);
  EXPECT_EQ(r.report.output_pieces, 1u);
  EXPECT_EQ(r.report.levels.size(), 5u);  // level 0 and four merge levels
  EXPECT_EQ(r.report.report.vertices_before, input.vertex_count());
  EXPECT_EQ(r.output.vertex_count(), r.report.report.vertices_after);
  // It gets as far as an in-core run (polycrystal: both stop early, its grain junctions pinned).
  TetMesh whole = build_tet_mesh(input);
  SimplifyOptions options;
  options.target_vertex_ratio = 0.2;
  options.relax_tolerance = options.relax_quality = options.relax_features = false;  // as out of core keeps them
  simplify(whole, options);
  EXPECT_LE(r.output.vertex_count(), std::max<std::size_t>(static_cast<std::size_t>(0.2 * input.vertex_count()) + 1,
                                                           static_cast<std::size_t>(1.1 * whole.to_mesh_data().vertex_count())));
  expect_same_topology(input, r.output);
  // Both directions of the distance between the surfaces, per label, within H (sampled: up to
  // its sampling error).
  const SurfaceDistance d = surface_distance(input, r.output);
  EXPECT_EQ(d.unmatched_labels, 0u);
  EXPECT_LE(d.hausdorff, r.report.report.tolerance * (1 + 1e-9) + d.sampling_error);
  EXPECT_GT(r.report.report.tolerance, 0.0);
  for (const std::string& e : folder.entries()) {
    EXPECT_EQ(e.find(".topotet-scratch"), std::string::npos) << e;
    EXPECT_EQ(e.find(".tmp-"), std::string::npos) << e;
  }
}

// The limits relax as in core (relax_limits.h) in the last level's run, which holds the whole mesh:
// a tolerance far below the surfaces' jitter stops a run held to it; relaxed, the run reaches its
// target, the report gives the H that holds (the levels' shares, the last one doubled), and the
// surfaces stay within it.
TEST(OutOfCoreRelax, TheLastLevelRelaxesTheToleranceAsInCore) {
  const MeshData input = generated("cube-sphere", 8000);
  test::TempDir folder;
  const std::string in = folder.file("in.mesh"), out = folder.file("out.mesh");
  write_mesh(in, input);
  const auto run_with = [&](bool relax, int threads = 2) {
    SimplifyOptions options;
    options.target_vertex_ratio = 0.05;
    options.tolerance_rel = 1e-4;
    options.feature_angle = 180.0;
    options.num_threads = threads;
    options.relax_tolerance = options.relax_quality = relax;
    OutOfCoreOptions ooc;
    ooc.pieces = 4;
    return simplify_out_of_core(in, out, options, ooc);
  };
  const std::uint64_t target = static_cast<std::uint64_t>(std::llround(0.05 * static_cast<double>(input.vertex_count())));
  const OutOfCoreReport held = run_with(false);
  EXPECT_EQ(held.report.status, Status::kStoppedEarly);
  EXPECT_GT(held.report.vertices_after, 2 * target);
  EXPECT_TRUE(held.report.relaxations.empty());

  const OutOfCoreReport relaxed = run_with(true);
  const Report& r = relaxed.report;
  ASSERT_EQ(r.status, Status::kOk) << r.message;
  EXPECT_EQ(r.vertices_after, target);
  ASSERT_FALSE(r.relaxations.empty());
  EXPECT_STREQ(r.relaxations.front().limit, "tolerance");
  EXPECT_EQ(r.relaxations.front().from, r.tolerance_asked);
  EXPECT_EQ(r.relaxations.back().to, r.tolerance);
  EXPECT_GT(r.tolerance, r.tolerance_asked);
  const MeshData output = read_mesh(out);
  expect_same_topology(input, output);
  SurfaceDistanceOptions distance_options;
  distance_options.sample_spacing_rel = 5e-4;
  const SurfaceDistance d = surface_distance(input, output, distance_options);
  EXPECT_LE(d.hausdorff, r.tolerance * (1 + 1e-9) + d.sampling_error);
  // The same bytes and relaxations on one thread.
  const std::string bytes = test::read_text(out);
  const OutOfCoreReport one_thread = run_with(true, 1);
  EXPECT_EQ(one_thread.report.relaxations.size(), r.relaxations.size());
  EXPECT_EQ(one_thread.report.tolerance, r.tolerance);
  EXPECT_EQ(test::read_text(out), bytes);
}

// The linked tori: two interlocked rings (b1 of each, and their linking) across many pieces.
TEST(OutOfCoreLinkedTori, InterlockedRingsAcrossManyPieces) {
  const MeshData input = generated("linked-tori", 40000);
  test::TempDir folder;
  const Outcome r = run(input, folder, 32, 0.2, 2);
  EXPECT_EQ(r.report.pieces, 32u);
  expect_same_topology(input, r.output);
}

INSTANTIATE_TEST_SUITE_P(Families, OutOfCore, ::testing::Values("cube-sphere", "slab", "polycrystal"),
                         [](const auto& p) {
                           std::string s = p.param;
                           for (char& c : s)
                             if (c == '-') c = '_';
                           return s;
                         });

TEST(OutOfCoreDeterminism, SameBytesForOneAndTwoThreadsAndForEveryRun) {
  const MeshData input = generated("cube-sphere", 20000);
  test::TempDir a, b, c;
  const Outcome one = run(input, a, 8, 0.15, 1);
  const Outcome two = run(input, b, 8, 0.15, 2);
  const Outcome again = run(input, c, 8, 0.15, 2);
  EXPECT_EQ(one.bytes, two.bytes);
  EXPECT_EQ(two.bytes, again.bytes);
}

TEST(OutOfCoreFields, FieldsAndCellFieldsTravelWithTheirVertices) {
  MeshData input = generated("cube-sphere", 12000);
  CellField cells{"cellsol0", 1, CellFieldKind::kIntensive, {}};
  for (std::size_t t = 0; t < input.tet_count(); ++t) cells.values.push_back(input.tet_material[t] * 10.0);
  input.cell_fields.push_back(cells);
  test::TempDir folder;
  const Outcome r = run(input, folder, 8, 0.3, 2);
  ASSERT_EQ(r.output.fields.size(), input.fields.size());
  ASSERT_EQ(r.output.cell_fields.size(), 1u);
  // Each vertex keeps its own field values through the pieces, the merges and the output: the
  // field error (measured at every vertex of both meshes, metrics/) is that of an in-core run to
  // the same count, within a factor (the levels restart the quadrics: docs/performance.md, "Out of
  // core"); values landing on the wrong vertices would multiply it.
  TetMesh whole = build_tet_mesh(input);
  SimplifyOptions options;
  options.target_vertices = r.output.vertex_count();
  simplify(whole, options);
  const double in_core = compare_fields(input, whole.to_mesh_data()).worst_rms_rel;
  const double out_of_core = compare_fields(input, r.output).worst_rms_rel;
  EXPECT_GT(in_core, 0.0);
  EXPECT_LE(out_of_core, 2.0 * in_core) << "in core " << in_core;
  // A value constant per material stays that constant.
  for (std::size_t t = 0; t < r.output.tet_count(); ++t)
    EXPECT_NEAR(r.output.cell_fields[0].values[t], r.output.tet_material[t] * 10.0, 1e-9);
}

TEST(OutOfCoreLimit, ATinyLimitCutsIntoPiecesAndOneTooSmallIsRefusedBeforeAnyWork) {
  const MeshData input = generated("cube-sphere", 60000);
  test::TempDir folder;
  const std::string in = folder.file("in.mesh"), out = folder.file("out.mesh");
  write_mesh(in, input);
  OutOfCoreOptions ooc;
  ooc.memory_limit_bytes = 1024 * 1024;  // 1 MiB: below the process itself
  SimplifyOptions options;
  options.target_vertex_ratio = 0.2;
  try {
    simplify_out_of_core(in, out, options, ooc);
    FAIL() << "a 1 MiB limit was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--memory-limit"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("at least"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
  for (const std::string& e : folder.entries()) EXPECT_EQ(e.find(".topotet-scratch"), std::string::npos) << e;
  ooc::InputCounts counts;
  counts.vertex_stride = 1;  // the generated field
  // Room for pieces of about 25,000 tets beside what the process holds: several pieces, merged
  // back into one (the output at 20% is small), the topology kept.
  ooc.memory_limit_bytes =
      static_cast<std::uint64_t>((static_cast<double>(ooc::budget_baseline(ooc::resident_bytes())) +
                                  25000.0 * static_cast<double>(ooc::bytes_per_piece_tet(counts)) +
                                  2.0 * static_cast<double>(input.vertex_count())) /
                                 (1.0 - ooc::kHeadroom));
  const OutOfCoreReport r = simplify_out_of_core(in, out, options, ooc);
  EXPECT_GE(r.pieces, 2u);
  EXPECT_LE(r.piece_tet_limit, 30000u);
  expect_same_topology(input, read_mesh(out));
}

// What the reader holds while the mesh streams (a .msh's node tag map, sparse: 48 bytes a node)
// is counted beside the cut's own arrays, and named when it is what does not fit.
TEST(OutOfCoreLimit, TheReadersNodeTagMapIsCountedInTheFirstCheck) {
  ooc::MemoryBudget budget;
  budget.baseline = ooc::kBaselineStep;
  const std::uint64_t vertices = 1'000'000;
  const double cut = static_cast<double>(vertices * ooc::kCutBytesPerVertex + ooc::kMinPieceTets * ooc::kBytesPerPieceTet / 8);
  budget.limit = static_cast<std::uint64_t>((static_cast<double>(budget.baseline) + cut + 10e6) / (1.0 - ooc::kHeadroom));
  EXPECT_NO_THROW(budget.check_vertices(vertices, 0, "in.msh"));
  EXPECT_NO_THROW(budget.check_vertices(vertices, 4 * vertices, "in.msh"));  // compact tags: 4 MB
  try {
    budget.check_vertices(vertices, 48 * vertices, "in.msh");
    FAIL() << "a 48 MB node tag map fit in 10 MB";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("node tag map"), std::string::npos) << e.what();
  }
}

// A Gmsh MSH 4.1 input (ASCII, binary, gzipped ASCII) streams as the same mesh: the output has
// the bytes of the run on that mesh written as MEDIT.
TEST(OutOfCoreGmsh, AnMsh41InputGivesTheBytesOfTheSameMeshAsMedit) {
  MeshData input = generated("cube-sphere", 12000);
  input.fields.clear();  // the fields of a .msh are not streamed (topotet/mesh_stream.h)
  plant_in_mid_plane(input);
  test::TempDir folder;
  SimplifyOptions options;
  options.target_vertex_ratio = 0.2;
  options.num_threads = 2;
  OutOfCoreOptions ooc;
  ooc.pieces = 8;
  const auto simplified = [&](const std::string& in) {
    const std::string out = folder.file("out.mesh");
    simplify_out_of_core(in, out, options, ooc);
    return test::read_text(out);
  };
  const std::string ascii = folder.file("in.msh"), binary = folder.file("in_binary.msh");
  write_mesh(ascii, input);
  WriteOptions b;
  b.binary = true;
  write_mesh(binary, input, b);
  const std::string medit = folder.file("in.mesh");
  write_mesh(medit, read_mesh(ascii));  // the mesh as the .msh gives it (listed faces grouped by ref)
  const std::string expected = simplified(medit);
  ASSERT_FALSE(expected.empty());
  EXPECT_EQ(simplified(ascii), expected);
  EXPECT_EQ(simplified(binary), expected);
  const std::string gz = folder.file("in.msh.gz");
  ASSERT_EQ(std::system(("gzip -c " + ascii + " > " + gz).c_str()), 0);
  EXPECT_EQ(simplified(gz), expected);
  for (const std::string& e : folder.entries()) EXPECT_EQ(e.find(".topotet-scratch"), std::string::npos) << e;
}

// A .msh with node and cell fields (ASCII and binary): the $NodeData and $ElementData views stream
// as read_mesh reads them (a later view of a name replaces it, a partial one leaves 0 elsewhere, an
// exactly symmetric 3x3 comes back as 6 components, "topotet:vertex_ref" as the vertex refs), so
// the output has the bytes of the run on the mesh read_mesh gives, written as MEDIT.
TEST(OutOfCoreGmsh, FieldsStreamAsReadMeshReadsThem) {
  MeshData input = generated("cube-sphere", 12000);
  input.vertex_refs.resize(input.vertex_count());
  VertexField stress{"stress", 6, {}};
  for (std::size_t v = 0; v < input.vertex_count(); ++v) {
    input.vertex_refs[v] = static_cast<std::int32_t>(v % 3);
    const auto& p = input.positions[v];
    for (double x : {p[0], p[1], p[2], p[0] * p[1], p[1] * p[2], 1.0}) stress.values.push_back(x);
  }
  input.fields.push_back(stress);
  CellField density{"density", 1, CellFieldKind::kIntensive, {}};
  for (std::size_t t = 0; t < input.tet_count(); ++t) density.values.push_back(0.5 + input.tet_material[t]);
  input.cell_fields.push_back(density);
  test::TempDir folder;
  SimplifyOptions options;
  options.target_vertex_ratio = 0.2;
  OutOfCoreOptions ooc;
  ooc.pieces = 8;
  const std::string ascii = folder.file("in.msh"), binary = folder.file("in_b.msh");
  write_mesh(ascii, input);
  WriteOptions b;
  b.binary = true;
  write_mesh(binary, input, b);
  // A later, partial time step of "f": it replaces the first; the nodes it leaves out read 0.
  std::ofstream(ascii, std::ios::app) << "$NodeData\n1\n\"f\"\n1\n1.0\n3\n1\n1\n2\n1 5.5\n3 -7.25\n$EndNodeData\n";
  const auto simplified = [&](const std::string& in, const std::string& out) {
    simplify_out_of_core(in, folder.file(out), options, ooc);
    return test::read_text(folder.file(out)) + test::read_text(folder.file(out.substr(0, out.size() - 5) + ".sol"));
  };
  for (const std::string& msh : {ascii, binary}) {
    const MeshData as_read = read_mesh(msh);
    ASSERT_EQ(as_read.fields.size(), 2u);
    ASSERT_EQ(as_read.cell_fields.size(), 1u);
    EXPECT_EQ(as_read.fields[1].components, 6);  // the symmetric tensor, back to 6
    EXPECT_FALSE(as_read.vertex_refs.empty());
    write_mesh(folder.file("as_read.mesh"), as_read);
    EXPECT_EQ(simplified(msh, "from_msh.mesh"), simplified(folder.file("as_read.mesh"), "from_mesh.mesh")) << msh;
  }
  for (const std::string& e : folder.entries()) EXPECT_EQ(e.find(".topotet-scratch"), std::string::npos) << e;
}

// A binary MEDIT input (.meshb with its .solb: fields and cell fields streamed from the binary
// file) gives the bytes of the run on the ASCII .mesh; a .meshb output reads back as that output.
TEST(OutOfCoreMeshb, ABinaryMeditInputGivesTheBytesOfTheAsciiOne) {
  MeshData input = generated("cube-sphere", 12000);
  CellField cells{"density", 1, CellFieldKind::kIntensive, {}};
  for (std::size_t t = 0; t < input.tet_count(); ++t) cells.values.push_back(1.0 + input.tet_material[t]);
  input.cell_fields.push_back(cells);
  plant_in_mid_plane(input);
  test::TempDir folder;
  SimplifyOptions options;
  options.target_vertex_ratio = 0.2;
  OutOfCoreOptions ooc;
  ooc.pieces = 8;
  write_mesh(folder.file("in.mesh"), input);
  write_mesh(folder.file("bin.meshb"), input);
  ASSERT_TRUE(fs::exists(folder.file("bin.solb")));
  simplify_out_of_core(folder.file("in.mesh"), folder.file("a.mesh"), options, ooc);
  simplify_out_of_core(folder.file("bin.meshb"), folder.file("b.mesh"), options, ooc);
  EXPECT_EQ(test::read_text(folder.file("b.mesh")), test::read_text(folder.file("a.mesh")));
  EXPECT_EQ(test::read_text(folder.file("b.sol")), test::read_text(folder.file("a.sol")));
  simplify_out_of_core(folder.file("bin.meshb"), folder.file("c.meshb"), options, ooc);
  EXPECT_EQ(read_mesh(folder.file("c.meshb")), read_mesh(folder.file("a.mesh")));
}

TEST(OutOfCoreErrors, BadInputAndOptionsAreClearErrorsAndLeaveNothing) {
  MeshData input = generated("cube-sphere", 5000);
  test::TempDir folder;
  const std::string in = folder.file("in.mesh"), out = folder.file("out.mesh");
  OutOfCoreOptions ooc;
  ooc.pieces = 4;
  const auto message = [&](const SimplifyOptions& options) -> std::string {
    try {
      simplify_out_of_core(in, out, options, ooc);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  // A listed triangle that is no face of a tet.
  MeshData bad = input;
  bad.triangles.push_back({{bad.tets[0][0], bad.tets[100][1], bad.tets[200][2]}, 77});
  write_mesh(in, bad);
  EXPECT_NE(message({}).find("is not a face of any tet"), std::string::npos) << message({});
  // Options an out-of-core run cannot honour.
  write_mesh(in, input);
  SimplifyOptions iso;
  iso.isosurfaces.push_back({});
  EXPECT_NE(message(iso).find("isosurfaces are not available out of core"), std::string::npos) << message(iso);
  // A truncated file names itself.
  {
    std::ifstream f(in, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(f)), {});
    std::ofstream(in, std::ios::binary) << text.substr(0, text.size() / 2);
  }
  EXPECT_NE(message({}).find("in.mesh"), std::string::npos) << message({});
  EXPECT_FALSE(fs::exists(out));
  for (const std::string& e : folder.entries()) EXPECT_EQ(e.find(".topotet-scratch"), std::string::npos) << e;
  EXPECT_THROW(parse_memory_size("lots"), InputError);
  EXPECT_EQ(parse_memory_size("2G"), 2ull << 30);
  EXPECT_EQ(parse_memory_size("256M"), 256ull << 20);
  EXPECT_EQ(parse_memory_size("1.5GiB"), 3ull << 29);
}

}  // namespace
}  // namespace topotet

namespace topotet {
namespace {

// The whole mesh's cost units, as the cut computes them.
CostUnits units_of(const MeshData& m) {
  CostUnits u;
  std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const auto& p : m.positions)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  for (int k = 0; k < 3; ++k) u.origin[k] = lo[k];
  u.diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
  double volume = 0.0;
  for (const auto& t : m.tets) {
    const auto& a = m.positions[t[0]];
    double e[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) e[i][k] = m.positions[t[i + 1]][k] - a[k];
    volume += std::fabs(e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                        e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) / 6.0;
  }
  u.mean_tet_volume = volume / static_cast<double>(m.tets.size());
  for (const VertexField& f : m.fields)
    for (int c = 0; c < f.components; ++c) {
      double a = 1e300, b = -1e300;
      for (std::size_t v = 0; v < m.positions.size(); ++v) a = std::min(a, f.values[v * f.components + c]), b = std::max(b, f.values[v * f.components + c]);
      u.field_min.push_back(a);
      u.field_range.push_back(b - a);
    }
  return u;
}

TEST(CarriedQuadrics, TwoRunsWithThemActLikeOne) {
  const MeshData input = generated("cube-sphere", 60000);
  const CostUnits units = units_of(input);
  SimplifyOptions options;
  options.cost_units = &units;
  options.tolerance_rel = 0.0;
  const std::size_t target = input.vertex_count() / 20;
  const auto rms = [&](const TetMesh& m) { return compare_fields(input, m.to_mesh_data()).worst_rms_rel; };

  TetMesh one = build_tet_mesh(input);
  SimplifyOptions o1 = options;
  o1.target_vertices = target;
  ASSERT_EQ(simplify(one, o1).status, Status::kOk);

  const auto two_runs = [&](bool carry) {
    TetMesh m = build_tet_mesh(input);
    std::vector<double> quadrics;
    SimplifyOptions first = options;
    first.target_vertices = input.vertex_count() * 3 / 8;
    first.quadrics_out = &quadrics;
    EXPECT_EQ(simplify(m, first).status, Status::kOk);
    EXPECT_EQ(quadrics.size() % m.to_mesh_data().vertex_count(), 0u);
    EXPECT_GT(quadrics.size(), 0u);
    TetMesh again = build_tet_mesh(m.to_mesh_data());
    SimplifyOptions second = options;
    second.target_vertices = target;
    if (carry) second.quadrics_in = &quadrics;
    EXPECT_EQ(simplify(again, second).status, Status::kOk);
    return rms(again);
  };
  const double fresh = two_runs(false), carried = two_runs(true), whole = rms(one);
  std::printf("one run %.5f, two runs %.5f, two runs carrying the quadrics %.5f\n", whole, fresh, carried);
  EXPECT_LE(carried, fresh);
  EXPECT_LE(carried, 1.05 * whole);
}

}  // namespace
}  // namespace topotet
