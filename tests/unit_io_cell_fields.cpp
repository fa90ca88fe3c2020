// Cell fields through the core formats: MEDIT SolAtTetrahedra, Gmsh $ElementData (4.1 ASCII and
// binary, 2.2), VTU CellData (written here; read back in unit_io_vtk_cell_fields.cpp), and the
// errors of bad input, which name the file and the line.
#include <gtest/gtest.h>

#include "cell_fields_test_mesh.h"
#include "io_test_files.h"
#include "topotet/error.h"
#include "topotet/io.h"

namespace topotet {
namespace {

using test::cell_values_by_tet;
using test::TempDir;
using test::mesh_with_cell_fields;

using test::read_text;
using test::write_text;

void expect_error(const std::string& path, const std::string& where, const std::string& needle, const ReadOptions& options = {}) {
  test::expect_input_error([&] { read_mesh(path, options); }, {where, needle});
}

TEST(CellFieldsIo, medit_sol_keeps_names_kinds_and_values) {
  TempDir dir;
  const MeshData m = mesh_with_cell_fields();
  write_mesh(dir.file("a.mesh"), m);
  EXPECT_NE(read_text(dir.file("a.sol")).find("SolAtTetrahedra\n3\n4 1 1 2 3"), std::string::npos) << read_text(dir.file("a.sol"));
  const MeshData back = read_mesh(dir.file("a.mesh"));
  EXPECT_TRUE(back == m);  // the order of the tets is the file's: everything comes back exactly
}

TEST(CellFieldsIo, medit_default_names_need_no_names_file) {
  TempDir dir;
  MeshData m = mesh_with_cell_fields();
  m.fields.clear();
  m.cell_fields.resize(1);
  m.cell_fields[0].name = "cellsol0";
  write_mesh(dir.file("a.mesh"), m);
  EXPECT_FALSE(std::filesystem::exists(dir.file("a.sol.fields.txt")));
  EXPECT_TRUE(read_mesh(dir.file("a.mesh")) == m);
}

TEST(CellFieldsIo, medit_sol_count_must_match_the_tets) {
  TempDir dir;
  MeshData m = mesh_with_cell_fields();
  m.cell_fields.resize(1);
  m.fields.clear();
  write_mesh(dir.file("a.mesh"), m);
  write_text(dir.file("a.sol"), "MeshVersionFormatted 2\nDimension 3\nSolAtTetrahedra\n4\n1 1\n1\n2\n3\n4\nEnd\n");
  expect_error(dir.file("a.mesh"), dir.file("a.sol") + ":4:", "SolAtTetrahedra: 4 entries but the mesh has 3 tetrahedra");
}

void expect_gmsh_round_trip(const WriteOptions& options, const std::string& name) {
  SCOPED_TRACE(name);
  TempDir dir;
  const MeshData m = mesh_with_cell_fields();
  write_mesh(dir.file(name), m, options);
  const MeshData back = read_mesh(dir.file(name));
  ASSERT_EQ(back.tets.size(), m.tets.size());
  EXPECT_NE(back.tets, m.tets);  // grouped by material: the tags had to be followed
  ASSERT_EQ(back.cell_fields.size(), m.cell_fields.size());
  for (std::size_t f = 0; f < m.cell_fields.size(); ++f) {
    EXPECT_EQ(back.cell_fields[f].name, m.cell_fields[f].name);
    EXPECT_EQ(back.cell_fields[f].components, m.cell_fields[f].components);
    EXPECT_EQ(back.cell_fields[f].kind, CellFieldKind::kIntensive);  // Gmsh views hold reals
  }
  EXPECT_TRUE(cell_values_by_tet(back) == cell_values_by_tet(m));
}

TEST(CellFieldsIo, gmsh_element_data_round_trips) {
  expect_gmsh_round_trip({}, "a41.msh");
  expect_gmsh_round_trip({.binary = true}, "b41.msh");
  expect_gmsh_round_trip({.msh22 = true}, "a22.msh");
}

// Tets tagged 10 and 11, a triangle 5, a hexahedron 20 (with --tets-only).
constexpr const char* kMsh22Head =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n9\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n"
    "6 5 5 5\n7 6 5 5\n8 6 6 5\n9 5 6 5\n$EndNodes\n$Elements\n4\n5 2 2 1 1 1 2 3\n10 4 2 1 1 1 2 3 4\n"
    "11 4 2 1 1 2 3 4 5\n20 5 2 1 1 6 7 8 9 6 7 8 9\n$EndElements\n";

TEST(CellFieldsIo, gmsh_element_data_maps_tags_and_drops_left_out_cells) {
  TempDir dir;
  write_text(dir.file("a.msh"), std::string(kMsh22Head) +
                                    "$ElementData\n1\n\"q\"\n1\n0\n3\n0\n1\n3\n11 2.5\n20 9\n10 1.5\n$EndElementData\n");
  ReadOptions tets_only;
  tets_only.tets_only = true;
  const MeshData m = read_mesh(dir.file("a.msh"), tets_only);
  ASSERT_EQ(m.cell_fields.size(), 1u);
  EXPECT_EQ(m.cell_fields[0].name, "q");
  EXPECT_EQ(m.cell_fields[0].values, (std::vector<double>{1.5, 2.5}));
}

TEST(CellFieldsIo, gmsh_element_data_on_a_triangle_is_an_error) {
  TempDir dir;
  write_text(dir.file("a.msh"), std::string(kMsh22Head) +
                                    "$ElementData\n1\n\"q\"\n1\n0\n3\n0\n1\n2\n10 1\n5 2\n$EndElementData\n");
  ReadOptions tets_only;
  tets_only.tets_only = true;
  expect_error(dir.file("a.msh"), dir.file("a.msh") + ":33:", "element tag 5 is not a tetrahedron", tets_only);
}

TEST(CellFieldsIo, a_cell_array_of_the_wrong_size_is_not_written) {
  TempDir dir;
  MeshData m = mesh_with_cell_fields();
  m.cell_fields[1].values.pop_back();
  for (const char* name : {"a.mesh", "a.msh", "a.vtu"}) {
    try {
      write_mesh(dir.file(name), m);
      ADD_FAILURE() << name << ": written";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("cell array 'region': 2 values for 3 tets"), std::string::npos) << e.what();
    }
  }
}

TEST(CellFieldsIo, vtu_writes_cell_data) {
  TempDir dir;
  write_mesh(dir.file("a.vtu"), mesh_with_cell_fields());
  const std::string text = read_text(dir.file("a.vtu"));
  EXPECT_NE(text.find("<DataArray type=\"Float64\" Name=\"density\""), std::string::npos);
  EXPECT_NE(text.find("<DataArray type=\"Int32\" Name=\"region\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"stress\" NumberOfComponents=\"6\""), std::string::npos);
}

}  // namespace
}  // namespace topotet
