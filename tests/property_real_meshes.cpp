// The collapse property on meshes written by real meshers and simulation codes (../shared/data):
// random collapses accepted by the kernel keep every Betti number the independent checker computes,
// and whole simplifications (both engines) keep them too.
//
// TOPOTET_PROPERTY_COLLAPSES scales the number of random collapses per mesh (default 200).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <ostream>
#include <string>

#include "kernel/collapse.h"
#include "entry_points.h"
#include "mesh/mesh_model.h"
#include "topotet/io.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

struct RealMesh {
  const char* path;      // relative to the shared data folder
  int check_every;       // run the checker after every n-th accepted collapse (and at the end)
};

const RealMesh kMeshes[] = {
    {"mfem/nested_cubes.msh", 1},          // cube in a cube, 2 materials
    {"simnibs/sphere3.msh", 10},           // nested spherical shells, binary Gmsh 2.2
    {"palace/circular_hole.msh", 10},      // embedded sheet with a hole: free rim curves
    {"mmg/tinyBoxt.mesh", 10},             // ridges, corners, required vertices
};

// Names the parameter in test listings (instead of its bytes).
void PrintTo(const RealMesh& mesh, std::ostream* os) { *os << mesh.path; }

std::string shared(const char* rel) { return std::string(TOPOTET_SHARED_DATA_DIR) + "/" + rel; }

class RealMeshProperty : public ::testing::TestWithParam<RealMesh> {};

TEST_P(RealMeshProperty, RandomAcceptedCollapsesKeepTopology) {
  const RealMesh& rm = GetParam();
  if (!std::filesystem::exists(shared(rm.path))) GTEST_SKIP() << shared(rm.path) << " not found";
  const MeshData data = read_mesh(shared(rm.path));
  const MeshModel input = build_mesh_model(data);
  MeshModel mesh = input;
  const auto baseline = topotet::compute_topology(mesh.to_mesh_data());
  const char* env = std::getenv("TOPOTET_PROPERTY_COLLAPSES");
  const std::uint64_t target = env ? std::strtoull(env, nullptr, 10) : 200;
  std::mt19937_64 rng(12345);
  CollapseScratch scratch;
  std::uint32_t refs_used = static_cast<std::uint32_t>(mesh.refs_table.size());
  std::uint64_t accepted = 0, attempts = 0, since_last = 0;
  while (accepted < target && attempts < 200 * target) {
    ++attempts;
    if (++since_last > 5000) {  // a small mesh is exhausted: start again from the input
      mesh = input;
      refs_used = static_cast<std::uint32_t>(mesh.refs_table.size());
      since_last = 0;
    }
    const TetId t = static_cast<TetId>(rng() % mesh.tets.size());
    if (mesh.is_dead_tet(t)) continue;
    const auto& e = kTetEdges[rng() % 6];
    VertId u = mesh.tets[t][e[0]], v = mesh.tets[t][e[1]];
    if (rng() & 1) std::swap(u, v);
    const glm::dvec3 p = (rng() % 3 == 0) ? 0.5 * (mesh.positions[u] + mesh.positions[v]) : mesh.positions[u];
    if (may_collapse(mesh, u, v, p, CollapseOptions{}, scratch) != CollapseReason::kOk) continue;
    reserve_refs_headroom(mesh, refs_used, scratch.star_u.size() + scratch.star_v.size());
    collapse(mesh, u, v, p, nullptr, scratch, refs_used);
    ++accepted;
    since_last = 0;
    if (accepted % rm.check_every == 0 || accepted == target) {
      std::string differences;
      ASSERT_TRUE(topotet::same_topology(baseline, topotet::compute_topology(mesh.to_mesh_data()), &differences))
          << rm.path << ": after " << accepted << " accepted collapses (last " << v << " -> " << u << "):\n"
          << differences;
    }
  }
  std::printf("[ property ] %s: %llu accepted collapses of %llu attempts, topology unchanged\n", rm.path,
              static_cast<unsigned long long>(accepted), static_cast<unsigned long long>(attempts));
  EXPECT_EQ(accepted, target);
}

TEST_P(RealMeshProperty, SimplificationKeepsTopologyWithBothEngines) {
  const RealMesh& rm = GetParam();
  if (!std::filesystem::exists(shared(rm.path))) GTEST_SKIP() << shared(rm.path) << " not found";
  const MeshData data = read_mesh(shared(rm.path));
  for (Engine engine : {Engine::kSequential, Engine::kParallel}) {
    MeshModel mesh = build_mesh_model(data);
    const auto before = topotet::compute_topology(mesh.to_mesh_data());
    SimplifyOptions options;
    options.engine = engine;
    options.target_vertex_ratio = 0.25;
    const Report report = simplify(mesh, options);
    ASSERT_TRUE(report.status == Status::kOk || report.status == Status::kStoppedEarly) << report.message;
    std::string differences;
    EXPECT_TRUE(topotet::same_topology(before, topotet::compute_topology(mesh.to_mesh_data()), &differences))
        << rm.path << (engine == Engine::kSequential ? " sequential" : " parallel") << ":\n" << differences;
    std::printf("[ simplify ] %s %s: %llu -> %llu vertices in %.3f s (%s)\n", rm.path,
                engine == Engine::kSequential ? "sequential" : "parallel", (unsigned long long)report.vertices_before,
                (unsigned long long)report.vertices_after, report.seconds, to_string(report.status));
  }
}

INSTANTIATE_TEST_SUITE_P(SharedData, RealMeshProperty, ::testing::ValuesIn(kMeshes),
                         [](const ::testing::TestParamInfo<RealMesh>& param) {
                           std::string name = param.param.path;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

}  // namespace
}  // namespace topotet
