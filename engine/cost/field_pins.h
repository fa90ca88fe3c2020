// Field values pinned on isosurfaces (SimplifyOptions::isosurfaces, topotet/isosurface.h).
//
// Every vertex of a triangle listed with a level's ref must keep that field component at exactly
// the level through the whole simplification: the isosurface's vertices then stay ON the level
// set of the simplified field, not next to it. A vertex's pins are a bit mask over the field
// components (field_stride() order, at most kMaxPinnedComponents). The value pinned is the
// vertex's own, which compute_field_pins checks is the level at the start; after a collapse
// u <- v the survivor's mask is the union of both (a vertex of a level triangle after the
// collapse was one before as u or as v: a collapse only renames v to u), and each pinned
// component takes the value of the end that pinned it (fields_at in cost.cpp). Two ends pinned in
// one component to different values (two levels of one field) never merge (cost.cpp refuses it):
// the link conditions keep two distinct surfaces from touching anyway, this makes it explicit.
// Why not the quadric: the cost could also be evaluated with the pinned component fixed, but the
// values are set after the placement is chosen, and a pinned vertex is on a surface whose
// placements are its endpoints or the midpoint of an edge in it, where the level is already the
// field's value (both ends at the level): the quadric's choice there differs by its fit only.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mesh/mesh_model.h"
#include "topotet/isosurface.h"

namespace topotet {

inline constexpr int kMaxPinnedComponents = 32;

// pins[v] = the components pinned at vertex v (bit k = component k of the interleaved field
// values). Returns an empty string, or why the levels do not fit the mesh (unknown field, a
// component past kMaxPinnedComponents, a level's triangle vertex whose value is not the level).
// A level whose ref lists no triangle pins nothing (the level set missed the mesh).
std::string compute_field_pins(const MeshModel& mesh, const std::vector<IsoLevel>& levels,
                               std::vector<std::uint32_t>& pins);

}  // namespace topotet
