// Material labels for a mesh that lost them: each tet takes the material of the input tet that
// contains its centroid; and a count of the tets that an input interface runs through.
//
// The VTK peer comparison uses it to *show* what an unlabelled decimation does to the interfaces:
// VTK's output has no materials, so the checker cannot even compare its interfaces. The same
// transfer applied to topotet's output is the control (agreement with topotet's own labels).
// Note: the relabelled mesh is no topology test. A few mislabelled tets near a curved interface
// (where the coarse interface has moved) make small islands, so even topotet's output, relabelled,
// fails the checker; we therefore report the straddling count, not a verdict.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet::bench {

struct MaterialTransfer {
  std::vector<std::int32_t> tet_material;  // [tet of the target]
  std::size_t outside = 0;  // centroids in no source tet (labelled from the least-outside candidate)
  // Tets with an input interface running through them: points near their corners lie in another
  // input material than their centroid. topotet keeps interfaces on faces, so its count measures
  // only the geometric drift of the coarse interface; VTK's also counts tets cut by one.
  std::size_t straddling = 0;
};

// Point location on a uniform grid over the source tets' bounding boxes (single-threaded; a few
// hundred ms for 1M source tets).
MaterialTransfer transfer_materials(const MeshData& source, const MeshData& target);

}  // namespace topotet::bench
