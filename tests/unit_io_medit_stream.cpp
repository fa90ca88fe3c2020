// MEDIT read and written as a stream (topotet/medit_stream.h), the io layer under the out-of-core
// path: the visitor and SolStream see exactly what read_mesh keeps, the stream writer refuses
// misuse and leaves nothing behind, and what it needs to stream (Vertices first, fields in the
// .sol) is refused with a message when a file does not give it.
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "io_test_files.h"
#include "topotet/error.h"
#include "topotet/io.h"
#include "topotet/medit_stream.h"
#include "stream_recorder.h"

namespace topotet {
namespace {

namespace fs = std::filesystem;
using test::read_text;
using test::TempDir;
using test::write_text;
using test::Recorder;

std::string shared(const std::string& rel) { return std::string(TOPOTET_SHARED_DATA_DIR) + "/" + rel; }

void expect_stream_matches_read_mesh(const std::string& path) {
  SCOPED_TRACE(path);
  const MeshData full = read_mesh(path);
  Recorder rec;
  ReadNotes notes;
  stream_medit(path, rec, ReadOptions{}, notes);
  test::expect_recorded(rec, full, true);

  // SolStream gives each vertex's values of every field, in field order, then each tet's.
  SolStream sol(path, full.positions.size(), full.tets.size());
  ASSERT_EQ(sol.vertex_fields().size(), full.fields.size());
  ASSERT_EQ(sol.cell_fields().size(), full.cell_fields.size());
  for (std::size_t f = 0; f < full.fields.size(); ++f) {
    EXPECT_EQ(sol.vertex_fields()[f].name, full.fields[f].name);
    EXPECT_EQ(sol.vertex_fields()[f].components, full.fields[f].components);
  }
  std::vector<double> values(static_cast<std::size_t>(std::max(sol.vertex_stride(), sol.cell_stride())) + 1);
  for (std::size_t v = 0; v < full.positions.size(); ++v) {
    sol.next_vertex(values.data());
    int k = 0;
    for (const VertexField& f : full.fields)
      for (int c = 0; c < f.components; ++c) ASSERT_EQ(values[k++], f.values[v * f.components + c]) << "vertex " << v;
  }
  for (std::size_t t = 0; t < full.tets.size() && sol.cell_stride() > 0; ++t) {
    sol.next_tet(values.data());
    int k = 0;
    for (const CellField& f : full.cell_fields)
      for (int c = 0; c < f.components; ++c) ASSERT_EQ(values[k++], f.values[t * f.components + c]) << "tet " << t;
  }
}

TEST(MeditStream, VisitorAndSolStreamSeeWhatReadMeshKeeps) {
  for (const char* rel : {"mmg/tinyBoxt.mesh", "mmg/torus.mesh", "volume/lox_post_tets.mesh.gz"}) {
    if (!fs::exists(shared(rel))) GTEST_SKIP() << "missing test input " << shared(rel);
    expect_stream_matches_read_mesh(shared(rel));
  }
}

// Every section and both kinds of fields (test::two_tets and a cell field), through write_mesh
// (built on the stream writer).
MeshData every_section() {
  MeshData m = test::two_tets();
  m.cell_fields = {{"conductivity", 1, CellFieldKind::kIntensive, {5.0, 6.5}}};
  return m;
}

TEST(MeditStream, MeshWithFieldsStreamsBack) {
  TempDir dir;
  write_mesh(dir.file("a.mesh"), every_section());
  EXPECT_TRUE(fs::exists(dir.file("a.sol")));
  EXPECT_TRUE(fs::exists(dir.file("a.sol.fields.txt")));  // names other than sol0..
  expect_stream_matches_read_mesh(dir.file("a.mesh"));
}

// The writer fed by hand gives the bytes write_mesh gives for the same mesh.
TEST(MeditStream, WriterByHandGivesWriteMeshBytes) {
  TempDir dir;
  const MeshData m = every_section();
  write_mesh(dir.file("ref.mesh"), m);
  {
    MeditStreamWriter w(dir.file("hand.mesh"), m.fields, m.cell_fields);
    w.begin_vertices(m.positions.size());
    std::vector<double> values;
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
      values.clear();  // every field's values of vertex v, in field order
      for (const VertexField& f : m.fields)
        values.insert(values.end(), f.values.begin() + v * f.components, f.values.begin() + (v + 1) * f.components);
      w.vertex(m.positions[v], m.vertex_refs[v], values.data());
    }
    w.begin_tets(m.tets.size());
    for (std::size_t t = 0; t < m.tets.size(); ++t) w.tet(m.tets[t], m.tet_material[t], &m.cell_fields[0].values[t]);
    w.begin_triangles(1);
    w.triangle(m.triangles[0]);
    w.begin_segments(2);
    w.segment(m.segments[0]);
    w.segment(m.segments[1]);
    w.begin_ridges(1);
    w.ridge(1);
    w.begin_corners(1);
    w.corner(0);
    w.begin_required_vertices(2);
    w.required_vertex(0);
    w.required_vertex(4);
    EXPECT_FALSE(fs::exists(dir.file("hand.mesh"))) << "nothing at the path before commit";
    w.commit();
  }
  EXPECT_EQ(read_text(dir.file("hand.mesh")), read_text(dir.file("ref.mesh")));
  EXPECT_EQ(read_text(dir.file("hand.sol")), read_text(dir.file("ref.sol")));
  EXPECT_EQ(read_text(dir.file("hand.sol.fields.txt")), read_text(dir.file("ref.sol.fields.txt")));
}

TEST(MeditStream, WriterMisuseThrowsAndLeavesNothing) {
  TempDir dir;
  const std::array<double, 3> p{0, 0, 0};
  {  // fewer entries than declared
    MeditStreamWriter w(dir.file("short.mesh"));
    w.begin_vertices(3);
    w.vertex(p, 0, nullptr);
    EXPECT_THROW(w.commit(), std::logic_error);
  }
  {  // a section out of order
    MeditStreamWriter w(dir.file("order.mesh"));
    w.begin_vertices(1);
    w.vertex(p, 0, nullptr);
    w.begin_triangles(0);
    EXPECT_THROW(w.begin_tets(0), std::logic_error);
  }
  {  // destroyed without commit
    MeditStreamWriter w(dir.file("dropped.mesh"), {{"s", 1, {}}});
    w.begin_vertices(1);
    const double s = 1.0;
    w.vertex(p, 0, &s);
  }
  EXPECT_TRUE(dir.entries().empty()) << "left: " << (dir.entries().empty() ? "" : dir.entries()[0]);
}

TEST(MeditStream, WhatCannotBeStreamedIsRefusedWithTheLine) {
  TempDir dir;
  const std::string head = "MeshVersionFormatted 2\nDimension 3\n";
  const std::string vertices = "Vertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n";
  // read_mesh takes sections in any order; the stream needs Vertices first and Edges before Ridges.
  write_text(dir.file("tets_first.mesh"), head + "Tetrahedra\n1\n1 2 3 4 0\n" + vertices + "End\n");
  write_text(dir.file("ridges_first.mesh"), head + vertices + "Ridges\n1\n1\nEdges\n1\n1 2 0\nEnd\n");
  write_text(dir.file("sol_inside.mesh"), head + vertices + "SolAtVertices\n4\n1 1\n1\n2\n3\n4\nEnd\n");
  EXPECT_NO_THROW(read_mesh(dir.file("tets_first.mesh")));
  EXPECT_NO_THROW(read_mesh(dir.file("ridges_first.mesh")));
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"tets_first.mesh", ":3:"}, {"ridges_first.mesh", ":10:"}, {"sol_inside.mesh", ":9:"}};
  for (const auto& [file, line] : cases) {
    SCOPED_TRACE(file);
    MeditVisitor nothing;
    ReadNotes notes;
    test::expect_input_error([&] { stream_medit(dir.file(file), nothing, ReadOptions{}, notes); },
                             {dir.file(file), line});
  }
  // Out-of-range indices and truncation: the same messages as read_mesh.
  write_text(dir.file("range.mesh"), head + vertices + "Tetrahedra\n1\n1 2 3 9 0\nEnd\n");
  write_text(dir.file("cut.mesh"), head + vertices + "Tetrahedra\n2\n1 2 3 4 0\n");
  for (const char* file : {"range.mesh", "cut.mesh"}) {
    SCOPED_TRACE(file);
    MeditVisitor nothing;
    ReadNotes notes;
    std::string streamed, whole;
    try {
      stream_medit(dir.file(file), nothing, ReadOptions{}, notes);
    } catch (const InputError& e) {
      streamed = e.what();
    }
    try {
      read_mesh(dir.file(file));
    } catch (const InputError& e) {
      whole = e.what();
    }
    EXPECT_FALSE(streamed.empty());
    EXPECT_EQ(streamed, whole);
  }
}

}  // namespace
}  // namespace topotet
