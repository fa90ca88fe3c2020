// Mesh files: MEDIT .mesh (+ .sol) and binary .meshb (+ .solb: libMeshb's GMF, versions 1-4 read,
// 3 written, 4 when the vertex count needs int64), Gmsh .msh (4.1 read/write, ASCII or binary; 2.x ASCII/binary
// read), VTK .vtu (write). The format is chosen by the file extension; a trailing ".gz" is read
// transparently (writing .gz is refused).
// The VTK formats (.vtu/.pvtu/.vtk input, Exodus II, CGNS) are the optional component
// topotet::io_vtk (topotet/io_vtk.h: read_vtk_mesh, write_exodus, read_any_mesh); read_mesh and
// write_mesh refuse them with a message that names it.
//
// read_mesh throws InputError naming the file and line ("box.mesh:12: ...", or "x.msh: byte N:"
// inside Gmsh binary data) on malformed input; it never crashes on bad bytes. It rejects NaN/inf
// values, indices out of range, negative or lying counts, truncation; it does not check geometry
// (orientation, volumes): that is the mesh builder's job. A ".sol" (or ".sol.gz") beside a ".mesh"
// with the same stem is read automatically (SolAtVertices of any type: scalars, vectors and
// tensors keep their type) and SolAtTetrahedra (cell fields, in the order of the tets);
// "<stem>.sol.fields.txt", if present, names its solutions (else "sol0", "sol1", ... and
// "cellsol0", ...). vertex_refs comes back empty when every vertex ref is 0.
//
// Cell fields (MeshData::cell_fields): MEDIT SolAtTetrahedra in the .sol, Gmsh $ElementData of
// the tets (4.1 and 2.2, read and written), VTU CellData (written; read by topotet/io_vtk.h).
//
// write_mesh writes to a temporary file in the same folder and renames it over `path`, so a failed
// run never leaves a half-written file. A symlink is followed and its target replaced; "-"
// (stdout), FIFOs and character devices are written straight through (nothing to rename). For .mesh it also writes `<stem>.sol` when there are fields
// (and `<stem>.sol.fields.txt` when their names are not the defaults); companion files left from
// an earlier write of the same stem that this one does not produce are removed, so a later read
// never attaches a stale .sol to the new mesh. A Gmsh file written here reads back as the
// identical MeshData: refs <= 0, ridges, corners, required vertices and vertex refs travel as
// named physical groups / a $NodeData (see io/gmsh.cpp). For .vtu it writes the tets (with
// material and fields) and, when there are substructures, `<stem>_substructures.vtp` with the
// listed triangles and segments and their refs.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet {

enum class MeshFormat { kMedit, kGmsh, kVtu, kTetgen };

// Throws InputError for an unknown extension.
MeshFormat format_from_path(std::string_view path);

// The paths of the VTK component (topotet/io_vtk.h), by extension, case-insensitive: .vtu .pvtu
// .vtk .exo .e .ex2 .cgns (is_vtk_path: what read_vtk_mesh reads), .exo .e .ex2 (is_exodus_path:
// what write_exodus writes). In the core so that a program can route paths without loading VTK.
bool is_vtk_path(std::string_view path);
bool is_exodus_path(std::string_view path);

// Mixed meshes. topotet simplifies tetrahedral meshes: hexahedra, prisms and pyramids are refused
// by default (InputError naming the file and the line of the first one), because dropping them
// silently leaves holes in the output. With tets_only they are left out and counted in ReadNotes.
// Quadrilaterals are never faces of a tet: they are always left out and counted.
//
// "-" reads standard input; its format must then be given (ReadOptions::format), and a MEDIT mesh
// from stdin has no .sol beside it. Errors name it "<stdin>".
struct ReadOptions {
  bool tets_only = false;
  std::optional<MeshFormat> format;  // overrides the extension; required for "-"
  // Gmsh 4.1: fill ReadNotes::node_tags and ReadNotes::tet_partition (topotet-mpi reads the parts
  // of a partitioned file with them).
  bool keep_partitions = false;
  // VTK formats only (topotet/io_vtk.h): the integer cell array that gives the materials and the
  // refs of triangles and edges; empty = the first present of "material", "gmsh:physical",
  // "ObjectId", "ElementBlockIds", "CellEntityIds" (Exodus: element block ids). read_mesh refuses it for the other
  // formats, whose materials are fixed by the format.
  std::string material_array;
};
struct ReadNotes {
  std::uint64_t hexahedra = 0, prisms = 0, pyramids = 0;  // left out (tets_only)
  std::uint64_t polyhedra = 0;  // VTK polyhedra, pentagonal and hexagonal prisms: left out (tets_only)
  std::uint64_t quadrilaterals = 0;                        // left out
  std::uint64_t dropped_corners = 0;  // MEDIT Corners with an out-of-range vertex (TetGen -g): left out
  // Gmsh 4.1 partitioned files (gmsh -part N, with or without -part_split): N, from
  // $PartitionedEntities; 0 for an unpartitioned file.
  std::uint64_t partitions = 0;
  // With ReadOptions::keep_partitions (Gmsh 4.1 only, else empty): [vertex] its node tag (tags
  // are global over the split files of one mesh), and [tet] the partition (1..N) of its entity,
  // 0 for a tet on an unpartitioned entity.
  std::vector<std::uint64_t> node_tags;
  std::vector<std::int32_t> tet_partition;
  // VTK formats: the arrays that are not carried into MeshData, one line each ("cell array
  // 'name' (not numeric: vtkStringArray)", "point array 'name' (not on every zone)"). Numeric
  // cell arrays of the tets are carried (MeshData::cell_fields); those of surface pieces are not.
  std::vector<std::string> unread_arrays;
  // VTK formats: the cell array the materials were taken from (ReadOptions::material_array or the
  // first default present; "ObjectId" for Exodus block ids); empty when there was none (CGNS
  // zones, or every material 0). paraview/ names its output's material array the same.
  std::string material_array;
  std::uint64_t volume_cells() const { return hexahedra + prisms + pyramids + polyhedra; }
};

MeshData read_mesh(const std::string& path, const ReadOptions& options = {}, ReadNotes* notes = nullptr);

struct WriteOptions {
  bool binary = false;  // Gmsh: binary MSH 4.1; VTU: raw appended data instead of inline base64
  bool msh22 = false;   // Gmsh: MSH 2.2 ASCII instead of 4.1, for tools that read only the old format
  std::optional<MeshFormat> format;  // overrides the extension; required for "-" (stdout)
};
void write_mesh(const std::string& path, const MeshData& mesh, const WriteOptions& options = {});

// Writes `text` to `path` the way write_mesh writes (atomically to regular files and through
// symlinks, straight through "-", FIFOs and devices; see io/atomic_file.h). Throws InputError.
void write_text_file(const std::string& path, std::string_view text);

// Removes the temporary files of the writes in progress. Async-signal-safe: a program's SIGINT /
// SIGTERM handler calls it before exiting (the library installs no handler itself).
void remove_temporary_files() noexcept;

}  // namespace topotet
