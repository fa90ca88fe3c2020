// MeshData <-> vtkUnstructuredGrid for the VTK peer comparison (bench/bench_vtk_peer.cpp only).
//
// VTK stays out of the library: this file is compiled into the bench target alone, and only when
// CMake finds VTK 9.
#pragma once

#include <string>
#include <vector>

#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include "topotet/mesh_data.h"

namespace topotet::bench {

// Positions (as doubles) and tets (VTK_TETRA). `scalar` becomes the point data's active scalars,
// named `scalar_name`; vtkUnstructuredGridQuadricDecimation refuses a grid without scalars, so the
// caller passes a constant array when the mesh has no field. Material ids, refs, triangles,
// segments and pinned vertices have no place in the filter's input and are dropped.
// Positions and scalar values are multiplied by `scale` (see --vtk-scale in bench_vtk_peer.cpp).
vtkSmartPointer<vtkUnstructuredGrid> to_vtk_grid(const MeshData& mesh, const std::vector<double>& scalar,
                                                 const std::string& scalar_name, double scale = 1.0);

// Positions and tets of `grid` (which must hold tets only), plus its point array `array_name`
// (first component) as a one-component field named `field_name` when the array exists; positions
// and values are divided by `scale`.
MeshData from_vtk_grid(vtkUnstructuredGrid& grid, const std::string& array_name, const std::string& field_name,
                       double scale = 1.0);

}  // namespace topotet::bench
