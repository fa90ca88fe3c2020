// Betti numbers of complexes certified to be manifolds, private to the topology checker: the fast
// path of compute_topology, linear in the complex's size and free of elimination.
//
//   surface  (pure 2-complex) certified when every edge is in at most 2 triangles and the
//            triangles around every vertex are connected through its edges (its link is one
//            cycle or one arc): a compact 2-manifold with boundary. Then, over Z2,
//              b0 = components, b2 = closed components, b1 = b0 + b2 - chi.
//            Exact for every compact surface, orientable or not, however it sits in space.
//   solid    (pure 3-complex) certified when every triangle is in at most 2 tets, the tets
//            around every edge are connected through its triangles (edge link: one cycle or one
//            arc), and around every vertex the tets are connected through its triangles and
//            their count gives a vertex link of Euler characteristic 2 (interior vertex: a
//            sphere) or 1 (boundary vertex: a disk): a compact 3-manifold with boundary M.
//            For M embedded in R^3 with every component bounded (no closed component), Alexander
//            duality gives, per component, b2 = boundary components - 1 (each boundary surface
//            separates space, and the complement components match them one to one), b3 = 0, and
//              b1 = b0 + b2 - chi.
//            The embedding is an assumption about the coordinates, not checked here: the caller
//            allows the solid path only when every tet is positively oriented (exact sign), and a
//            mesh of positively oriented tets that overlap elsewhere (an immersion, no valid mesh)
//            could get wrong b1 and b2. TopologyOptions::manifold_fast_path = false avoids it.
// Anything else (a certificate fails, a closed 3-manifold component, mixed dimensions) returns
// false, and the caller runs the algebraic reduction (z2_homology.h) instead.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "z2_homology.h"

namespace topotet::metrics::detail {

// Buffers reused across calls.
struct ManifoldScratch {
  std::vector<std::uint32_t> parent;  // union-find over vertex or (simplex, top simplex) pairs
  std::vector<std::uint32_t> face_cofaces;  // 2 per face (surface: per edge)
  std::vector<std::uint8_t> coface_count;
  std::vector<std::array<std::uint32_t, 3>> face_vertices;  // the 3 vertices of each triangle
  std::vector<std::array<std::uint32_t, 4>> tet_vertices;   // solid: vertex k opposite local face k
  std::vector<std::array<std::uint32_t, 6>> tet_edges;      // solid: by the pair of local faces sharing it
  std::vector<std::uint8_t> is_on_boundary;   // per vertex
  std::vector<std::int32_t> link_euler;       // per vertex: Euler characteristic of its link
};

// Pure 2-complex (no tets, every edge in a triangle). True with `betti` set when certified.
bool surface_betti(const LocalComplex& complex, ManifoldScratch& scratch, std::array<std::int64_t, 4>& betti);

// Pure 3-complex (every triangle in a tet). True with `betti` set when certified.
bool solid_betti(const LocalComplex& complex, ManifoldScratch& scratch, std::array<std::int64_t, 4>& betti);

}  // namespace topotet::metrics::detail
