// Nearly flat patches of the original surfaces: what lets the tolerance check prove a large new
// triangle within h of a surface made of many small original triangles in one step.
//
// A patch is a set of original triangles of ONE label, connected through manifold edges, oriented
// consistently, whose normals all lie within 60 degrees of the patch normal n and whose vertices
// all lie within `deviation` (<= the asked maximum) of the patch plane P (the plane of the seed
// triangle). Then the orthogonal projection onto P is a local homeomorphism on the patch (no fold:
// every triangle keeps its orientation), so the boundary of the patch's shadow on P lies in the
// shadow of the patch's boundary edges. Consequence used by the check (surface_tolerance.cpp,
// triangle_within): for a piece Q of a new triangle with centre c and radius r (c to its farthest
// corner), if c's shadow c' lies in the shadow of a patch triangle and no boundary edge of the
// patch is within sqrt(r^2 + deviation^2) of c', the disk of radius r around c' lies in the patch's
// shadow, so every point x of Q has a patch point s with the same shadow, and
//   |x - s| <= dist(x, P) + deviation <= max over Q's corners of dist(corner, P) + deviation
// (the distance to a plane is convex). That is a proof for the whole piece whatever the number of
// original triangles below it, where the Lipschitz pieces of the check would need pieces of about
// h in size.
//
// Built once per reference, in triangle order (deterministic): seeds are taken in index order,
// and a patch grows breadth-first over edges shared by exactly two triangles of its label.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "topotet/mesh_data.h"

namespace topotet {

struct SurfaceSoup;

struct FlatPatches {
  struct Patch {
    glm::dvec3 normal;  // unit
    double offset;      // the plane is dot(normal, x) = offset
    double deviation;   // largest distance of a patch vertex from the plane
  };
  std::vector<Patch> patches;
  std::vector<std::uint32_t> patch_of;               // [soup triangle]
  std::vector<std::array<VertId, 2>> boundary;       // boundary edges of every patch
  std::vector<std::uint32_t> boundary_patch;         // [boundary edge] its patch
  // [3 t + k]: the only other triangle of t's label across t's edge k (corner k to k + 1), or
  // kInvalid (border, non-manifold edge). Also used by the crease test (surface_tolerance.cpp).
  std::vector<std::uint32_t> neighbour;
};

// max_deviation > 0: the largest distance from the plane a patch vertex may have.
FlatPatches find_flat_patches(const SurfaceSoup& soup, double max_deviation);

}  // namespace topotet
