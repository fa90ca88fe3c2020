// Mesh files: MEDIT .mesh (+ .sol), Gmsh .msh (4.1 read/write, ASCII or binary; 2.x ASCII/binary
// read), VTK .vtu (write). The format is chosen by the file extension; a trailing ".gz" is read
// transparently (writing .gz is refused). Binary MEDIT (.meshb) is refused with a clear message.
//
// read_mesh throws InputError naming the file and line ("box.mesh:12: ...", or "x.msh: byte N:"
// inside Gmsh binary data) on malformed input; it never crashes on bad bytes. It rejects NaN/inf
// values, indices out of range, negative or lying counts, truncation; it does not check geometry
// (orientation, volumes): that is the mesh builder's job. A ".sol" (or ".sol.gz") beside a ".mesh"
// with the same stem is read automatically (SolAtVertices of any type: scalars, vectors and
// tensors keep their type); "<stem>.sol.fields.txt", if present, names its solutions (else
// "sol0", "sol1", ...). vertex_refs comes back empty when every vertex ref is 0.
//
// write_mesh writes to a temporary file in the same folder and renames it over `path`, so a failed
// run never leaves a half-written file. For .mesh it also writes `<stem>.sol` when there are fields
// (and `<stem>.sol.fields.txt` when their names are not the defaults); companion files left from
// an earlier write of the same stem that this one does not produce are removed, so a later read
// never attaches a stale .sol to the new mesh. A Gmsh file written here reads back as the
// identical MeshData: refs <= 0, ridges, corners, required vertices and vertex refs travel as
// named physical groups / a $NodeData (see engine/io/gmsh.cpp). For .vtu it writes the tets (with
// material and fields) and, when there are substructures, `<stem>_substructures.vtp` with the
// listed triangles and segments and their refs.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "topotet/mesh_data.h"

namespace topotet {

enum class MeshFormat { kMedit, kGmsh, kVtu };

// Throws InputError for an unknown extension.
MeshFormat format_from_path(std::string_view path);

// Mixed meshes. topotet simplifies tetrahedral meshes: hexahedra, prisms and pyramids are refused
// by default (InputError naming the file and the line of the first one), because dropping them
// silently leaves holes in the output. With tets_only they are left out and counted in ReadNotes.
// Quadrilaterals are never faces of a tet: they are always left out and counted.
struct ReadOptions {
  bool tets_only = false;
};
struct ReadNotes {
  std::uint64_t hexahedra = 0, prisms = 0, pyramids = 0;  // left out (tets_only)
  std::uint64_t quadrilaterals = 0;                        // left out
  std::uint64_t volume_cells() const { return hexahedra + prisms + pyramids; }
};

MeshData read_mesh(const std::string& path, const ReadOptions& options = {}, ReadNotes* notes = nullptr);

struct WriteOptions {
  bool binary = false;  // Gmsh: binary MSH 4.1; VTU: raw appended data instead of inline base64
  bool msh22 = false;   // Gmsh: MSH 2.2 ASCII instead of 4.1, for tools that read only the old format
};
void write_mesh(const std::string& path, const MeshData& mesh, const WriteOptions& options = {});

}  // namespace topotet
