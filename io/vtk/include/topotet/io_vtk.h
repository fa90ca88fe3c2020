// The VTK formats: an optional component (library topotet::io_vtk, built when VTK 9.1+ is found;
// Debian: libvtk9-dev). topotet::engine never depends on VTK: a program that wants these formats
// links topotet::io_vtk and calls the functions below (or read_any_mesh / write_any_mesh, which
// add them to topotet::read_mesh / write_mesh). There is no registration: plain
// topotet::read_mesh refuses these paths with a message naming this component.
//
// Read, with VTK's own readers (no parser of ours):
//   .vtu    VTK XML unstructured grid (+ <stem>_substructures.vtp, as topotet's writer makes it)
//   .pvtu   VTK XML parallel unstructured grid (pieces merged, shared points joined)
//   .vtk    legacy VTK unstructured grid (ASCII or binary)
//   .exo .e .ex2   Exodus II (element blocks, side sets, nodal variables of the first time step)
//   .cgns   CGNS, HDF5-based, unstructured zones (boundary patches of a BC family)
// Write (Exodus II only: .vtu stays topotet's own writer, topotet::write_mesh):
//   .exo .e .ex2   one element block per material (id = material), listed triangles as side sets
//                  (id = ref), listed edges as line blocks "topotet:edges ref=R", corners and
//                  required vertices as node sets "topotet:corners" / "topotet:required_vertices",
//                  fields as nodal variables, group names as block / set names; read_vtk_mesh reads
//                  all of it back (the tets in material order, a triangle in its tet's side order).
// The mapping of each format onto MeshData (materials, surfaces, polylines, corners, fields) is
// in docs/formats.md.
//
// Errors are InputError naming the file (and the cell or point where relevant): a missing or
// unreadable file, a file VTK cannot parse, NaN/inf coordinates, connectivity out of range, no
// tets, a mixed mesh without ReadOptions::tets_only, a --material-array that is not there. VTK's
// own messages never reach the terminal: while a call runs, VTK's output window and its logger's
// stderr output are redirected into the error (a process-wide setting of VTK's, switched for the
// duration of the call and restored; the calls of this header are serialized by one mutex).
#pragma once

#include <string>
#include <string_view>

#include "topotet/io.h"
#include "topotet/mesh_data.h"

namespace topotet {

// is_vtk_path / is_exodus_path (which paths go here) are in topotet/io.h.

// Reads a VTK-format mesh. ReadOptions::format == MeshFormat::kVtu reads `path` as .vtu whatever
// its extension ("-": standard input, without substructures). ReadOptions::material_array names the
// integer cell array the materials (and the refs of triangles and edges) come from; empty = the
// first present of "material", "gmsh:physical", "ObjectId", "ElementBlockIds", "CellEntityIds" (Exodus:
// the element block ids; CGNS: the zone numbers). Throws InputError.
MeshData read_vtk_mesh(const std::string& path, const ReadOptions& options = {}, ReadNotes* notes = nullptr);

// Writes an Exodus II file through VTK's vtkExodusIIWriter, to a temporary file in the same
// folder renamed over `path` at the end (a failed write leaves no half-written file). Not written:
// ridge marks and vertex refs. Every listed triangle must be a face of a tet. Throws InputError.
void write_exodus(const std::string& path, const MeshData& mesh);

// topotet::read_mesh / write_mesh with the VTK formats added: VTK paths (is_vtk_path, or
// ReadOptions::format kVtu with a path that is not a core format) go to read_vtk_mesh, Exodus
// paths to write_exodus, everything else to the core functions.
MeshData read_any_mesh(const std::string& path, const ReadOptions& options = {}, ReadNotes* notes = nullptr);
void write_any_mesh(const std::string& path, const MeshData& mesh, const WriteOptions& options = {});

}  // namespace topotet
