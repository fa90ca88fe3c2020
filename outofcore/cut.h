// Step 1 of an out-of-core run: the input, streamed once, cut into spatial pieces.
//
//   mesh pass   stream_mesh (topotet/mesh_stream.h: MEDIT, or Gmsh MSH 4.1, whose fields are
//               spilled as they come: field_views.h): vertex
//               positions and refs kept (28 bytes a vertex: the only part of the input held
//               whole), each tet spilled to the scratch
//               folder with the Morton code of its centroid, counted in a histogram of 2^18 bins
//               of those codes; listed triangles, edges, corners and ridges kept (surfaces, not
//               volumes: they grow like the boundary);
//   .sol pass   the vertex and tet fields, spilled in vertex (tet) order: a MEDIT file's from
//               its .sol (SolStream), a .msh's node views read back from their spill;
//   split       the Morton bins cut into `pieces` ranges of about equal tet counts: Morton order
//               keeps a range spatially compact, and neighbouring ranges are neighbours in space,
//               which is what the merges pair (2i with 2i + 1);
//   distribute  each tet to its range's bucket file;
//   build       each bucket becomes a piece (piece.h): its vertices with their fields, and every
//               listed triangle (edge) that is a face (edge) of one of its tets; corners and
//               required vertices among its vertices. A listed triangle or edge that no piece
//               holds is not a face (edge) of any tet: the input error read_mesh would give.
// With a hierarchy asked for, the input as read goes to its original section between the .sol pass
// and the split (hierarchy_spool.h), while the cut holds the input's vertices anyway.
// The number of pieces is chosen by the caller from the counts (choose_pieces), between the mesh
// pass and the split, so that it depends on the input and the limit only (determinism).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "scratch.h"
#include "topotet/cell_fields.h"
#include "topotet/mesh_data.h"
#include "topotet/simplify.h"

namespace topotet::ooc {

class HierarchySpool;

struct InputCounts {
  std::uint64_t vertices = 0, tets = 0, triangles = 0, segments = 0;
  int vertex_stride = 0, cell_stride = 0;  // field values per vertex, per tet
};

struct CutResult {
  InputCounts counts;
  std::uint32_t pieces = 0;
  std::vector<std::uint64_t> piece_tets;  // [piece]
  // [global vertex] how many pieces hold it (1 = inside one piece; more = on a border).
  std::vector<std::uint8_t> holders;
  CostUnits units;      // the whole input's (cost_shares: every piece's costs in the same units)
  double diagonal = 0;  // of the bounding box
  // [vertex field component] over the vertices a tet uses (the field error bounds' range and
  // magnitude, as an in-core run takes them; units above count every vertex of the file).
  std::vector<double> used_min, used_max, used_magnitude;
  std::vector<VertexField> vertex_fields;  // layouts (no values)
  std::vector<CellField> cell_fields;
};

// on_vertex_count(n, reader_bytes) runs as soon as the vertex count is read (before any work: the
// memory check), with the bytes the reader holds beside the cut while it streams (a .msh's node
// tag map; 0 for MEDIT); it returns true when it checked them against a memory limit (then the
// cut, and the reader, reserve them at once), and throws when the limit is too small.
// choose_pieces(counts) -> the number of pieces (a power of two <= kMaxPieces), called once the
// mesh pass has counted the input; it may throw (a limit too small for this input). `log` gets
// one line per step (may be empty).
CutResult cut_input(const std::string& input, ScratchFolder& scratch,
                    const std::function<std::uint32_t(const InputCounts&)>& choose_pieces,
                    const std::function<void(const std::string&)>& log,
                    const std::function<bool(std::uint64_t vertices, std::uint64_t reader_bytes)>& on_vertex_count,
                    const CellRemapOptions& cell_kinds,  // the kinds of the cell fields (--extensive...)
                    HierarchySpool* original = nullptr);  // given: the input written as a .tth's original

}  // namespace topotet::ooc
