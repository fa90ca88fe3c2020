// A small mesh with cell fields of every kind, for the round trips of the formats that carry them
// (unit_io_cell_fields.cpp, unit_io_vtk_cell_fields.cpp).
#pragma once

#include <algorithm>
#include <map>
#include <string>

#include "topotet/mesh_data.h"

namespace topotet::test {

// Three tets, materials 2, 1, 2 (writers that group tets by material reorder them), a vertex
// field, and cell fields: a real scalar, a label, a 3-vector and a symmetric tensor.
inline MeshData mesh_with_cell_fields() {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {-1, 0, 0}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}, {0, 2, 5, 3}};
  m.tet_material = {2, 1, 2};
  m.fields = {{"p", 1, {0.5, 1.5, 2.5, 3.5, 4.5, 5.5}}};
  m.cell_fields = {
      {"density", 1, CellFieldKind::kIntensive, {1.25, -2.0e-7, 3.0 / 7.0}},
      {"region", 1, CellFieldKind::kCategorical, {7, -3, 12}},
      {"velocity", 3, CellFieldKind::kIntensive, {1, 2, 3, 4, 5, 6, 7, 8, 9}},
      {"stress", 6, CellFieldKind::kIntensive, std::vector<double>(18, 0.0)},
  };
  for (std::size_t i = 0; i < 18; ++i) m.cell_fields[3].values[i] = 0.1 * static_cast<double>(i) - 0.3;
  return m;
}

// The values of each cell field by tet (its sorted vertices), so that files that reorder the tets
// compare equal; `kinds` compares the kinds too.
inline std::map<std::string, std::map<std::array<VertId, 4>, std::vector<double>>> cell_values_by_tet(const MeshData& m) {
  std::map<std::string, std::map<std::array<VertId, 4>, std::vector<double>>> out;
  for (const CellField& f : m.cell_fields) {
    const auto c = static_cast<std::size_t>(f.components);
    for (std::size_t t = 0; t < m.tets.size(); ++t) {
      std::array<VertId, 4> key = m.tets[t];
      std::sort(key.begin(), key.end());
      out[f.name][key].assign(f.values.begin() + static_cast<std::ptrdiff_t>(t * c),
                              f.values.begin() + static_cast<std::ptrdiff_t>((t + 1) * c));
    }
  }
  return out;
}

}  // namespace topotet::test
