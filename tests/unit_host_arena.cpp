// A host that runs topotet inside its own oneTBB task arena of 1 thread keeps it: no stage (mesh
// build, simplify with the Embree tolerance scene, the checker, quality, field error, surface
// distance) brings in another thread. A global scheduler observer sees every thread that joins
// any arena.
#include <gtest/gtest.h>

#include <mutex>
#include <set>
#include <thread>

#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include "topotet/generate.h"
#include "topotet/metrics/field_error.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/surface_distance.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

class ThreadCounter : public tbb::task_scheduler_observer {
 public:
  ThreadCounter() { observe(true); }
  ~ThreadCounter() override { observe(false); }
  void on_scheduler_entry(bool) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    threads_.insert(std::this_thread::get_id());
  }
  std::set<std::thread::id> threads() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return threads_;
  }

 private:
  std::mutex mutex_;
  std::set<std::thread::id> threads_;
};

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
  EXPECT_TRUE(metrics::same_topology(metrics::compute_topology(input), metrics::compute_topology(output), &differences))
      << differences;
  EXPECT_EQ(compute_quality(output).inverted, 0u);
  compare_fields(input, output);
  surface_distance(input, output);
}

TEST(HostArena, OneThreadArenaIsRespectedByEveryStage) {
  ThreadCounter counter;
  tbb::task_arena arena(1);
  arena.execute([] { every_stage(0); });
  // The caller's thread alone (an arena's own thread is reported when it enters).
  EXPECT_LE(counter.threads().size(), 1u);
  EXPECT_EQ(counter.threads().count(std::this_thread::get_id()), counter.threads().size());
}

// The control: without the host arena and with num_threads = 2, the observer does see a second
// thread, so the test above would catch a stage that escapes the arena.
TEST(HostArena, TheObserverSeesWorkersWhenTwoThreadsAreAllowed) {
  if (std::thread::hardware_concurrency() < 2) GTEST_SKIP() << "one core: no worker to see";
  ThreadCounter counter;
  every_stage(2);
  EXPECT_GE(counter.threads().size(), 2u);
}

}  // namespace
}  // namespace topotet
