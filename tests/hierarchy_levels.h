// Levels of a hierarchy for the tests that check them (property_hierarchy.cpp in core,
// unit_out_of_core_hierarchy.cpp out of core): random downward-closed selections, and the checks
// every level must pass, and their replay through the kernel.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "kernel/collapse.h"
#include "mesh/glm_convert.h"
#include "mesh/mesh_model.h"
#include "topotet/hierarchy.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/topology.h"

namespace topotet::test {

// The largest downward-closed subset of a random wish list.
inline std::vector<std::uint8_t> random_closed(const Hierarchy& h, double p, std::mt19937& rng) {
  std::bernoulli_distribution want(p);
  std::vector<std::uint8_t> applied(h.collapse_count(), 0);
  for (std::size_t i = 0; i < applied.size(); ++i) {
    bool ok = want(rng);
    for (std::uint32_t k = h.parent_offsets[i]; k < h.parent_offsets[i + 1] && ok; ++k) ok = applied[h.parents[k]];
    applied[i] = ok;
  }
  return applied;
}

inline void expect_valid_level(const MeshData& input, const metrics::TopologyReport& input_topology, const MeshData& level,
                        const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_NO_THROW(build_mesh_model(level, BuildOptions{.reorient_inverted = false}));
  const QualityStats q = compute_quality(level);
  EXPECT_EQ(q.inverted, 0u);
  EXPECT_EQ(q.zero_volume, 0u);
  std::string differences;
  EXPECT_TRUE(metrics::same_topology(input_topology, metrics::compute_topology(level), &differences)) << differences;
  EXPECT_EQ(level.fields.size(), input.fields.size());
}

// Applies the selected collapses to `mesh` (built from h.original) in recording order through the
// kernel itself: each must pass may_collapse with `kernel` (a test failure naming the first that
// does not, and the replay stops there).
inline void replay_through_kernel(const Hierarchy& h, const std::vector<std::uint8_t>& applied,
                                  const CollapseOptions& kernel, SurfaceCoverage* coverage, MeshModel& mesh) {
  CollapseScratch scratch;
  std::uint32_t refs_used = static_cast<std::uint32_t>(mesh.refs_table.size());
  for (std::size_t i = 0; i < applied.size(); ++i) {
    if (!applied[i]) continue;
    const CollapseReason reason = may_collapse(mesh, h.u[i], h.v[i], to_glm(h.u_after[i]), kernel, scratch);
    ASSERT_EQ(reason, CollapseReason::kOk) << "collapse " << i << ": " << to_string(reason);
    reserve_refs_headroom(mesh, refs_used, scratch.star_u.size() + scratch.star_v.size());
    collapse(mesh, h.u[i], h.v[i], to_glm(h.u_after[i]), h.fields_after.data() + i * h.field_stride, scratch,
             refs_used, nullptr, coverage);
  }
}

}  // namespace topotet::test
