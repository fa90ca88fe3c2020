// flip_at_stall (flip_at_stall.h): the flips of the optimisation, on the mesh where the collapses
// stalled, with the coverage carried across the retriangulation.
#include "flip_at_stall.h"

#include <algorithm>
#include <chrono>

#include "optimize/swap.h"

namespace topotet::detail {

bool flip_at_stall(MeshModel& mesh, SurfaceCoverage* coverage, InputSamples* samples, Report& report) {
  const auto start = std::chrono::steady_clock::now();
  SwapOptions swap;  // the optimisation's light settings (optimize.cpp)
  swap.dihedral_floor = DihedralFloor::degrees(report.min_dihedral_used);
  if (samples != nullptr) samples->index(mesh);
  // The flips compact the tets (ids change): the coverage's lists go with their tets' vertices.
  SurfaceCoverage::Detached held;
  if (coverage != nullptr) held = coverage->detach(mesh);
  // The flips append the side-table records of their new tets: trim the collapses' headroom first
  // (the engine takes its next slots after the table's end: engines.h), or each stall would leave
  // it behind and the next round grow the table by half again.
  std::uint32_t used = 0;
  for (TetId t = 0; t < mesh.tets.size(); ++t)
    if (!mesh.is_dead_tet(t) && mesh.tet_refs_slot[t] != kInvalid) used = std::max(used, mesh.tet_refs_slot[t] + 1);
  mesh.refs_table.resize(used);
  const SwapStats stats = swap_bad_tets(mesh, swap, samples);
  if (coverage != nullptr) coverage->attach(mesh, std::move(held));
  const std::uint64_t flips = stats.flips_23 + stats.edge_removals;
  report.stall_flips += flips;
  report.stall_flip_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return flips > 0;
}

}  // namespace topotet::detail
