// Renumbering a MeshModel for memory locality before it is simplified.
//
// Every kernel of the engines walks stars: a vertex's tets through the incidence chains, then
// their vertices' positions, flags and quadrics. On a large mesh those reads miss the cache unless
// neighbours in space are neighbours in memory. Meshers write vertices and tets in all kinds of
// orders (a randomly shuffled 1M-tet mesh simplified 1.7x slower than the same mesh in grid
// order), so simplify() first sorts the live vertices along a Morton (Z-order) curve of their
// positions and the live tets along the curve of their centroids, then rebuilds the incidence.
// Ties are broken by the old ids, so the result is a pure function of the mesh (deterministic for
// any thread count). Dead vertices and tets are dropped, as compact() would.
#pragma once

#include <vector>

#include "mesh/mesh_model.h"

namespace topotet {

// new2old, when given, receives the old id of every new vertex id; tet_old2new the new id of
// every old tet (kInvalid for a dead one).
void reorder_for_locality(MeshModel& mesh, std::vector<VertId>* new2old = nullptr,
                          std::vector<TetId>* tet_old2new = nullptr);

}  // namespace topotet
