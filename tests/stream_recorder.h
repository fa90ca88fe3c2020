// A MeditVisitor that rebuilds a MeshData (fields aside) from the calls of a stream
// (topotet/medit_stream.h, topotet/mesh_stream.h), with the counts each section declared: the
// stream readers' tests compare it with what read_mesh keeps.
#pragma once

#include <cstdint>

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

}  // namespace topotet::test
