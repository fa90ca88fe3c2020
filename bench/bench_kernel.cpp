// may_collapse per second on a generated mesh, on random interior edges and on random edges that
// touch a substructure (surface, interface, polyline), with placement at an endpoint.
//   build/bench/bench_kernel --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// TOPOTET_BENCH_TETS sets the mesh size (default 1,000,000).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <random>
#include <vector>

#include "kernel/collapse.h"
#include "kernel/link_condition.h"
#include "mesh/mesh_model.h"
#include "topotet/generate.h"

namespace {

using namespace topotet;

struct Fixture {
  MeshModel mesh;
  std::vector<std::pair<VertId, VertId>> interior, feature;
};

const Fixture& fixture() {
  static std::unique_ptr<Fixture> f = [] {
    auto fx = std::make_unique<Fixture>();
    GenerateOptions g;
    g.family = "cube-sphere";
    g.target_tets = std::getenv("TOPOTET_BENCH_TETS") ? std::strtoull(std::getenv("TOPOTET_BENCH_TETS"), nullptr, 10)
                                                      : 1000000;
    fx->mesh = build_mesh_model(generate_mesh(g));
    LinkScratch scratch;
    std::mt19937_64 rng(7);
    while (fx->interior.size() < 20000 || fx->feature.size() < 20000) {
      const TetId t = static_cast<TetId>(rng() % fx->mesh.tets.size());
      const auto& e = kTetEdges[rng() % 6];
      const VertId u = fx->mesh.tets[t][e[0]], v = fx->mesh.tets[t][e[1]];
      const bool on_feature = vertex_orders(fx->mesh, u, scratch).ktilde > 0 || vertex_orders(fx->mesh, v, scratch).ktilde > 0;
      auto& list = on_feature ? fx->feature : fx->interior;
      if (list.size() < 20000) list.push_back({u, v});
    }
    return fx;
  }();
  return *f;
}

void run(benchmark::State& state, bool feature) {
  const Fixture& f = fixture();
  const auto& edges = feature ? f.feature : f.interior;
  CollapseScratch scratch;
  std::size_t i = 0, ok = 0;
  for (auto _ : state) {
    const auto [u, v] = edges[i++ % edges.size()];
    const CollapseReason r = may_collapse(f.mesh, u, v, f.mesh.positions[u], CollapseOptions{}, scratch);
    ok += r == CollapseReason::kOk;
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  state.counters["accepted_share"] = static_cast<double>(ok) / static_cast<double>(state.iterations());
}

void BM_may_collapse_interior(benchmark::State& state) { run(state, false); }
void BM_may_collapse_substructure(benchmark::State& state) { run(state, true); }

void BM_link_conditions_only(benchmark::State& state) {
  const Fixture& f = fixture();
  CollapseScratch scratch;
  std::size_t i = 0;
  for (auto _ : state) {
    const auto [u, v] = f.feature[i++ % f.feature.size()];
    gather_stars(f.mesh, u, v, scratch);
    benchmark::DoNotOptimize(check_link_conditions(f.mesh, u, v, scratch.star_uv, scratch.link));
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

BENCHMARK(BM_may_collapse_interior);
BENCHMARK(BM_may_collapse_substructure);
BENCHMARK(BM_link_conditions_only);

}  // namespace

BENCHMARK_MAIN();
