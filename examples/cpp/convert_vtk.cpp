// Reads a mesh in any format topotet knows, the VTK ones included (.vtu, .pvtu, .vtk, Exodus II,
// CGNS), and writes it in another (Exodus II included): the library side of the optional VTK
// component, topotet::io_vtk (find_package(topotet CONFIG COMPONENTS io_vtk)).
//   convert_vtk IN OUT [MATERIAL_ARRAY]
#include <cstdio>

#include "topotet/error.h"
#include "topotet/io_vtk.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s IN OUT [MATERIAL_ARRAY]\n", argv[0]);
    return 2;
  }
  try {
    topotet::ReadOptions options;
    if (argc > 3) options.material_array = argv[3];
    topotet::ReadNotes notes;
    const topotet::MeshData mesh = topotet::read_any_mesh(argv[1], options, &notes);
    for (const std::string& array : notes.unread_arrays) std::printf("not carried: %s\n", array.c_str());
    topotet::write_any_mesh(argv[2], mesh);
    std::printf("%s -> %s: %zu vertices, %zu tets, %zu triangles, %zu fields\n", argv[1], argv[2], mesh.vertex_count(),
                mesh.tet_count(), mesh.triangles.size(), mesh.fields.size());
  } catch (const topotet::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}
