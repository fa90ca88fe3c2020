// Property: every collapse the kernel accepts keeps the Betti numbers of the mesh and of every
// substructure (as computed by the independent checker in metrics/) and inverts no tet.
//
// Random edges of meshes with planted features are offered to the kernel with random placements
// (an endpoint or the midpoint); after each accepted collapse the checker compares the whole
// topology report with the input's. Rejected link-condition candidates are sampled, applied anyway
// on a copy, and checked by brute force: the share that turn out to keep the topology is the
// kernel's false-rejection rate (paper 001 §4.7 says it should be small).
//
// Environment: TOPOTET_PROPERTY_COLLAPSES (accepted collapses per mesh, default 300),
// TOPOTET_PROPERTY_SEED (a fixed seed; default: fixed seeds, plus one random seed printed).
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <map>
#include <set>
#include <string>

#include <glm/geometric.hpp>

#include "kernel/collapse.h"
#include "mesh/mesh_model.h"
#include "test_meshes.h"
#include "topotet/metrics/topology.h"

namespace topotet {
namespace {

using topotet::compute_topology;
using topotet::same_topology;

std::uint64_t env_u64(const char* name, std::uint64_t fallback) {
  const char* s = std::getenv(name);
  return s ? std::strtoull(s, nullptr, 10) : fallback;
}

// Incidence lists must equal the live tets holding each vertex.
::testing::AssertionResult incidence_is_consistent(const MeshModel& m) {
  std::vector<std::vector<TetId>> expected(m.positions.size());
  for (TetId t = 0; t < m.tets.size(); ++t)
    if (!m.is_dead_tet(t))
      for (VertId v : m.tets[t]) expected[v].push_back(t);
  for (VertId v = 0; v < m.positions.size(); ++v) {
    std::vector<TetId> got;
    m.for_each_tet_of(v, [&](TetId t) { got.push_back(t); });
    if (got != expected[v]) return ::testing::AssertionFailure() << "incidence of vertex " << v << " is wrong";
    if (m.is_dead_vertex(v) != expected[v].empty())
      return ::testing::AssertionFailure() << "vertex " << v << " dead flag disagrees with its star";
  }
  return ::testing::AssertionSuccess();
}

struct PropertyStats {
  std::uint64_t accepted = 0, attempts = 0;
  std::array<std::uint64_t, kCollapseReasonCount> rejected{};
  std::uint64_t sampled_link_rejections = 0, false_rejections = 0;
  // By failed test: "D~" = test (D) in the K~ filtration, "A" = test (A) (K); sampled and false.
  std::map<std::string, std::pair<std::uint64_t, std::uint64_t>> by_test;
};

// Runs random collapses on the mesh until `accepted_target` are accepted (restarting from the
// input when the mesh gets stuck). Returns false (with a message) at the first violation.
void run_random_collapses(const testing::PlantedMesh& planted, std::uint64_t seed, std::uint64_t accepted_target,
                          PropertyStats& stats) {
  SCOPED_TRACE(std::string(planted.name) + ", seed " + std::to_string(seed));
  const testing::Grid grid = planted.make();
  const MeshModel input = build_mesh_model(grid.data);
  const topotet::TopologyReport baseline = compute_topology(input.to_mesh_data());
  ASSERT_TRUE(same_topology(baseline, baseline));

  std::mt19937_64 rng(seed);
  MeshModel m = input;
  CollapseScratch scratch;
  std::uint32_t refs_used = static_cast<std::uint32_t>(m.refs_table.size());
  std::uint64_t accepted_here = 0, failures_in_a_row = 0;
  while (accepted_here < accepted_target) {
    if (failures_in_a_row > 4000) {  // the mesh is as coarse as it gets: start over
      m = input;
      refs_used = static_cast<std::uint32_t>(m.refs_table.size());
      failures_in_a_row = 0;
    }
    ++stats.attempts;
    const TetId t = static_cast<TetId>(rng() % m.tets.size());
    if (m.is_dead_tet(t)) continue;
    const int e = static_cast<int>(rng() % 6);
    VertId u = m.tets[t][kTetEdges[e][0]], v = m.tets[t][kTetEdges[e][1]];
    if (rng() & 1) std::swap(u, v);
    const glm::dvec3 p = (rng() % 3 == 0) ? 0.5 * (m.positions[u] + m.positions[v]) : m.positions[u];
    const CollapseReason reason = may_collapse(m, u, v, p, CollapseOptions{}, scratch);
    if (reason != CollapseReason::kOk) {
      ++stats.rejected[static_cast<int>(reason)];
      ++failures_in_a_row;
      // Brute force on a sample of link rejections: apply anyway and ask the checker.
      if ((reason == CollapseReason::kLinkK || reason == CollapseReason::kLinkKtilde) && rng() % 8 == 0) {
        MeshModel copy = m;
        std::uint32_t copy_used = refs_used;
        CollapseScratch s2;
        gather_stars(copy, u, v, s2);
        reserve_refs_headroom(copy, copy_used, s2.star_u.size() + s2.star_v.size());
        // Only topology is being judged: skip samples whose geometry would be invalid anyway.
        bool flips = false;
        for (const auto* star : {&s2.star_u, &s2.star_v})
          for (TetId k : *star) {
            if (std::binary_search(s2.star_uv.begin(), s2.star_uv.end(), k)) continue;
            glm::dvec3 q[4];
            for (int j = 0; j < 4; ++j) {
              const VertId x = copy.tets[k][j];
              q[j] = (x == u || x == v) ? p : copy.positions[x];
            }
            const glm::dvec3 a = q[1] - q[0], b = q[2] - q[0], c = q[3] - q[0];
            flips |= glm::dot(a, glm::cross(b, c)) <= 0.0;
          }
        if (!flips) {
          const std::string test = std::string(1, scratch.link.failed_test) + (scratch.link.failed_filtration ? "~" : "");
          collapse(copy, u, v, p, nullptr, s2, copy_used);
          ++stats.sampled_link_rejections;
          ++stats.by_test[test].first;
          if (same_topology(baseline, compute_topology(copy.to_mesh_data()))) {
            ++stats.false_rejections;
            ++stats.by_test[test].second;
          }
        }
      }
      continue;
    }
    reserve_refs_headroom(m, refs_used, scratch.star_u.size() + scratch.star_v.size());
    collapse(m, u, v, p, nullptr, scratch, refs_used);
    ++accepted_here;
    ++stats.accepted;
    failures_in_a_row = 0;
    std::string differences;
    const bool same = same_topology(baseline, compute_topology(m.to_mesh_data()), &differences);
    ASSERT_TRUE(same) << "collapse " << v << " -> " << u << " (accepted #" << accepted_here
                      << ") changed the topology:\n" << differences;
    if (accepted_here % 64 == 0) {
      ASSERT_TRUE(incidence_is_consistent(m));
    }
  }
  ASSERT_TRUE(incidence_is_consistent(m));
}

class PlantedProperty : public ::testing::TestWithParam<std::size_t> {};

TEST_P(PlantedProperty, AcceptedCollapsesPreserveEveryBettiNumber) {
  const auto meshes = testing::planted_meshes();
  const testing::PlantedMesh& planted = meshes[GetParam()];
  const std::uint64_t per_mesh = env_u64("TOPOTET_PROPERTY_COLLAPSES", 300);
  std::vector<std::uint64_t> seeds = {1, 2};
  if (const char* fixed = std::getenv("TOPOTET_PROPERTY_SEED")) {
    seeds = {std::strtoull(fixed, nullptr, 10)};
  } else {
    seeds.push_back(std::random_device{}());
  }
  PropertyStats stats;
  for (std::uint64_t seed : seeds) {
    std::printf("[ property ] %s seed %llu (rerun: TOPOTET_PROPERTY_SEED=%llu)\n", planted.name,
                static_cast<unsigned long long>(seed), static_cast<unsigned long long>(seed));
    run_random_collapses(planted, seed, per_mesh / seeds.size() + 1, stats);
    if (HasFatalFailure()) return;
  }
  std::printf("[ property ] %s: %llu accepted of %llu attempts; rejected link_K %llu, link_Ktilde %llu, "
              "pinned %llu, inversion %llu, quality %llu; false rejections %llu of %llu sampled\n",
              planted.name, (unsigned long long)stats.accepted, (unsigned long long)stats.attempts,
              (unsigned long long)stats.rejected[1], (unsigned long long)stats.rejected[2],
              (unsigned long long)stats.rejected[3], (unsigned long long)stats.rejected[4],
              (unsigned long long)stats.rejected[5], (unsigned long long)stats.false_rejections,
              (unsigned long long)stats.sampled_link_rejections);
  for (const auto& [test, counts] : stats.by_test)
    std::printf("[ property ]   test %s: %llu sampled, %llu kept the Betti numbers\n", test.c_str(),
                (unsigned long long)counts.first, (unsigned long long)counts.second);
  EXPECT_GT(stats.accepted, 0u);
}

INSTANTIATE_TEST_SUITE_P(Planted, PlantedProperty, ::testing::Range<std::size_t>(0, testing::planted_meshes().size()),
                         [](const ::testing::TestParamInfo<std::size_t>& param) {
                           return std::string(testing::planted_meshes()[param.param].name);
                         });

}  // namespace
}  // namespace topotet
