// The build from a caller's strided arrays (engine/mesh/mesh_view.h, used by the C API and Python):
// it gives the model that build_tet_mesh gives from the same mesh in a MeshData, and refuses bad
// input with the same messages, because both go through one validation path.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/mesh_view.h"
#include "test_meshes.h"
#include "topotet/error.h"

namespace topotet {
namespace {

// The caller's layout: one struct per vertex (float32 position between other members) and 1-based
// int32 tets, so every view is strided and typed unlike MeshData.
struct CallerVertex {
  std::int64_t id;
  float xyz[3];
  double temperature;
};

struct CallerMesh {
  std::vector<CallerVertex> vertices;
  std::vector<std::array<std::int32_t, 4>> tets;  // 1-based
  std::vector<std::int64_t> materials;

  explicit CallerMesh(const MeshData& d) {
    for (std::size_t v = 0; v < d.vertex_count(); ++v)
      vertices.push_back({static_cast<std::int64_t>(v),
                          {static_cast<float>(d.positions[v][0]), static_cast<float>(d.positions[v][1]),
                           static_cast<float>(d.positions[v][2])},
                          d.fields.empty() ? 0.0 : d.fields[0].values[v]});
    for (const auto& t : d.tets)
      tets.push_back({static_cast<std::int32_t>(t[0] + 1), static_cast<std::int32_t>(t[1] + 1),
                      static_cast<std::int32_t>(t[2] + 1), static_cast<std::int32_t>(t[3] + 1)});
    materials.assign(d.tet_material.begin(), d.tet_material.end());
  }

  MeshView view() const {
    MeshView m;
    m.vertex_count = vertices.size();
    m.tet_count = tets.size();
    m.positions = {&vertices[0].xyz[0], StridedArray::Type::kFloat32, sizeof(CallerVertex), 0};
    m.tets = {tets.data(), StridedArray::Type::kInt32, 0, 0};
    m.materials = {materials.data(), StridedArray::Type::kInt64, 0, 0};
    m.index_base = 1;
    m.fields.push_back({"temperature", 1, {&vertices[0].temperature, StridedArray::Type::kFloat64,
                                           sizeof(CallerVertex), 0}});
    return m;
  }
};

// The same mesh as a MeshData: positions rounded to float as the caller holds them.
MeshData as_float(MeshData d) {
  for (auto& p : d.positions)
    for (double& x : p) x = static_cast<float>(x);
  return d;
}

testing::Grid grid_with_field() {
  testing::Grid g = testing::make_grid(3, 3, 3, [](int i, int, int) { return i < 2 ? 1 : 7; }, 0.2);
  g.data.fields.push_back({"temperature", 1, std::vector<double>(g.data.vertex_count())});
  for (std::size_t v = 0; v < g.data.vertex_count(); ++v) g.data.fields[0].values[v] = 0.5 * static_cast<double>(v);
  return g;
}

std::string message_of(const auto& build) {
  try {
    build();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(MeshView, BuildsTheModelThatTheMeshDataGives) {
  const testing::Grid g = grid_with_field();
  const CallerMesh caller(g.data);
  const MeshModel from_view = build_mesh_model(caller.view());
  const MeshModel from_data = build_mesh_model(as_float(g.data));
  EXPECT_EQ(from_view.to_mesh_data(), from_data.to_mesh_data());
  EXPECT_EQ(from_view.v2t, from_data.v2t);
  EXPECT_EQ(from_view.flags, from_data.flags);
}

TEST(MeshView, ColumnStridesReadATransposedArray) {
  const testing::Grid g = testing::make_grid(2, 2, 2, [](int, int, int) { return 1; });
  // Coordinates stored column by column (x of every vertex, then y, then z), as a transposed
  // numpy array is: the column stride is a whole column.
  const std::size_t nv = g.data.vertex_count();
  std::vector<double> columns(3 * nv);
  for (std::size_t v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) columns[k * nv + v] = g.data.positions[v][k];
  std::vector<std::int64_t> tets;
  for (const auto& t : g.data.tets) tets.insert(tets.end(), t.begin(), t.end());
  MeshView view;
  view.vertex_count = nv;
  view.tet_count = g.data.tet_count();
  view.positions = {columns.data(), StridedArray::Type::kFloat64, sizeof(double),
                    static_cast<std::int64_t>(nv * sizeof(double))};
  view.tets = {tets.data(), StridedArray::Type::kInt64, 0, 0};
  MeshData data = g.data;
  data.tet_material.assign(data.tet_count(), 0);  // no materials given: all 0
  EXPECT_EQ(build_mesh_model(view).to_mesh_data(), build_mesh_model(data).to_mesh_data());
}

TEST(MeshView, BadInputHasTheMessagesOfTheMeshDataBuild) {
  const testing::Grid g = grid_with_field();
  CallerMesh caller(g.data);
  MeshData data = as_float(g.data);
  // An index past the last vertex (1-based view, so both count the same way).
  caller.tets[3][1] = static_cast<std::int32_t>(g.data.vertex_count() + 5);
  data.tets[3][1] = static_cast<VertId>(g.data.vertex_count() + 4);
  const std::string out_of_range = message_of([&] { build_mesh_model(caller.view()); });
  EXPECT_NE(out_of_range.find("tet 4: vertex index"), std::string::npos) << out_of_range;
  EXPECT_EQ(out_of_range, message_of([&] { build_mesh_model(data); }));
  caller = CallerMesh(g.data);
  data = as_float(g.data);
  // A non-finite coordinate and a non-finite field value.
  caller.vertices[5].xyz[1] = NAN;
  data.positions[5][1] = NAN;
  EXPECT_EQ(message_of([&] { build_mesh_model(caller.view()); }), message_of([&] { build_mesh_model(data); }));
  caller = CallerMesh(g.data);
  data = as_float(g.data);
  caller.vertices[8].temperature = INFINITY;
  data.fields[0].values[8] = INFINITY;
  const std::string field = message_of([&] { build_mesh_model(caller.view()); });
  EXPECT_NE(field.find("field 'temperature', vertex 9"), std::string::npos) << field;
  EXPECT_EQ(field, message_of([&] { build_mesh_model(data); }));
  // A repeated vertex.
  caller = CallerMesh(g.data);
  data = as_float(g.data);
  caller.tets[2][3] = caller.tets[2][0];
  data.tets[2][3] = data.tets[2][0];
  EXPECT_EQ(message_of([&] { build_mesh_model(caller.view()); }), message_of([&] { build_mesh_model(data); }));
}

TEST(MeshView, IndicesAndLabelsThatFitNoIdAreRefusedByName) {
  const testing::Grid g = grid_with_field();
  CallerMesh caller(g.data);
  caller.tets[6][2] = 0;  // below index_base 1
  EXPECT_EQ(message_of([&] { build_mesh_model(caller.view()); }),
            "tet 7: vertex index 0 out of range (index_base 1)");
  caller = CallerMesh(g.data);
  caller.materials[2] = std::int64_t{1} << 40;
  EXPECT_EQ(message_of([&] { build_mesh_model(caller.view()); }), "material 3: 1099511627776 does not fit in 32 bits");
  MeshView no_tets = caller.view();
  no_tets.tet_count = 0;
  EXPECT_EQ(message_of([&] { build_mesh_model(no_tets); }), "the mesh has no tetrahedra");
  MeshView reals_as_tets = caller.view();
  reals_as_tets.tets.type = StridedArray::Type::kFloat64;
  EXPECT_EQ(message_of([&] { build_mesh_model(reals_as_tets); }), "tets: must hold integers");
}

}  // namespace
}  // namespace topotet
