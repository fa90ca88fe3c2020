// Region growing on a Freudenthal grid that keeps every material region a 3-ball.
//
// Why not classify and repair (repair_pinches in freudenthal_grid.h): that grows one material
// over a background at interior vertices. With hundreds of cells there is no background, a repair
// of one cell can pinch its neighbour, cells meet the box everywhere, and a repaired region can
// still hold a tunnel or a cavity. Growing by ball-preserving steps makes the guarantee hold by
// construction instead.
//
// A region starts as one seed tet (a ball) and only ever changes by steps that keep it a ball
// (TetNeighbourhood::joins_as_ball, leaves_as_ball), so every region is a ball at every step,
// whatever the order of the steps: one component, no pinch, no tunnel, no cavity.
//
//   grow breadth first from the seeds, each region within the tets that prefer it;
//   repeat until every tet has a region:
//     pass over the free tets: each joins the best region across its faces that it can join
//       (its preferred one first, then the one whose site is nearest its centroid);
//     if a pass assigns nothing, some free tet is wedged: each region across its faces also
//       touches it along an edge or at a vertex outside those faces. Grow one of them around the
//       tet (move neighbours of the tet into it, each move keeping both regions balls) until the
//       tet can join; undo and try the next region if it cannot.
// Throws std::logic_error when no region can take a wedged tet. That has not happened on any
// polycrystal the tests sweep (tens of sizes and cell counts); it would need the neighbours of the
// tet to be locked by regions wrapping around them too.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "generate/freudenthal_grid.h"

namespace topotet::gen {

struct GrowthStats {
  std::uint64_t off_preference_tets = 0;  // tets whose region is not the one they preferred
  std::uint64_t wedged_tets = 0;          // free tets that needed neighbour moves to join
  std::uint64_t moves = 0;                // those neighbour moves
};

// Fills `material` (one entry per tet of the grid) with 1..seeds.size(): region m grows from the
// tet seeds[m - 1] (distinct tets). preferred[t] (1-based) is the region t should join when it
// can; sites[m - 1] (lattice coordinates) ranks the others by distance to t's centroid.
GrowthStats grow_ball_regions(const FreudenthalGrid& grid, const std::vector<TetId>& seeds,
                              const std::vector<std::int32_t>& preferred, const std::vector<glm::dvec3>& sites,
                              std::vector<std::int32_t>& material);

}  // namespace topotet::gen
