// Mesh files: MEDIT .mesh (+ .sol), Gmsh .msh (4.1 read/write, 2.2 ASCII/binary read), VTK .vtu
// (write). The format is chosen by the file extension; a trailing ".gz" is read transparently.
//
// read_mesh throws InputError naming the file and line (or element) on malformed input; it never
// crashes on bad bytes. A ".sol" file beside a ".mesh" with the same stem is read automatically
// (SolAtVertices fields of any type: scalars, vectors and tensors are kept with their type).
//
// write_mesh writes to a temporary file in the same folder and renames it over `path`, so a failed
// run never leaves a half-written file. For .mesh it also writes `<stem>.sol` when there are fields.
// For .vtu it writes the tets (with material and fields) and, when there are substructures,
// `<stem>_substructures.vtp` with the listed triangles and segments and their refs.
#pragma once

#include <string>
#include <string_view>

#include "topotet/mesh_data.h"

namespace topotet {

enum class MeshFormat { kMedit, kGmsh, kVtu };

// Throws InputError for an unknown extension.
MeshFormat format_from_path(std::string_view path);

MeshData read_mesh(const std::string& path);

struct WriteOptions {
  bool binary = false;  // Gmsh: binary 4.1 if supported; VTU: raw appended data vs base64 inline
};
void write_mesh(const std::string& path, const MeshData& mesh, const WriteOptions& options = {});

}  // namespace topotet
