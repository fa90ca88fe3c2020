// Proving a piece of a new surface triangle within h of the original surface with the few original
// triangles around it, by cutting the piece where the nearest facet changes.
//
// Why: on a curved surface a new triangle spans several original triangles and passes near their
// shared vertices. One facet (convexity) or two across an edge (the crease test) prove only the
// parts of it over one facet or one edge, so the check split every piece that straddles an
// original vertex down to the Lipschitz scale, about h, with a nearest-triangle search per piece:
// sphere3 at 10%, 25 pieces per new triangle and 42% of the run.
//
// The proof: the distance to one triangle is convex, so a convex polygon whose vertices are all
// within h of one facet lies within h of it everywhere. The piece is cut by planes (a binary space
// partition: the parts of each cut cover the region cut) until every part has such a facet among
// the candidates (the facets near the piece's nearest one). A cut keeps the vertices of the facet
// most of them are near on one side: it goes through the crease between that facet and an adjacent
// one a vertex outside it needs, where that separates them, else through the perpendicular
// bisector of that vertex and the farthest inside one, which always separates them. "Yes" is a proof
// whatever the planes are; "no" (a vertex within h of no candidate, or the budget of parts spent)
// only sends the piece back to the caller's split.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "topotet/mesh_data.h"

namespace topotet {

struct SurfaceSoup;

// Is every point of triangle q within h of the soup triangles of `nearest`'s label? Candidates:
// `nearest` and the triangles reached from it through `neighbour` (FlatPatches::neighbour: the
// other triangle of the label across each edge) that come within r + h of q's centre, a ring at a
// time as the parts need them (at most 64).
bool within_by_facets(const SurfaceSoup& soup, const std::vector<std::uint32_t>& neighbour,
                      const std::array<glm::dvec3, 3>& q, double h, std::uint32_t nearest);

}  // namespace topotet
