// File formats (io/): the real meshes of /work/shared/data with their exact counts, exact
// round trips through every writer, Gmsh-produced files, malformed input, atomic writes.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <zlib.h>

#include <charconv>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "io/atomic_file.h"
#include "io/line_reader.h"
#include "io_test_files.h"
#include "mesh/mesh_model.h"
#include "topotet/error.h"
#include "topotet/io.h"

namespace topotet {
namespace {

namespace fs = std::filesystem;

std::string shared(const std::string& rel) { return std::string(TOPOTET_SHARED_DATA_DIR) + "/" + rel; }
std::string test_data(const std::string& rel) { return std::string(TOPOTET_TEST_DATA_DIR) + "/" + rel; }

#define REQUIRE_FILE(path)                                                     \
  do {                                                                         \
    if (!fs::exists(path)) GTEST_SKIP() << "missing test input " << (path);    \
  } while (0)

using test::read_text;
using test::two_tets;
using test::TempDir;
using test::write_text;

// Reads `path`, expecting an InputError whose message names the file, the line (":<line>:",
// or "byte" for binary files) and contains `needle`.
void expect_input_error(const std::string& path, const std::string& line_tag, const std::string& needle) {
  test::expect_input_error([&] { read_mesh(path); }, {path, line_tag, needle});
}

template <class T>
std::set<std::int32_t> ref_set(const std::vector<T>& items) {
  std::set<std::int32_t> s;
  for (const T& x : items) s.insert(x.ref);
  return s;
}

// Exact comparison, member by member for readable failures; positions and field values bit for bit.
// MEDIT has no group names: `with_names` = false compares everything else.
void expect_same_mesh(const MeshData& a, const MeshData& b, const std::string& what, bool with_names = true) {
  SCOPED_TRACE(what);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  const auto same_bytes = [](const auto& x, const auto& y) {
    return x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
  };
  EXPECT_TRUE(same_bytes(a.positions, b.positions)) << "positions differ";
  EXPECT_TRUE(a.vertex_refs == b.vertex_refs) << "vertex_refs differ";
  EXPECT_TRUE(a.tets == b.tets) << "tets differ";
  EXPECT_TRUE(a.tet_material == b.tet_material) << "tet_material differs";
  EXPECT_TRUE(a.triangles == b.triangles) << "triangles differ";
  EXPECT_TRUE(a.segments == b.segments) << "segments differ";
  EXPECT_TRUE(a.ridges == b.ridges) << "ridges differ";
  EXPECT_TRUE(a.corners == b.corners) << "corners differ";
  EXPECT_TRUE(a.required_vertices == b.required_vertices) << "required vertices differ";
  ASSERT_EQ(a.fields.size(), b.fields.size());
  for (std::size_t i = 0; i < a.fields.size(); ++i) {
    EXPECT_EQ(a.fields[i].name, b.fields[i].name);
    EXPECT_EQ(a.fields[i].components, b.fields[i].components);
    ASSERT_EQ(a.fields[i].values.size(), b.fields[i].values.size());
    EXPECT_TRUE(same_bytes(a.fields[i].values, b.fields[i].values)) << "field " << a.fields[i].name << " values differ";
  }
  if (with_names) {
    EXPECT_TRUE(a.group_names == b.group_names) << "group names differ";
    EXPECT_TRUE(a == b);
  } else {
    MeshData a2 = a, b2 = b;
    a2.group_names.clear();
    b2.group_names.clear();
    EXPECT_TRUE(a2 == b2);
  }
}

// The element order write_gmsh gives (one block per entity): the elements of each dimension
// grouped by entity (tets by material, triangles by ref, segments by ref and ridge), entities in
// order of first use, elements in their order within an entity.
MeshData grouped_by_entity(const MeshData& m) {
  const auto order = [](std::size_t n, auto key) {
    std::map<decltype(key(0)), std::size_t> rank;
    for (std::size_t i = 0; i < n; ++i) rank.try_emplace(key(i), rank.size());
    std::vector<std::size_t> idx(n);
    for (std::size_t i = 0; i < n; ++i) idx[i] = i;
    std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return rank[key(a)] < rank[key(b)]; });
    return idx;
  };
  MeshData g = m;
  const auto tets = order(m.tets.size(), [&](std::size_t i) { return m.tet_material[i]; });
  for (std::size_t i = 0; i < tets.size(); ++i) {
    g.tets[i] = m.tets[tets[i]];
    g.tet_material[i] = m.tet_material[tets[i]];
  }
  const auto tris = order(m.triangles.size(), [&](std::size_t i) { return m.triangles[i].ref; });
  for (std::size_t i = 0; i < tris.size(); ++i) g.triangles[i] = m.triangles[tris[i]];
  std::vector<char> ridge(m.segments.size(), 0);
  for (std::uint32_t r : m.ridges) ridge[r] = 1;
  const auto segs = order(m.segments.size(), [&](std::size_t i) { return std::make_pair(m.segments[i].ref, ridge[i]); });
  g.ridges.clear();
  for (std::size_t i = 0; i < segs.size(); ++i) {
    g.segments[i] = m.segments[segs[i]];
    if (ridge[segs[i]]) g.ridges.push_back(static_cast<std::uint32_t>(i));
  }
  return g;
}

// ---------------------------------------------------------------------------------------------
// The shared meshes: counts from the README table, the rest counted by hand (grep / awk, and a
// small independent parser for the binary 2.2 files).

struct SharedCase {
  const char* file;
  std::size_t verts, tets, triangles, segments, ridges, corners, required;
  std::set<std::int32_t> materials, triangle_refs, segment_refs;
  std::vector<int> field_components;
};

std::ostream& operator<<(std::ostream& os, const SharedCase& c) { return os << c.file; }

const SharedCase kShared[] = {
    {"mfem/nested_cubes.msh", 138, 520, 240, 0, 0, 0, 0, {1, 2}, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}, {}, {}},
    {"simnibs/sphere3.msh", 4556, 22704, 7826, 0, 0, 0, 0, {3, 4, 5}, {1003, 1004, 1005}, {}, {}},
    {"palace/circular_hole.msh", 5387, 30614, 3798, 0, 0, 0, 0, {1}, {2, 3, 4, 5, 6, 7, 8, 9}, {}, {}},
    {"palace/sheet_w_two_holes.msh", 5313, 30335, 3766, 0, 0, 0, 0, {1}, {2, 3, 4, 5, 6, 7, 8, 9, 10}, {}, {}},
    {"palace/parallel_plate.msh", 1529, 5184, 2516, 0, 0, 0, 0, {1}, {2, 3, 4, 5}, {}, {}},
    {"mmg/tinyBoxt.mesh", 11866, 63434, 5056, 233, 233, 8, 8, {2, 3}, {2, 10}, {0}, {3}},
    {"mmg/torus.mesh", 4351, 20067, 2954, 94, 94, 0, 0, {0}, {2, 92, 104, 116, 122}, {61, 62, 64, 65, 68, 70, 71, 73},
     {6, 3}},
    {"volume/lox_post_tets.mesh.gz", 109744, 513375, 0, 0, 0, 0, 0, {0}, {}, {}, {1, 1, 1}},
};

class SharedData : public ::testing::TestWithParam<SharedCase> {};

TEST_P(SharedData, ExactCounts) {
  const SharedCase& c = GetParam();
  REQUIRE_FILE(shared(c.file));
  const MeshData m = read_mesh(shared(c.file));
  EXPECT_EQ(m.vertex_count(), c.verts);
  EXPECT_EQ(m.tet_count(), c.tets);
  EXPECT_EQ(m.tet_material.size(), c.tets);
  EXPECT_EQ(m.triangles.size(), c.triangles);
  EXPECT_EQ(m.segments.size(), c.segments);
  EXPECT_EQ(m.ridges.size(), c.ridges);
  EXPECT_EQ(m.corners.size(), c.corners);
  EXPECT_EQ(m.required_vertices.size(), c.required);
  EXPECT_EQ(std::set<std::int32_t>(m.tet_material.begin(), m.tet_material.end()), c.materials);
  EXPECT_EQ(ref_set(m.triangles), c.triangle_refs);
  EXPECT_EQ(ref_set(m.segments), c.segment_refs);
  ASSERT_EQ(m.fields.size(), c.field_components.size());
  for (std::size_t i = 0; i < m.fields.size(); ++i) {
    EXPECT_EQ(m.fields[i].components, c.field_components[i]);
    EXPECT_EQ(m.fields[i].values.size(), c.verts * static_cast<std::size_t>(c.field_components[i]));
  }
}

// read -> write (.mesh, .msh ASCII, .msh binary) -> read gives back identical MeshData, and so
// does MEDIT -> Gmsh -> MEDIT: the Gmsh writer carries ridges, corners, required vertices,
// vertex refs and non-positive refs through its named physical groups (see gmsh.cpp).
TEST_P(SharedData, RoundTripsAreExact) {
  const SharedCase& c = GetParam();
  REQUIRE_FILE(shared(c.file));
  const MeshData original = read_mesh(shared(c.file));
  TempDir dir;
  write_mesh(dir.file("a.mesh"), original);
  expect_same_mesh(original, read_mesh(dir.file("a.mesh")), "via .mesh", false);
  // .msh groups the elements by entity: a file read from .msh already is (a fixed point).
  const MeshData grouped = grouped_by_entity(original);
  write_mesh(dir.file("a.msh"), original);
  const MeshData via_msh = read_mesh(dir.file("a.msh"));
  expect_same_mesh(grouped, via_msh, "via .msh");
  write_mesh(dir.file("b.msh"), original, WriteOptions{.binary = true});
  expect_same_mesh(grouped, read_mesh(dir.file("b.msh")), "via binary .msh");
  write_mesh(dir.file("c.mesh"), via_msh);
  expect_same_mesh(grouped, read_mesh(dir.file("c.mesh")), "via .msh then .mesh", false);
  write_mesh(dir.file("d.msh"), original, WriteOptions{.msh22 = true});
  expect_same_mesh(grouped, read_mesh(dir.file("d.msh")), "via .msh 2.2");
  write_mesh(dir.file("e.meshb"), original);  // binary MEDIT (+ .solb)
  expect_same_mesh(original, read_mesh(dir.file("e.meshb")), "via .meshb", false);
  if (c.file == std::string_view("mfem/nested_cubes.msh")) expect_same_mesh(original, grouped, "a Gmsh file is grouped");
}

std::string shared_case_name(const ::testing::TestParamInfo<SharedCase>& param) {
  std::string name = param.param.file;
  name = name.substr(name.find('/') + 1);
  return name.substr(0, name.find('.'));
}

INSTANTIATE_TEST_SUITE_P(Meshes, SharedData, ::testing::ValuesIn(kShared), shared_case_name);

TEST(SharedDataDetails, TinyBoxtVertexRefsCornersAndVectorSol) {
  REQUIRE_FILE(shared("mmg/tinyBoxt.mesh"));
  const MeshData m = read_mesh(shared("mmg/tinyBoxt.mesh"));
  ASSERT_EQ(m.vertex_refs.size(), m.vertex_count());
  EXPECT_EQ(std::count_if(m.vertex_refs.begin(), m.vertex_refs.end(), [](int r) { return r != 0; }), 1885);
  EXPECT_EQ(m.corners, (std::vector<VertId>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(m.required_vertices, m.corners);
  // Ridges list every edge, in order.
  for (std::size_t i = 0; i < m.ridges.size(); ++i) EXPECT_EQ(m.ridges[i], i);
  ASSERT_EQ(m.fields.size(), 1u);
  EXPECT_EQ(m.fields[0].name, "sol0");
  EXPECT_EQ(m.fields[0].values[0], 4.88255696107129e-32);
  EXPECT_EQ(m.fields[0].values[2], 5.38604484441492e-32);
  EXPECT_EQ(m.fields[0].values[3], 5.99701369957223e-32);
}

TEST(SharedDataDetails, TorusTensorAndVectorSol) {
  REQUIRE_FILE(shared("mmg/torus.mesh"));
  const MeshData m = read_mesh(shared("mmg/torus.mesh"));
  ASSERT_EQ(m.fields.size(), 2u);
  // First line of torus.sol: "32.5918  0 25 0 0 25 32.5918 1.5 1.3".
  const std::vector<double> tensor(m.fields[0].values.begin(), m.fields[0].values.begin() + 6);
  EXPECT_EQ(tensor, (std::vector<double>{32.5918, 0, 25, 0, 0, 25}));
  const std::vector<double> vec(m.fields[1].values.begin(), m.fields[1].values.begin() + 3);
  EXPECT_EQ(vec, (std::vector<double>{32.5918, 1.5, 1.3}));
}

TEST(SharedDataDetails, LoxPostGzipWithNamedFields) {
  REQUIRE_FILE(shared("volume/lox_post_tets.mesh.gz"));
  const MeshData m = read_mesh(shared("volume/lox_post_tets.mesh.gz"));
  ASSERT_EQ(m.fields.size(), 3u);
  EXPECT_EQ(m.fields[0].name, "Pressure");
  EXPECT_EQ(m.fields[1].name, "VelocityMagnitude");
  EXPECT_EQ(m.fields[2].name, "StagnationEnergy");
  // First value line of the .sol: "0.955898345 0 2.38974595".
  EXPECT_EQ(m.fields[0].values[0], 0.955898345);
  EXPECT_EQ(m.fields[1].values[0], 0.0);
  EXPECT_EQ(m.fields[2].values[0], 2.38974595);
  // First tet line: "40 2 2890 1 0".
  EXPECT_EQ(m.tets[0], (std::array<VertId, 4>{39, 1, 2889, 0}));
}

// The real-object performance case (1.31M tets); read and write times are printed.
TEST(SharedData, LiverLarge) {
  const std::string path = shared("large/liver_1.31M.mesh.gz");
  REQUIRE_FILE(path);
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const MeshData m = read_mesh(path);
  const auto t1 = clock::now();
  EXPECT_EQ(m.vertex_count(), 229691u);
  EXPECT_EQ(m.tet_count(), 1311411u);
  EXPECT_EQ(m.triangles.size(), 66276u);
  EXPECT_EQ(m.segments.size(), 379u);
  EXPECT_EQ(std::set<std::int32_t>(m.tet_material.begin(), m.tet_material.end()), (std::set<std::int32_t>{85, 127, 255}));
  EXPECT_EQ(ref_set(m.triangles), (std::set<std::int32_t>{1, 2, 3, 4, 5}));
  TempDir dir;
  const auto t2 = clock::now();
  write_mesh(dir.file("liver.mesh"), m);
  const auto t3 = clock::now();
  const MeshData back = read_mesh(dir.file("liver.mesh"));
  const auto t4 = clock::now();
  expect_same_mesh(m, back, "liver via .mesh");
  const auto secs = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  std::printf("liver: read .mesh.gz %.3f s, write .mesh %.3f s, read .mesh %.3f s (%.0f MB/s)\n", secs(t0, t1),
              secs(t2, t3), secs(t3, t4), static_cast<double>(fs::file_size(dir.file("liver.mesh"))) / 1e6 / secs(t3, t4));
}

// ---------------------------------------------------------------------------------------------
// Gmsh-produced files: tests/data/gmsh_sphere_in_box.geo (a ball in a box, a sheet and a wire
// embedded in the box volume, physical groups 1..7) and its committed MSH 4.1 output.

void expect_sphere_in_box(const MeshData& m, bool with_corners) {
  EXPECT_EQ(std::set<std::int32_t>(m.tet_material.begin(), m.tet_material.end()), (std::set<std::int32_t>{1, 2}));
  EXPECT_EQ(ref_set(m.triangles), (std::set<std::int32_t>{3, 4, 5}));
  EXPECT_EQ(ref_set(m.segments), (std::set<std::int32_t>{6}));
  if (with_corners) {
    EXPECT_EQ(m.corners.size(), 2u);  // the wire's end points (Physical Point 7)
  }
}

TEST(GmshFiles, CommittedSphereInBox) {
  const MeshData m = read_mesh(test_data("gmsh_sphere_in_box.msh"));
  EXPECT_EQ(m.vertex_count(), 385u);
  EXPECT_EQ(m.tet_count(), 1399u);
  EXPECT_EQ(m.triangles.size(), 630u);
  EXPECT_EQ(m.segments.size(), 6u);
  expect_sphere_in_box(m, true);
  // The sheet (ref 5) is embedded: its vertices are tet vertices.
  std::set<VertId> tet_vertices;
  for (const auto& t : m.tets) tet_vertices.insert(t.begin(), t.end());
  for (const Triangle& t : m.triangles)
    for (VertId v : t.v) EXPECT_TRUE(tet_vertices.count(v));
}

bool have_gmsh() { return fs::exists("/usr/bin/gmsh"); }

void run_gmsh(const std::string& args) {
  const std::string cmd = "/usr/bin/gmsh " + args + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

TEST(GmshFiles, GeneratedMshAndMeshAgree) {
  if (!have_gmsh()) GTEST_SKIP() << "no /usr/bin/gmsh";
  TempDir dir;
  const std::string geo = test_data("gmsh_sphere_in_box.geo");
  ASSERT_NO_FATAL_FAILURE(run_gmsh("-3 " + geo + " -format msh41 -o " + dir.file("a.msh")));
  // MEDIT has one ref per element: ask for the physical tag rather than the elementary one.
  ASSERT_NO_FATAL_FAILURE(
      run_gmsh("-3 " + geo + " -format mesh -setnumber Mesh.SaveElementTagType 2 -o " + dir.file("a.mesh")));
  const MeshData msh = read_mesh(dir.file("a.msh"));
  const MeshData mesh = read_mesh(dir.file("a.mesh"));
  EXPECT_GT(msh.tet_count(), 100u);
  EXPECT_EQ(msh.vertex_count(), mesh.vertex_count());
  EXPECT_EQ(msh.tet_count(), mesh.tet_count());
  EXPECT_EQ(msh.triangles.size(), mesh.triangles.size());
  EXPECT_EQ(msh.segments.size(), mesh.segments.size());
  expect_sphere_in_box(msh, true);
  expect_sphere_in_box(mesh, false);  // Gmsh's MEDIT writer has no Corners
  EXPECT_TRUE(msh.tets == mesh.tets);
  EXPECT_TRUE(msh.tet_material == mesh.tet_material);
}

TEST(GmshFiles, BinaryAndMsh22VariantsReadTheSame) {
  if (!have_gmsh()) GTEST_SKIP() << "no /usr/bin/gmsh";
  TempDir dir;
  const std::string in = test_data("gmsh_sphere_in_box.msh");
  const MeshData ref = read_mesh(in);
  const char* variants[][2] = {{"-format msh41 -bin", "b41.msh"}, {"-format msh22", "a22.msh"}, {"-format msh22 -bin", "b22.msh"}};
  for (const auto& [args, name] : variants) {
    ASSERT_NO_FATAL_FAILURE(run_gmsh(in + " -0 " + args + " -o " + dir.file(name)));
    expect_same_mesh(ref, read_mesh(dir.file(name)), name);
  }
}

// What we write, Gmsh reads: re-saved by Gmsh (which groups elements by entity, so compare them
// as sets), the file gives back the same vertices, elements and refs, ridges, corners and
// required vertices. Gmsh does not re-save $NodeData views, so fields and vertex refs are lost.
template <class T, class Key>
std::vector<Key> sorted_keys(const std::vector<T>& items, Key (*key)(const T&)) {
  std::vector<Key> out;
  for (const T& x : items) out.push_back(key(x));
  std::sort(out.begin(), out.end());
  return out;
}

TEST(GmshFiles, GmshReadsWhatWeWrite) {
  if (!have_gmsh()) GTEST_SKIP() << "no /usr/bin/gmsh";
  REQUIRE_FILE(shared("mmg/tinyBoxt.mesh"));
  TempDir dir;
  const MeshData m = read_mesh(shared("mmg/tinyBoxt.mesh"));
  using TetKey = std::pair<std::array<VertId, 4>, std::int32_t>;
  std::vector<TetKey> tets;
  for (std::size_t i = 0; i < m.tets.size(); ++i) tets.emplace_back(m.tets[i], m.tet_material[i]);
  std::sort(tets.begin(), tets.end());
  const auto tri_key = +[](const Triangle& t) { return std::make_pair(t.v, t.ref); };
  const auto seg_key = +[](const Segment& s) { return std::make_pair(s.v, s.ref); };
  for (const bool binary : {false, true}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    write_mesh(dir.file("ours.msh"), m, WriteOptions{.binary = binary});
    ASSERT_NO_FATAL_FAILURE(run_gmsh(dir.file("ours.msh") + " -0 -format msh41 -o " + dir.file("gmsh.msh")));
    const MeshData back = read_mesh(dir.file("gmsh.msh"));
    ASSERT_EQ(back.positions, m.positions);
    std::vector<TetKey> back_tets;
    for (std::size_t i = 0; i < back.tets.size(); ++i) back_tets.emplace_back(back.tets[i], back.tet_material[i]);
    std::sort(back_tets.begin(), back_tets.end());
    EXPECT_TRUE(back_tets == tets);
    EXPECT_TRUE(sorted_keys(back.triangles, tri_key) == sorted_keys(m.triangles, tri_key));
    EXPECT_TRUE(sorted_keys(back.segments, seg_key) == sorted_keys(m.segments, seg_key));
    EXPECT_EQ(back.ridges.size(), m.ridges.size());
    EXPECT_EQ(back.corners, m.corners);
    EXPECT_EQ(back.required_vertices, m.required_vertices);
  }
}

// ---------------------------------------------------------------------------------------------
// The tokenizer on files larger than its 4 MiB chunks: tokens and long comments straddle chunk
// boundaries, in plain and gzip'd files.

TEST(LineReader, ChunkBoundariesCommentsAndLineNumbers) {
  TempDir dir;
  std::mt19937_64 rng(7);
  std::string text;
  std::uint64_t sum = 0, count = 0, lines = 0;
  const auto add_numbers_until = [&](std::size_t size) {
    while (text.size() < size) {
      const std::uint64_t v = rng() >> 1;
      text += std::to_string(v) + (rng() % 3 == 0 ? "\t\r\n" : " \n");
      sum += v;
      ++count;
      ++lines;
    }
  };
  const auto add_comment = [&](std::size_t length) {
    text += "# " + std::string(length, 'x') + " 12345\n";  // comments hide numbers too
    ++lines;
  };
  // The first chunk ends at 4 MiB exactly: put a number across it.
  add_numbers_until((std::size_t{4} << 20) - 40);
  text += std::string((std::size_t{4} << 20) - 5 - text.size(), ' ');
  text += "1234567890\n";
  sum += 1234567890;
  ++count;
  ++lines;
  // The next chunk ends a few bytes before 8 MiB: put a 300 kB comment across it.
  add_numbers_until((std::size_t{8} << 20) - 150000);
  add_comment(300000);
  add_numbers_until(std::size_t{9} << 20);
  add_comment(10);
  write_text(dir.file("big.txt"), text);
  gzFile gz = gzopen(dir.file("big.txt.gz").c_str(), "wb1");
  ASSERT_NE(gz, nullptr);
  gzwrite(gz, text.data(), static_cast<unsigned>(text.size()));
  gzclose(gz);
  for (const char* name : {"big.txt", "big.txt.gz"}) {
    SCOPED_TRACE(name);
    io::LineReader r(dir.file(name));
    r.set_comment_char('#');
    std::uint64_t got_sum = 0, got_count = 0;
    for (std::string_view tok = r.next_token(); !tok.empty(); tok = r.next_token()) {
      std::uint64_t v = 0;
      ASSERT_EQ(std::from_chars(tok.data(), tok.data() + tok.size(), v).ptr, tok.data() + tok.size()) << tok;
      got_sum += v;
      ++got_count;
    }
    EXPECT_EQ(got_count, count);
    EXPECT_EQ(got_sum, sum);
    EXPECT_EQ(r.line(), lines + 1);  // end of file is on the line after the last newline
  }
}

// ---------------------------------------------------------------------------------------------
// Small hand-written inputs.

const char* kTetMesh =
    "MeshVersionFormatted 2\n"
    "Dimension 3\n"
    "Vertices\n4\n"
    "0 0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
    "Tetrahedra\n1\n1 2 3 4 7\n"
    "End\n";

TEST(Medit, KeywordsCommentsAndSkippedSections) {
  TempDir dir;
  write_text(dir.file("a.mesh"),
             "# leading comment\n"
             "meshversionformatted 1\n"
             "DIMENSION\n 3  # on the next line\n"
             "Vertices # count follows\n4\n"
             "0 0 0 0\n+1 0 0 0\n0 1.0e0 0 0\n0 0 1 0 # trailing\n"
             "Normals\n2\n0 0 1\n0 1 0\n"
             "NormalAtVertices\n2\n1 1\n2 2\n"
             "RequiredEdges\n1\n1\n"
             "BoundingBox\n0 1 0 1 0 1\n"
             "Identifier\n\"a name with spaces\"\n"
             "Hexahedra\n0\n"
             "tetrahedra\n1\n1 2 3 4 -3\n"
             "Edges\n1\n1 2 5\n"
             "End\n"
             "anything after End is ignored\n");
  const MeshData m = read_mesh(dir.file("a.mesh"));
  EXPECT_EQ(m.vertex_count(), 4u);
  EXPECT_EQ(m.positions[1], (std::array<double, 3>{1, 0, 0}));
  EXPECT_TRUE(m.vertex_refs.empty());  // all zero
  ASSERT_EQ(m.tet_count(), 1u);
  EXPECT_EQ(m.tet_material[0], -3);
  ASSERT_EQ(m.segments.size(), 1u);
  EXPECT_EQ(m.segments[0].ref, 5);
}

TEST(Medit, SectionsBeforeVerticesAreCheckedAtTheEnd) {
  TempDir dir;
  write_text(dir.file("ok.mesh"), "Dimension 3\nRidges\n1\n1\nTetrahedra\n1\n1 2 3 4 0\nEdges\n1\n1 2 0\nVertices\n4\n"
                                  "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nEnd\n");
  const MeshData m = read_mesh(dir.file("ok.mesh"));
  EXPECT_EQ(m.tet_count(), 1u);
  EXPECT_EQ(m.ridges, (std::vector<std::uint32_t>{0}));
  write_text(dir.file("bad.mesh"), "Dimension 3\nTetrahedra\n1\n1 2 3 9 0\nVertices\n4\n"
                                   "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nEnd\n");
  expect_input_error(dir.file("bad.mesh"), ":2:", "Tetrahedra entry 1: index 9 out of range [1, 4]");
}

TEST(Medit, SolFieldNamesFile) {
  TempDir dir;
  write_text(dir.file("a.mesh"), kTetMesh);
  write_text(dir.file("a.sol"), "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n4\n2 1 2\n"
                                "1 0 0 0\n2 0 0 0\n3 0 0 0\n4 1e-400 0 0\nEnd\n");
  MeshData m = read_mesh(dir.file("a.mesh"));
  ASSERT_EQ(m.fields.size(), 2u);
  EXPECT_EQ(m.fields[0].name, "sol0");
  EXPECT_EQ(m.fields[1].name, "sol1");
  EXPECT_EQ(m.fields[1].components, 3);
  EXPECT_EQ(m.fields[1].values[9], 0.0);  // 1e-400 underflows to 0, it is not an error
  write_text(dir.file("a.sol.fields.txt"), "temperature\nvelocity\n");
  m = read_mesh(dir.file("a.mesh"));
  EXPECT_EQ(m.fields[0].name, "temperature");
  EXPECT_EQ(m.fields[1].name, "velocity");
  write_text(dir.file("a.sol.fields.txt"), "only one\n");
  EXPECT_THROW(read_mesh(dir.file("a.mesh")), InputError);
  // Writing keeps names (in <stem>.sol.fields.txt) and values.
  m.fields[0].name = "T";
  m.fields[1].name = "U, with comma";
  write_mesh(dir.file("b.mesh"), m);
  const MeshData back = read_mesh(dir.file("b.mesh"));
  EXPECT_EQ(back.fields[0].name, "T");
  EXPECT_EQ(back.fields[1].name, "U_ with comma");
  EXPECT_EQ(back.fields[1].values, m.fields[1].values);
}

TEST(Medit, RewritingWithoutFieldsRemovesTheStaleSol) {
  TempDir dir;
  MeshData m = two_tets();
  write_mesh(dir.file("a.mesh"), m);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a.mesh", "a.sol", "a.sol.fields.txt"}));
  m.fields.clear();
  write_mesh(dir.file("a.mesh"), m);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a.mesh"}));
  expect_same_mesh(m, read_mesh(dir.file("a.mesh")), "rewritten");
}

TEST(Medit, GzipMeshFindsGzipSol) {
  TempDir dir;
  const auto gz_write = [](const std::string& path, const std::string& text) {
    gzFile f = gzopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    gzwrite(f, text.data(), static_cast<unsigned>(text.size()));
    gzclose(f);
  };
  gz_write(dir.file("a.mesh.gz"), kTetMesh);
  gz_write(dir.file("a.sol.gz"), "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n4\n1 1\n1\n2\n3\n4\nEnd\n");
  const MeshData m = read_mesh(dir.file("a.mesh.gz"));
  ASSERT_EQ(m.fields.size(), 1u);
  EXPECT_EQ(m.fields[0].values, (std::vector<double>{1, 2, 3, 4}));
  EXPECT_EQ(m.vertex_refs, (std::vector<std::int32_t>{1, 0, 0, 0}));
  // A truncated gzip stream is an error, not a silently shorter mesh.
  const std::string bytes = read_text(dir.file("a.mesh.gz"));
  write_text(dir.file("cut.mesh.gz"), bytes.substr(0, bytes.size() / 2));
  EXPECT_THROW(read_mesh(dir.file("cut.mesh.gz")), InputError);
  // A corrupt one names the file once, and a position in the compressed file.
  std::string corrupt = bytes;
  for (std::size_t i = 20; i < 40 && i < corrupt.size(); ++i) corrupt[i] = static_cast<char>(corrupt[i] ^ 0x5a);
  write_text(dir.file("bad.mesh.gz"), corrupt);
  try {
    read_mesh(dir.file("bad.mesh.gz"));
    ADD_FAILURE() << "corrupt gzip accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find(dir.file("bad.mesh.gz")), 0u) << msg;
    EXPECT_EQ(msg.find(dir.file("bad.mesh.gz"), 1), std::string::npos) << "the file is named twice: " << msg;
  }
}

const char* kGmsh41 =
    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
    "$PhysicalNames\n1\n3 5 \"solid part\"\n$EndPhysicalNames\n"
    "$Entities\n0 0 1 1\n"
    "7 0 0 0 1 1 0 0 0\n"
    "3 0 0 0 1 1 1 1 5 0\n"
    "$EndEntities\n"
    "$Periodic\n0\n$EndPeriodic\n"
    "$SomethingNew\nwhatever 1 2 3\n$EndSomethingNew\n"
    "$Nodes\n2 5 10 50\n"
    "3 3 0 3\n10\n20\n30\n0 0 0\n1 0 0\n0 1 0\n"
    "2 7 1 2\n40\n50\n0 0 1 0.5 0.5\n1 1 1 0.2 0.2\n"
    "$EndNodes\n"
    "$Elements\n3 4 1 4\n"
    "3 3 4 2\n1 10 20 30 40\n2 20 30 40 50\n"
    "2 7 2 1\n3 10 20 30\n"
    "3 3 5 1\n4 10 20 30 40 50 10 20 30\n"
    "$EndElements\n"
    "$NodeData\n1\n\"temperature\"\n1\n0.0\n3\n0\n1\n2\n10 1.5\n50 2.5\n$EndNodeData\n";

TEST(Gmsh, Msh41SparseTagsEntitiesUnknownSectionsAndIgnoredElements) {
  TempDir dir;
  write_text(dir.file("a.msh"), kGmsh41);
  // The hexahedron makes it a mixed mesh: refused, naming the line of its block...
  expect_input_error(dir.file("a.msh"), ":41:", "1 hexahedra: topotet simplifies tetrahedral meshes only");
  // ...or left out and counted.
  ReadNotes notes;
  const MeshData m = read_mesh(dir.file("a.msh"), ReadOptions{.tets_only = true}, &notes);
  EXPECT_EQ(notes.hexahedra, 1u);
  EXPECT_EQ(notes.volume_cells(), 1u);
  EXPECT_EQ(m.group_names, (std::vector<GroupName>{{3, 5, "solid part"}}));
  ASSERT_EQ(m.vertex_count(), 5u);
  EXPECT_EQ(m.positions[4], (std::array<double, 3>{1, 1, 1}));
  EXPECT_EQ(m.tets, (std::vector<std::array<VertId, 4>>{{0, 1, 2, 3}, {1, 2, 3, 4}}));
  EXPECT_EQ(m.tet_material, (std::vector<std::int32_t>{5, 5}));  // physical tag of volume 3
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0].ref, 7);  // surface 7 has no physical tag: its entity tag
  ASSERT_EQ(m.fields.size(), 1u);
  EXPECT_EQ(m.fields[0].name, "temperature");
  EXPECT_EQ(m.fields[0].values, (std::vector<double>{1.5, 0, 0, 0, 2.5}));
}

// A surface in two physical groups: each triangle comes out once per group.
TEST(Gmsh, SurfaceInTwoPhysicalGroupsListsItsTrianglesForEach) {
  TempDir dir;
  write_text(dir.file("a.msh"),
             "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
             "$PhysicalNames\n2\n2 10 \"walls\"\n2 20 \"cut\"\n$EndPhysicalNames\n"
             "$Entities\n0 0 1 1\n"
             "7 0 0 0 1 1 0 2 10 20 0\n"
             "3 0 0 0 1 1 1 1 5 0\n"
             "$EndEntities\n"
             "$Nodes\n1 4 1 4\n3 3 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
             "$Elements\n2 2 1 2\n3 3 4 1\n1 1 2 3 4\n2 7 2 1\n2 1 2 3\n$EndElements\n");
  const MeshData m = read_mesh(dir.file("a.msh"));
  EXPECT_EQ(m.triangles, (std::vector<Triangle>{{{0, 1, 2}, 10}, {{0, 1, 2}, 20}}));
  EXPECT_EQ(m.group_names, (std::vector<GroupName>{{2, 10, "walls"}, {2, 20, "cut"}}));
  // Both refs survive .msh and MSH 2.2 out and in (2.2 repeats the element per group).
  for (const bool msh22 : {false, true}) {
    write_mesh(dir.file("b.msh"), m, WriteOptions{.msh22 = msh22});
    expect_same_mesh(m, read_mesh(dir.file("b.msh")), msh22 ? "2.2" : "4.1");
  }
  const std::string text = read_text(dir.file("b.msh"));
  EXPECT_NE(text.find("2 10 \"walls\""), std::string::npos) << text;
}

// The same element listed twice with one group in MSH 2.2 is a repeat, not a second surface;
// a copy for a flag-only group (our ridges) just marks the first copy.
TEST(Gmsh, Msh22CopiesPerGroup) {
  TempDir dir;
  write_text(dir.file("a.msh"),
             "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
             "$PhysicalNames\n1\n1 9 \"topotet:ridges\"\n$EndPhysicalNames\n"
             "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
             "$Elements\n7\n"
             "1 4 2 1 1 1 2 3 4\n"
             "2 2 2 10 7 1 2 3\n3 2 2 20 7 1 2 3\n4 2 2 20 7 1 2 3\n"
             "5 1 2 3 4 1 2\n6 1 2 9 4 1 2\n7 1 2 3 4 2 3\n"
             "$EndElements\n");
  const MeshData m = read_mesh(dir.file("a.msh"));
  EXPECT_EQ(m.triangles, (std::vector<Triangle>{{{0, 1, 2}, 10}, {{0, 1, 2}, 20}}));
  EXPECT_EQ(m.segments, (std::vector<Segment>{{{0, 1}, 3}, {{1, 2}, 3}}));
  EXPECT_EQ(m.ridges, (std::vector<std::uint32_t>{0}));
}

// One element block per entity, however the elements are interleaved.
TEST(Gmsh, OneElementBlockPerEntity) {
  TempDir dir;
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}, {0, 1, 2, 3}, {1, 2, 3, 4}};  // not a valid mesh: the writer does not care
  m.tet_material = {1, 2, 1, 2};
  m.triangles = {{{0, 1, 2}, 3}, {{1, 2, 3}, 4}, {{0, 1, 3}, 3}, {{1, 3, 4}, 4}};
  write_mesh(dir.file("a.msh"), m);
  const std::string text = read_text(dir.file("a.msh"));
  const std::size_t at = text.find("$Elements\n");
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(text.substr(at + 10, text.find('\n', at + 10) - at - 10), "4 8 1 8");  // 4 blocks
  const MeshData back = read_mesh(dir.file("a.msh"));
  EXPECT_EQ(back.tet_material, (std::vector<std::int32_t>{1, 1, 2, 2}));
  EXPECT_EQ(back.triangles, (std::vector<Triangle>{{{0, 1, 2}, 3}, {{0, 1, 3}, 3}, {{1, 2, 3}, 4}, {{1, 3, 4}, 4}}));
}

// `gmsh -part 2`: the elements sit on partitioned entities; materials and refs still come from
// the physical groups, and the partition boundaries add nothing.
TEST(GmshFiles, PartitionedFileReadsLikeTheWholeOne) {
  if (!have_gmsh()) GTEST_SKIP() << "no /usr/bin/gmsh";
  TempDir dir;
  const std::string in = test_data("gmsh_sphere_in_box.msh");
  ASSERT_NO_FATAL_FAILURE(run_gmsh(in + " -0 -part 3 -format msh41 -o " + dir.file("p.msh")));
  ASSERT_NE(read_text(dir.file("p.msh")).find("$PartitionedEntities"), std::string::npos);
  const MeshData whole = read_mesh(in);
  const MeshData parts = read_mesh(dir.file("p.msh"));
  EXPECT_EQ(parts.tet_count(), whole.tet_count());
  EXPECT_EQ(parts.triangles.size(), whole.triangles.size());
  EXPECT_EQ(parts.segments.size(), whole.segments.size());
  expect_sphere_in_box(parts, true);
  EXPECT_EQ(parts.group_names, whole.group_names);
}

// Gmsh reads our MSH 2.2 (what --msh22 is for) and gives back the same elements and refs.
TEST(GmshFiles, GmshReadsOurMsh22) {
  if (!have_gmsh()) GTEST_SKIP() << "no /usr/bin/gmsh";
  TempDir dir;
  const MeshData m = read_mesh(test_data("gmsh_sphere_in_box.msh"));
  write_mesh(dir.file("ours22.msh"), m, WriteOptions{.msh22 = true});
  ASSERT_NE(read_text(dir.file("ours22.msh")).rfind("$MeshFormat\n2.2 0 8\n", 0), std::string::npos);
  ASSERT_NO_FATAL_FAILURE(run_gmsh(dir.file("ours22.msh") + " -0 -format msh41 -o " + dir.file("gmsh.msh")));
  const MeshData back = read_mesh(dir.file("gmsh.msh"));  // Gmsh renumbers the nodes of a 2.2 file
  EXPECT_EQ(back.vertex_count(), m.vertex_count());
  EXPECT_EQ(back.tet_count(), m.tet_count());
  EXPECT_EQ(back.triangles.size(), m.triangles.size());
  EXPECT_EQ(back.segments.size(), m.segments.size());
  expect_sphere_in_box(back, true);
  EXPECT_EQ(back.group_names, m.group_names);
}

// TetGen -g lists Corners by input point; those beyond the mesh's vertices are left out and counted.
TEST(Medit, OutOfRangeCornersAreLeftOut) {
  TempDir dir;
  for (const bool corners_first : {false, true}) {
    const std::string corners = "Corners\n3\n2\n9\n0\n";
    write_text(dir.file("a.mesh"), "MeshVersionFormatted 1\nDimension 3\n" + (corners_first ? corners : "") +
                                       "Vertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nTetrahedra\n1\n1 2 3 4 1\n" +
                                       (corners_first ? "" : corners) + "End\n");
    ReadNotes notes;
    const MeshData m = read_mesh(dir.file("a.mesh"), {}, &notes);
    EXPECT_EQ(m.corners, (std::vector<VertId>{1}));
    EXPECT_EQ(notes.dropped_corners, 2u);
  }
}

// TetGen's own files: region attributes are materials, face and edge markers are refs.
const char* kTwoRegionCubePoly =
    "# a unit cube split at z = 0.5 into two regions; facet markers 1 (bottom, sides), 2 (middle), 3 (top half)\n"
    "12 3 0 0\n"
    "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 0.5\n6 1 0 0.5\n7 1 1 0.5\n8 0 1 0.5\n"
    "9 0 0 1\n10 1 0 1\n11 1 1 1\n12 0 1 1\n"
    "11 1\n"
    "1 0 1\n4 1 2 3 4\n1 0 2\n4 5 6 7 8\n1 0 3\n4 9 10 11 12\n"
    "1 0 1\n4 1 2 6 5\n1 0 1\n4 2 3 7 6\n1 0 1\n4 3 4 8 7\n1 0 1\n4 4 1 5 8\n"
    "1 0 3\n4 5 6 10 9\n1 0 3\n4 6 7 11 10\n1 0 3\n4 7 8 12 11\n1 0 3\n4 8 5 9 12\n"
    "0\n"
    "2\n1 0.5 0.5 0.25 10 0\n2 0.5 0.5 0.75 20 0\n";

TEST(TetgenFiles, RegionsAndMarkersFromDebianTetgen) {
  if (!fs::exists("/usr/bin/tetgen")) GTEST_SKIP() << "no /usr/bin/tetgen";
  TempDir dir;
  write_text(dir.file("cube.poly"), kTwoRegionCubePoly);
  const std::string cmd = "cd " + dir.file("") + " && /usr/bin/tetgen -pqAeg -a0.02 cube.poly > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  for (const char* name : {"cube.1.ele", "cube.1.node"}) {
    SCOPED_TRACE(name);
    const MeshData m = read_mesh(dir.file(name));
    EXPECT_GT(m.tet_count(), 20u);
    EXPECT_EQ(std::set<std::int32_t>(m.tet_material.begin(), m.tet_material.end()), (std::set<std::int32_t>{10, 20}));
    EXPECT_EQ(ref_set(m.triangles), (std::set<std::int32_t>{1, 2, 3}));
    EXPECT_FALSE(m.segments.empty());
    const MeshModel model = build_mesh_model(m);  // a valid mesh: every face and edge is on a tet
    EXPECT_EQ(model.live_tet_count(), m.tet_count());
  }
  // The -g MEDIT file of the same run reads too (its Corners are input points), with the same tets.
  ReadNotes notes;
  const MeshData g = read_mesh(dir.file("cube.1.mesh"), {}, &notes);
  EXPECT_EQ(g.tet_count(), read_mesh(dir.file("cube.1.ele")).tet_count());
}

TEST(TetgenFiles, ZeroBasedExtraColumnsAndErrors) {
  TempDir dir;
  write_text(dir.file("a.node"), "# zero-based\n5 3 1 1\n0 0 0 0 7.5 1\n1 1 0 0 0 1\n2 0 1 0 0 0\n3 0 0 1 0 1\n4 1 1 1 0 0\n");
  write_text(dir.file("a.ele"), "2 4 1\n0 0 1 2 3 4\n1 1 2 3 4 5\n");
  write_text(dir.file("a.face"), "3 1\n0 0 1 2 6 0 -1\n1 1 2 3 0 0 1\n2 1 2 4 9 1 -1\n");
  write_text(dir.file("a.edge"), "1 0\n0 0 1\n");
  const MeshData m = read_mesh(dir.file("a.face"));
  EXPECT_EQ(m.tets, (std::vector<std::array<VertId, 4>>{{0, 1, 2, 3}, {1, 2, 3, 4}}));
  EXPECT_EQ(m.tet_material, (std::vector<std::int32_t>{4, 5}));
  EXPECT_EQ(m.triangles, (std::vector<Triangle>{{{0, 1, 2}, 6}, {{1, 2, 4}, 9}}));  // marker 0: not listed
  EXPECT_TRUE(m.segments.empty());                                                 // no markers: not listed
  EXPECT_EQ(m.vertex_refs, (std::vector<std::int32_t>{1, 1, 0, 1, 0}));
  write_text(dir.file("a.ele"), "1 4 1\n0 0 1 2 9 4\n");
  expect_input_error(dir.file("a.ele"), "a.ele:2:", ".ele: node index 9 out of range [0, 4]");
  write_text(dir.file("a.ele"), "1 4 1\n0 0 1 2 3 4.5\n");
  expect_input_error(dir.file("a.ele"), "a.ele:2:", "is not an integer");
  write_text(dir.file("a.ele"), "1 10 0\n");
  expect_input_error(dir.file("a.ele"), "a.ele:1:", "second-order");
}

TEST(Medit, MixedMeshIsRefusedOrLeftOut) {
  TempDir dir;
  write_text(dir.file("a.mesh"),
             "MeshVersionFormatted 2\nDimension 3\nVertices\n5\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n1 1 1 0\n"
             "Tetrahedra\n1\n1 2 3 4 1\nPyramids\n1\n1 2 3 4 5 2\nQuadrilaterals\n1\n1 2 3 4 0\nEnd\n");
  expect_input_error(dir.file("a.mesh"), ":13:", "1 pyramids: topotet simplifies tetrahedral meshes only");
  ReadNotes notes;
  const MeshData m = read_mesh(dir.file("a.mesh"), ReadOptions{.tets_only = true}, &notes);
  EXPECT_EQ(m.tet_count(), 1u);
  EXPECT_EQ(notes.pyramids, 1u);
  EXPECT_EQ(notes.quadrilaterals, 1u);
}

// ---------------------------------------------------------------------------------------------
// Malformed input: InputError naming the file and the line.

struct Malformed {
  const char* name;
  const char* ext;
  const char* text;
  const char* line_tag;
  const char* needle;
};

const Malformed kMalformed[] = {
    {"truncated", ".mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n3\n0 0 0 0\n1 0 0 0\n", ":7:",
     "unexpected end of file while reading Vertices coordinate"},
    {"count_larger_than_data", ".mesh", "Dimension 3\nVertices\n2\n0 0 0 0\n1 0 0 0\nTetrahedra\n5\n1 2 1 2 0\n",
     ":9:", "unexpected end of file while reading Tetrahedra"},
    {"count_smaller_than_data", ".mesh", "Dimension 3\nVertices\n1\n0 0 0 0\n1 0 0 0\nEnd\n", ":5:",
     "expected a section keyword, got '1'"},
    {"negative_count", ".mesh", "Dimension 3\nVertices\n-4\n", ":3:", "Vertices: negative count -4"},
    {"huge_count", ".mesh", "Dimension 3\nVertices\n99999999999\n", ":3:", "Vertices: count 99999999999 too large"},
    {"lying_count", ".mesh", "Dimension 3\nVertices\n4000000000\n0 0 0 0\n", ":5:", "unexpected end of file"},
    {"index_out_of_range", ".mesh", "Dimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n\nTetrahedra\n1\n1 2 3 5 0\n",
     ":11:", "Tetrahedra: vertex index 5 out of range [1, 4]"},
    {"index_zero", ".mesh", "Dimension 3\nVertices\n1\n0 0 0 0\nRequiredVertices\n1\n0\n", ":7:", "vertex index 0 out of range"},
    {"ridge_out_of_range", ".mesh", "Dimension 3\nVertices\n2\n0 0 0 0\n1 0 0 0\nEdges\n1\n1 2 0\nRidges\n1\n2\n",
     ":11:", "Ridges: edge index 2 out of range [1, 1]"},
    {"nan_coordinate", ".mesh", "Dimension 3\nVertices\n2\n0 0 0 0\n1 nan 0 0\n", ":5:", "non-finite value"},
    {"inf_coordinate", ".mesh", "Dimension 3\nVertices\n1\n\n-inf 0 0 0\n", ":5:", "non-finite value"},
    {"non_numeric", ".mesh", "Dimension 3\nVertices\n1\n0 0 zero 0\n", ":4:",
     "Vertices coordinate: expected a number, got 'zero'"},
    {"float_index", ".mesh", "Dimension 3\nVertices\n1\n0 0 0 0\nCorners\n1\n1.0\n", ":7:", "expected an integer, got '1.0'"},
    {"ref_overflow", ".mesh", "Dimension 3\nVertices\n1\n0 0 0 4294967296\n", ":4:", "out of range"},
    {"wrong_dimension", ".mesh", "MeshVersionFormatted 2\nDimension 2\nVertices\n1\n0 0 0\n", ":2:",
     "Dimension 2 is not supported"},
    {"unknown_keyword", ".mesh", "Dimension 3\nFancyStuff\n3\n1 2 3\n", ":2:", "unknown section 'FancyStuff'"},
    {"second_order_medit", ".mesh", "Dimension 3\nTetrahedraP2\n0\n", ":2:", "second-order elements not supported"},
    {"duplicate_section", ".mesh", "Dimension 3\nVertices\n0\nVertices\n0\n", ":4:", "duplicate section Vertices"},
    {"bad_version", ".mesh", "MeshVersionFormatted 7\n", ":1:", "MeshVersionFormatted 7 is not supported"},
    {"msh_missing_end_nodes", ".msh",
     "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 0 0\n$Elements\n0 0 0 0\n$EndElements\n", ":9:",
     "expected $EndNodes, got '$Elements'"},
    {"msh_truncated_nodes", ".msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 3\n3 1 0 3\n1\n2\n3\n0 0 0\n1 1",
     ":11:", "unexpected end of file while reading $Nodes coordinate"},
    {"msh_unknown_node", ".msh",
     "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 0 0\n$EndNodes\n"
     "$Elements\n1 1 1 1\n0 1 15 1\n1 2\n$EndElements\n",
     ":13:", "unknown node tag 2"},
    {"msh_second_order", ".msh",
     "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n0 0 0 0\n$EndNodes\n$Elements\n1 1 1 1\n3 1 11 1\n", ":9:",
     "element type 11 (10-node tetrahedron): second-order elements not supported"},
    {"msh_nan", ".msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 NaN 0\n$EndNodes\n", ":6:", "non-finite"},
    {"msh_duplicate_node", ".msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n1 1 0 0\n$EndNodes\n",
     ":7:", "duplicate node tag 1"},
    {"msh_node_count_mismatch", ".msh",
     "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 1\n3 1 0 1\n1\n0 0 0\n$EndNodes\n", ":8:",
     "header announces 3 nodes, blocks hold 1"},
    {"msh_version_3", ".msh", "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n", ":2:", "MSH version 3.0 is not supported"},
    {"msh_missing_end_of_unknown", ".msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Custom\n1 2 3\n", ":6:",
     "missing $EndCustom"},
    {"msh_not_gmsh", ".msh", "hello\n", ":1:", "not a Gmsh file"},
};

class MalformedInput : public ::testing::TestWithParam<Malformed> {};

TEST_P(MalformedInput, NamesFileAndLine) {
  const Malformed& c = GetParam();
  TempDir dir;
  const std::string path = dir.file(std::string("bad") + c.ext);
  write_text(path, c.text);
  expect_input_error(path, c.line_tag, c.needle);
}

std::string malformed_name(const ::testing::TestParamInfo<Malformed>& param) { return param.param.name; }

INSTANTIATE_TEST_SUITE_P(Cases, MalformedInput, ::testing::ValuesIn(kMalformed), malformed_name);

TEST(Malformed, SolProblemsNameTheSolFile) {
  TempDir dir;
  write_text(dir.file("a.mesh"), kTetMesh);
  write_text(dir.file("a.sol"), "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n3\n1 1\n1\n2\n3\nEnd\n");
  try {
    read_mesh(dir.file("a.mesh"));
    ADD_FAILURE();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(dir.file("a.sol") + ":4:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("SolAtVertices: 3 entries but the mesh has 4 vertices"), std::string::npos) << msg;
  }
  write_text(dir.file("a.sol"), "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n4\n1 5\n");
  EXPECT_THROW(read_mesh(dir.file("a.mesh")), InputError);
}

TEST(Malformed, TruncatedBinaryMshNamesByteOffset) {
  TempDir dir;
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  m.tet_material = {1};
  write_mesh(dir.file("a.msh"), m, WriteOptions{.binary = true});
  const std::string bytes = read_text(dir.file("a.msh"));
  const std::size_t cut = bytes.find("$EndNodes") - 10;
  write_text(dir.file("cut.msh"), bytes.substr(0, cut));
  expect_input_error(dir.file("cut.msh"), ": byte ", "unexpected end of file");
}

TEST(Malformed, FormatsAndPaths) {
  EXPECT_EQ(format_from_path("a/b.MESH"), MeshFormat::kMedit);
  EXPECT_EQ(format_from_path("b.mesh.gz"), MeshFormat::kMedit);
  EXPECT_EQ(format_from_path("b.msh"), MeshFormat::kGmsh);
  EXPECT_EQ(format_from_path("b.vtu"), MeshFormat::kVtu);
  EXPECT_EQ(format_from_path("b.meshb"), MeshFormat::kMedit);  // binary MEDIT (GMF)
  EXPECT_THROW(format_from_path("b.stl"), InputError);
  EXPECT_THROW(read_mesh("b.vtu"), InputError);
  EXPECT_THROW(read_mesh("/nonexistent/file.mesh"), InputError);
  MeshData empty;
  EXPECT_THROW(write_mesh("/tmp/x.mesh.gz", empty), InputError);
  TempDir dir;
  fs::create_directory(dir.file("folder.mesh"));
  EXPECT_THROW(read_mesh(dir.file("folder.mesh")), InputError);
}

// ---------------------------------------------------------------------------------------------
// Writers: atomicity, consistency checks, VTU content.


TEST(Writers, HandMadeMeshesRoundTripExactly) {
  TempDir dir;
  MeshData surface_only;  // no tets: the Gmsh writer still needs an entity for the nodes
  surface_only.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  surface_only.triangles = {{{0, 1, 2}, 0}};
  surface_only.fields = {{"m", 9, {1, 2, 3, 4, 5, 6, 7, 8, 9, 1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 0, 0, 0, 0, 0, 0, 0, 0}}};
  const MeshData meshes[] = {two_tets(), MeshData{}, surface_only};
  for (const MeshData& m : meshes) {
    for (const char* name : {"a.mesh", "a.msh", "a.meshb"}) {
      write_mesh(dir.file(name), m);
      expect_same_mesh(m, read_mesh(dir.file(name)), name);
    }
    write_mesh(dir.file("b.msh"), m, WriteOptions{.binary = true});
    expect_same_mesh(m, read_mesh(dir.file("b.msh")), "binary");
    write_mesh(dir.file("c.msh"), m, WriteOptions{.msh22 = true});
    expect_same_mesh(m, read_mesh(dir.file("c.msh")), "msh 2.2");
  }
}

// Special files (issue #13): only regular files are replaced by a rename.
TEST(Writers, SymlinkIsFollowedAndStaysALink) {
  TempDir dir;
  write_text(dir.file("real.txt"), "old");
  fs::create_symlink("real.txt", dir.file("link.txt"));
  write_text_file(dir.file("link.txt"), "new");
  EXPECT_TRUE(fs::is_symlink(dir.file("link.txt")));
  EXPECT_EQ(read_text(dir.file("real.txt")), "new");
  // A dangling link: its target is created.
  fs::create_symlink("sub_target.txt", dir.file("dangling.txt"));
  write_text_file(dir.file("dangling.txt"), "made");
  EXPECT_TRUE(fs::is_symlink(dir.file("dangling.txt")));
  EXPECT_EQ(read_text(dir.file("sub_target.txt")), "made");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"dangling.txt", "link.txt", "real.txt", "sub_target.txt"}));
}

TEST(Writers, FifoAndDevicesAreWrittenStraightThrough) {
  TempDir dir;
  const std::string fifo = dir.file("pipe");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string got;
  std::thread reader([&] { got = read_text(fifo); });
  write_text_file(fifo, "through the pipe");
  reader.join();
  EXPECT_EQ(got, "through the pipe");
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_TRUE(io::is_direct_output(fifo));
  write_text_file("/dev/null", "discarded");
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"pipe"}));
}

TEST(Writers, SignalCleanupRemovesTemporariesInProgress) {
  TempDir dir;
  io::AtomicFile f(dir.file("a.mesh"));
  f.put("partial");
  const std::string temp = f.temp_path();
  ASSERT_TRUE(fs::exists(temp));
  remove_temporary_files();  // what the CLI's SIGINT/SIGTERM handler calls
  EXPECT_FALSE(fs::exists(temp));
  EXPECT_FALSE(fs::exists(dir.file("a.mesh")));
}

TEST(Writers, MissingDirectoryThrowsAndLeavesNothing) {
  TempDir dir;
  EXPECT_THROW(write_mesh(dir.file("missing/a.mesh"), two_tets()), InputError);
  EXPECT_FALSE(fs::exists(dir.file("missing")));
  EXPECT_TRUE(dir.entries().empty());
}

TEST(Writers, FailedRenameLeavesNoTemporaryFile) {
  TempDir dir;
  fs::create_directory(dir.file("target.mesh"));  // rename over a directory fails
  EXPECT_THROW(write_mesh(dir.file("target.mesh"), two_tets()), InputError);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"target.mesh"}));
  EXPECT_TRUE(fs::is_directory(dir.file("target.mesh")));
}

TEST(Writers, FailureMidWriteKeepsTheOldFileAndNoLitter) {
  TempDir dir;
  write_text(dir.file("a.mesh"), "old");
  MeshData m = two_tets();
  m.fields[0].components = 5;  // consistent sizes, but .sol cannot store 5 components
  m.fields[0].values.assign(25, 0.0);
  try {
    write_mesh(dir.file("a.mesh"), m);
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a.sol"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_text(dir.file("a.mesh")), "old");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a.mesh"}));
}

TEST(Writers, AtomicFileWithoutCommitRemovesItsTemporary) {
  TempDir dir;
  {
    io::AtomicFile f(dir.file("x.txt"));
    f.put("partial");
    EXPECT_TRUE(fs::exists(f.temp_path()));
    EXPECT_EQ(f.temp_path().find(dir.file("x.txt.tmp-")), 0u);
  }
  EXPECT_TRUE(dir.entries().empty());
  {
    io::AtomicFile f(dir.file("x.txt"));
    f.put_double(0.1);
    f.put(' ');
    f.put_int(-42);
    f.commit();
  }
  EXPECT_EQ(read_text(dir.file("x.txt")), "0.1 -42");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"x.txt"}));
}

TEST(Writers, InconsistentMeshIsRefused) {
  TempDir dir;
  MeshData m = two_tets();
  m.tets[1][2] = 17;
  EXPECT_THROW(write_mesh(dir.file("a.mesh"), m), InputError);
  m = two_tets();
  m.fields[1].values.pop_back();
  EXPECT_THROW(write_mesh(dir.file("a.msh"), m), InputError);
  m = two_tets();
  m.ridges = {5};
  EXPECT_THROW(write_mesh(dir.file("a.vtu"), m), InputError);
  EXPECT_TRUE(dir.entries().empty());
}

// Minimal VTK XML decoding, enough to check what ParaView will read: arrays are found by name;
// a block is a UInt64 byte count then the data, base64 encoded as one stream (VTK seeks into it
// by decoded offsets) or raw in the appended section.
std::vector<unsigned char> base64_decode(const std::string& s, std::size_t& pos) {
  const auto val = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
  };
  std::vector<unsigned char> out;
  while (pos + 4 <= s.size() && val(s[pos]) >= 0) {
    const int a = val(s[pos]), b = val(s[pos + 1]), c = val(s[pos + 2]), d = val(s[pos + 3]);
    out.push_back(static_cast<unsigned char>((a << 2) | (b >> 4)));
    if (s[pos + 2] != '=') out.push_back(static_cast<unsigned char>(((b & 15) << 4) | (c >> 2)));
    if (s[pos + 3] != '=') out.push_back(static_cast<unsigned char>(((c & 3) << 6) | d));
    pos += 4;
    if (s[pos - 1] == '=') break;  // padding ends the block
  }
  return out;
}

template <class T>
std::vector<T> vtk_array(const std::string& xml, const std::string& name) {
  const std::size_t at = xml.find("Name=\"" + name + "\"");
  EXPECT_NE(at, std::string::npos) << name;
  if (at == std::string::npos) return {};
  std::vector<unsigned char> bytes;
  const std::size_t off_attr = xml.find("offset=\"", at);
  if (off_attr != std::string::npos && off_attr < xml.find('>', at)) {
    const std::size_t offset = std::stoull(xml.substr(off_attr + 8));
    const std::size_t base = xml.find('_', xml.find("<AppendedData")) + 1;
    std::uint64_t n;
    std::memcpy(&n, xml.data() + base + offset, 8);
    bytes.assign(xml.begin() + static_cast<std::ptrdiff_t>(base + offset + 8),
                 xml.begin() + static_cast<std::ptrdiff_t>(base + offset + 8 + n));
  } else {
    std::size_t pos = xml.find_first_not_of(" \n", xml.find('>', at) + 1);
    bytes = base64_decode(xml, pos);
    EXPECT_GE(bytes.size(), 8u);
    std::uint64_t n;
    std::memcpy(&n, bytes.data(), 8);
    bytes.erase(bytes.begin(), bytes.begin() + 8);
    EXPECT_EQ(bytes.size(), n);
  }
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

TEST(Writers, VtuAndSubstructuresInBothEncodings) {
  TempDir dir;
  const MeshData m = two_tets();
  for (const bool binary : {false, true}) {
    SCOPED_TRACE(binary ? "appended raw" : "inline base64");
    write_mesh(dir.file("a.vtu"), m, WriteOptions{.binary = binary});
    const std::string vtu = read_text(dir.file("a.vtu"));
    EXPECT_NE(vtu.find("<VTKFile type=\"UnstructuredGrid\""), std::string::npos);
    EXPECT_NE(vtu.find("NumberOfPoints=\"5\" NumberOfCells=\"2\""), std::string::npos);
    EXPECT_EQ(vtk_array<std::int64_t>(vtu, "connectivity"), (std::vector<std::int64_t>{0, 1, 2, 3, 1, 2, 3, 4}));
    EXPECT_EQ(vtk_array<std::int64_t>(vtu, "offsets"), (std::vector<std::int64_t>{4, 8}));
    EXPECT_EQ(vtk_array<std::uint8_t>(vtu, "types"), (std::vector<std::uint8_t>{10, 10}));
    EXPECT_EQ(vtk_array<std::int32_t>(vtu, "material"), (std::vector<std::int32_t>{1, 2}));
    EXPECT_EQ(vtk_array<double>(vtu, "s"), m.fields[0].values);
    EXPECT_EQ(vtk_array<double>(vtu, "t"), m.fields[1].values);
    EXPECT_NE(vtu.find("Name=\"t\" NumberOfComponents=\"6\""), std::string::npos);
    const std::string vtp = read_text(dir.file("a_substructures.vtp"));
    EXPECT_NE(vtp.find("NumberOfPoints=\"4\" NumberOfVerts=\"0\" NumberOfLines=\"2\" NumberOfStrips=\"0\" NumberOfPolys=\"1\""),
              std::string::npos);
    EXPECT_EQ(vtk_array<std::int32_t>(vtp, "ref"), (std::vector<std::int32_t>{-1, 0, 9}));
  }
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a.vtu", "a_substructures.vtp"}));
  for (const bool binary : {false, true}) {  // an empty mesh is a valid, empty grid
    write_mesh(dir.file("empty.vtu"), MeshData{}, WriteOptions{.binary = binary});
    EXPECT_NE(read_text(dir.file("empty.vtu")).find("NumberOfPoints=\"0\" NumberOfCells=\"0\""), std::string::npos);
  }
}

}  // namespace
}  // namespace topotet
