// A mesh file read as a stream, whatever its format can be streamed: MEDIT .mesh (stream_medit,
// topotet/medit_stream.h) and Gmsh MSH 4.1, ASCII or binary, each optionally gzipped. For meshes
// larger than memory (topotet/out_of_core.h): the vertices and tets go to the visitor as they are
// read and are never held; what is held grows like the surfaces (the listed triangles, lines and
// points of a .msh, whose refs come from their entities).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "topotet/io.h"
#include "topotet/medit_stream.h"

namespace topotet {

// Streams `path` through `visitor` in the order MeditVisitor describes, with read_mesh's checks
// and messages, and the entities read_mesh would give: the same vertices, tets and materials, and
// the same triangles, segments, ridges, corners and required vertices (a .msh gives its vertex
// refs as 0 and begin_tets its element count, an upper bound). The fields of a MEDIT file are in
// its .sol (SolStream); those of a .msh come as node and cell views (MeditVisitor::begin_node_view,
// begin_cell_view), raw: the visitor applies read_mesh's two rules (a node view
// "topotet:vertex_ref" of integers is the vertex refs; a 9-component view exactly symmetric
// everywhere is 6 components). A cell view needs the tets' element tags consecutive (what Gmsh
// writes): the tet of a tag is then tag - first, with nothing held. Throws InputError for another
// format, MSH 2, views the visitor does not take, and cell views of a file whose tets are not
// numbered consecutively: each says how to convert.
void stream_mesh(const std::string& path, MeditVisitor& visitor, const ReadOptions& options, ReadNotes& notes);

// read_mesh's two rules for the views of a .msh, shared with a visitor that takes them raw:
//  - the node view named kVertexRefField, one component, every value an exact int32: the vertex refs;
//  - a 9-component view exactly symmetric everywhere: 6 components in MEDIT's order.
inline constexpr std::string_view kVertexRefField = "topotet:vertex_ref";
// x as an int32 when it is exactly one.
bool exact_int32(double x, std::int32_t& out);
// Whether the row-major 3x3 `a` is exactly symmetric, and its 6 components (xx, xy, yy, xz, yz, zz).
bool is_symmetric_3x3(const double* a);
void symmetric_components(const double* a, double* six);

}  // namespace topotet
