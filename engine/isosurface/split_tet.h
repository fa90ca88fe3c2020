// Splitting one tet, or one triangle, along a level (marching tets with a consistent subdivision).
//
// The level cuts a tet with vertices strictly on both sides into two convex pieces: a tet and a
// prism (1-3 cut), two prisms (2-2), or a tet and a pyramid / two tets when vertices lie on the
// level. Each piece is triangulated by PULLING from its smallest vertex id v0: the tets are v0
// coned over the faces of the piece that do not contain v0, and every such face (a convex polygon)
// is fanned from its own smallest id. A face containing v0 is then fanned from v0, which is its
// smallest id too. So every face, whether shared with a neighbour tet (a clipped tet face), with the
// other piece (the cap, i.e. the isosurface polygon) or not at all, is triangulated by its own ids
// alone: from its smallest one (the global min-vertex-index diagonal rule for quads). Neighbours
// therefore agree on every shared face, and the cyclic prism that no tets can fill cannot arise
// (pulling triangulates any convex polytope). Ids are global: new crossing vertices have ids above
// every input vertex, which the rule does not care about.
#pragma once

#include <array>
#include <cstdint>

#include "topotet/mesh_data.h"

namespace topotet::iso {

// Side of the level: -1 below, 0 on it, +1 above.
using Side = std::int8_t;

struct TetPieces {
  int tet_count = 0;                         // 2..6
  std::array<std::array<VertId, 4>, 6> tets; // positively oriented when the input tet is
  int cap_count = 0;                         // 1..2 isosurface triangles
  // Oriented as the faces of the piece below the level (kTetFaces order of mesh_model.h): every
  // isosurface triangle of a level faces the same way.
  std::array<std::array<VertId, 3>, 2> cap;
};

// `crossing(a, b)` returns the id of the new vertex on edge ab (sides strictly opposite).
// `tet` must have vertices strictly on both sides.
template <class Crossing>
TetPieces split_tet(const std::array<VertId, 4>& tet, const std::array<Side, 4>& side, Crossing&& crossing);

// The pieces of triangle `tri` (vertices strictly on both sides) as triangles with the input's
// orientation, fanned as split_tet fans the same face: up to 3.
struct TrianglePieces {
  int count = 0;
  std::array<std::array<VertId, 3>, 3> tris;
};
template <class Crossing>
TrianglePieces split_triangle(const std::array<VertId, 3>& tri, const std::array<Side, 3>& side, Crossing&& crossing);

}  // namespace topotet::iso

#include "isosurface/split_tet_impl.h"
