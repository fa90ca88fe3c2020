// The tets around a tet of a Freudenthal grid, in closed form, and the test that keeps grown
// material regions balls (ball_growth.h).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "generate/freudenthal_grid.h"

namespace topotet::gen {

// Every Kuhn tet shares at least a vertex with 70 others (4 of them across its faces), all in
// the 27 cubes around its own; a table per Kuhn path gives their id offsets.
class TetNeighbourhood {
 public:
  explicit TetNeighbourhood(const FreudenthalGrid& grid);

  // True when adding tet t (not of material m) to the region of tets with material m keeps that
  // region a ball: t meets the region in one, two or three of its faces and touches it nowhere
  // else (no further edge or vertex of t is in a tet of m). Two 3-balls whose intersection is a
  // disc in both boundaries make a ball (a standard PL lemma, Rourke & Sanderson ch. 3).
  bool joins_as_ball(TetId t, std::int32_t m, const std::vector<std::int32_t>& material) const;

  // True when removing tet t from its region (material[t]) leaves a ball. The region's complement
  // in the 3-sphere (the other tets and everything outside the box) is a ball too (Alexander), and
  // removing t from the region is adding it to the complement: t must meet the complement in a
  // disc. Unlike the join test this must count the box boundary: a region touching the boundary
  // along an edge of t would otherwise be left pinched along that edge.
  bool leaves_as_ball(TetId t, const std::vector<std::int32_t>& material) const;

  // Calls f(u) for each tet u across a face of t (4 of them; fewer on the box boundary).
  template <class F>
  void for_each_face_neighbour(TetId t, F&& f) const {
    const Place at = place(t);
    for (const Entry& e : faces_[at.perm])
      if (at.is_interior || inside(at, e)) f(static_cast<TetId>(t + e.delta));
  }
  // Calls f(u) for each tet u sharing a vertex with t, in a fixed order.
  template <class F>
  void for_each_neighbour(TetId t, F&& f) const {
    const Place at = place(t);
    for (const Entry& e : entries_[at.perm])
      if (at.is_interior || inside(at, e)) f(static_cast<TetId>(t + e.delta));
  }

 private:
  struct Entry {
    std::int32_t delta;  // tet id step
    std::uint8_t shared;  // bit q: the q-th vertex along the centre tet's Kuhn path is shared
    std::array<std::int8_t, 3> cube_offset;
  };
  struct Place {
    std::array<std::uint32_t, 3> cube;
    int perm;
    bool is_interior;  // no neighbour cube falls outside the grid
  };
  Place place(TetId t) const;
  bool inside(const Place& at, const Entry& e) const {
    for (int a = 0; a < 3; ++a) {
      const std::int64_t c = std::int64_t{at.cube[a]} + e.cube_offset[a];
      if (c < 0 || c >= cells_[a]) return false;
    }
    return true;
  }
  // The simplices of t (bit s = vertex subset s along the path) that lie on the box boundary.
  std::uint32_t boundary_contact(const Place& at) const;
  // The simplices of t's boundary shared with tets for which is_in(material) holds.
  template <class IsIn>
  std::uint32_t contact(TetId t, const Place& at, const std::vector<std::int32_t>& material, IsIn&& is_in) const {
    std::uint32_t bits = 0;
    if (at.is_interior) {
      for (const Entry& e : entries_[at.perm])
        bits |= std::uint32_t{is_in(material[static_cast<std::size_t>(std::int64_t{t} + e.delta)])} << e.shared;
    } else {
      for (const Entry& e : entries_[at.perm])
        if (inside(at, e))
          bits |= std::uint32_t{is_in(material[static_cast<std::size_t>(std::int64_t{t} + e.delta)])} << e.shared;
    }
    return bits;
  }

  Cells cells_;
  std::array<std::vector<Entry>, 6> entries_;  // the 70 tets sharing a vertex
  std::array<std::vector<Entry>, 6> faces_;    // the 4 sharing a face
};

// Centroid of a grid tet, in lattice coordinates.
glm::dvec3 tet_centroid(const FreudenthalGrid& grid, TetId t);

// The vertex ids of a grid tet, along its Kuhn path.
std::array<VertId, 4> tet_vertices(const FreudenthalGrid& grid, TetId t);

}  // namespace topotet::gen
