// Seams: what the last level does with pieces the memory limit keeps apart.
//
// Two neighbouring pieces that do not fit together would keep their common border as the input
// had it (frozen at every level), and the run would stop short of its target by about that
// border's vertices. Instead, a band on each side of the border (the tets at its vertices, then
// ring after ring while the two bands fit in one piece) is cut out of each piece, and the two
// bands become one piece, the seam, in which the border is interior. The rest of each piece keeps
// its other borders and gains one with the seam: the band's outer layer, vertices that the
// earlier levels already simplified. Then every piece of the last level, rests and seams, is
// simplified once, each with the vertices it shares frozen: a vertex moves in one run of the
// level at most, so the level's tolerance, the topology argument (topotet/out_of_core.h) and the
// hierarchy's independence of pieces (hierarchy_spool.h) hold as for any level.
// Memory: cutting a seam holds one piece's arrays split in two and the other's (about three
// pieces' arrays, not the engine's: within what a piece's run may take, memory_budget.h); the seam
// itself is at most a piece.
#pragma once

#include <cstdint>
#include <vector>

#include "piece.h"
#include "piece_slot.h"
#include "scratch.h"

namespace topotet::ooc {

// How deep a band goes into its piece, in rings of tets around the border: enough to spread the
// border's vertices over the simplified mesh beside it (the 5M cube-sphere's seam gives the same
// field error and dihedral spread with 3 rings as with 6), shallow so that a band takes little of
// its piece's other borders (each would call for a seam of its own) and freezes few vertices on
// its cut (measured: 3 rings leave fewer vertices than 6 where many pieces stay apart).
inline constexpr int kSeamRings = 3;

// The pieces of slots a and b, loaded and merged (merge_pieces); the vertices they shared lose a
// holder (those left with one are interior now); b's file is removed. `merged` is a's file with
// both regions, the border made interior and the larger bounds; its tets are the caller's to set.
Piece merge_slots(const ScratchFolder& scratch, std::vector<std::uint8_t>& holders, const PieceSlot& a,
                  const PieceSlot& b, PieceSlot& merged);

struct Seams {
  std::vector<PieceSlot> slots;  // the pieces' rests (those not emptied), then the seams
  std::uint32_t made = 0;        // seams
  // Neighbours left without a seam: their bands would not fit in one piece, or would freeze more
  // vertices on their cuts than the seam frees (pieces small against the bands' depth).
  std::uint32_t declined = 0;
};

// Cuts a seam out of every two pieces of `pieces` (saved, not yet run at this level) that share
// vertices, in order (i < j), and again between the seams and the pieces they border, until no
// two pieces share a border that a seam has not freed (the cuts between bands and rests do not
// count: the earlier levels simplified them). Each seam is at most piece_limit tets.
// Deterministic: it depends on the pieces and the limit only.
Seams cut_seams(std::vector<PieceSlot> pieces, const ScratchFolder& scratch, std::vector<std::uint8_t>& holders,
                std::uint64_t piece_limit);

}  // namespace topotet::ooc
