// relax_limits (relax_limits.h): which limit held the vertices left, and one step of it.
//
//   census <- diagnose_stop (the reason that holds each live vertex)
//   excess <- live - target
//   tolerance may relax: relax_tolerance, H > 0 and below the bounding box diagonal
//   quality may relax:   relax_quality and a floor above 0
//   of those, the one holding more vertices, if it holds at least min(excess, 1% of the live
//   ones) and no less than any other limit an option sets (the tolerance, the floors, a field
//   error limit, the feature corners of feature_angle), relaxable or not: a limit holding a few
//   while a hard one holds the rest is kept, since relaxing it would loosen the whole output's
//   guarantee for a few vertices (measured: a hard tolerance holding 77% let the floors halve 7
//   times, 5 degrees -> 0.04, for 388 -> 371 vertices). The topology and inverted tets are left
//   out of that comparison: what they hold changes as the mesh around changes (sphere3 at 2%: held
//   56% by inversion at 3.2%, it reaches 2% once the tolerance relaxes on).
//     tolerance: H <- 2 H        quality: both floors <- half (0 below 1/256 of the asked ones)
#include "relax_limits.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "stop_diagnosis.h"

namespace topotet::detail {
namespace {

// Floors below this share of the asked one are dropped: at 1/256 (5 degrees -> 0.02 degrees) a
// floor no longer tells tets apart from what the inversion check already refuses.
constexpr double kLastFloorShare = 1.0 / 256.0;

double halved(double floor, double asked) {
  const double h = 0.5 * floor;
  return h < asked * kLastFloorShare ? 0.0 : h;
}

}  // namespace

bool relax_limits(const MeshModel& mesh, const SimplifyOptions& options, CollapseOptions& kernel,
                  SurfaceCoverage* coverage, std::uint64_t target, Report& report) {
  const auto start = std::chrono::steady_clock::now();
  diagnose_stop(mesh, options, kernel, target, report);
  report.relax_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const StopDiagnosis& d = report.stop;
  const std::uint64_t live = mesh.live_vertex_count();
  if (live <= target || d.vertices == 0) return false;
  const std::uint64_t enough = std::max<std::uint64_t>(1, std::min<std::uint64_t>(live - target, live / 100));
  const std::uint64_t most = std::max({d.quality, d.tolerance, d.field_error, d.pinned_features});
  const auto stops_the_run = [&](std::uint64_t held) { return held >= enough && held == most; };
  const bool tolerance_may = options.relax_tolerance && kernel.tolerance > 0.0 && coverage != nullptr &&
                             kernel.tolerance < bounding_box_diagonal(mesh) && stops_the_run(d.tolerance);
  const bool quality_may = options.relax_quality && (kernel.quality_floor > 0.0 || kernel.dihedral_floor.active()) &&
                           stops_the_run(d.quality);
  if (!tolerance_may && !quality_may) return false;
  const double share_base = static_cast<double>(d.vertices);
  if (tolerance_may && (!quality_may || d.tolerance >= d.quality)) {
    const double h = 2.0 * kernel.tolerance;
    report.relaxations.push_back({"tolerance", kernel.tolerance, h, live, static_cast<double>(d.tolerance) / share_base});
    kernel.tolerance = h;
    coverage->raise_tolerance(h);
    report.tolerance = h;
  } else {
    const double share = static_cast<double>(d.quality) / share_base;
    if (report.min_dihedral_used > 0.0) {
      const double to = halved(report.min_dihedral_used, options.min_dihedral);
      report.relaxations.push_back({"min_dihedral", report.min_dihedral_used, to, live, share});
      report.min_dihedral_used = to;
      kernel.dihedral_floor = DihedralFloor::degrees(to);
    }
    if (report.min_quality_used > 0.0) {
      const double to = halved(report.min_quality_used, options.min_quality);
      report.relaxations.push_back({"min_quality", report.min_quality_used, to, live, share});
      report.min_quality_used = to;
      kernel.quality_floor = to;
    }
  }
  report.stop = StopDiagnosis{};  // the run goes on: the census is no longer its stop diagnosis
  return true;
}

}  // namespace topotet::detail
