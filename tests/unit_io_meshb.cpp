// Binary MEDIT (.meshb / .solb: libMeshb's GMF binary, io/medit_input.h). Files are spelled here by
// a small encoder of the format written from libMeshb's description, independent of topotet's
// writer, in the four versions (1: float32 reals, int32 positions; 2: float64; 3: int64 positions;
// 4: int64 integers): each reads as the same mesh as its ASCII twin; unknown keywords are skipped
// by their position; a file whose sections disagree with their positions, a truncated one, a
// big-endian one are errors naming the file and the byte; a stream reads what read_mesh reads; the
// writer's files read back exactly and are the bytes it writes for the same mesh every time.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "io_test_files.h"
#include "stream_recorder.h"
#include "topotet/error.h"
#include "topotet/io.h"
#include "topotet/medit_stream.h"
#include "topotet/mesh_stream.h"

namespace topotet {
namespace {

using test::TempDir;

// A GMF binary file under construction (little-endian host).
class Gmf {
 public:
  explicit Gmf(int version) : version_(version) {
    word(1);
    word(version);
  }
  // Starts a keyword; its next-keyword position is patched by the next keyword (or end()).
  void keyword(std::int32_t code) {
    patch();
    word(code);
    patch_at_ = bytes_.size();
    if (version_ >= 3) put(std::int64_t{0});
    else put(std::int32_t{0});
  }
  void integer(std::int64_t v) {
    if (version_ >= 4) put(v);
    else put(static_cast<std::int32_t>(v));
  }
  void real(double v) {
    if (version_ == 1) put(static_cast<float>(v));
    else put(v);
  }
  void word(std::int32_t v) { put(v); }
  std::string end() {
    keyword(54);
    return bytes_;
  }

 private:
  void patch() {
    if (patch_at_ == 0) return;
    const std::int64_t here = static_cast<std::int64_t>(bytes_.size());
    if (version_ >= 3) std::memcpy(&bytes_[patch_at_], &here, 8);
    else std::memcpy(&bytes_[patch_at_], &here, 4);
  }
  template <class T>
  void put(const T& v) {
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  int version_;
  std::string bytes_;
  std::size_t patch_at_ = 0;
};

// test::two_tets() (refs, ridges, corners, required vertices) without its fields, in version `v`,
// with an unknown keyword (code 77, three words) between the sections.
std::string two_tets_gmf(int version) {
  const MeshData m = test::two_tets();
  Gmf g(version);
  g.keyword(3);
  g.word(3);
  g.keyword(4);
  g.integer(static_cast<std::int64_t>(m.positions.size()));
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    for (double x : m.positions[i]) g.real(x);
    g.integer(m.vertex_refs[i]);
  }
  g.keyword(77);
  g.word(1), g.word(2), g.word(3);
  g.keyword(8);
  g.integer(static_cast<std::int64_t>(m.tets.size()));
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    for (VertId v : m.tets[t]) g.integer(v + 1);
    g.integer(m.tet_material[t]);
  }
  g.keyword(6);
  g.integer(static_cast<std::int64_t>(m.triangles.size()));
  for (const Triangle& t : m.triangles) {
    for (VertId v : t.v) g.integer(v + 1);
    g.integer(t.ref);
  }
  g.keyword(5);
  g.integer(static_cast<std::int64_t>(m.segments.size()));
  for (const Segment& s : m.segments) {
    for (VertId v : s.v) g.integer(v + 1);
    g.integer(s.ref);
  }
  g.keyword(14);
  g.integer(static_cast<std::int64_t>(m.ridges.size()));
  for (std::uint32_t r : m.ridges) g.integer(r + 1);
  g.keyword(13);
  g.integer(static_cast<std::int64_t>(m.corners.size()));
  for (VertId v : m.corners) g.integer(v + 1);
  g.keyword(15);
  g.integer(static_cast<std::int64_t>(m.required_vertices.size()));
  for (VertId v : m.required_vertices) g.integer(v + 1);
  return g.end();
}

void write_bytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

std::string error_of(const std::string& path) {
  try {
    read_mesh(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

class MeshbVersion : public ::testing::TestWithParam<int> {};

TEST_P(MeshbVersion, ReadsAsItsAsciiTwin) {
  TempDir dir;
  write_bytes(dir.file("m.meshb"), two_tets_gmf(GetParam()));
  MeshData expected = test::two_tets();
  expected.fields.clear();
  const MeshData m = read_mesh(dir.file("m.meshb"));
  EXPECT_EQ(m.tets, expected.tets);
  EXPECT_EQ(m.tet_material, expected.tet_material);
  EXPECT_EQ(m.triangles, expected.triangles);
  EXPECT_EQ(m.segments, expected.segments);
  EXPECT_EQ(m.ridges, expected.ridges);
  EXPECT_EQ(m.corners, expected.corners);
  EXPECT_EQ(m.required_vertices, expected.required_vertices);
  EXPECT_EQ(m.vertex_refs, expected.vertex_refs);
  EXPECT_EQ(m.positions, expected.positions);  // exact in float32 too: small integers
  // A stream of the same file gives what read_mesh keeps.
  test::Recorder rec;
  ReadNotes notes;
  stream_mesh(dir.file("m.meshb"), rec, {}, notes);
  test::expect_recorded(rec, m, true);
}

INSTANTIATE_TEST_SUITE_P(Gmf, MeshbVersion, ::testing::Values(1, 2, 3, 4));

TEST(Meshb, WriterRoundTripsFieldsAndCellFieldsWithASolb) {
  TempDir dir;
  MeshData m = test::two_tets();
  m.cell_fields = {{"density", 1, CellFieldKind::kIntensive, {2.5, -1.0}}, {"label", 1, CellFieldKind::kCategorical, {7, 8}}};
  write_mesh(dir.file("a.meshb"), m);
  EXPECT_TRUE(std::filesystem::exists(dir.file("a.solb")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("a.sol")));
  const MeshData back = read_mesh(dir.file("a.meshb"));
  EXPECT_EQ(back, m);
  // Deterministic bytes; ASCII -> binary -> ASCII is the identity on the text.
  const std::string first = test::read_text(dir.file("a.meshb"));
  write_mesh(dir.file("a.meshb"), back);
  EXPECT_EQ(test::read_text(dir.file("a.meshb")), first);
  write_mesh(dir.file("t.mesh"), m);
  write_mesh(dir.file("u.mesh"), read_mesh(dir.file("a.meshb")));
  EXPECT_EQ(test::read_text(dir.file("t.mesh")), test::read_text(dir.file("u.mesh")));
  EXPECT_EQ(test::read_text(dir.file("t.sol")), test::read_text(dir.file("u.sol")));
  // Rewritten without fields: the stale .solb goes, so the next read does not attach it.
  MeshData plain = m;
  plain.fields.clear();
  plain.cell_fields.clear();
  write_mesh(dir.file("a.meshb"), plain);
  EXPECT_FALSE(std::filesystem::exists(dir.file("a.solb")));
  EXPECT_EQ(read_mesh(dir.file("a.meshb")), plain);
}

// A .mesh and a .meshb of one stem are two meshes: writing one never touches the other's .sol or
// names file (converting a.mesh to a.meshb keeps a.sol), and each reads its own.
TEST(Meshb, AMeshAndAMeshbOfOneStemKeepTheirOwnCompanions) {
  TempDir dir;
  MeshData named = test::two_tets();
  named.fields[0].name = "pressure";
  write_mesh(dir.file("a.mesh"), named);
  MeshData other = test::two_tets();
  other.fields.resize(1);
  other.fields[0].name = "temperature";
  write_mesh(dir.file("a.meshb"), other);
  EXPECT_TRUE(std::filesystem::exists(dir.file("a.sol")));
  EXPECT_TRUE(std::filesystem::exists(dir.file("a.sol.fields.txt")));
  EXPECT_TRUE(std::filesystem::exists(dir.file("a.solb.fields.txt")));
  EXPECT_EQ(read_mesh(dir.file("a.mesh")), named);
  EXPECT_EQ(read_mesh(dir.file("a.meshb")), other);
  MeshData plain = test::two_tets();
  plain.fields.clear();
  write_mesh(dir.file("a.meshb"), plain);  // its own .solb and names go, the .mesh's stay
  EXPECT_FALSE(std::filesystem::exists(dir.file("a.solb")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("a.solb.fields.txt")));
  EXPECT_EQ(read_mesh(dir.file("a.mesh")), named);
  EXPECT_EQ(read_mesh(dir.file("a.meshb")), plain);
}

TEST(Meshb, GzippedMeshbReads) {
  TempDir dir;
  write_bytes(dir.file("g.meshb"), two_tets_gmf(3));
  ASSERT_EQ(std::system(("gzip -k " + dir.file("g.meshb")).c_str()), 0);
  EXPECT_EQ(read_mesh(dir.file("g.meshb.gz")), read_mesh(dir.file("g.meshb")));
}

TEST(Meshb, BadFilesAreErrorsNamingTheFileAndTheByte) {
  TempDir dir;
  const std::string good = two_tets_gmf(3);
  write_bytes(dir.file("cut.meshb"), good.substr(0, good.size() / 2));
  EXPECT_NE(error_of(dir.file("cut.meshb")).find("cut.meshb: byte "), std::string::npos) << error_of(dir.file("cut.meshb"));
  write_bytes(dir.file("text.meshb"), "MeshVersionFormatted 2\nDimension 3\n");
  EXPECT_NE(error_of(dir.file("text.meshb")).find("not a binary MEDIT"), std::string::npos) << error_of(dir.file("text.meshb"));
  std::string swapped = good;
  const std::int32_t big = 16777216;
  std::memcpy(&swapped[0], &big, 4);
  write_bytes(dir.file("big.meshb"), swapped);
  EXPECT_NE(error_of(dir.file("big.meshb")).find("big-endian"), std::string::npos);
  std::string version = good;
  const std::int32_t nine = 9;
  std::memcpy(&version[4], &nine, 4);
  write_bytes(dir.file("v9.meshb"), version);
  EXPECT_NE(error_of(dir.file("v9.meshb")).find("version 9"), std::string::npos);
  // A vertex count one too large: the section runs past the position the file gives the next
  // keyword (or the indices go out of range): either way an error, never a silent misread.
  std::string count = good;
  const std::size_t vertices = good.find(std::string("\x04\0\0\0", 4));
  ASSERT_NE(vertices, std::string::npos);
  const std::int32_t six = 6;
  std::memcpy(&count[vertices + 12], &six, 4);
  write_bytes(dir.file("count.meshb"), count);
  EXPECT_NE(error_of(dir.file("count.meshb")).find("count.meshb: byte "), std::string::npos) << error_of(dir.file("count.meshb"));
  // Curved elements are refused, not skipped, as in ASCII.
  Gmf g(3);
  g.keyword(3);
  g.word(3);
  g.keyword(30);  // TetrahedraP2
  g.integer(0);
  write_bytes(dir.file("p2.meshb"), g.end());
  EXPECT_NE(error_of(dir.file("p2.meshb")).find("second-order"), std::string::npos) << error_of(dir.file("p2.meshb"));
}

}  // namespace
}  // namespace topotet
