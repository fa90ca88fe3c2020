// Property: the kernel's fast paths give the same answers as the general code they short-cut, and
// collapses taken through them keep every Betti number (independent checker) and the flag
// invariants of the mesh model.
//
//   - is_interior_vertex(a)            ==  (vertex_orders(a).ktilde == 0)
//   - check_link_conditions with both ends hinted interior (interior_link_test)
//                                      ==  the same check without hints (the general tests A-I)
//   - check_link_conditions reusing classifications (ReuseClassifications: edges sharing ends, in
//     either order, with a scratch that kept those of the mesh before the last collapse)
//                                      ==  the same check classifying both ends
//   - CostModel::edge_cost(a, b)       ==  CostModel::candidates(a, b)[0].cost (up to rounding)
//   - after every accepted collapse: every order the cost model still holds (all but the
//     survivor's) == vertex_orders(x).ktilde, on the link of the collapsed edge and, every 25
//     collapses, on every vertex
//   - after every accepted collapse: a face's flag and ref are the same in both of its tets, a
//     polyline edge's flag, ref and ridge bit are the same in all of its tets (collapse() only
//     recomputes the faces and edges through the survivor).
// The collapses are the ones the engines take: hints from is_interior_vertex, placements from the
// cost model, in random edge order, on the planted meshes of test_meshes.h.
//
// Environment: TOPOTET_PROPERTY_COLLAPSES (accepted collapses per mesh, default 300).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <tuple>

#include "kernel/collapse.h"
#include "cost/cost.h"
#include "kernel/link_condition.h"
#include "mesh/mesh_model.h"
#include "test_meshes.h"
#include "topotet/metrics/topology.h"
#include "topotet/simplify.h"

namespace topotet {
namespace {

std::uint64_t env_u64(const char* name, std::uint64_t fallback) {
  const char* s = std::getenv(name);
  return s ? std::strtoull(s, nullptr, 10) : fallback;
}

// Every face must carry the same flag and ref in both of its tets, every edge the same polyline
// flag, ref and ridge bit in all of its tets.
::testing::AssertionResult flags_are_consistent(const MeshModel& m) {
  std::map<std::array<VertId, 3>, std::tuple<bool, std::int32_t, TetId>> faces;
  std::map<std::array<VertId, 2>, std::tuple<bool, std::int32_t, bool, TetId>> edges;
  for (TetId t = 0; t < m.tets.size(); ++t) {
    if (m.is_dead_tet(t)) continue;
    const auto& v = m.tets[t];
    const TetFlags fl = m.flags[t];
    const SubstructureRefs* refs = fl ? &m.refs_table[m.tet_refs_slot[t]] : nullptr;
    for (int f = 0; f < 4; ++f) {
      std::array<VertId, 3> key{v[kTetFaces[f][0]], v[kTetFaces[f][1]], v[kTetFaces[f][2]]};
      std::sort(key.begin(), key.end());
      const bool on = is_surface_face(fl, f);
      const std::int32_t ref = on ? refs->face[f] : 0;
      const auto [it, fresh] = faces.try_emplace(key, on, ref, t);
      if (!fresh && (std::get<0>(it->second) != on || std::get<1>(it->second) != ref))
        return ::testing::AssertionFailure() << "face " << key[0] << " " << key[1] << " " << key[2] << ": tet " << t
                                             << " says flag " << on << " ref " << ref << ", tet "
                                             << std::get<2>(it->second) << " says " << std::get<0>(it->second) << " "
                                             << std::get<1>(it->second);
    }
    for (int e = 0; e < 6; ++e) {
      const VertId x = v[kTetEdges[e][0]], y = v[kTetEdges[e][1]];
      const std::array<VertId, 2> key{std::min(x, y), std::max(x, y)};
      const bool on = is_polyline_edge(fl, e);
      const std::int32_t ref = on ? refs->edge[e] : 0;
      const bool ridge = on && ((refs->ridge_mask >> e) & 1u);
      const auto [it, fresh] = edges.try_emplace(key, on, ref, ridge, t);
      if (!fresh && (std::get<0>(it->second) != on || std::get<1>(it->second) != ref || std::get<2>(it->second) != ridge))
        return ::testing::AssertionFailure() << "edge " << key[0] << " " << key[1] << ": tet " << t << " and tet "
                                             << std::get<3>(it->second) << " disagree";
    }
  }
  return ::testing::AssertionSuccess();
}

struct FastPathStats {
  std::uint64_t accepted = 0, interior_checks = 0, interior_rejections = 0, cost_checks = 0, order_checks = 0;
  std::uint64_t kept_orders = 0;  // cached feature orders compared with a fresh classification
  std::uint64_t reuse_checks = 0, reuse_rejections = 0;  // link checks reusing classifications
};

void run(const testing::PlantedMesh& planted, std::uint64_t seed, std::uint64_t target, FastPathStats& stats) {
  SCOPED_TRACE(std::string(planted.name) + ", seed " + std::to_string(seed));
  const testing::Grid grid = planted.make();
  const MeshModel input = build_mesh_model(grid.data);
  const topotet::TopologyReport baseline = topotet::compute_topology(input.to_mesh_data());
  MeshModel m = input;
  SimplifyOptions options;
  CostModel cost(m, options);
  CollapseScratch scratch, general;
  LinkScratch link, reused;  // `reused` keeps its classifications from one attempt to the next
  std::vector<VertId> nbrs;
  std::mt19937_64 rng(seed);
  std::uint32_t refs_used = static_cast<std::uint32_t>(m.refs_table.size());
  std::vector<double> fields(static_cast<std::size_t>(m.field_stride()));
  std::uint64_t accepted = 0, misses = 0;
  while (accepted < target && misses < 20000) {
    const TetId t = static_cast<TetId>(rng() % m.tets.size());
    if (m.is_dead_tet(t)) continue;
    const int e = static_cast<int>(rng() % 6);
    VertId a = m.tets[t][kTetEdges[e][0]], b = m.tets[t][kTetEdges[e][1]];
    if (a > b) std::swap(a, b);

    // Orders: the fast interior test agrees with the classification.
    for (VertId x : {a, b}) {
      ASSERT_EQ(is_interior_vertex(m, x), vertex_orders(m, x, link).ktilde == 0) << "vertex " << x;
      ++stats.order_checks;
    }
    // The cost of ranking agrees with the cost of the cheapest candidate.
    CollapseCandidate cands[kMaxCandidates];
    const int n = cost.candidates(m, a, b, cands, scratch.link);
    const double ranked = cost.edge_cost(m, a, b, scratch.link);
    ++stats.cost_checks;
    if (n == 0) {
      ASSERT_TRUE(std::isinf(ranked));
      ++misses;
      continue;
    }
    ASSERT_NEAR(ranked, cands[0].cost, 1e-9 * (1.0 + std::fabs(cands[0].cost))) << "edge " << a << " " << b;

    // Link conditions: with both ends hinted interior, the verdict is the general one. Checked on
    // this edge and on a few more random ones per attempt (checks are cheap, collapses are not).
    for (int probe = 0; probe < 8; ++probe) {
      VertId x = a, y = b;
      if (probe > 0) {
        const TetId s = static_cast<TetId>(rng() % m.tets.size());
        if (m.is_dead_tet(s)) continue;
        const int k = static_cast<int>(rng() % 6);
        x = m.tets[s][kTetEdges[k][0]];
        y = m.tets[s][kTetEdges[k][1]];
      }
      if (!is_interior_vertex(m, x) || !is_interior_vertex(m, y)) continue;
      ASSERT_TRUE(gather_stars(m, x, y, general));
      general.link.known_interior = {kInvalid, kInvalid};
      const LinkResult reference = check_link_conditions(m, x, y, general.star_uv, general.link);
      general.link.known_interior = {x, y};
      const LinkResult fast = check_link_conditions(m, x, y, general.star_uv, general.link);
      ASSERT_EQ(fast, reference) << "edge " << x << " " << y;
      ++stats.interior_checks;
      stats.interior_rejections += reference != LinkResult::kOk;
    }

    // Link conditions reusing classifications, as the verify phase and the census do: a scope per
    // attempt (the mesh changed since the last one), edges through a, b or a vertex next to them,
    // their ends in either order; the verdict is the one classifying both ends.
    {
      const ReuseClassifications reuse(reused);
      VertId x = a;
      for (int probe = 0; probe < 8; ++probe) {
        if (probe == 4) x = b;
        m.neighbours(x, nbrs);
        if (nbrs.empty()) break;
        const VertId y = nbrs[rng() % nbrs.size()];
        const bool flip = rng() % 2 == 0;
        const VertId p = flip ? y : x, q = flip ? x : y;
        ASSERT_TRUE(gather_stars(m, p, q, general));
        general.link.known_interior = {kInvalid, kInvalid};
        const LinkResult reference = check_link_conditions(m, p, q, general.star_uv, general.link);
        ASSERT_EQ(check_link_conditions(m, p, q, general.star_uv, reused), reference) << "edge " << p << " " << q;
        ++stats.reuse_checks;
        stats.reuse_rejections += reference != LinkResult::kOk;
        if (probe % 2 == 1) x = y;  // walk on: the next edges share this end
      }
    }

    // The collapse the engines would take, through the hinted path.
    Placement placements[kMaxCandidates];
    for (int i = 0; i < n; ++i) placements[i] = placement_of(cands[i]);
    cost.hint_orders(a, b, scratch.link);
    const int chosen = first_acceptable(m, placements, n, CollapseOptions{}, scratch, nullptr);
    if (chosen < 0) {
      ++misses;
      continue;
    }
    misses = 0;
    const CollapseCandidate& c = cands[chosen];
    cost.fields_at(m, c, fields.data());
    reserve_refs_headroom(m, refs_used, scratch.star_u.size() + scratch.star_v.size());
    collapse(m, c.u, c.v, c.p, fields.data(), scratch, refs_used);
    cost.on_collapse(m, c.u, c.v);
    ++accepted;
    ++stats.accepted;
    // The cost model keeps every order but u's (cost.cpp, on_collapse): the link of uv keeps its
    // orders through the collapse, and so does every vertex (checked in full every 25 collapses).
    const auto order_is_current = [&](VertId x) {
      const std::optional<std::uint8_t> known = cost.known_order(x);
      if (!known) return;
      ASSERT_EQ(int(*known), int(vertex_orders(m, x, link).ktilde))
          << "vertex " << x << " after collapse " << c.v << " -> " << c.u;
      stats.kept_orders += *known > 0 ? 1 : 0;  // the interior ones never go stale
    };
    for (TetId removed : scratch.star_uv)
      for (VertId x : m.tets[removed])
        if (x != c.v) order_is_current(x);
    if (accepted % 25 == 0)
      for (VertId x = 0; x < m.positions.size(); ++x)
        if (!m.is_dead_vertex(x)) order_is_current(x);
    if (::testing::Test::HasFatalFailure()) return;
    ASSERT_TRUE(flags_are_consistent(m)) << "after collapse " << c.v << " -> " << c.u;
    std::string differences;
    ASSERT_TRUE(topotet::same_topology(baseline, topotet::compute_topology(m.to_mesh_data()), &differences))
        << "collapse " << c.v << " -> " << c.u << " changed the topology:\n" << differences;
  }
}

class FastPaths : public ::testing::TestWithParam<std::size_t> {};

TEST_P(FastPaths, AgreeWithTheGeneralCodeAndKeepTheTopology) {
  const auto meshes = testing::planted_meshes();
  const testing::PlantedMesh& planted = meshes[GetParam()];
  const std::uint64_t target = env_u64("TOPOTET_PROPERTY_COLLAPSES", 300);
  FastPathStats stats;
  for (std::uint64_t seed : {11u, 12u}) {
    run(planted, seed, target / 2 + 1, stats);
    if (HasFatalFailure()) return;
  }
  std::printf("[ fast paths ] %s: %llu collapses; %llu interior link checks (%llu rejected), %llu reusing "
              "classifications (%llu rejected), %llu cost and %llu order comparisons, %llu kept orders compared\n",
              planted.name, (unsigned long long)stats.accepted, (unsigned long long)stats.interior_checks,
              (unsigned long long)stats.interior_rejections, (unsigned long long)stats.reuse_checks,
              (unsigned long long)stats.reuse_rejections, (unsigned long long)stats.cost_checks,
              (unsigned long long)stats.order_checks, (unsigned long long)stats.kept_orders);
  EXPECT_GT(stats.accepted, 0u);
  EXPECT_GT(stats.kept_orders, stats.accepted);  // every mesh has substructures: their orders were compared
  EXPECT_GT(stats.interior_checks, 0u);
  EXPECT_GT(stats.reuse_rejections, 0u);  // refusals too were compared
}

INSTANTIATE_TEST_SUITE_P(Planted, FastPaths, ::testing::Range<std::size_t>(0, testing::planted_meshes().size()),
                         [](const ::testing::TestParamInfo<std::size_t>& param) {
                           return std::string(testing::planted_meshes()[param.param].name);
                         });

}  // namespace
}  // namespace topotet
