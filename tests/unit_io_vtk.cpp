// The VTK component (io/vtk/, topotet/io_vtk.h): round trips through topotet's own .vtu and
// write_exodus, files written by VTK's own writers (legacy .vtk, .pvtu, Exodus II) and by the CGNS
// library, a Gmsh-made .vtk, and bad input (each error names the file; VTK prints nothing).
#include <gtest/gtest.h>
#include <vtk_cgns.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridAlgorithm.h>
#include <vtkUnstructuredGridWriter.h>
#include <vtkXMLPUnstructuredGridWriter.h>
#include <vtkcgns/src/cgnslib.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "io/vtk/exodus_writer.h"
#include "io/vtk/vtk_grid.h"
#include "test_meshes.h"
#include "topotet/error.h"
#include "io_test_files.h"
#include "topotet/io.h"
#include "topotet/io_vtk.h"

namespace topotet {
namespace {

namespace fs = std::filesystem;

std::string test_data(const std::string& rel) { return std::string(TOPOTET_TEST_DATA_DIR) + "/" + rel; }

using test::read_text;
using test::TempDir;
using test::write_text;

// A 3x3x2 grid, two materials, a listed surface patch, a polyline, a scalar and a vector field;
// its tets sorted by material (the order an Exodus file keeps).
MeshData sample_mesh() {
  testing::Grid g = testing::make_grid(3, 3, 2, [](int i, int, int) { return i < 2 ? 1 : 2; });
  testing::add_patch(g, 2, 1, [](int a, int b) { return a < 2 && b < 2; }, 5);
  testing::add_polyline(g, testing::grid_line({0, 3, 0}, {0, 3, 2}), 8);
  testing::add_linear_field(g);
  MeshData m = std::move(g.data);
  VertexField v{"velocity", 3, {}};
  for (const auto& p : m.positions) v.values.insert(v.values.end(), {p[0], -p[1], 2 * p[2]});
  m.fields.push_back(std::move(v));
  std::vector<std::size_t> order(m.tets.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return m.tet_material[a] < m.tet_material[b]; });
  MeshData sorted = m;
  for (std::size_t i = 0; i < order.size(); ++i) {
    sorted.tets[i] = m.tets[order[i]];
    sorted.tet_material[i] = m.tet_material[order[i]];
  }
  return sorted;
}

// What the VTK formats carry: positions, tets, materials, triangles, segments, fields.
void expect_same_mesh(const MeshData& a, const MeshData& b) {
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.tets, b.tets);
  EXPECT_EQ(a.tet_material, b.tet_material);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.segments, b.segments);
  EXPECT_EQ(a.fields, b.fields);
}

// Triangles with their vertices in ascending order (an Exodus side lists its face in the tet's
// side order, not the listed triangle's).
std::vector<Triangle> unoriented(std::vector<Triangle> v) {
  for (Triangle& t : v) std::sort(t.v.begin(), t.v.end());
  return v;
}

template <class T>
std::vector<T> sorted_copy(std::vector<T> v) {
  std::sort(v.begin(), v.end(), [](const T& x, const T& y) { return std::tie(x.v, x.ref) < std::tie(y.v, y.ref); });
  return v;
}

// The mesh as VTK holds it: tets, triangles and lines as cells, a "material" cell array, the
// fields as point arrays.
vtkSmartPointer<vtkUnstructuredGrid> to_vtk(const MeshData& m, const std::vector<std::size_t>& tets) {
  auto g = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const auto& p : m.positions) points->InsertNextPoint(p.data());
  g->SetPoints(points);
  vtkNew<vtkIntArray> material;
  material->SetName("material");
  for (std::size_t t : tets) {
    const vtkIdType ids[4] = {m.tets[t][0], m.tets[t][1], m.tets[t][2], m.tets[t][3]};
    g->InsertNextCell(VTK_TETRA, 4, ids);
    material->InsertNextValue(m.tet_material[t]);
  }
  for (const Triangle& t : m.triangles) {
    const vtkIdType ids[3] = {t.v[0], t.v[1], t.v[2]};
    g->InsertNextCell(VTK_TRIANGLE, 3, ids);
    material->InsertNextValue(t.ref);
  }
  for (const Segment& s : m.segments) {
    const vtkIdType ids[2] = {s.v[0], s.v[1]};
    g->InsertNextCell(VTK_LINE, 2, ids);
    material->InsertNextValue(s.ref);
  }
  g->GetCellData()->AddArray(material);
  for (const VertexField& f : m.fields) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(f.name.c_str());
    a->SetNumberOfComponents(f.components);
    for (double x : f.values) a->InsertNextValue(x);
    g->GetPointData()->AddArray(a);
  }
  return g;
}
vtkSmartPointer<vtkUnstructuredGrid> to_vtk(const MeshData& m) {
  std::vector<std::size_t> all(m.tets.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  return to_vtk(m, all);
}

// Reads `path`, expecting an InputError that names the file and contains `needle`.
void expect_error(const std::string& path, const std::string& needle, const ReadOptions& options = {}) {
  ::testing::internal::CaptureStderr();
  try {
    read_vtk_mesh(path, options);
    ADD_FAILURE() << path << ": expected InputError containing '" << needle << "'";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path, 0), 0u) << what;
    EXPECT_NE(what.find(needle), std::string::npos) << what;
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "") << path << ": VTK printed";
}

// ---- topotet's own .vtu ----

TEST(VtkRead, OwnVtuWithSubstructuresRoundTrips) {
  TempDir dir;
  const MeshData m = sample_mesh();
  for (const bool binary : {false, true}) {
    SCOPED_TRACE(binary ? "raw appended" : "inline base64");
    write_mesh(dir.file("a.vtu"), m, WriteOptions{.binary = binary});
    ASSERT_TRUE(fs::exists(dir.file("a_substructures.vtp")));
    ReadNotes notes;
    const MeshData back = read_vtk_mesh(dir.file("a.vtu"), {}, &notes);
    expect_same_mesh(m, back);
    EXPECT_TRUE(notes.unread_arrays.empty());
    EXPECT_EQ(read_any_mesh(dir.file("a.vtu")), back);  // the dispatch goes the same way
  }
  // A mesh without substructures replaces the companion of an earlier write: none is read back.
  MeshData plain = m;
  plain.triangles.clear();
  plain.segments.clear();
  write_mesh(dir.file("a.vtu"), plain);
  EXPECT_FALSE(fs::exists(dir.file("a_substructures.vtp")));
  expect_same_mesh(plain, read_vtk_mesh(dir.file("a.vtu")));
}

// The in-memory form a VTK filter sees (io/vtk/vtk_grid.h, paraview/): substructures as cells of
// the grid, refs in the material array, and the array's name reported and kept.
TEST(VtkGrid, MeshRoundTripsThroughAGridInMemory) {
  MeshData m = sample_mesh();
  m.corners = {0, 5};
  ReadNotes notes;
  const MeshData back = io::vtk::mesh_from_grid(io::vtk::grid_from_mesh(m), "grid", {}, &notes);
  expect_same_mesh(m, back);
  EXPECT_EQ(back.corners, m.corners);
  EXPECT_EQ(notes.material_array, "material");
  EXPECT_TRUE(notes.unread_arrays.empty());

  ReadOptions named;
  named.material_array = "zone";
  expect_same_mesh(m, io::vtk::mesh_from_grid(io::vtk::grid_from_mesh(m, "zone"), "grid", named, &notes));
  EXPECT_EQ(notes.material_array, "zone");
  try {
    io::vtk::mesh_from_grid(io::vtk::grid_from_mesh(m, "zone"), "grid", ReadOptions{.material_array = "material"});
    ADD_FAILURE() << "a missing material array must be an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("grid: no cell array 'material'"), std::string::npos) << e.what();
  }
}

TEST(VtkRead, CompanionPointNotOnTheMeshIsAnError) {
  TempDir dir;
  MeshData m = sample_mesh();
  write_mesh(dir.file("a.vtu"), m);
  MeshData moved = m;
  moved.positions[moved.triangles[0].v[0]][0] += 0.5;  // the companion now lists a point the .vtu lacks
  write_mesh(dir.file("b.vtu"), moved);
  fs::copy_file(dir.file("b_substructures.vtp"), dir.file("a_substructures.vtp"), fs::copy_options::overwrite_existing);
  try {
    read_vtk_mesh(dir.file("a.vtu"));
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a_substructures.vtp: point "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is not a point of"), std::string::npos) << e.what();
  }
}

// ---- files written by VTK's own writers ----

TEST(VtkRead, LegacyVtkFromVtksWriter) {
  TempDir dir;
  const MeshData m = sample_mesh();
  for (const bool binary : {false, true}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    vtkNew<vtkUnstructuredGridWriter> w;
    w->SetInputData(to_vtk(m));
    w->SetFileName(dir.file("a.vtk").c_str());
    if (binary) w->SetFileTypeToBinary();
    ASSERT_EQ(w->Write(), 1);
    const MeshData back = read_vtk_mesh(dir.file("a.vtk"));
    ASSERT_EQ(back.positions.size(), m.positions.size());
    if (binary) {
      EXPECT_EQ(back.positions, m.positions);
    } else {  // ASCII: VTK's own precision
      for (std::size_t v = 0; v < m.positions.size(); ++v)
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(back.positions[v][k], m.positions[v][k], 1e-5);
    }
    EXPECT_EQ(back.tets, m.tets);
    EXPECT_EQ(back.tet_material, m.tet_material);
    EXPECT_EQ(back.triangles, m.triangles);
    EXPECT_EQ(back.segments, m.segments);
    ASSERT_EQ(back.fields.size(), 2u);
    EXPECT_EQ(back.fields[1].name, "velocity");
    EXPECT_EQ(back.fields[1].components, 3);
  }
}

// A source whose output is piece i of the grids it holds, as a distributed pipeline gives it.
class PieceSource final : public vtkUnstructuredGridAlgorithm {
 public:
  static PieceSource* New();
  vtkTypeMacro(PieceSource, vtkUnstructuredGridAlgorithm)
  std::vector<vtkSmartPointer<vtkUnstructuredGrid>> pieces;

 protected:
  PieceSource() { SetNumberOfInputPorts(0); }
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override {
    out->GetInformationObject(0)->Set(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST(), 1);
    return 1;
  }
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override {
    vtkInformation* info = out->GetInformationObject(0);
    const int piece = info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
    vtkUnstructuredGrid::GetData(info)->ShallowCopy(pieces.at(static_cast<std::size_t>(piece)));
    return 1;
  }
};
vtkStandardNewMacro(PieceSource)

// Two pieces written by VTK's parallel writer, their shared points repeated in each piece:
// joined by coordinates, or by VTK's global ids.
TEST(VtkRead, PvtuFromVtksWriter) {
  const MeshData m = sample_mesh();
  for (const bool global_ids : {false, true}) {
    SCOPED_TRACE(global_ids ? "global ids" : "coordinates");
    TempDir dir;
    vtkNew<PieceSource> source;
    const std::size_t half = m.tets.size() / 2;
    for (int piece = 0; piece < 2; ++piece) {
      std::vector<std::size_t> tets;
      for (std::size_t t = piece == 0 ? 0 : half; t < (piece == 0 ? half : m.tets.size()); ++t) tets.push_back(t);
      // Only the points the piece uses, in their original order.
      MeshData local;
      std::vector<VertId> local_id(m.positions.size(), kInvalid);
      std::vector<vtkIdType> global;
      for (std::size_t t : tets)
        for (VertId v : m.tets[t]) local_id[v] = 0;
      for (VertId v = 0; v < m.positions.size(); ++v)
        if (local_id[v] == 0) {
          local_id[v] = static_cast<VertId>(local.positions.size());
          local.positions.push_back(m.positions[v]);
          global.push_back(v);
        }
      for (std::size_t t : tets) {
        local.tets.push_back({local_id[m.tets[t][0]], local_id[m.tets[t][1]], local_id[m.tets[t][2]], local_id[m.tets[t][3]]});
        local.tet_material.push_back(m.tet_material[t]);
      }
      for (const VertexField& f : m.fields) {
        VertexField lf{f.name, f.components, {}};
        for (vtkIdType g : global)
          for (int c = 0; c < f.components; ++c) lf.values.push_back(f.values[static_cast<std::size_t>(g) * f.components + c]);
        local.fields.push_back(lf);
      }
      std::vector<std::size_t> all(local.tets.size());
      std::iota(all.begin(), all.end(), std::size_t{0});
      vtkSmartPointer<vtkUnstructuredGrid> grid = to_vtk(local, all);
      if (global_ids) {
        vtkNew<vtkIdTypeArray> ids;
        ids->SetName("GlobalPointIds");
        for (vtkIdType g : global) ids->InsertNextValue(g);
        grid->GetPointData()->SetGlobalIds(ids);
      }
      source->pieces.push_back(grid);
    }
    vtkNew<vtkXMLPUnstructuredGridWriter> w;
    w->SetInputConnection(source->GetOutputPort());
    w->SetFileName(dir.file("p.pvtu").c_str());
    w->SetNumberOfPieces(2);
    w->SetStartPiece(0);
    w->SetEndPiece(1);
    ASSERT_EQ(w->Write(), 1);
    const MeshData back = read_vtk_mesh(dir.file("p.pvtu"));
    // The points come back in order of first use, piece by piece: the same as the original order
    // here, since both pieces list their points in the original order and piece 0 uses them first.
    ASSERT_EQ(back.positions.size(), m.positions.size());
    EXPECT_EQ(back.tets.size(), m.tets.size());
    EXPECT_EQ(back.tet_material, m.tet_material);
    // Same tets by coordinates.
    for (std::size_t t = 0; t < m.tets.size(); ++t)
      for (int k = 0; k < 4; ++k) EXPECT_EQ(back.positions[back.tets[t][k]], m.positions[m.tets[t][k]]);
    ASSERT_EQ(back.fields.size(), 2u);
    for (std::size_t t = 0; t < m.tets.size(); ++t)
      for (int k = 0; k < 4; ++k)
        EXPECT_EQ(back.fields[0].values[back.tets[t][k]], m.fields[0].values[m.tets[t][k]]);
  }
}

// ---- Exodus II ----

TEST(VtkExodus, WriteExodusRoundTrips) {
  TempDir dir;
  MeshData m = sample_mesh();
  m.corners = {0, 5};
  m.required_vertices = {7};
  m.group_names = {{2, 5, "sheet"}, {3, 1, "left"}, {3, 2, "right"}};
  for (int components : {2, 6, 9}) {  // VTK's own reader would regroup these wrongly
    VertexField f{"t" + std::to_string(components), components, {}};
    for (std::size_t v = 0; v < m.positions.size(); ++v)
      for (int c = 0; c < components; ++c) f.values.push_back(static_cast<double>(v) + 0.125 * c);
    m.fields.push_back(f);
  }
  write_exodus(dir.file("a.exo"), m);
  ReadNotes notes;
  const MeshData back = read_vtk_mesh(dir.file("a.exo"), {}, &notes);
  EXPECT_EQ(back.positions, m.positions);
  EXPECT_EQ(back.tets, m.tets);  // sorted by material: the file's order
  EXPECT_EQ(back.tet_material, m.tet_material);
  EXPECT_EQ(sorted_copy(unoriented(back.triangles)), sorted_copy(unoriented(m.triangles)));
  EXPECT_EQ(sorted_copy(back.segments), sorted_copy(m.segments));
  EXPECT_EQ(back.corners, m.corners);
  EXPECT_EQ(back.required_vertices, m.required_vertices);
  EXPECT_EQ(back.group_names, m.group_names);
  ASSERT_EQ(back.fields.size(), m.fields.size());
  for (const VertexField& f : m.fields) {
    const auto at = std::find_if(back.fields.begin(), back.fields.end(), [&](const VertexField& b) { return b.name == f.name; });
    ASSERT_NE(at, back.fields.end()) << f.name;
    EXPECT_EQ(*at, f);
  }
  EXPECT_TRUE(notes.unread_arrays.empty());
  EXPECT_EQ(read_any_mesh(dir.file("a.exo")), back);
  // write_any_mesh goes to write_exodus for .e too; no temporary file is left.
  write_any_mesh(dir.file("b.e"), m);
  EXPECT_EQ(read_vtk_mesh(dir.file("b.e")).tets, m.tets);
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir.file(""))) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"a.exo", "b.e"}));
}

// Written by VTK's vtkExodusIIWriter directly (a third-party writer): two blocks (ids 3 and 5),
// a side set (id 7) and nodal variables.
TEST(VtkExodus, ThirdPartyFileWithBlocksAndSideSet) {
  TempDir dir;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  const double p[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  for (const auto& x : p) points->InsertNextPoint(x);
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  const vtkIdType t0[4] = {0, 1, 2, 3}, t1[4] = {1, 2, 3, 4};
  grid->InsertNextCell(VTK_TETRA, 4, t0);
  grid->InsertNextCell(VTK_TETRA, 4, t1);
  vtkNew<vtkIntArray> blocks;
  blocks->SetName("ElementBlockIds");
  blocks->InsertNextValue(3);
  blocks->InsertNextValue(5);
  grid->GetCellData()->AddArray(blocks);
  vtkNew<vtkDoubleArray> temperature;
  temperature->SetName("T");
  for (int i = 0; i < 5; ++i) temperature->InsertNextValue(1.5 * i);
  grid->GetPointData()->AddArray(temperature);
  vtkNew<vtkIdTypeArray> node_ids, element_ids;
  node_ids->SetName("GlobalNodeId");
  for (int i = 0; i < 5; ++i) node_ids->InsertNextValue(i + 1);
  grid->GetPointData()->SetGlobalIds(node_ids);
  element_ids->SetName("GlobalElementId");
  for (int i = 0; i < 2; ++i) element_ids->InsertNextValue(i + 1);
  grid->GetCellData()->SetGlobalIds(element_ids);
  // The side set as VTK's Exodus reader gives it: faces with their element and (0-based) side.
  vtkNew<vtkUnstructuredGrid> sides;
  sides->SetPoints(points);
  const vtkIdType f0[3] = {0, 2, 1}, f1[3] = {2, 3, 4};
  sides->InsertNextCell(VTK_TRIANGLE, 3, f0);
  sides->InsertNextCell(VTK_TRIANGLE, 3, f1);
  vtkNew<vtkIdTypeArray> element;
  element->SetName("SourceElementId");
  element->InsertNextValue(0);
  element->InsertNextValue(1);
  vtkNew<vtkIntArray> side;
  side->SetName("SourceElementSide");
  side->InsertNextValue(3);
  side->InsertNextValue(1);
  sides->GetCellData()->AddArray(element);
  sides->GetCellData()->AddArray(side);
  vtkNew<vtkMultiBlockDataSet> root, element_blocks, side_sets;
  element_blocks->SetNumberOfBlocks(1);
  element_blocks->SetBlock(0, grid);
  element_blocks->GetMetaData(0u)->Set(vtkCompositeDataSet::NAME(), "");
  side_sets->SetNumberOfBlocks(1);
  side_sets->SetBlock(0, sides);
  side_sets->GetMetaData(0u)->Set(vtkCompositeDataSet::NAME(), "wall ID: 7");
  root->SetNumberOfBlocks(2);
  root->SetBlock(0, element_blocks);
  root->GetMetaData(0u)->Set(vtkCompositeDataSet::NAME(), "Element Blocks");
  root->SetBlock(1, side_sets);
  root->GetMetaData(1u)->Set(vtkCompositeDataSet::NAME(), "Side Sets");
  vtkNew<topotet::io::vtk::ExodusWriter> w;  // VTK's writer, without its leak
  w->SetFileName(dir.file("third.exo").c_str());
  w->SetInputData(root);
  w->WriteAllTimeStepsOff();
  ASSERT_EQ(w->Write(), 1);

  const MeshData m = read_vtk_mesh(dir.file("third.exo"));
  EXPECT_EQ(m.positions.size(), 5u);
  EXPECT_EQ(m.tets, (std::vector<std::array<VertId, 4>>{{0, 1, 2, 3}, {1, 2, 3, 4}}));
  EXPECT_EQ(m.tet_material, (std::vector<std::int32_t>{3, 5}));
  EXPECT_EQ(m.triangles, (std::vector<Triangle>{{{0, 2, 1}, 7}, {{2, 3, 4}, 7}}));
  EXPECT_EQ(m.group_names, (std::vector<GroupName>{{2, 7, "wall"}}));
  ASSERT_EQ(m.fields.size(), 1u);
  EXPECT_EQ(m.fields[0].name, "T");
  EXPECT_EQ(m.fields[0].values, (std::vector<double>{0, 1.5, 3, 4.5, 6}));
  // An element variable as the material array: missing here, named in the error.
  expect_error(dir.file("third.exo"), "no cell array 'region'", ReadOptions{.material_array = "region"});
}

// ---- CGNS (written with the CGNS library VTK ships) ----

// Two unstructured zones (2 tets each, sharing no point), a vertex solution, and on zone 1 a
// triangle section used by a boundary condition of family "Wall"; `hexes` makes zone 2 hexahedral.
void write_cgns(const std::string& path, bool hexes = false) {
  int fn = 0, base = 0, family = 0, family_bc = 0;
  ASSERT_EQ(cg_open(path.c_str(), CG_MODE_WRITE, &fn), CG_OK) << cg_get_error();
  ASSERT_EQ(cg_base_write(fn, "Base", 3, 3, &base), CG_OK);
  ASSERT_EQ(cg_family_write(fn, base, "Wall", &family), CG_OK);
  ASSERT_EQ(cg_fambc_write(fn, base, family, "WallBC", CG_BCWall, &family_bc), CG_OK);
  for (int z = 0; z < 2; ++z) {
    const bool hex = hexes && z == 1;
    std::vector<double> x = {0, 1, 0, 0, 1}, y = {0, 0, 1, 0, 1}, zz = {0, 0, 0, 1, 1};
    if (hex) {
      x = {0, 1, 1, 0, 0, 1, 1, 0};
      y = {0, 0, 1, 1, 0, 0, 1, 1};
      zz = {0, 0, 0, 0, 1, 1, 1, 1};
    }
    const int nv = hex ? 8 : 5;
    for (double& v : x) v += 3.0 * z;
    const cgsize_t size[3] = {nv, hex ? 1 : 2, 0};
    int zone = 0, c = 0, s = 0, sol = 0, f = 0;
    ASSERT_EQ(cg_zone_write(fn, base, z == 0 ? "Fluid" : "Solid", size, CG_Unstructured, &zone), CG_OK);
    ASSERT_EQ(cg_coord_write(fn, base, zone, CG_RealDouble, "CoordinateX", x.data(), &c), CG_OK);
    ASSERT_EQ(cg_coord_write(fn, base, zone, CG_RealDouble, "CoordinateY", y.data(), &c), CG_OK);
    ASSERT_EQ(cg_coord_write(fn, base, zone, CG_RealDouble, "CoordinateZ", zz.data(), &c), CG_OK);
    if (hex) {
      const cgsize_t cells[8] = {1, 2, 3, 4, 5, 6, 7, 8};
      ASSERT_EQ(cg_section_write(fn, base, zone, "Hexes", CG_HEXA_8, 1, 1, 0, cells, &s), CG_OK);
    } else {
      const cgsize_t cells[8] = {1, 2, 3, 4, 2, 3, 4, 5};
      ASSERT_EQ(cg_section_write(fn, base, zone, "Tets", CG_TETRA_4, 1, 2, 0, cells, &s), CG_OK);
    }
    if (z == 0) {
      const cgsize_t tris[6] = {1, 3, 2, 2, 3, 5};
      ASSERT_EQ(cg_section_write(fn, base, zone, "WallFaces", CG_TRI_3, 3, 4, 0, tris, &s), CG_OK);
      const cgsize_t range[2] = {3, 4};
      int bc = 0;
      ASSERT_EQ(cg_boco_write(fn, base, zone, "wall", CG_FamilySpecified, CG_ElementRange, 2, range, &bc), CG_OK);
      ASSERT_EQ(cg_goto(fn, base, "Zone_t", zone, "ZoneBC_t", 1, "BC_t", bc, "end"), CG_OK);
      ASSERT_EQ(cg_famname_write("Wall"), CG_OK);
    }
    std::vector<double> pressure(static_cast<std::size_t>(nv));
    for (int i = 0; i < nv; ++i) pressure[static_cast<std::size_t>(i)] = 10.0 * z + i;
    ASSERT_EQ(cg_sol_write(fn, base, zone, "Flow", CG_Vertex, &sol), CG_OK);
    ASSERT_EQ(cg_field_write(fn, base, zone, sol, CG_RealDouble, "Pressure", pressure.data(), &f), CG_OK);
  }
  ASSERT_EQ(cg_close(fn), CG_OK);
}

TEST(VtkCgns, ZonesPatchesAndSolution) {
  TempDir dir;
  ASSERT_NO_FATAL_FAILURE(write_cgns(dir.file("a.cgns")));
  const MeshData m = read_vtk_mesh(dir.file("a.cgns"));
  EXPECT_EQ(m.positions.size(), 10u);
  EXPECT_EQ(m.tets.size(), 4u);
  EXPECT_EQ(m.tet_material, (std::vector<std::int32_t>{1, 1, 2, 2}));  // zone numbers
  ASSERT_EQ(m.triangles.size(), 2u);
  for (const Triangle& t : m.triangles) {
    EXPECT_EQ(t.ref, 1);
    for (VertId v : t.v) EXPECT_LT(m.positions[v][0], 2.0);  // on zone 1's points
  }
  EXPECT_EQ(m.group_names, (std::vector<GroupName>{{2, 1, "wall"}, {3, 1, "Fluid"}, {3, 2, "Solid"}}));
  ASSERT_EQ(m.fields.size(), 1u);
  EXPECT_EQ(m.fields[0].name, "Pressure");
  for (std::size_t v = 0; v < m.positions.size(); ++v)
    EXPECT_EQ(m.fields[0].values[v], m.positions[v][0] >= 2.0 ? 10.0 + static_cast<double>(v - 5) : static_cast<double>(v));
}

TEST(VtkCgns, HexahedralZoneAndDamagedFiles) {
  TempDir dir;
  ASSERT_NO_FATAL_FAILURE(write_cgns(dir.file("mixed.cgns"), true));
  expect_error(dir.file("mixed.cgns"), "zone 'Solid', cell 0 (hexahedron): topotet simplifies tetrahedral meshes only");
  ReadNotes notes;
  const MeshData m = read_vtk_mesh(dir.file("mixed.cgns"), ReadOptions{.tets_only = true}, &notes);
  EXPECT_EQ(m.tets.size(), 2u);
  EXPECT_EQ(notes.hexahedra, 1u);
  const std::string bytes = read_text(dir.file("mixed.cgns"));
  write_text(dir.file("cut.cgns"), bytes.substr(0, bytes.size() / 2));
  expect_error(dir.file("cut.cgns"), "not a readable CGNS file");
  write_text(dir.file("text.cgns"), "not a cgns file\n");
  expect_error(dir.file("text.cgns"), "not a CGNS file");
}

// ---- a real mesher: Gmsh's own legacy VTK output ----

TEST(VtkRead, GmshMadeLegacyVtk) {
  if (!fs::exists("/usr/bin/gmsh")) GTEST_SKIP() << "no /usr/bin/gmsh";
  TempDir dir;
  // The committed mesh re-saved by Gmsh as .vtk, with the physical tags as its CellEntityIds.
  const std::string cmd = "/usr/bin/gmsh " + test_data("gmsh_sphere_in_box.msh") +
                          " -0 -format vtk -setnumber Mesh.SaveElementTagType 2 -o " + dir.file("g.vtk") + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const MeshData v = read_vtk_mesh(dir.file("g.vtk"));
  const MeshData msh = read_mesh(test_data("gmsh_sphere_in_box.msh"));
  EXPECT_EQ(v.positions.size(), msh.positions.size());
  EXPECT_EQ(v.tets, msh.tets);
  EXPECT_EQ(v.tet_material, msh.tet_material);
  EXPECT_EQ(std::set<std::int32_t>(v.tet_material.begin(), v.tet_material.end()), (std::set<std::int32_t>{1, 2}));
  EXPECT_EQ(sorted_copy(v.triangles), sorted_copy(msh.triangles));
  EXPECT_EQ(sorted_copy(v.segments), sorted_copy(msh.segments));
  EXPECT_EQ(v.corners.size(), 2u);
}

// ---- bad input ----

std::string legacy_vtk(const std::string& points, const std::string& cells, const std::string& types) {
  return "# vtk DataFile Version 3.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\n" + points + cells + types;
}

TEST(VtkRead, BadInputNamesTheFile) {
  TempDir dir;
  const std::string five_points = "POINTS 5 double\n0 0 0 1 0 0 0 1 0 0 0 1 1 1 1\n";
  expect_error(dir.file("missing.vtu"), "cannot open: No such file or directory");
  expect_error(dir.file("missing.exo"), "cannot open");
  // A .vtu cut short.
  write_mesh(dir.file("a.vtu"), sample_mesh(), WriteOptions{.binary = true});
  const std::string vtu = read_text(dir.file("a.vtu"));
  write_text(dir.file("cut.vtu"), vtu.substr(0, vtu.size() / 2));
  expect_error(dir.file("cut.vtu"), "incomplete VTK XML file");
  write_text(dir.file("garbage.vtu"), "garbage\n</VTKFile>\n");
  expect_error(dir.file("garbage.vtu"), "VTK cannot read it");
  // NaN coordinates, connectivity out of range.
  MeshData nan = sample_mesh();
  nan.positions[2][1] = std::numeric_limits<double>::quiet_NaN();
  write_mesh(dir.file("nan.vtu"), nan);
  expect_error(dir.file("nan.vtu"), "point 2: coordinate is not finite");
  write_text(dir.file("range.vtk"), legacy_vtk(five_points, "CELLS 2 10\n4 0 1 2 3\n4 1 2 3 9\n", "CELL_TYPES 2\n10\n10\n"));
  expect_error(dir.file("range.vtk"), "cell 1: point index 9 out of range (5 points)");
  // A mixed grid: refused, or its tets kept with tets_only.
  const std::string eight = "POINTS 9 double\n0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1 2 2 2\n";
  write_text(dir.file("mixed.vtk"), legacy_vtk(eight, "CELLS 2 14\n8 0 1 2 3 4 5 6 7\n4 5 6 7 8\n", "CELL_TYPES 2\n12\n10\n"));
  expect_error(dir.file("mixed.vtk"), "cell 0 (hexahedron): topotet simplifies tetrahedral meshes only");
  ReadNotes notes;
  EXPECT_EQ(read_vtk_mesh(dir.file("mixed.vtk"), ReadOptions{.tets_only = true}, &notes).tets.size(), 1u);
  EXPECT_EQ(notes.hexahedra, 1u);
  // No tets at all (hexahedra only, even with tets_only; a surface mesh).
  write_text(dir.file("hex.vtk"), legacy_vtk(eight, "CELLS 1 9\n8 0 1 2 3 4 5 6 7\n", "CELL_TYPES 1\n12\n"));
  expect_error(dir.file("hex.vtk"), "the file has no tetrahedra", ReadOptions{.tets_only = true});
  write_text(dir.file("surface.vtk"), legacy_vtk(five_points, "CELLS 1 4\n3 0 1 2\n", "CELL_TYPES 1\n5\n"));
  expect_error(dir.file("surface.vtk"), "the file has no tetrahedra");
  write_text(dir.file("poly.vtk"), "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\n" + five_points);
  expect_error(dir.file("poly.vtk"), "not an unstructured grid (DATASET POLYDATA)");
  // Second-order cells.
  write_text(dir.file("quadratic.vtk"),
             legacy_vtk(eight + "", "CELLS 1 11\n10 0 1 2 3 4 5 6 7 8 0\n", "CELL_TYPES 1\n24\n"));
  expect_error(dir.file("quadratic.vtk"), "is not supported");
  // Material arrays: absent, not integral.
  write_text(dir.file("float.vtk"), legacy_vtk(five_points, "CELLS 1 5\n4 0 1 2 3\n", "CELL_TYPES 1\n10\n") +
                                        "CELL_DATA 1\nSCALARS material double 1\nLOOKUP_TABLE default\n1.5\n");
  expect_error(dir.file("float.vtk"), "cell 0: cell array 'material' value 1.5 is not an integer id");
  expect_error(dir.file("float.vtk"), "no cell array 'zone' (--material-array)", ReadOptions{.material_array = "zone"});
  // Exodus and CGNS files that are not.
  write_text(dir.file("text.exo"), "not exodus\n");
  expect_error(dir.file("text.exo"), "not an Exodus II file");
  write_exodus(dir.file("ok.exo"), sample_mesh());
  const std::string exo = read_text(dir.file("ok.exo"));
  write_text(dir.file("cut.exo"), exo.substr(0, 100));
  expect_error(dir.file("cut.exo"), "not an Exodus II file, or a truncated one");
  fs::create_directory(dir.file("folder.vtu"));
  expect_error(dir.file("folder.vtu"), "cannot open: is a directory");
}

TEST(VtkRead, CoreFunctionsPointAtTheComponent) {
  // topotet::read_mesh does not read VTK formats: its message names the component's functions.
  for (const char* path : {"x.exo", "x.vtk", "x.pvtu", "x.cgns"}) {
    try {
      read_mesh(path);
      ADD_FAILURE() << path;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("read_vtk_mesh"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(write_mesh("x.exo", sample_mesh()), InputError);
  // A material array is for the VTK formats only.
  try {
    read_mesh(test_data("gmsh_sphere_in_box.msh"), ReadOptions{.material_array = "material"});
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("applies to the VTK formats only"), std::string::npos) << e.what();
  }
  // read_any_mesh reads the core formats through read_mesh.
  EXPECT_EQ(read_any_mesh(test_data("gmsh_sphere_in_box.msh")), read_mesh(test_data("gmsh_sphere_in_box.msh")));
  EXPECT_TRUE(is_vtk_path("A.VTU") && is_vtk_path("b.ex2") && is_vtk_path("c.e") && !is_vtk_path("d.mesh"));
  EXPECT_TRUE(is_exodus_path("x.exo") && !is_exodus_path("x.vtu"));
}

}  // namespace
}  // namespace topotet
