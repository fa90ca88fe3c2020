// A uniform grid over a set of tets, for the remap's two searches (remap_cell_fields.cpp):
//  - which tets' bounding boxes meet a box (each tet is listed in every cell its box meets);
//  - which tet of a material has its centroid nearest a point (the fallback near moved surfaces;
//    a tet's centroid lies in its box, so it is listed in the centroid's cell too).
// About 8 tets per cell on average: small enough cells that a query box meets few tets it does
// not overlap, large enough that a tet is listed in few cells (the grid's memory is a few ids per
// tet). Cells are compressed (CSR); ids within a cell are increasing.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "topotet/mesh_data.h"

namespace topotet::cell_data {

struct Box {
  glm::dvec3 lo, hi;
  bool meets(const Box& o) const {
    return lo.x <= o.hi.x && o.lo.x <= hi.x && lo.y <= o.hi.y && o.lo.y <= hi.y && lo.z <= o.hi.z && o.lo.z <= hi.z;
  }
};

Box tet_box(const MeshData& m, std::size_t t);
glm::dvec3 tet_centroid(const MeshData& m, std::size_t t);

class TetGrid {
 public:
  explicit TetGrid(const MeshData& mesh);

  // Appends to `out` the tets of `material` whose boxes meet `box`, each once, in no useful order.
  // A tet listed in several of the cells `box` meets is taken in the first of them only (the cell
  // of its box's low corner, moved into the query's range: firsts_ says, per entry and axis,
  // whether the entry's cell is the tet's first along that axis), so repeats cost no sort and no
  // position load.
  void gather(const Box& box, std::int32_t material, std::vector<TetId>& out) const;

  // The tet of `material` (of any material when `any_material`) whose centroid is nearest `point`
  // (ties: the smaller id); kInvalid when the mesh has no such tet.
  TetId nearest(const glm::dvec3& point, std::int32_t material, bool any_material = false) const;

 private:
  std::array<int, 3> cell_of(const glm::dvec3& p) const;
  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(dims_[1]) + static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(dims_[0]) +
           static_cast<std::size_t>(x);
  }

  const MeshData& mesh_;
  glm::dvec3 lo_{0.0}, cell_size_{1.0};
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<std::size_t> offsets_;  // [cell] into ids_, one past the end at the back
  std::vector<TetId> ids_;
  std::vector<std::uint8_t> firsts_;  // [entry] bit a: the entry's cell is the tet's first along axis a
};

}  // namespace topotet::cell_data
