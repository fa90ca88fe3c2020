// The faces of a mesh that the substructures or the boundary make special: boundary faces and
// faces flagged on either side (listed surfaces, material interfaces). The tolerance's reference
// is built from them, and the feature detection looks only at their vertices, so the driver finds
// them once for both (a look at every vertex's star is the dearest part of either setup).
#pragma once

#include <cstdint>
#include <vector>

#include "mesh/mesh_model.h"

namespace topotet {

struct SpecialFace {
  TetId tet;            // the smaller of the face's tets
  std::uint8_t local;   // its local face there
  std::uint8_t other_local;
  TetId other;          // the tet on the other side (kInvalid: a boundary face)
};

struct SpecialFaces {
  std::vector<SpecialFace> faces;      // in (tet, local) order: the same for any schedule
  std::vector<std::uint8_t> on_face;   // [vertex] 1 if the vertex is on one of them
};

// Matches each face at its smallest vertex (a star's worth of faces there, sorted in cache),
// in parallel over blocks of vertices.
SpecialFaces find_special_faces(const detail::MeshModel& mesh);

}  // namespace topotet
