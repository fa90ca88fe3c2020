// Private to topotet's VTK code (io/vtk/ and the ParaView filter, paraview/): a dataset already in
// memory <-> MeshData, with the mapping read_vtk_mesh uses for a .vtu (docs/formats.md, "VTK
// formats"). A VTK filter has no file to read: its input is a vtkUnstructuredGrid, and its output
// must be one too.
//
// Not installed: the public headers keep VTK out (topotet/io_vtk.h). These are compiled against
// whichever VTK the build tree found, Debian's libvtk9 or ParaView's own (docs/paraview.md), never
// both in one tree.
#pragma once

#include <string>

#include <vtkSmartPointer.h>

#include "topotet/io.h"
#include "topotet/mesh_data.h"

class vtkDataSet;
class vtkUnstructuredGrid;

namespace topotet::io::vtk {

// The cells and arrays of `grid` as read_vtk_mesh reads a .vtu: tets with the material array
// (ReadOptions::material_array, else the first default present), triangles and lines with their
// ref from the same array, vertex cells as corners, numeric point arrays as fields, ghost cells
// left out. `name` stands for the file in error messages ("<name>: cell 12: ..."). `notes`
// receives what was left out and the material array's name. Throws InputError.
MeshData mesh_from_grid(vtkDataSet* grid, const std::string& name, const ReadOptions& options = {},
                        ReadNotes* notes = nullptr);

// The reverse, in a form mesh_from_grid reads back to the same mesh: the tets, then the listed
// triangles, the listed segments, and the corners and required vertices (VTK_VERTEX cells, both
// read back as corners: pinned either way), in that order; one int32 cell array named
// `material_array` ("material" when empty) holding the tets' materials, the triangles' and
// segments' refs and 0 for the vertex cells; each field as a double point array of its name and
// components. Vertex refs, ridge marks and group names have no place in it.
vtkSmartPointer<vtkUnstructuredGrid> grid_from_mesh(const MeshData& mesh, const std::string& material_array = {});

}  // namespace topotet::io::vtk
