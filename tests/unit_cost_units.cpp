// SimplifyOptions::cost_units (the units costs are normalised in, given by the caller: topotet::mpi
// passes the whole mesh's to every part) and RoundStats::max_cost (the cost curve of a run).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "mesh/glm_convert.h"
#include "test_meshes.h"
#include "topotet/round_log.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"

namespace topotet {
namespace {

// Unjittered: every tet has volume 1/6 exactly, so the mean volume is exact in any summation order
// (the engine sums in its own order, after renumbering for locality).
MeshData ball_in_box() {
  testing::Grid g = testing::make_grid(
      10, 9, 8,
      [](int i, int j, int k) {
        const double dx = i - 5, dy = j - 4.5, dz = k - 4;
        return dx * dx + dy * dy + dz * dz < 9 ? 2 : 1;
      },
      0.0);
  // A curved field: its error competes with the geometry's, so the units' balance matters.
  VertexField f{"f", 1, {}};
  for (const auto& p : g.data.positions) f.values.push_back(std::sin(0.7 * p[0]) * std::cos(0.5 * p[1]) + 0.05 * p[2] * p[2]);
  g.data.fields.push_back(std::move(f));
  return g.data;
}

// The units the cost model takes from the mesh itself (engine/cost/cost.cpp): bounding box, field
// ranges, mean tet volume.
CostUnits own_units(const MeshData& d) {
  CostUnits u;
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = std::numeric_limits<double>::max(), hi[k] = -lo[k];
  for (const auto& p : d.positions)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) u.origin[k] = lo[k], d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
  u.diagonal = std::sqrt(d2);
  double volume = 0.0;
  for (const auto& t : d.tets) {
    const glm::dvec3 a = to_glm(d.positions[t[0]]), b = to_glm(d.positions[t[1]]) - a, c = to_glm(d.positions[t[2]]) - a,
                     e = to_glm(d.positions[t[3]]) - a;
    volume += std::fabs(b[0] * (c[1] * e[2] - c[2] * e[1]) - b[1] * (c[0] * e[2] - c[2] * e[0]) + b[2] * (c[0] * e[1] - c[1] * e[0]));
  }
  u.mean_tet_volume = volume / 6.0 / static_cast<double>(d.tets.size());
  for (const VertexField& f : d.fields)
    for (int c = 0; c < f.components; ++c) {
      double mn = std::numeric_limits<double>::max(), mx = -mn;
      for (std::size_t v = 0; v < d.positions.size(); ++v) {
        mn = std::min(mn, f.values[v * f.components + c]);
        mx = std::max(mx, f.values[v * f.components + c]);
      }
      u.field_min.push_back(mn);
      u.field_range.push_back(mx - mn);
    }
  return u;
}

MeshData run(const MeshData& input, const CostUnits* units, Report* report = nullptr, std::vector<RoundStats>* log = nullptr) {
  TetMesh mesh = build_tet_mesh(input);
  SimplifyOptions o;
  o.target_vertex_ratio = 0.3;
  o.cost_units = units;
  o.round_log = log;
  const Report r = simplify(mesh, o);
  if (report != nullptr) *report = r;
  return mesh.to_mesh_data();
}

TEST(CostUnits, TheMeshsOwnUnitsGiveTheSameRun) {
  const MeshData input = ball_in_box();
  const CostUnits own = own_units(input);
  EXPECT_EQ(run(input, &own), run(input, nullptr));
}

TEST(CostUnits, OtherUnitsChangeTheBalanceOfTheCosts) {
  // A field range ten times the real one makes the field ten times cheaper to spoil (its error
  // counts squared, relative to the range): the run follows the geometry instead.
  const MeshData input = ball_in_box();
  CostUnits wide = own_units(input);
  for (double& r : wide.field_range) r *= 10.0;
  Report report;
  const MeshData out = run(input, &wide, &report);
  EXPECT_EQ(report.status, Status::kOk);
  EXPECT_NE(out, run(input, nullptr));
}

TEST(CostUnits, WrongSizesAreInvalidInput) {
  const MeshData input = ball_in_box();
  CostUnits u = own_units(input);
  u.field_min.push_back(0.0);
  Report report;
  const MeshData out = run(input, &u, &report);
  EXPECT_EQ(report.status, Status::kInvalidInput);
  EXPECT_NE(report.message.find("cost_units"), std::string::npos);
  EXPECT_EQ(out.tet_count(), input.tet_count());  // untouched
  u = own_units(input);
  u.diagonal = 0.0;
  run(input, &u, &report);
  EXPECT_EQ(report.status, Status::kInvalidInput);
}

TEST(RoundLog, MaxCostOfTheRoundsIsTheReportsMaxCost) {
  const MeshData input = ball_in_box();
  std::vector<RoundStats> log;
  Report report;
  run(input, nullptr, &report, &log);
  ASSERT_FALSE(log.empty());
  double top = 0.0;
  std::uint64_t collapses = 0;
  for (const RoundStats& r : log) {
    top = std::max(top, r.max_cost);
    collapses += r.collapses;
    if (r.collapses == 0) {
      EXPECT_EQ(r.max_cost, 0.0);
    }
  }
  EXPECT_EQ(top, report.max_cost);
  EXPECT_EQ(collapses, report.collapses);
}

}  // namespace
}  // namespace topotet
