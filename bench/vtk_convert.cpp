#include "vtk_convert.h"

#include <stdexcept>

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>

namespace topotet::bench {

vtkSmartPointer<vtkUnstructuredGrid> to_vtk_grid(const MeshData& mesh, const std::vector<double>& scalar,
                                                 const std::string& scalar_name, double scale) {
  const auto vertex_count = static_cast<vtkIdType>(mesh.vertex_count());
  const auto tet_count = static_cast<vtkIdType>(mesh.tet_count());

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(vertex_count);
  for (vtkIdType v = 0; v < vertex_count; ++v) {
    const std::array<double, 3>& p = mesh.positions[static_cast<std::size_t>(v)];
    points->SetPoint(v, p[0] * scale, p[1] * scale, p[2] * scale);
  }

  // Offsets + connectivity in one go: inserting 1M cells one by one costs more than the copy.
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(tet_count + 1);
  connectivity->SetNumberOfValues(4 * tet_count);
  for (vtkIdType t = 0; t <= tet_count; ++t) offsets->SetValue(t, 4 * t);
  for (vtkIdType t = 0; t < tet_count; ++t)
    for (int k = 0; k < 4; ++k) connectivity->SetValue(4 * t + k, mesh.tets[static_cast<std::size_t>(t)][k]);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);

  vtkNew<vtkDoubleArray> values;
  values->SetName(scalar_name.c_str());
  values->SetNumberOfValues(vertex_count);
  for (vtkIdType v = 0; v < vertex_count; ++v) values->SetValue(v, scalar[static_cast<std::size_t>(v)] * scale);

  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->SetCells(VTK_TETRA, cells);
  grid->GetPointData()->SetScalars(values);
  return grid;
}

MeshData from_vtk_grid(vtkUnstructuredGrid& grid, const std::string& array_name, const std::string& field_name,
                       double scale) {
  MeshData out;
  const vtkIdType vertex_count = grid.GetNumberOfPoints();
  out.positions.resize(static_cast<std::size_t>(vertex_count));
  for (vtkIdType v = 0; v < vertex_count; ++v) {
    double p[3];
    grid.GetPoint(v, p);
    out.positions[static_cast<std::size_t>(v)] = {p[0] / scale, p[1] / scale, p[2] / scale};
  }

  vtkCellArray* cells = grid.GetCells();
  const vtkIdType tet_count = cells ? cells->GetNumberOfCells() : 0;
  out.tets.resize(static_cast<std::size_t>(tet_count));
  out.tet_material.assign(static_cast<std::size_t>(tet_count), 0);
  for (vtkIdType t = 0; t < tet_count; ++t) {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    cells->GetCellAtId(t, n, ids);
    if (n != 4) throw std::runtime_error("VTK output holds a cell that is not a tet");
    for (int k = 0; k < 4; ++k) out.tets[static_cast<std::size_t>(t)][k] = static_cast<VertId>(ids[k]);
  }

  if (vtkDataArray* array = grid.GetPointData()->GetArray(array_name.c_str())) {
    VertexField field;
    field.name = field_name;
    field.values.resize(static_cast<std::size_t>(vertex_count));
    for (vtkIdType v = 0; v < vertex_count; ++v) field.values[static_cast<std::size_t>(v)] = array->GetComponent(v, 0) / scale;
    out.fields.push_back(std::move(field));
  }
  return out;
}

}  // namespace topotet::bench
