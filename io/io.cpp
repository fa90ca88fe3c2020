// Format dispatch by file extension, and the consistency check every writer relies on.
#include "topotet/io.h"

#include <string>

#include "io/formats.h"
#include "topotet/error.h"
#include "topotet/mesh_stream.h"

namespace topotet {
namespace io {

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    char x = a[i], y = b[i];
    if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
    if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
    if (x != y) return false;
  }
  return true;
}

std::string mixed_mesh_message(std::string_view what) {
  return std::string(what) +
         ": topotet simplifies tetrahedral meshes only (--tets-only / ReadOptions::tets_only leaves the "
         "hexahedra, prisms and pyramids out)";
}

bool iends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && iequals(s.substr(s.size() - suffix.size()), suffix);
}

bool is_exodus_extension(std::string_view path) {
  return iends_with(path, ".exo") || iends_with(path, ".e") || iends_with(path, ".ex2");
}

std::string vtk_format_name(std::string_view path) {
  if (iends_with(path, ".vtu")) return ".vtu (VTK XML) input";
  if (iends_with(path, ".pvtu")) return ".pvtu (VTK parallel XML) input";
  if (iends_with(path, ".vtk")) return ".vtk (legacy VTK)";
  if (is_exodus_extension(path)) return "Exodus II";
  if (iends_with(path, ".cgns")) return "CGNS";
  return {};
}

std::string vtk_component_message(std::string_view path, std::string_view format) {
#if TOPOTET_HAVE_VTK_COMPONENT
  return std::string(path) + ": " + std::string(format) +
         " goes through topotet's VTK component: read_vtk_mesh, write_exodus or read_any_mesh / write_any_mesh "
         "(topotet/io_vtk.h, library topotet::io_vtk), not read_mesh / write_mesh";
#else
  return std::string(path) + ": " + std::string(format) +
         " needs topotet's VTK component, which this build does not have: install VTK 9.1 or newer (Debian: "
         "apt-get install libvtk9-dev) and rebuild topotet";
#endif
}

void check_writable(const std::string& path, const MeshData& mesh) {
  const auto bad = [&](const std::string& what) { throw InputError(path + ": cannot write: " + what); };
  const std::size_t nv = mesh.positions.size();
  if (nv >= kInvalid) bad("too many vertices");
  if (!mesh.vertex_refs.empty() && mesh.vertex_refs.size() != nv) bad("vertex_refs size differs from vertex count");
  if (!mesh.tet_material.empty() && mesh.tet_material.size() != mesh.tets.size())
    bad("tet_material size differs from tet count");
  const auto check_vertex = [&](VertId v, const char* what, std::size_t i) {
    if (v >= nv) bad(std::string(what) + " " + std::to_string(i) + ": vertex " + std::to_string(v) + " out of range");
  };
  for (std::size_t i = 0; i < mesh.tets.size(); ++i)
    for (VertId v : mesh.tets[i]) check_vertex(v, "tet", i);
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (VertId v : mesh.triangles[i].v) check_vertex(v, "triangle", i);
  for (std::size_t i = 0; i < mesh.segments.size(); ++i)
    for (VertId v : mesh.segments[i].v) check_vertex(v, "segment", i);
  for (std::size_t i = 0; i < mesh.corners.size(); ++i) check_vertex(mesh.corners[i], "corner", i);
  for (std::size_t i = 0; i < mesh.required_vertices.size(); ++i)
    check_vertex(mesh.required_vertices[i], "required vertex", i);
  for (std::size_t i = 0; i < mesh.ridges.size(); ++i)
    if (mesh.ridges[i] >= mesh.segments.size()) bad("ridge " + std::to_string(i) + ": segment index out of range");
  for (const VertexField& f : mesh.fields) {
    if (f.components < 1) bad("field '" + f.name + "': components < 1");
    if (f.values.size() != nv * static_cast<std::size_t>(f.components))
      bad("field '" + f.name + "': " + std::to_string(f.values.size()) + " values for " + std::to_string(nv) +
          " vertices x " + std::to_string(f.components) + " components");
  }
  for (const CellField& f : mesh.cell_fields) {
    if (f.components < 1) bad("cell array '" + f.name + "': components < 1");
    if (f.values.size() != mesh.tets.size() * static_cast<std::size_t>(f.components))
      bad("cell array '" + f.name + "': " + std::to_string(f.values.size()) + " values for " +
          std::to_string(mesh.tets.size()) + " tets x " + std::to_string(f.components) + " components");
  }
}

}  // namespace io

bool is_vtk_path(std::string_view path) { return !io::vtk_format_name(path).empty(); }
bool is_exodus_path(std::string_view path) { return io::is_exodus_extension(path); }

MeshFormat format_from_path(std::string_view path) {
  std::string_view p = path;
  if (io::iends_with(p, ".gz")) p.remove_suffix(3);
  if (io::iends_with(p, ".mesh") || io::iends_with(p, ".meshb")) return MeshFormat::kMedit;
  if (io::iends_with(p, ".msh")) return MeshFormat::kGmsh;
  if (io::iends_with(p, ".vtu")) return MeshFormat::kVtu;
  if (io::is_tetgen_path(p)) return MeshFormat::kTetgen;
  if (const std::string vtk = io::vtk_format_name(p); !vtk.empty()) throw InputError(io::vtk_component_message(path, vtk));
  throw InputError(std::string(path) + ": unknown mesh format (expected .mesh, .msh, .vtu or TetGen .node/.ele, optionally + .gz)");
}

MeshData read_mesh(const std::string& path, const ReadOptions& options, ReadNotes* notes) {
  ReadNotes local;
  ReadNotes& n = notes ? *notes : local;
  n = {};
  if (path == "-" && !options.format) throw InputError("<stdin>: the input format must be given (--format mesh or msh)");
  const MeshFormat format = options.format ? *options.format : format_from_path(path);
  if (!options.material_array.empty() && format != MeshFormat::kVtu)
    throw InputError((path == "-" ? std::string("<stdin>") : path) +
                     ": a material array (--material-array) applies to the VTK formats only; this format's materials "
                     "are fixed by the file");
  switch (format) {
    case MeshFormat::kMedit:
      return io::read_medit(path, options, n);
    case MeshFormat::kGmsh:
      return io::read_gmsh(path, options, n);
    case MeshFormat::kTetgen:
      if (path == "-") throw InputError("<stdin>: TetGen meshes are several files and cannot come from stdin");
      return io::read_tetgen(path);
    case MeshFormat::kVtu:
      break;
  }
  throw InputError(io::vtk_component_message(path == "-" ? "<stdin>" : path, ".vtu (VTK XML) input"));
}

void stream_mesh(const std::string& path, MeditVisitor& visitor, const ReadOptions& options, ReadNotes& notes) {
  notes = {};
  switch (options.format ? *options.format : format_from_path(path)) {
    case MeshFormat::kMedit:
      return stream_medit(path, visitor, options, notes);
    case MeshFormat::kGmsh:
      return io::stream_gmsh(path, visitor, options, notes);
    default:
      throw InputError(path + ": streamed formats are MEDIT (.mesh) and Gmsh MSH 4.1 (.msh), optionally .gz: convert it "
                              "first (topotet convert " + path + " in.mesh)");
  }
}

void write_mesh(const std::string& path, const MeshData& mesh, const WriteOptions& options) {
  if (path == "-" && !options.format) throw InputError("<stdout>: the output format must be given (--format mesh, msh or vtu)");
  const MeshFormat format = options.format ? *options.format : format_from_path(path);
  if (io::iends_with(path, ".gz")) throw InputError(path + ": writing compressed (.gz) files is not supported");
  io::check_writable(path, mesh);
  switch (format) {
    case MeshFormat::kMedit:
      return io::write_medit(path, mesh);
    case MeshFormat::kGmsh:
      return io::write_gmsh(path, mesh, options.binary, options.msh22);
    case MeshFormat::kVtu:
      return io::write_vtu(path, mesh, options.binary);
    case MeshFormat::kTetgen:
      break;
  }
  throw InputError(path + ": writing TetGen files is not supported (write .mesh, .msh or .vtu)");
}

}  // namespace topotet
