// Private to io/: the per-format readers and writers that io.cpp dispatches to, and the
// few helpers they share. The public API is topotet/io.h.
#pragma once

#include <string>
#include <string_view>

#include "topotet/io.h"
#include "topotet/medit_stream.h"
#include "topotet/mesh_data.h"

namespace topotet::io {

// MEDIT ASCII .mesh (+ <stem>.sol / <stem>.sol.gz and <stem>.sol.fields.txt beside it).
MeshData read_medit(const std::string& path, const ReadOptions& options, ReadNotes& notes);
void write_medit(const std::string& path, const MeshData& mesh);

// Gmsh .msh: reads 4.1 (ASCII and binary) and 2.x (ASCII and binary); writes 4.1.
MeshData read_gmsh(const std::string& path, const ReadOptions& options, ReadNotes& notes);
// The same parser, streaming MSH 4.1 into a visitor (topotet/mesh_stream.h).
void stream_gmsh(const std::string& path, MeditVisitor& visitor, const ReadOptions& options, ReadNotes& notes);
void write_gmsh(const std::string& path, const MeshData& mesh, bool binary, bool msh22);

// TetGen .node/.ele (+ .face/.edge); read only. `path` names any of them.
MeshData read_tetgen(const std::string& path);
bool is_tetgen_path(std::string_view path);

// VTK XML .vtu (+ <stem>_substructures.vtp); write only.
void write_vtu(const std::string& path, const MeshData& mesh, bool binary);

// Throws InputError "PATH: cannot write: ..." when `mesh` is not self-consistent (array sizes,
// indices in range, field sizes): writers may then index without checks.
void check_writable(const std::string& path, const MeshData& mesh);

// The message of a refused mixed mesh: "<what>: topotet simplifies tetrahedral meshes only ...".
std::string mixed_mesh_message(std::string_view what);

// The formats of the VTK component (topotet/io_vtk.h), by extension: ".vtu (VTK XML)", ".exo
// (Exodus II)", ...; empty for the others. `writable`: Exodus II, the one it writes.
std::string vtk_format_name(std::string_view path);
bool is_exodus_extension(std::string_view path);
// "PATH: <format> needs the VTK component ..." (the message depends on whether this build has it).
std::string vtk_component_message(std::string_view path, std::string_view format);

// ASCII case-insensitive helpers for keywords and extensions.
bool iequals(std::string_view a, std::string_view b);
bool iends_with(std::string_view s, std::string_view suffix);

}  // namespace topotet::io
