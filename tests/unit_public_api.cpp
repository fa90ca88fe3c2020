// The public header's library-facing forms: the non-throwing read/build/write (status + message),
// the named rejection reasons and phase times, and the generated version.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "test_meshes.h"
#include "topotet/nothrow.h"
#include "topotet/simplify.h"
#include "topotet/version.h"

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
