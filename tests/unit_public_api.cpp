// The public header's library-facing forms: the non-throwing read/build/write (status + message),
// TetMesh's accessors (its arrays are private), the named rejection reasons and phase times, and
// the generated version; and that no public header brings glm into a user's program.
//
// Every installed C++ header first, alone: if one of them included glm, GLM_VERSION would be set.
#include "topotet/error.h"
#include "topotet/features.h"
#include "topotet/generate.h"
#include "topotet/hierarchy.h"
#include "topotet/io.h"
#include "topotet/mesh_data.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/surface_distance.h"
#include "topotet/metrics/topology.h"
#include "topotet/nothrow.h"
#include "topotet/round_log.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"
#include "topotet/threads.h"
#include "topotet/version.h"
#if defined(GLM_VERSION)
#error "a public topotet header includes glm: positions in the public API are std::array<double, 3>"
#endif

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>

#include "test_meshes.h"

namespace topotet {
namespace {

TEST(NoThrow, ReadingAMissingFileIsAStatusNamingTheFile) {
  MeshData data;
  std::string message;
  EXPECT_EQ(try_read_mesh("/nonexistent/box.mesh", data, message), Status::kInvalidInput);
  EXPECT_NE(message.find("box.mesh"), std::string::npos) << message;
}

TEST(NoThrow, BuildingABadMeshIsAStatusNamingTheTet) {
  testing::Grid g = testing::make_grid(2, 2, 2, [](int, int, int) { return 1; });
  g.data.tets[3][1] = 999;
  TetMesh mesh;
  std::string message;
  EXPECT_EQ(try_build_tet_mesh(g.data, mesh, message), Status::kInvalidInput);
  EXPECT_NE(message.find("tet 4: vertex index 1000"), std::string::npos) << message;  // 1-based, as in files
  EXPECT_EQ(try_build_tet_mesh(g.data, mesh, message, {}, -1), Status::kInvalidInput);
}

TEST(NoThrow, AGoodMeshBuildsAndWritesWithAnEmptyMessage) {
  const testing::Grid g = testing::make_grid(2, 2, 2, [](int, int, int) { return 1; });
  TetMesh mesh;
  std::string message = "stale";
  ASSERT_EQ(try_build_tet_mesh(g.data, mesh, message, {}, 1), Status::kOk);
  EXPECT_TRUE(message.empty());
  EXPECT_EQ(mesh.live_tet_count(), g.data.tet_count());
  EXPECT_EQ(try_write_mesh("/nonexistent-folder/out.mesh", mesh.to_mesh_data(), message), Status::kInvalidInput);
  EXPECT_FALSE(message.empty());
}

// The model's arrays are not part of the public API: a user sees the accessors only.
template <class M>
concept ExposesArrays = requires(M m) { m.positions; } || requires(M m) { m.tets; } ||
                        requires(M m) { m.v2t; } || requires(M m) { m.vertex_states; };
static_assert(!ExposesArrays<TetMesh>);
// Plain arrays in the public API: a caller's double[n][3] has this layout.
static_assert(std::is_same_v<decltype(MeshData::positions)::value_type, std::array<double, 3>>);
static_assert(std::is_same_v<decltype(Voi::centre), std::array<double, 3>>);
static_assert(sizeof(std::array<double, 3>) == 3 * sizeof(double));

TEST(PublicTetMesh, AccessorsReadTheBuiltModel) {
  const testing::Grid g = testing::make_grid(2, 2, 2, [](int i, int, int) { return i == 0 ? 3 : 4; });
  const TetMesh mesh = build_tet_mesh(g.data);
  ASSERT_EQ(mesh.vertex_capacity(), g.data.vertex_count());
  ASSERT_EQ(mesh.tet_capacity(), g.data.tet_count());
  EXPECT_EQ(mesh.live_vertex_count(), g.data.vertex_count());
  for (VertId v = 0; v < mesh.vertex_capacity(); ++v) {
    const std::array<double, 3> p = mesh.position(v);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(p[c], g.data.positions[v][c]);
      EXPECT_EQ(mesh.positions_data()[3 * v + c], p[c]);
    }
    EXPECT_FALSE(mesh.is_dead_vertex(v));
  }
  for (TetId t = 0; t < mesh.tet_capacity(); ++t) {
    EXPECT_EQ(mesh.material(t), g.data.tet_material[t]);
    EXPECT_EQ(mesh.materials_data()[t], g.data.tet_material[t]);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(mesh.tets_data()[4 * t + k], mesh.tet(t)[k]);
    std::array<VertId, 4> built = mesh.tet(t), given = g.data.tets[t];
    std::sort(built.begin(), built.end());
    std::sort(given.begin(), given.end());
    EXPECT_EQ(built, given);  // the same tet, possibly reoriented
  }
  EXPECT_GT(mesh.memory_bytes(), 0u);
  EXPECT_EQ(mesh.to_mesh_data().tet_count(), g.data.tet_count());
}

TEST(PublicTetMesh, FieldsAreReadThroughTheirLayout) {
  testing::Grid g = testing::make_grid(2, 2, 2, [](int, int, int) { return 1; });
  const std::size_t nv = g.data.vertex_count();
  VertexField scalar{"s", 1, std::vector<double>(nv)}, vector{"v", 3, std::vector<double>(3 * nv)};
  for (std::size_t v = 0; v < nv; ++v) {
    scalar.values[v] = static_cast<double>(v);
    for (int c = 0; c < 3; ++c) vector.values[3 * v + c] = 100.0 * static_cast<double>(v) + c;
  }
  g.data.fields = {scalar, vector};
  const TetMesh mesh = build_tet_mesh(g.data);
  ASSERT_EQ(mesh.fields().size(), 2u);
  EXPECT_EQ(mesh.fields()[1].name, "v");
  ASSERT_EQ(mesh.field_stride(), 4);
  for (std::size_t v = 0; v < nv; ++v) {
    EXPECT_EQ(mesh.field_values_data()[4 * v], scalar.values[v]);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(mesh.field_values_data()[4 * v + 1 + c], vector.values[3 * v + c]);
  }
}

TEST(PublicTetMesh, CopiesAreIndependentAndMovesTransferTheModel) {
  const testing::Grid g = testing::make_grid(4, 4, 4, [](int, int, int) { return 1; });
  TetMesh original = build_tet_mesh(g.data);
  TetMesh copy = original;
  SimplifyOptions options;
  options.target_vertex_ratio = 0.3;
  ASSERT_NE(simplify(copy, options).status, Status::kInvalidInput);
  EXPECT_LT(copy.vertex_capacity(), original.vertex_capacity());  // simplify compacts the copy only
  EXPECT_EQ(original.vertex_capacity(), g.data.vertex_count());
  const std::size_t simplified = copy.vertex_capacity();
  TetMesh moved = std::move(copy);
  EXPECT_EQ(moved.vertex_capacity(), simplified);
  copy = original;  // a moved-from mesh can be assigned to
  EXPECT_EQ(copy.vertex_capacity(), g.data.vertex_count());
  EXPECT_EQ(TetMesh{}.vertex_capacity(), 0u);
}

TEST(PublicReport, RejectionsAndPhasesHaveNames) {
  EXPECT_STREQ(to_string(RejectReason::kLinkKtilde), "link_Ktilde");
  EXPECT_STREQ(to_string(RejectReason::kTolerance), "tolerance");
  EXPECT_STREQ(to_string(Status::kInternalError), "internal_error");
  Report r;
  r.rejected[static_cast<std::size_t>(RejectReason::kQuality)] = 7;
  r.phase_seconds = {1.0, 2.0, 3.0, 4.0};
  EXPECT_EQ(r.rejected_by(RejectReason::kQuality), 7u);
  EXPECT_EQ(r.rejected_by(RejectReason::kInversion), 0u);
  EXPECT_EQ(r.evaluate_seconds() + r.select_seconds() + r.apply_seconds(), 6.0);
  EXPECT_EQ(r.compact_seconds(), 4.0);
}

TEST(PublicReport, CountsRejectionsOfARealRun) {
  testing::Grid g = testing::make_grid(6, 6, 6, [](int i, int, int) { return i < 3 ? 1 : 2; });
  TetMesh mesh = build_tet_mesh(g.data);
  SimplifyOptions options;
  options.target_vertex_ratio = 0.05;
  const Report report = simplify(mesh, options);
  std::uint64_t named = 0;
  for (RejectReason reason : kRejectReasons) named += report.rejected_by(reason);
  EXPECT_GT(named, 0u);  // an interface and a box boundary: some collapses must be refused
}

TEST(Version, IsOneNumber) {
  EXPECT_EQ(TOPOTET_VERSION, TOPOTET_VERSION_MAJOR * 10000 + TOPOTET_VERSION_MINOR * 100 + TOPOTET_VERSION_PATCH);
  EXPECT_EQ(std::string(TOPOTET_VERSION_STRING), std::to_string(TOPOTET_VERSION_MAJOR) + "." +
                                                     std::to_string(TOPOTET_VERSION_MINOR) + "." +
                                                     std::to_string(TOPOTET_VERSION_PATCH));
}

}  // namespace
}  // namespace topotet
