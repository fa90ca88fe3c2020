// MeshView: a mesh held in a caller's own arrays, seen through typed strided views, so that the C
// API and the Python module build the model straight from them (build_mesh_model below) instead of
// copying them into a MeshData first: the model's arrays are the only copy the library makes.
// Internal (not installed): the public forms are topotet_view (topotet/topotet_c.h) and numpy.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/mesh_model.h"

namespace topotet {

// One array of rows: value `col` of row `row` is at data + row * row_stride + col * column_stride.
struct StridedArray {
  enum class Type : std::uint8_t { kFloat64, kFloat32, kInt32, kInt64 };
  const void* data = nullptr;  // nullptr: not given
  Type type = Type::kFloat64;
  std::int64_t row_stride = 0;     // bytes; 0 = rows packed one after the other
  std::int64_t column_stride = 0;  // bytes; 0 = the values of a row packed

  bool given() const { return data != nullptr; }
  bool is_integer() const { return type == Type::kInt32 || type == Type::kInt64; }
  // `width`: values per row, for the packed defaults.
  double real(std::size_t row, int col, int width) const;
  std::int64_t integer(std::size_t row, int col, int width) const;
};

struct FieldView {
  std::string name;
  int components = 1;
  StridedArray values;  // rows of `components` reals, one per vertex
};

struct MeshView {
  std::size_t vertex_count = 0;
  std::size_t tet_count = 0;
  StridedArray positions;    // rows of 3 reals
  StridedArray tets;         // rows of 4 integer vertex indices, counted from index_base
  StridedArray materials;    // one integer per tet; not given = all 0
  StridedArray vertex_refs;  // one integer per vertex; not given = all 0
  int index_base = 0;        // 0 or 1
  std::vector<FieldView> fields;
  // Listed substructures, 0-based: surfaces and curves are small next to the volume, so callers
  // convert them into these lists.
  std::vector<Triangle> triangles;
  std::vector<Segment> segments;
  std::vector<VertId> corners;
};

// build_mesh_model for a view: the same checks and messages as for a MeshData (tet_mesh.h), plus
// "tet N: vertex index X out of range" for an index that is not a vertex id at all (negative, or
// 2^32 and above, counted from index_base) and "material N: X does not fit in 32 bits". Elements
// are counted from 1 in the messages, as build_tet_mesh counts them.
MeshModel build_mesh_model(const MeshView& view, const BuildOptions& options = {}, BuildNotes* notes = nullptr);

namespace detail {

struct ListedSubstructures {
  const std::vector<Triangle>& triangles;
  const std::vector<Segment>& segments;
  const std::vector<std::uint32_t>& ridges;
  const std::vector<VertId>& corners;
  const std::vector<VertId>& required_vertices;
};

// The one validation and build path (build_mesh.cpp): `loaded` holds the input's positions, tets,
// materials, vertex refs, fields and group names, unchecked; everything else is derived here.
MeshModel build_loaded_model(MeshModel loaded, const ListedSubstructures& listed, const BuildOptions& options,
                             BuildNotes* notes);

}  // namespace detail

}  // namespace topotet
