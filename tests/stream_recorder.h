// A MeditVisitor that rebuilds a MeshData (fields aside) from the calls of a stream
// (topotet/medit_stream.h, topotet/mesh_stream.h), with the counts each section declared: the
// stream readers' tests compare it with what read_mesh keeps.
#pragma once

#include <cstdint>
#include <cstring>

#include <gtest/gtest.h>

#include "topotet/medit_stream.h"
#include "topotet/mesh_data.h"

namespace topotet::test {

struct Recorder : MeditVisitor {
  MeshData m;
  std::uint64_t declared_vertices = 0, declared_tets = 0, declared_triangles = 0, declared_segments = 0;
  void begin_vertices(std::uint64_t n) override { declared_vertices = n; }
  void vertex(const std::array<double, 3>& p, std::int32_t ref) override {
    m.positions.push_back(p);
    m.vertex_refs.push_back(ref);
  }
  void begin_tets(std::uint64_t n) override { declared_tets = n; }
  void tet(const std::array<VertId, 4>& v, std::int32_t material) override {
    m.tets.push_back(v);
    m.tet_material.push_back(material);
  }
  void begin_triangles(std::uint64_t n) override { declared_triangles = n; }
  void triangle(const Triangle& t) override { m.triangles.push_back(t); }
  void begin_segments(std::uint64_t n) override { declared_segments = n; }
  void segment(const Segment& s) override { m.segments.push_back(s); }
  void corner(VertId v) override { m.corners.push_back(v); }
  void required_vertex(VertId v) override { m.required_vertices.push_back(v); }
  void ridge(std::uint32_t i) override { m.ridges.push_back(i); }
};

// What `rec` recorded is what read_mesh kept in `full` (fields aside): the vertices bit for bit, their
// refs (0 where `full` has none), the tets and materials, and every listed entity in order.
// `exact_tet_count`: begin_tets declared the tet count (MEDIT), else an upper bound (a .msh gives
// its element count).
inline void expect_recorded(const Recorder& rec, const MeshData& full, bool exact_tet_count) {
  ASSERT_EQ(rec.m.positions.size(), full.positions.size());
  EXPECT_EQ(rec.declared_vertices, full.positions.size());
  EXPECT_EQ(std::memcmp(rec.m.positions.data(), full.positions.data(), full.positions.size() * sizeof(full.positions[0])), 0);
  if (full.vertex_refs.empty()) {
    for (std::int32_t r : rec.m.vertex_refs) ASSERT_EQ(r, 0);
  } else {
    EXPECT_EQ(rec.m.vertex_refs, full.vertex_refs);
  }
  if (exact_tet_count) {
    EXPECT_EQ(rec.declared_tets, full.tets.size());
  } else {
    EXPECT_GE(rec.declared_tets, full.tets.size());
  }
  EXPECT_EQ(rec.m.tets, full.tets);
  EXPECT_EQ(rec.m.tet_material, full.tet_material);
  EXPECT_EQ(rec.m.triangles, full.triangles);
  EXPECT_EQ(rec.m.segments, full.segments);
  EXPECT_EQ(rec.m.ridges, full.ridges);
  EXPECT_EQ(rec.m.corners, full.corners);
  EXPECT_EQ(rec.m.required_vertices, full.required_vertices);
}

}  // namespace topotet::test
