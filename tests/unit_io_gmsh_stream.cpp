// Gmsh MSH 4.1 read as a stream (topotet/mesh_stream.h), for the out-of-core path: the visitor
// sees exactly the vertices, tets, materials, listed triangles and lines (one copy per physical
// group), ridges, corners and required vertices that read_mesh keeps, in ASCII and binary, on a
// file Gmsh itself wrote and on ours; MSH 2 and fields, which a stream does not take, are refused
// with a message that says where and how to convert.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace topotet
