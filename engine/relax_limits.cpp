// relax_limits (relax_limits.h): which limit held the vertices left, and one step of it.
//
//   census <- diagnose_stop (the reason that holds each live vertex): on an even sample of about
//             256 of them when there are at least twice as many, then on every one when the
//             sample's choice below is not clear or the run is to stop
//   excess <- live - target
//   tolerance may relax: relax_tolerance, H > 0 and below the bounding box diagonal
//   quality may relax:   relax_quality and a floor above 0
//   features may go:     relax_features and pinned feature corners left
//   inverted tets holding at least min(excess, 1% of the live ones) and no fewer than any limit
//   an option sets: the driver's flips first (flip_at_stall.h), if they change anything
//   of the limits, the one holding more vertices, if it holds at least min(excess, 1% of the live
//   ones) and no less than any other limit an option sets (the tolerance, the floors, a field
//   error limit, the feature corners of feature_angle), relaxable or not: a limit holding a few
//   while a hard one holds the rest is kept, since relaxing it would loosen the whole output's
//   guarantee for a few vertices (measured: a hard tolerance holding 77% let the floors halve 7
//   times, 5 degrees -> 0.04, for 388 -> 371 vertices). The topology and inverted tets are left
//   out of that comparison: what they hold changes as the mesh around changes (sphere3 at 2%: held
//   56% by inversion at 3.2%, it reaches 2% once the tolerance relaxes on).
//     tolerance: H <- the first of 2H, 4H, 8H that frees at least an eighth of the excess
//                (tolerance_frees on a sample of the vertices it holds), else 2H
//     quality: both floors <- half (0 below 1/256 of the asked ones)
//     features: the feature curves judged again at 2H, 4H, 8H (drop_features_below); at the first
//               scale where some are lower than it, those go (with their corners, the cost
//               model's orders and the coverage's segments) and H becomes that scale
#include "relax_limits.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "features/features.h"
#include "mesh/dihedral.h"
#include "mesh/moved_corner.h"
#include "stop_diagnosis.h"

namespace topotet::detail {
namespace {

// Floors below this share of the asked one are dropped: at 1/256 (5 degrees -> 0.02 degrees) a
// floor no longer tells tets apart from what the inversion check already refuses.
constexpr double kLastFloorShare = 1.0 / 256.0;

// Feature corners that hold a run are judged again at 2, 4 and 8 times H, no further: a curve that
// is still a feature at 8H is a shape (a box's edges), and a run it holds stops and says so (the
// box of tests/property_features.cpp at 10%: its edges went at 32 H for two vertices of target).
constexpr int kFeatureLookAhead = 3;

// The tolerance looks ahead this many doublings (2H, 4H, 8H) for one that frees an eighth of the
// excess. Polycrystal 30k at 10%: at its first stall (1,675 vertices for 583) 2H freed 50 of the
// 1,267 vertices the tolerance held, 4H 1,027: the doubling made 30 collapses and stalled again, a
// census and a look at every edge for nothing (13% of the run's instructions). Elsewhere (sphere3,
// torus, polycrystal at 2%) 2H freed most of them and stays the step.
constexpr int kToleranceLookAhead = 3;
// The look-ahead asks a sample of the vertices the tolerance holds, this many at most: a full
// count proved every placement of the vertices a step does not free (those proofs fail slowly)
// and cost as much as it saved (polycrystal 30k: -3.7% instructions, sphere3 at 2% +1.9%).
constexpr std::size_t kToleranceSample = 128;

// A census that only chooses a step asks about this many of the unpinned vertices left, evenly
// spread (diagnose_stop's stride), when there are at least twice as many; the full census runs
// when the sample's choice is not clear (clear_choice) and whenever the run is to stop (its report
// names exact counts). Polycrystal 30k at 10%: its two censuses asked all of 1,676 and 1,010
// vertices, about 360k instructions each, 15% of the run's instructions; polycrystal 200k 15%.
constexpr std::size_t kCensusSample = 256;
// A sampled choice is clear when the limit it acts on holds at least this many of the asked
// vertices, and at least twice as many as any other limit and the inversion, and twice the least
// count that relaxes (enough_of): a full census would then choose the same, but for a sample as
// unlucky as several standard deviations.
constexpr double kLeastAsked = 32.0;

// The least count of vertices a limit must hold to be relaxed: min(excess, 1% of the live ones).
std::uint64_t enough_of(std::uint64_t live, std::uint64_t target) {
  return std::max<std::uint64_t>(1, std::min<std::uint64_t>(live - target, live / 100));
}

// The most any limit an option sets holds.
std::uint64_t most_of(const StopDiagnosis& d) { return std::max({d.quality, d.tolerance, d.field_error, d.pinned_features}); }

// lowest_floors over `count` tets, corners(t, p) giving tet t's corners (false: no tet there).
template <class Corners>
void lowest_floors_of(std::size_t count, const Corners& corners, const SimplifyOptions& asked, Report& report) {
  // The worst mean ratio of every tet; the worst dihedral angle only of the tets the asked floor's
  // screen does not clear (the others are above the asked floor, which bounds the answer anyway).
  const DihedralFloor floor = DihedralFloor::degrees(asked.min_dihedral);
  double worst_q3 = 1.0, worst_sine_sq = 1.0;
  glm::dvec3 p[4];
  for (std::size_t t = 0; t < count; ++t) {
    if (!corners(t, p)) continue;
    const double q3 = std::fabs(mean_ratio_cubed(p[0], p[1], p[2], p[3]));
    worst_q3 = std::min(worst_q3, q3);
    if (floor.active() && q3 < floor.screen_q3) worst_sine_sq = std::min(worst_sine_sq, min_dihedral_sine_sq(p[0], p[1], p[2], p[3]));
  }
  // The dihedral floor compares sines (dihedral.h: an angle near 180 degrees is as flat as one
  // near 0): the same measure here, as the acute angle of that sine.
  const double worst_degrees = std::asin(std::sqrt(std::clamp(worst_sine_sq, 0.0, 1.0))) * 180.0 / 3.14159265358979323846;
  report.min_quality_lowest = std::min(asked.min_quality, std::cbrt(worst_q3));
  report.min_dihedral_lowest = std::min(asked.min_dihedral, worst_degrees);
}

// The tolerance's next value: the first of 2H, 4H, 8H under which at least an eighth of the
// excess (live - target) of the vertices the tolerance holds could go (tolerance_frees's
// estimate); 2H when none: the doubling, as without the look-ahead.
// `scale`: the vertices one flagged vertex stands for (a sampled census's, diagnose_stop).
double next_tolerance(const MeshModel& mesh, const CollapseOptions& kernel, CostModel& cost,
                      const std::vector<std::uint8_t>& held_by_tolerance, double scale, std::uint64_t live,
                      std::uint64_t target) {
  const auto wanted = static_cast<std::uint64_t>(std::ceil(static_cast<double>((live - target + 7) / 8) / scale));
  for (int step = 1; step <= kToleranceLookAhead; ++step) {
    const double h = std::ldexp(kernel.tolerance, step);
    if (tolerance_frees(mesh, kernel, cost, h, held_by_tolerance, wanted, kToleranceSample)) return h;
  }
  return 2.0 * kernel.tolerance;
}

// Is acting on `held` (one of the census's counts: d.tolerance, d.quality, d.pinned_features or
// d.inversion) a clear choice of a census sampled at `scale` (kLeastAsked above)?
bool clear_choice(const StopDiagnosis& d, const std::uint64_t& held, double scale, std::uint64_t live,
                  std::uint64_t target) {
  if (static_cast<double>(held) < kLeastAsked * scale || held < 2 * enough_of(live, target)) return false;
  for (const std::uint64_t* other : {&d.quality, &d.tolerance, &d.field_error, &d.pinned_features, &d.inversion})
    if (other != &held && 2 * *other > held) return false;
  return true;
}

}  // namespace

void lowest_floors(const MeshModel& mesh, const SimplifyOptions& asked, Report& report) {
  lowest_floors_of(
      mesh.tet_capacity(),
      [&](std::size_t t, glm::dvec3* p) {
        if (mesh.is_dead_tet(static_cast<TetId>(t))) return false;
        for (int k = 0; k < 4; ++k) p[k] = mesh.positions[mesh.tets[t][k]];
        return true;
      },
      asked, report);
}

void lowest_floors(const MeshData& mesh, const SimplifyOptions& asked, Report& report) {
  lowest_floors_of(
      mesh.tet_count(),
      [&](std::size_t t, glm::dvec3* p) {
        for (int k = 0; k < 4; ++k) {
          const auto& x = mesh.positions[mesh.tets[t][k]];
          p[k] = glm::dvec3(x[0], x[1], x[2]);
        }
        return true;
      },
      asked, report);
}

StopDiagnosis floors_at_lowest(const StopDiagnosis& census, bool relax_quality, const Report& report) {
  StopDiagnosis d = census;
  if (relax_quality && !report.floors_may_relax()) d.quality = 0;
  return d;
}

void halve_floors(const SimplifyOptions& asked, std::uint64_t live, double share, Report& report) {
  const auto halve = [&](const char* limit, double& used, double asked_floor, double lowest) {
    if (!(used > lowest)) return;
    const double h = 0.5 * used;
    const double to = std::max(h < asked_floor * kLastFloorShare ? 0.0 : h, lowest);
    report.relaxations.push_back({limit, used, to, live, share});
    used = to;
  };
  halve("min_dihedral", report.min_dihedral_used, asked.min_dihedral, report.min_dihedral_lowest);
  halve("min_quality", report.min_quality_used, asked.min_quality, report.min_quality_lowest);
}

bool inversion_holds_most(const StopDiagnosis& d, std::uint64_t live, std::uint64_t target) {
  return live > target && d.inversion >= enough_of(live, target) && d.inversion >= most_of(d);
}

RelaxChoice choose_relaxation(const StopDiagnosis& d, std::uint64_t live, std::uint64_t target, bool may_tolerance,
                              bool may_floors, bool may_features) {
  if (live <= target || d.vertices == 0) return RelaxChoice::kNone;
  const std::uint64_t enough = enough_of(live, target), most = most_of(d);
  const auto stops_the_run = [&](std::uint64_t held) { return held >= enough && held == most; };
  if (may_tolerance && stops_the_run(d.tolerance)) return RelaxChoice::kTolerance;
  if (may_floors && stops_the_run(d.quality)) return RelaxChoice::kFloors;
  if (may_features && stops_the_run(d.pinned_features)) return RelaxChoice::kFeatures;
  return RelaxChoice::kNone;
}

namespace {

// The step relax_limits chose, on its census d (scale: diagnose_stop's). False: none was possible
// (no feature curve lower than the scales looked at).
bool relax_one(MeshModel& mesh, const SimplifyOptions& options, CollapseOptions& kernel, SurfaceCoverage* coverage,
               CostModel& cost, const StopDiagnosis& d, RelaxChoice choice, bool tolerance_can_grow,
               const std::vector<std::uint8_t>& held_by_tolerance, double scale, std::uint64_t live,
               std::uint64_t target, Report& report) {
  const double share_base = static_cast<double>(d.vertices);
  const auto raise_h = [&](double h, std::uint64_t held) {
    report.relaxations.push_back({"tolerance", kernel.tolerance, h, live, static_cast<double>(held) / share_base});
    kernel.tolerance = h;
    coverage->raise_tolerance(h);
    report.tolerance = h;
  };
  if (choice == RelaxChoice::kTolerance) {
    raise_h(next_tolerance(mesh, kernel, cost, held_by_tolerance, scale, live, target), d.tolerance);
  } else if (choice == RelaxChoice::kFloors) {
    halve_floors(options, live, static_cast<double>(d.quality) / share_base, report);
    kernel.dihedral_floor = DihedralFloor::degrees(report.min_dihedral_used);
    kernel.quality_floor = report.min_quality_used;
  } else if (choice == RelaxChoice::kFeatures) {
    // Features are judged at the scale of H (features.h): the curves are judged again at 2H, 4H,
    // 8H (or at H when H may not grow), and at the first of those where some are lower than it,
    // they go and H becomes it. None: the features are shapes at those scales, and stay.
    std::vector<double> scales{kernel.tolerance};
    if (tolerance_can_grow) {
      scales.clear();
      for (int step = 1; step <= kFeatureLookAhead; ++step) scales.push_back(std::ldexp(kernel.tolerance, step));
    }
    const FeatureDrop drop = drop_features_below(mesh, options.feature_angle, scales);
    if (drop.edges_after == drop.edges_before) return false;
    if (drop.scale > kernel.tolerance) raise_h(drop.scale, d.pinned_features);
    report.relaxations.push_back({"features", static_cast<double>(drop.edges_before), static_cast<double>(drop.edges_after),
                                  live, static_cast<double>(d.pinned_features) / share_base});
    report.features_dropped += drop.edges_before - drop.edges_after;
    cost.forget_orders();
    coverage->drop_unheld_segments(mesh, kFeatureCurveRef);
  } else {
    return false;
  }
  report.stop = StopDiagnosis{};  // the run goes on: the census is no longer its stop diagnosis
  return true;
}

}  // namespace

bool relax_limits(MeshModel& mesh, const SimplifyOptions& options, CollapseOptions& kernel, SurfaceCoverage* coverage,
                  CostModel& cost, std::uint64_t target, Report& report, const std::function<bool()>& flip) {
  const std::uint64_t live = mesh.live_vertex_count();
  std::vector<std::uint8_t> held_by_tolerance;
  bool flipped_nothing = false;
  // A sampled census first where the vertices left are many; the full one when its choice is not
  // clear or the run is to stop (kCensusSample).
  for (std::size_t stride = live >= 2 * kCensusSample ? live / kCensusSample : 1;; stride = 1) {
    const bool sampled = stride > 1;
    const auto start = std::chrono::steady_clock::now();
    const double scale = diagnose_stop(mesh, options, kernel, cost, target, report, true, &held_by_tolerance, stride);
    report.relax_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (live <= target || report.stop.vertices == 0) {
      if (sampled) continue;
      return false;
    }
    // The floors relax last: once at their lowest, what they hold no longer keeps the other limits
    // (and the flips) from relaxing for the vertices those hold (issue #50).
    const StopDiagnosis d = floors_at_lowest(report.stop, options.relax_quality, report);
    // Inverted tets hold the most: flips first (they cost no guarantee).
    if (flip && !flipped_nothing && inversion_holds_most(d, live, target)) {
      if (sampled && !clear_choice(d, d.inversion, scale, live, target)) continue;
      if (flip()) {
        report.stop = StopDiagnosis{};
        return true;
      }
      flipped_nothing = true;
    }
    const bool tolerance_can_grow = options.relax_tolerance && kernel.tolerance > 0.0 && coverage != nullptr &&
                                    kernel.tolerance < bounding_box_diagonal(mesh);
    const RelaxChoice choice = choose_relaxation(d, live, target, tolerance_can_grow,
                                                 options.relax_quality && report.floors_may_relax(),
                                                 options.relax_features && coverage != nullptr);
    if (sampled) {
      const std::uint64_t& held = choice == RelaxChoice::kTolerance ? d.tolerance
                                  : choice == RelaxChoice::kFloors  ? d.quality
                                                                    : d.pinned_features;
      if (choice == RelaxChoice::kNone || !clear_choice(d, held, scale, live, target)) continue;
    }
    if (relax_one(mesh, options, kernel, coverage, cost, d, choice, tolerance_can_grow, held_by_tolerance, scale,
                  live, target, report))
      return true;
    if (!sampled) return false;
  }
}

}  // namespace topotet::detail
