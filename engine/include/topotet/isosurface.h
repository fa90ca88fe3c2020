// Isosurfaces as embedded structures (issue #24, paper 001 §6.1): "keep the topology of the 0.5
// level set of this field".
//
//   topotet::MeshData data = topotet::read_mesh("volume.mesh");   // with a field "density"
//   std::vector<topotet::IsoLevel> levels = {{"density", 0, 0.5}};
//   topotet::IsoEmbedReport embedded = topotet::embed_isosurfaces(data, levels);
//   topotet::TetMesh mesh = topotet::build_tet_mesh(data);
//   topotet::SimplifyOptions options;
//   options.isosurfaces = embedded.levels;  // their vertices keep the value 0.5 exactly
//   topotet::simplify(mesh, options);
//
// embed_isosurfaces splits every tet the level set crosses so that the level set becomes a union of
// tet faces, and lists those faces as triangles with a ref of their own per level. From then on the
// isosurface is a listed surface like any other: the link conditions keep its topology (Betti
// numbers) and the tolerance keeps it within H of where it was. SimplifyOptions::isosurfaces then
// keeps the field value of its vertices at exactly the level.
//
// The level set of a level c is the boundary of the region {f < c} of the piecewise-linear field
// f (linear in every tet): inside a tet with vertices strictly on both sides it is the plane
// section; a tet face whose three vertices all have f == c belongs to it when exactly one of the
// two tets that share it has its fourth vertex below c (the face bounds {f < c}; on the mesh
// boundary: when its one tet is below). Edges and vertices at c with no such face add nothing.
// engine/isosurface/README.md says how the tets are split and why the split is consistent.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet {

// One level of one field component.
struct IsoLevel {
  std::string field;       // a VertexField name of the mesh
  int component = 0;       // 0-based, < the field's components
  double value = 0.0;      // the level (finite)
  std::int32_t ref = 0;    // the ref of its triangles: set by embed_isosurfaces
  friend bool operator==(const IsoLevel&, const IsoLevel&) = default;
};

struct IsoEmbedOptions {
  // A crossing at edge parameter t (0 at one end, 1 at the other) with t < snap or t > 1 - snap
  // is moved onto the nearer vertex, whose field component is set to the level exactly: a
  // change of at most snap x |f(a) - f(b)| to the input field, instead of a tet of relative
  // thickness below snap. 0 = never snap (exact crossings only).
  double snap = 1e-6;
};

struct IsoLevelStats {
  std::uint64_t tets_split = 0;       // crossed tets, each replaced by 2..6 tets
  std::uint64_t tets_added = 0;       // net tets added
  std::uint64_t vertices_added = 0;   // one per crossed edge
  std::uint64_t vertices_snapped = 0; // input vertices set to the level (IsoEmbedOptions::snap)
  std::uint64_t triangles = 0;        // isosurface triangles listed
  std::uint64_t triangles_split = 0;  // listed triangles replaced by their pieces
  std::uint64_t segments_split = 0;   // listed segments replaced by their two halves
  double seconds = 0.0;
};

struct IsoEmbedReport {
  std::vector<IsoLevel> levels;      // the levels as embedded, refs set (SimplifyOptions::isosurfaces)
  std::vector<IsoLevelStats> stats;  // per level
  double seconds = 0.0;
};

// Embeds the levels one after the other (a later level splits the tets, and the triangles, of an
// earlier one). New vertices go after the input's, in the order of the crossed edges (sorted by
// (smaller id, larger id)); their field values are linear along the edge, and exactly the level
// for the level's component; their vertex ref (MeshData::vertex_refs, when given) is 0. Tets keep
// their material, and their cell arrays (MeshData::cell_fields) stay aligned: each piece takes its
// tet's values, an extensive array's amount shared out by the pieces' volumes; listed triangles and segments cut by a level are replaced by their pieces with
// the same ref; the level's triangles get a ref that no listed triangle or triangle group name uses, and a GroupName (dim 2) "iso:FIELD=VALUE" (FIELD:C
// for component C of a field with several). Parallel, and identical for every thread count.
// The pieces of a tet have its orientation (so a mesh with all tets negatively oriented, which
// build_tet_mesh flips as a whole, stays consistent). Throws InputError on an unknown field or
// component, a non-finite level, a level given twice, or a piece that would be flat or inverted
// relative to its tet (a crossed tet that is itself flat, or a crossing too close to a vertex for
// a certified orientation with snap 0); `data` then holds the levels before the failing one.
IsoEmbedReport embed_isosurfaces(MeshData& data, const std::vector<IsoLevel>& levels, const IsoEmbedOptions& options = {});

// Parses "FIELD=VALUE[,VALUE...]" (FIELD may be "name:component") into levels appended to `out`.
// Returns an empty string, or what is wrong with `spec`.
std::string parse_isosurface_spec(const std::string& spec, std::vector<IsoLevel>& out);

// "iso:FIELD=VALUE", the group name embed_isosurfaces gives a level's triangles (VALUE printed
// with the shortest text that reads back as the same double).
std::string isosurface_group_name(const IsoLevel& level, int field_components);

}  // namespace topotet
