// A piece between levels: where it is in the scratch folder and what the levels need to know of it
// without loading it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace topotet::ooc {

struct PieceSlot {
  std::uint32_t file = 0;  // ScratchFolder::piece_path(file)
  std::uint64_t tets = 0;
  // The input vertices that this piece alone stands for: its interior at level 0; a merge adds
  // the two regions and the border they shared; a band cut out of a piece takes its share.
  std::uint64_t region = 0;
  std::vector<double> field_bound;  // [component] the largest bound of its tets (with field bounds)
  // Of the vertices its region asks it to keep, how many are frozen on its border and kept there
  // (a seam's: its bands' cuts, seams.h); its interior keeps that many fewer.
  std::uint64_t kept_frozen = 0;
};

// into[c] = max(into[c], from[c]): the largest bound per component over several pieces.
inline void raise_to(std::vector<double>& into, const std::vector<double>& from) {
  if (into.size() < from.size()) into.resize(from.size(), 0.0);
  for (std::size_t c = 0; c < from.size(); ++c) into[c] = std::max(into[c], from[c]);
}

}  // namespace topotet::ooc
