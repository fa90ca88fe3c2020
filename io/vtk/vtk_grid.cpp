// MeshData -> vtkUnstructuredGrid (vtk_grid.h). The other direction, mesh_from_grid, lives with
// the readers' conversion it shares (vtk_read.cpp).
#include "io/vtk/vtk_grid.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkSmartPointer.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <cmath>

namespace topotet::io::vtk {

vtkSmartPointer<vtkUnstructuredGrid> grid_from_mesh(const MeshData& m, const std::string& material_array) {
  const auto nv = static_cast<vtkIdType>(m.positions.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nv);
  for (vtkIdType v = 0; v < nv; ++v) points->SetPoint(v, m.positions[static_cast<std::size_t>(v)].data());

  // One pass over every cell kind in the documented order, filling the connectivity, the offsets,
  // the types and the material array together.
  const std::size_t pinned = m.corners.size() + m.required_vertices.size();
  const std::size_t cell_count = m.tets.size() + m.triangles.size() + m.segments.size() + pinned;
  const std::size_t id_count = 4 * m.tets.size() + 3 * m.triangles.size() + 2 * m.segments.size() + pinned;
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(static_cast<vtkIdType>(cell_count + 1));
  connectivity->SetNumberOfValues(static_cast<vtkIdType>(id_count));
  vtkNew<vtkUnsignedCharArray> types;
  types->SetNumberOfValues(static_cast<vtkIdType>(cell_count));
  vtkNew<vtkIntArray> material;
  material->SetName(material_array.empty() ? "material" : material_array.c_str());
  material->SetNumberOfValues(static_cast<vtkIdType>(cell_count));
  vtkIdType cell = 0, at = 0;
  const auto add = [&](int type, const VertId* v, int n, std::int32_t value) {
    offsets->SetValue(cell, at);
    for (int k = 0; k < n; ++k) connectivity->SetValue(at++, v[k]);
    types->SetValue(cell, static_cast<unsigned char>(type));
    material->SetValue(cell++, value);
  };
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    add(VTK_TETRA, m.tets[t].data(), 4, m.tet_material.empty() ? 0 : m.tet_material[t]);
  for (const Triangle& f : m.triangles) add(VTK_TRIANGLE, f.v.data(), 3, f.ref);
  for (const Segment& s : m.segments) add(VTK_LINE, s.v.data(), 2, s.ref);
  for (const auto* list : {&m.corners, &m.required_vertices})
    for (const VertId& v : *list) add(VTK_VERTEX, &v, 1, 0);
  offsets->SetValue(cell, at);

  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->SetCells(types, cells);
  grid->GetCellData()->AddArray(material);
  grid->GetCellData()->SetActiveScalars(material->GetName());
  // Cell fields on the tets (the first cells); the substructure cells get 0. Labels that are all
  // int32 values become an int array, as the readers expect of labels.
  for (const CellField& f : m.cell_fields) {
    const bool as_int = f.kind == CellFieldKind::kCategorical &&
                        std::all_of(f.values.begin(), f.values.end(), [](double x) {
                          return x == std::trunc(x) && std::abs(x) < 2147483647.0;
                        });
    vtkSmartPointer<vtkDataArray> a;
    if (as_int) {
      a = vtkSmartPointer<vtkIntArray>::New();
    } else {
      a = vtkSmartPointer<vtkDoubleArray>::New();
    }
    a->SetName(f.name.c_str());
    a->SetNumberOfComponents(f.components);
    a->SetNumberOfTuples(static_cast<vtkIdType>(cell_count));
    a->Fill(0.0);
    const auto c = static_cast<std::size_t>(f.components);
    for (std::size_t t = 0; t < m.tets.size(); ++t)
      for (std::size_t k = 0; k < c; ++k) a->SetComponent(static_cast<vtkIdType>(t), static_cast<int>(k), f.values[t * c + k]);
    grid->GetCellData()->AddArray(a);
  }
  for (const VertexField& f : m.fields) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(f.name.c_str());
    a->SetNumberOfComponents(f.components);
    a->SetNumberOfTuples(nv);
    std::copy(f.values.begin(), f.values.end(), a->GetPointer(0));
    grid->GetPointData()->AddArray(a);
  }
  return grid;
}

}  // namespace topotet::io::vtk
