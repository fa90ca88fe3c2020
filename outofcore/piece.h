// A piece of an out-of-core run: a part of the mesh (whole tets, with the listed triangles, edges,
// corners and required vertices among its vertices) in its own numbering, plus each vertex's
// global id (its index in the input, which a vertex keeps through every collapse: the surviving
// end of a collapse keeps its id). Global ids are how pieces find their common vertices: the
// vertices a piece shares with another are its border, frozen while the pieces are apart.
//
// Pieces live in the scratch folder between levels (save_piece / load_piece: a raw binary dump,
// read back only by the same run) and two neighbours become one (merge_pieces) at each level of
// paper 002's binary hierarchy. When two neighbours no longer fit together, a band on each side of
// their common border is cut out of each (band_tets, sub_piece) and the two bands become one
// piece, a seam, in which that border is simplified (simplify_out_of_core.cpp).
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

// Each vertex's tets, for finding which listed triangles (edges) are faces (edges) of a piece's
// tets: the cut, sub_piece and band_tets need it for a piece at a time (freed with it).
struct VertexTets {
  std::vector<std::uint32_t> first, incident;  // vertex v's tets: incident[first[v] .. first[v + 1])
  explicit VertexTets(const MeshData& mesh);
  bool has_face(const MeshData& mesh, VertId a, VertId b, VertId c) const;
  bool has_edge(const MeshData& mesh, VertId a, VertId b) const;
};

// The piece's vertices no other piece holds (holders[g]: how many pieces hold global vertex g, as
// the cut counts them): the ones its run may move.
std::uint64_t interior_vertices(const Piece& piece, const std::vector<std::uint8_t>& holders);

void save_piece(const std::string& path, const Piece& piece);  // throws InputError (disk full...)
Piece load_piece(const std::string& path);

// The union of a and b: common vertices (same global id) once, a's vertices first in a's order,
// then b's new ones; tets of both (a piece's tets are its own); triangles, edges, corners and
// required vertices that both list (those on the common border) once, a's copy first; the
// quadrics of common vertices added; the field samples of both (a sample is in one piece only);
// each tet's last collapse. The field layouts must agree (they come from one input), and so must
// the quadrics' (both or neither).
Piece merge_pieces(Piece a, Piece b);

// The piece made of the listed tets of `piece` (increasing indices), as the cut would have made
// it: the vertices they use (in the piece's order, with their global ids, fields and quadrics),
// their materials, cell fields, last collapses, field samples and bounds, and the listed
// triangles and edges that are faces (edges) of them, corners and required vertices among their
// vertices. A vertex the rest of the piece uses too is in both parts (the caller counts the new
// holder).
Piece sub_piece(const Piece& piece, const std::vector<std::uint32_t>& tets);

// The tets within max_rings rings of the vertices whose global ids are `seeds` (sorted): the tets
// at those vertices (all of them, whatever max_tets: so that the seeds are inside the band), then
// ring after ring of the tets at the vertices reached, while the band stays within max_tets.
// Increasing indices.
std::vector<std::uint32_t> band_tets(const Piece& piece, const std::vector<GlobalId>& seeds, std::uint64_t max_tets,
                                     int max_rings);

}  // namespace topotet::ooc
