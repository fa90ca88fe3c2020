// vtkTopotetSimplify (paraview/filter/), run as a plain VTK filter without ParaView's GUI or
// server: built only in a tree configured with -DTOPOTET_BUILD_PARAVIEW=ON, against ParaView's VTK.
// A two-material grid with a listed surface, a polyline and a field goes through the filter; the
// output is read back with the io/vtk mapping and refereed by the checker (metrics/), not only by
// the verdict the filter reports about itself.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>

#include <set>
#include <string>

#include "io/vtk/vtk_grid.h"
#include "test_meshes.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"
#include "vtkTopotetSimplify.h"

namespace {

using topotet::MeshData;

// Two materials (x below / above the middle), the plane between them as a listed surface (ref 7),
// a polyline along an edge of the box (ref 9), and a linear point field "f": 10x6x6 cubes,
// 2,160 tets, 539 vertices.
MeshData two_materials() {
  topotet::testing::Grid g = topotet::testing::make_grid(10, 6, 6, [](int i, int, int) { return i < 5 ? 1 : 2; });
  topotet::testing::add_patch(g, 0, 5, [](int, int) { return true; }, 7);
  topotet::testing::add_polyline(g, topotet::testing::grid_line({0, 0, 0}, {10, 0, 0}), 9);
  topotet::testing::add_linear_field(g);
  return g.data;
}

// Counts the errors the filter reports (vtkErrorMacro), which would otherwise go to the terminal.
class ErrorCounter final : public vtkCommand {
 public:
  static ErrorCounter* New() { return new ErrorCounter; }
  void Execute(vtkObject*, unsigned long, void* data) override {
    ++count;
    last = data ? static_cast<const char*>(data) : "";
  }
  int count = 0;
  std::string last;
};

std::string field_string(vtkUnstructuredGrid* grid, const char* name) {
  auto* a = vtkStringArray::SafeDownCast(grid->GetFieldData()->GetAbstractArray(name));
  return a && a->GetNumberOfValues() > 0 ? a->GetValue(0) : std::string("<missing>");
}

}  // namespace

TEST(ParaViewFilter, defaults_are_the_library_defaults) {
  vtkNew<vtkTopotetSimplify> filter;
  const topotet::SimplifyOptions defaults;
  EXPECT_EQ(filter->GetTargetRatio(), defaults.target_vertex_ratio);
  EXPECT_EQ(filter->GetTargetVertices(), static_cast<vtkIdType>(defaults.target_vertices));
  EXPECT_EQ(filter->GetToleranceRel(), defaults.tolerance_rel);
  EXPECT_EQ(filter->GetTolerance(), defaults.tolerance);
  EXPECT_EQ(filter->GetFeatureAngle(), defaults.feature_angle);
  EXPECT_EQ(filter->GetMinQuality(), defaults.min_quality);
  EXPECT_EQ(filter->GetMinDihedral(), defaults.min_dihedral);
  EXPECT_EQ(filter->GetRelaxLimits() != 0, defaults.relax_tolerance && defaults.relax_quality && defaults.relax_features);
  EXPECT_EQ(filter->GetMaxCost(), defaults.max_cost);
  EXPECT_EQ(filter->GetMaxFieldErrorRel(), defaults.max_field_error_rel);
  EXPECT_EQ(filter->GetOptimize(), static_cast<int>(defaults.optimize));
  EXPECT_EQ(filter->GetSequential() != 0, defaults.engine == topotet::Engine::kSequential);
  EXPECT_EQ(filter->GetNumberOfThreads(), defaults.num_threads);
  EXPECT_EQ(std::string(filter->GetMaterialArrayName()), topotet::ReadOptions{}.material_array);
  EXPECT_EQ(filter->GetTetsOnly() != 0, topotet::ReadOptions{}.tets_only);
}

TEST(ParaViewFilter, simplifies_two_materials_and_keeps_their_topology) {
  const MeshData input = two_materials();
  vtkNew<vtkTopotetSimplify> filter;
  filter->SetInputData(topotet::io::vtk::grid_from_mesh(input));
  filter->SetTargetRatio(0.3);
  ASSERT_EQ(filter->GetExecutive()->Update(), 1);
  vtkUnstructuredGrid* out = filter->GetOutput();

  // The target: 30% of 539 vertices, give or take what the guarantees keep.
  EXPECT_LE(out->GetNumberOfPoints(), 0.3 * 539 + 20);
  EXPECT_GT(out->GetNumberOfPoints(), 30);
  EXPECT_EQ(field_string(out, "topotet_status"), "ok");
  EXPECT_EQ(field_string(out, "topotet_topology"), "PASS");
  auto* vertices = vtkIdTypeArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("topotet_vertices"));
  ASSERT_NE(vertices, nullptr);
  EXPECT_EQ(vertices->GetValue(0), 539);
  EXPECT_EQ(vertices->GetValue(1), out->GetNumberOfPoints());

  // The material array keeps its name and its two values; the field comes back.
  vtkDataArray* material = out->GetCellData()->GetArray("material");
  ASSERT_NE(material, nullptr);
  std::set<int> tet_materials;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
    if (out->GetCellType(c) == VTK_TETRA) tet_materials.insert(static_cast<int>(material->GetComponent(c, 0)));
  EXPECT_EQ(tet_materials, (std::set<int>{1, 2}));
  ASSERT_NE(out->GetPointData()->GetArray("f"), nullptr);

  // The independent referee, on the output read back as any VTK grid is read.
  const MeshData after = topotet::io::vtk::mesh_from_grid(out, "output");
  EXPECT_FALSE(after.triangles.empty());
  EXPECT_FALSE(after.segments.empty());
  std::string differences;
  EXPECT_TRUE(topotet::same_topology(topotet::compute_topology(input), topotet::compute_topology(after), &differences))
      << differences;
}

TEST(ParaViewFilter, output_is_the_same_for_every_thread_count) {
  const auto run = [](int threads) {
    vtkNew<vtkTopotetSimplify> filter;
    filter->SetInputData(topotet::io::vtk::grid_from_mesh(two_materials()));
    filter->SetTargetRatio(0.3);
    filter->SetNumberOfThreads(threads);
    filter->Update();
    return topotet::io::vtk::mesh_from_grid(filter->GetOutput(), "output");
  };
  EXPECT_EQ(run(1), run(2));
}

TEST(ParaViewFilter, a_named_material_array_is_used_and_kept) {
  const MeshData input = two_materials();
  vtkNew<vtkTopotetSimplify> filter;
  filter->SetInputData(topotet::io::vtk::grid_from_mesh(input, "zone"));
  filter->SetMaterialArrayName("zone");
  ASSERT_EQ(filter->GetExecutive()->Update(), 1);
  EXPECT_NE(filter->GetOutput()->GetCellData()->GetArray("zone"), nullptr);
  EXPECT_EQ(filter->GetOutput()->GetCellData()->GetArray("material"), nullptr);
}

TEST(ParaViewFilter, bad_input_is_an_error_and_an_empty_output) {
  // A material array that is not there, then a grid without tets: each an error message naming
  // the problem, no crash, and no stale output from the run before.
  vtkNew<vtkTopotetSimplify> filter;
  vtkNew<ErrorCounter> errors, pipeline_errors;  // the pipeline's: "returned failure", once per failed run
  filter->AddObserver(vtkCommand::ErrorEvent, errors);
  filter->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline_errors);
  filter->SetInputData(topotet::io::vtk::grid_from_mesh(two_materials()));
  ASSERT_EQ(filter->GetExecutive()->Update(), 1);
  ASSERT_GT(filter->GetOutput()->GetNumberOfCells(), 0);

  filter->SetMaterialArrayName("no_such_array");
  EXPECT_EQ(filter->GetExecutive()->Update(), 0);
  EXPECT_EQ(errors->count, 1);
  EXPECT_NE(errors->last.find("no_such_array"), std::string::npos) << errors->last;
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);

  MeshData no_tets = two_materials();
  no_tets.tets.clear();
  no_tets.tet_material.clear();
  no_tets.segments.clear();
  filter->SetMaterialArrayName("");
  filter->SetInputData(topotet::io::vtk::grid_from_mesh(no_tets));
  EXPECT_EQ(filter->GetExecutive()->Update(), 0);
  EXPECT_EQ(errors->count, 2);
  EXPECT_NE(errors->last.find("no tetrahedra"), std::string::npos) << errors->last;
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);
  EXPECT_EQ(pipeline_errors->count, 2);
}
