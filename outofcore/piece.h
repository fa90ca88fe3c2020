// A piece of an out-of-core run: a part of the mesh (whole tets, with the listed triangles, edges,
// corners and required vertices among its vertices) in its own numbering, plus each vertex's
// global id (its index in the input, which a vertex keeps through every collapse: the surviving
// end of a collapse keeps its id). Global ids are how pieces find their common vertices: the
// vertices a piece shares with another are its border, frozen while the pieces are apart.
//
// Pieces live in the scratch folder between levels (save_piece / load_piece: a raw binary dump,
// read back only by the same run) and two neighbours become one (merge_pieces) at each level of
// paper 002's binary hierarchy.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "topotet/mesh_data.h"
#include "topotet/simplify.h"

namespace topotet::ooc {

using GlobalId = std::uint32_t;

struct Piece {
  MeshData mesh;                    // group_names are the run's, not a piece's: left empty
  std::vector<GlobalId> global_ids;  // [vertex] its index in the input
  // [vertex] its quadric (quadric_doubles values each) as the last run on the piece left it
  // (SimplifyOptions::quadrics_out), so that the next level ranks collapses by the error against
  // the input, as one run would; empty before the first run. A vertex two pieces share has a part
  // in each (from each piece's tets): a merge adds them.
  std::vector<double> quadrics;
  std::uint32_t quadric_doubles = 0;
  // With field error bounds: the input vertices this piece's tets hold as samples, and its tets'
  // bounds (SimplifyOptions::field_samples), carried from level to level; components = 0 before
  // the first run, or without bounds.
  FieldBoundSamples samples;
  // With a hierarchy file: [tet] the (run-wide) id of the collapse that last changed it, kInvalid
  // for none; the next level's log is seeded with it (hierarchy_spool.h). Empty otherwise.
  std::vector<std::uint32_t> last_collapse;
};

void save_piece(const std::string& path, const Piece& piece);  // throws InputError (disk full...)
Piece load_piece(const std::string& path);

// The union of a and b: common vertices (same global id) once, a's vertices first in a's order,
// then b's new ones; tets of both (a piece's tets are its own); triangles, edges, corners and
// required vertices that both list (those on the common border) once, a's copy first; the
// quadrics of common vertices added; the field samples of both (a sample is in one piece only);
// each tet's last collapse. The field layouts must agree (they come from one input), and so must
// the quadrics' (both or neither).
Piece merge_pieces(Piece a, Piece b);

}  // namespace topotet::ooc
