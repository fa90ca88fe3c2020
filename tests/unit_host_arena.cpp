// A host that runs topotet inside its own oneTBB task arena of 1 thread keeps it: no stage (mesh
// build, simplify with the Embree tolerance scene, the checker, quality, field error, surface
// distance) runs on another thread. The threads that ran are counted from the kernel's per-thread
// CPU accounting (/proc/self/task/*/stat), which sees every thread whatever started it (a oneTBB
// observer only sees the arena it observes).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>

#include <tbb/task_arena.h>

#include "topotet/generate.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/surface_distance.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

// CPU ticks (user + system) of every thread of this process, by thread id.
std::map<int, long> thread_cpu_ticks() {
  std::map<int, long> ticks;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream file(entry.path() / "stat");
    std::string line;
    if (!std::getline(file, line)) continue;  // the thread ended meanwhile
    // Fields after the ") " closing the command name: state is field 3, utime 14, stime 15.
    std::istringstream in(line.substr(line.rfind(')') + 2));
    std::string field;
    long total = 0;
    for (int k = 3; k <= 15 && in >> field; ++k)
      if (k >= 14) total += std::stol(field);
    ticks[std::stoi(entry.path().filename().string())] = total;
  }
  return ticks;
}

int threads_that_ran(const std::map<int, long>& before, const std::map<int, long>& after) {
  int n = 0;
  for (const auto& [tid, ticks] : after) {
    const auto it = before.find(tid);
    if (ticks > (it == before.end() ? 0 : it->second)) ++n;
  }
  return n;
}

// Every stage a library user calls, on a mesh large enough for the parallel loops to split.
void every_stage(int num_threads) {
  const MeshData input = generate_mesh({.family = "cube-sphere", .target_tets = 8000});
  TetMesh mesh = build_tet_mesh(input);
  SimplifyOptions options;
  options.target_vertex_ratio = 0.3;
  options.tolerance_rel = 0.01;
  options.num_threads = num_threads;
  std::vector<VertId> map;
  const Report report = simplify(mesh, options, map);
  ASSERT_TRUE(report.status == Status::kOk || report.status == Status::kStoppedEarly) << report.message;
  const MeshData output = mesh.to_mesh_data();
  std::string differences;
  EXPECT_TRUE(topotet::same_topology(topotet::compute_topology(input), topotet::compute_topology(output), &differences))
      << differences;
  EXPECT_EQ(compute_quality(output).inverted, 0u);
  compare_fields(input, output);
  surface_distance(input, output);
}

TEST(HostArena, OneThreadArenaIsRespectedByEveryStage) {
  const auto before = thread_cpu_ticks();
  tbb::task_arena arena(1);
  arena.execute([] { every_stage(0); });
  EXPECT_EQ(threads_that_ran(before, thread_cpu_ticks()), 1);
}

// The control: with two threads allowed, the same count sees the second one, so the check above
// can fail.
TEST(HostArena, TwoThreadsAllowedAreSeenRunning) {
  if (std::thread::hardware_concurrency() < 2) GTEST_SKIP() << "one core: no second thread to see";
  const auto before = thread_cpu_ticks();
  tbb::task_arena arena(2);
  arena.execute([] { every_stage(0); });
  EXPECT_GE(threads_that_ran(before, thread_cpu_ticks()), 2);
}

}  // namespace
}  // namespace topotet
