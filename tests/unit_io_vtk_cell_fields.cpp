// Cell fields through the VTK component: topotet's .vtu read back by VTK's reader, Exodus element
// variables, a grid in memory (the ParaView filter's path), and what is not carried.
#include <gtest/gtest.h>

#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>

#include "cell_fields_test_mesh.h"
#include "io_test_files.h"
#include "io/vtk/vtk_grid.h"
#include "topotet/io.h"
#include "topotet/io_vtk.h"

namespace topotet {
namespace {

using test::cell_values_by_tet;
using test::TempDir;
using test::mesh_with_cell_fields;

TEST(CellFieldsVtk, vtu_round_trip_keeps_values_and_kinds) {
  TempDir dir;
  const MeshData m = mesh_with_cell_fields();
  for (const bool binary : {false, true}) {
    write_mesh(dir.file("a.vtu"), m, WriteOptions{.binary = binary});
    ReadNotes notes;
    const MeshData back = read_vtk_mesh(dir.file("a.vtu"), {}, &notes);
    EXPECT_TRUE(notes.unread_arrays.empty());
    EXPECT_TRUE(back.cell_fields == m.cell_fields);  // Int32 "region" comes back categorical
  }
}

TEST(CellFieldsVtk, exodus_element_variables_round_trip) {
  TempDir dir;
  const MeshData m = mesh_with_cell_fields();
  write_exodus(dir.file("a.exo"), m);
  const MeshData back = read_vtk_mesh(dir.file("a.exo"));
  ASSERT_EQ(back.cell_fields.size(), m.cell_fields.size());
  for (std::size_t f = 0; f < m.cell_fields.size(); ++f) {
    EXPECT_EQ(back.cell_fields[f].name, m.cell_fields[f].name);
    EXPECT_EQ(back.cell_fields[f].components, m.cell_fields[f].components);
  }
  EXPECT_TRUE(cell_values_by_tet(back) == cell_values_by_tet(m));
}

TEST(CellFieldsVtk, grid_in_memory_round_trip) {
  const MeshData m = mesh_with_cell_fields();
  const MeshData back = io::vtk::mesh_from_grid(io::vtk::grid_from_mesh(m), "grid", {}, nullptr);
  EXPECT_TRUE(back.cell_fields == m.cell_fields);
}

TEST(CellFieldsVtk, non_numeric_arrays_are_noted) {
  const MeshData m = mesh_with_cell_fields();
  auto g = io::vtk::grid_from_mesh(m);
  vtkNew<vtkStringArray> names;
  names->SetName("label");
  names->SetNumberOfValues(g->GetNumberOfCells());
  g->GetCellData()->AddArray(names);
  ReadNotes notes;
  const MeshData back = io::vtk::mesh_from_grid(g, "grid", {}, &notes);
  ASSERT_EQ(notes.unread_arrays.size(), 1u);
  EXPECT_NE(notes.unread_arrays[0].find("label"), std::string::npos);
  EXPECT_TRUE(back.cell_fields == m.cell_fields);
}

TEST(CellFieldsVtk, tets_only_drops_the_values_of_left_out_cells) {
  // A hexahedron between two tets: its value leaves with it.
  vtkNew<vtkPoints> points;
  for (int i = 0; i < 8; ++i) points->InsertNextPoint(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  points->InsertNextPoint(3, 3, 3);
  vtkNew<vtkUnstructuredGrid> g;
  g->SetPoints(points);
  const vtkIdType tet0[4] = {0, 1, 2, 4}, hex[8] = {0, 1, 3, 2, 4, 5, 7, 6}, tet1[4] = {7, 6, 5, 8};
  g->InsertNextCell(VTK_TETRA, 4, tet0);
  g->InsertNextCell(VTK_HEXAHEDRON, 8, hex);
  g->InsertNextCell(VTK_TETRA, 4, tet1);
  vtkNew<vtkDoubleArray> q;
  q->SetName("q");
  for (double x : {1.0, 2.0, 3.0}) q->InsertNextValue(x);
  g->GetCellData()->AddArray(q);
  ReadOptions options;
  options.tets_only = true;
  const MeshData back = io::vtk::mesh_from_grid(g, "grid", options, nullptr);
  ASSERT_EQ(back.cell_fields.size(), 1u);
  EXPECT_EQ(back.cell_fields[0].values, (std::vector<double>{1.0, 3.0}));
  EXPECT_EQ(back.cell_fields[0].kind, CellFieldKind::kIntensive);
}

}  // namespace
}  // namespace topotet
