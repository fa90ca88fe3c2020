// Gmsh MSH 4.1 read as a stream (topotet/mesh_stream.h), for the out-of-core path: the visitor
// sees exactly the vertices, tets, materials, listed triangles and lines (one copy per physical
// group), ridges, corners and required vertices that read_mesh keeps, in ASCII and binary, on a
// file Gmsh itself wrote and on ours; MSH 2 and fields, which a stream does not take, are refused
// with a message that says where and how to convert.
#include <gtest/gtest.h>

#include <fstream>

#include <string>

#include "io_test_files.h"
#include "stream_recorder.h"
#include "topotet/error.h"
#include "topotet/generate.h"
#include "topotet/io.h"
#include "topotet/mesh_stream.h"

namespace topotet {
namespace {

using test::Recorder;
using test::TempDir;

void expect_stream_matches_read_mesh(const std::string& path) {
  SCOPED_TRACE(path);
  const MeshData full = read_mesh(path);
  ASSERT_TRUE(full.fields.empty() && full.cell_fields.empty() && full.vertex_refs.empty());
  Recorder rec;
  ReadNotes notes;
  stream_mesh(path, rec, ReadOptions{}, notes);
  test::expect_recorded(rec, full, false);  // begin_tets: the element count
  EXPECT_EQ(rec.declared_triangles, full.triangles.size());
  EXPECT_EQ(rec.declared_segments, full.segments.size());
}

// A mesh with every kind of listed data the conventions of write_gmsh carry (refs <= 0, a face on
// two surfaces, ridges, corners, required vertices), no fields.
MeshData listed_mesh() {
  MeshData m = generate_mesh({"cube-sphere", 3000, 1});
  m.fields.clear();
  m.cell_fields.clear();
  m.vertex_refs.clear();
  m.triangles.push_back({m.triangles[0].v, -4});  // the same face listed on a second surface
  m.segments.push_back({{m.tets[0][0], m.tets[0][1]}, 0});
  m.segments.push_back({{m.tets[0][1], m.tets[0][2]}, 12});
  m.ridges = {static_cast<std::uint32_t>(m.segments.size() - 1)};
  m.corners = {m.tets[5][0], m.tets[9][3]};
  m.required_vertices = {m.tets[5][0], m.tets[7][2]};
  return m;
}

TEST(GmshStream, SeesWhatReadMeshKeeps) {
  TempDir dir;
  const MeshData m = listed_mesh();
  for (const bool binary : {false, true}) {
    const std::string path = dir.file(binary ? "b.msh" : "a.msh");
    WriteOptions w;
    w.binary = binary;
    write_mesh(path, m, w);
    expect_stream_matches_read_mesh(path);
  }
  // A file Gmsh wrote (4.1 ASCII, physical groups on volumes and surfaces).
  expect_stream_matches_read_mesh(std::string(TOPOTET_TEST_DATA_DIR) + "/gmsh_sphere_in_box.msh");
}

TEST(GmshStream, Msh2AndFieldsAreRefusedWithWhereAndHow) {
  TempDir dir;
  const auto message = [](const std::string& path) -> std::string {
    Recorder rec;
    ReadNotes notes;
    try {
      stream_mesh(path, rec, ReadOptions{}, notes);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  const MeshData m = listed_mesh();
  WriteOptions old;
  old.msh22 = true;
  const std::string v2 = dir.file("v2.msh");
  write_mesh(v2, m, old);
  const std::string e2 = message(v2);
  EXPECT_NE(e2.find("v2.msh"), std::string::npos) << e2;
  EXPECT_NE(e2.find("MSH 2.2 is not streamed"), std::string::npos) << e2;
  EXPECT_NE(e2.find("convert"), std::string::npos) << e2;
  MeshData with_field = m;
  with_field.fields.push_back({"u", 1, std::vector<double>(m.positions.size(), 1.0)});
  const std::string f = dir.file("field.msh");
  write_mesh(f, with_field);
  const std::string ef = message(f);
  EXPECT_NE(ef.find("field.msh:"), std::string::npos) << ef;  // FILE:LINE
  EXPECT_NE(ef.find("$NodeData"), std::string::npos) << ef;
  EXPECT_NE(ef.find("topotet convert"), std::string::npos) << ef;
  const std::string vtu = dir.file("x.vtu");
  EXPECT_NE(message(vtu).find("streamed formats are MEDIT"), std::string::npos) << message(vtu);
}

// A visitor that takes node views gets each $NodeData view raw, as the file has it (the rules of
// read_mesh are the caller's: field_views.h): names, components, and the values at the vertices
// read_mesh puts them. $ElementData is refused to a visitor that takes no cell views, naming it.
TEST(GmshStream, NodeViewsGoToAVisitorThatTakesThem) {
  struct Views : test::Recorder {
    std::vector<std::pair<std::string, int>> views;
    std::vector<std::vector<double>> values;  // [view] vertex-major, 0 where not given
    std::size_t vertices = 0;
    bool begin_node_view(const std::string& name, int components) override {
      views.push_back({name, components});
      values.emplace_back(m.positions.size() * static_cast<std::size_t>(components), 0.0);
      return true;
    }
    void node_values(VertId v, const double* x) override {
      const auto c = static_cast<std::size_t>(views.back().second);
      std::copy(x, x + c, values.back().begin() + static_cast<std::ptrdiff_t>(v * c));
    }
  };
  TempDir dir;
  MeshData m = listed_mesh();
  m.fields.push_back({"u", 1, {}});
  m.fields.push_back({"w", 3, {}});
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    m.fields[0].values.push_back(0.5 * static_cast<double>(v));
    for (int k = 0; k < 3; ++k) m.fields[1].values.push_back(m.positions[v][static_cast<std::size_t>(k)]);
  }
  for (const bool binary : {false, true}) {
    const std::string path = dir.file(binary ? "fields_b.msh" : "fields.msh");
    WriteOptions options;
    options.binary = binary;
    write_mesh(path, m, options);
    Views rec;
    ReadNotes notes;
    stream_mesh(path, rec, ReadOptions{}, notes);
    const MeshData full = read_mesh(path);
    ASSERT_EQ(rec.views.size(), 2u);
    EXPECT_EQ(rec.views[0], (std::pair<std::string, int>{"u", 1}));
    EXPECT_EQ(rec.views[1], (std::pair<std::string, int>{"w", 3}));
    EXPECT_EQ(rec.values[0], full.fields[0].values);
    EXPECT_EQ(rec.values[1], full.fields[1].values);
    test::expect_recorded(rec, full, false);
  }
  MeshData cells = m;
  cells.fields.clear();
  cells.cell_fields.push_back({"rho", 1, CellFieldKind::kIntensive, std::vector<double>(m.tets.size(), 2.0)});
  write_mesh(dir.file("cells.msh"), cells);
  Views rec;
  ReadNotes notes;
  try {
    stream_mesh(dir.file("cells.msh"), rec, ReadOptions{}, notes);
    FAIL() << "a .msh with $ElementData streamed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("$ElementData"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("topotet convert"), std::string::npos) << e.what();
  }
}

// A visitor that takes cell views gets each $ElementData view at the tets read_mesh gives it; a
// file whose tets are not numbered consecutively cannot map tags to tets without holding them: it
// is refused with the line and the conversion.
TEST(GmshStream, CellViewsNeedConsecutiveTetTags) {
  struct Cells : test::Recorder {
    std::vector<double> values;
    bool begin_cell_view(const std::string&, int components) override {
      values.assign(m.tets.size() * static_cast<std::size_t>(components), 0.0);
      return components == 1;
    }
    void cell_values(std::uint64_t t, const double* x) override { values.at(t) = x[0]; }
  };
  TempDir dir;
  MeshData m = listed_mesh();
  m.cell_fields.push_back({"rho", 1, CellFieldKind::kIntensive, {}});
  for (std::size_t t = 0; t < m.tets.size(); ++t) m.cell_fields[0].values.push_back(1.0 + static_cast<double>(t));
  write_mesh(dir.file("cells.msh"), m);
  Cells rec;
  ReadNotes notes;
  stream_mesh(dir.file("cells.msh"), rec, ReadOptions{}, notes);
  EXPECT_EQ(rec.values, read_mesh(dir.file("cells.msh")).cell_fields.at(0).values);
  std::ofstream(dir.file("gaps.msh")) << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 5 1 5\n3 1 0 5\n1\n2\n3\n4\n5\n"
                                         "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n$EndNodes\n$Elements\n1 2 1 10\n3 1 4 2\n"
                                         "1 1 2 3 4\n10 2 3 5 4\n$EndElements\n$ElementData\n1\n\"rho\"\n1\n0.0\n3\n0\n1\n2\n"
                                         "1 1.5\n10 2.5\n$EndElementData\n";
  EXPECT_EQ(read_mesh(dir.file("gaps.msh")).cell_fields.at(0).values, (std::vector<double>{1.5, 2.5}));
  Cells gaps;
  try {
    stream_mesh(dir.file("gaps.msh"), gaps, ReadOptions{}, notes);
    FAIL() << "cell data streamed with non-consecutive tet tags";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gaps.msh:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not consecutive"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("topotet convert"), std::string::npos) << e.what();
  }
}

// The reader announces its node tag map with the vertex count (the out-of-core budget counts it
// beside the cut's arrays): 4 bytes a tag up to the largest when the tags are compact, a hash
// node each when they are sparse; a visitor that checked it (returns true) gets the same vertices.
TEST(GmshStream, TheNodeTagMapIsAnnouncedWithTheVertices) {
  struct Holding : test::Recorder {
    std::uint64_t announced = 0, bytes = 0;
    bool checked = false;
    bool begin_vertices_holding(std::uint64_t count, std::uint64_t reader_bytes) override {
      announced = count;
      bytes = reader_bytes;
      begin_vertices(count);
      return checked;
    }
  };
  TempDir dir;
  const auto one_tet = [&](const std::string& name, std::uint64_t last_tag) {
    const std::string path = dir.file(name);
    std::ofstream(path) << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 " << last_tag
                        << "\n3 1 0 4\n1\n2\n3\n" << last_tag << "\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
                        << "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 " << last_tag << "\n$EndElements\n";
    return path;
  };
  for (const bool checked : {false, true}) {
    for (const std::uint64_t last : {std::uint64_t{4}, std::uint64_t{4'000'000'000}}) {
      Holding h;
      h.checked = checked;
      ReadNotes notes;
      stream_mesh(one_tet("t" + std::to_string(last) + ".msh", last), h, ReadOptions{}, notes);
      EXPECT_EQ(h.announced, 4u);
      EXPECT_EQ(h.bytes, last == 4 ? 4u * 5u : 48u * 4u) << last;
      ASSERT_EQ(h.m.tets.size(), 1u);
      EXPECT_EQ(h.m.tets[0], (std::array<VertId, 4>{0, 1, 2, 3}));
    }
  }
}

}  // namespace
}  // namespace topotet
