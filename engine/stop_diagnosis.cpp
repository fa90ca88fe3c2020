// diagnose_stop (stop_diagnosis.h): for every live vertex, what keeps every collapse that would
// remove it from happening, then the dominant reason and one suggestion.
//
//   for each live vertex v (parallel; a sample: the slots that are multiples of the stride):
//     pinned                                   -> pinned
//     for each edge uv, the placements of the cost model (the engines try the same) that remove
//     v (v merges into u, or both move to the midpoint or the quadric's optimum):
//       none (v is a curve junction or end, or of higher order than u: it stays) -> topology
//       the link conditions of K or K~ fail    -> topology (they do not depend on the placement)
//       else the furthest a placement gets in the kernel's order:
//         inversion < quality < tolerance < field_error < collapsible
//     v's reason <- the furthest over all its edges (what would have to give first)
//   a sample's counts, but the pinned (counted exactly), scaled to the live unpinned vertices
//   dominant <- the reason with most vertices; suggestion <- what relaxes it, and when an option
//   cannot (topology, inversion, pinned by the input), also what relaxes the largest reason an
//   option can
#include "stop_diagnosis.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cost/cost.h"
#include "kernel/link_condition.h"
#include "parallel/for_range.h"

namespace topotet::detail {
namespace {

enum Verdict : int { kPinnedEnd, kTopology, kInversion, kQuality, kTolerance, kFieldError, kCollapsible, kVerdicts };

// How far a placement refused for `reason` got in the kernel (may_collapse's order).
int stage_of(CollapseReason reason) {
  switch (reason) {
    case CollapseReason::kOk: return kCollapsible;
    case CollapseReason::kPinned: return kPinnedEnd;
    case CollapseReason::kInversion: return kInversion;
    case CollapseReason::kQuality: return kQuality;
    case CollapseReason::kTolerance: return kTolerance;
    case CollapseReason::kFieldError: return kFieldError;
    case CollapseReason::kLinkK:
    case CollapseReason::kLinkKtilde: return kTopology;
  }
  return kTopology;
}

std::string percent(double share) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f%%", 100.0 * share);
  return buf;
}

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

// The placements of edge ab (a < b) that remove v (one of them): v merges into the other end, or
// both move to one new point. Each placement is kept, the quality fallbacks included (as if
// reached: no flag is set). Returns their count.
int placements_removing(const MeshModel& mesh, CostModel& cost, VertId a, VertId b, VertId v, LinkScratch& link,
                        CollapseCandidate* kept, Placement* placements) {
  CollapseCandidate cands[kMaxCandidates];
  const int n = cost.candidates(mesh, a, b, cands, link);
  int m = 0;
  for (int k = 0; k < n; ++k)
    if (cands[k].v == v || cands[k].placement != 0) {
      kept[m] = cands[k];
      placements[m++] = {cands[k].u, cands[k].v, cands[k].p};
    }
  return m;
}

}  // namespace

double diagnose_stop(const MeshModel& mesh, const SimplifyOptions& options, const CollapseOptions& kernel,
                     CostModel& cost, std::uint64_t target, Report& report, bool every_edge_refused,
                     std::vector<std::uint8_t>* held_by_tolerance, std::size_t stride) {
  stride = std::max<std::size_t>(stride, 1);
  StopDiagnosis& d = report.stop;
  if (held_by_tolerance != nullptr) held_by_tolerance->assign(mesh.vertex_capacity(), 0);
  d = StopDiagnosis{};
  d.is_filled = true;
  const std::size_t nv = mesh.vertex_capacity();
  std::array<std::atomic<std::uint64_t>, kVerdicts> counts{};
  CollapseOptions geometry = kernel;  // inversion and quality only
  geometry.surfaces = nullptr;
  geometry.coverage = nullptr;
  geometry.field_bounds = nullptr;
  const bool field_limit = kernel.field_bounds != nullptr && kernel.field_bounds->has_limit();
  // After a stall the engine has refused every placement of every edge: one that passes the
  // geometry and the link conditions, is no quality fallback (tried by the engine only after a
  // quality refusal) and moves a surface vertex was refused by the tolerance (with no field limit,
  // the only check after it). Its proof, most of the census where the tolerance holds (polycrystal
  // 30k: 22% of the run), is not run again. Same verdicts (StopDiagnosis.
  // TheEnginesRefusalsGiveTheFullCensus).
  const bool refused_by_tolerance = every_edge_refused && !field_limit && kernel.surfaces != nullptr;
  const std::size_t asked_slots = (nv + stride - 1) / stride, grain = std::max<std::size_t>(1, 256 / stride);
  parallel::for_range<std::size_t>(0, asked_slots, grain, "diagnose_stop", [&](std::size_t begin, std::size_t end) {
    CollapseScratch scratch;
    const ReuseClassifications reuse(scratch.link);  // the mesh is read only; each edge is seen from both ends
    std::vector<VertId> nbrs;
    std::vector<double> fields;
    std::array<std::uint64_t, kVerdicts> local{};
    // The furthest stage the placements reach in the kernel with `o`, tried in one call (the
    // edge's stars gathered once): each placement it tries is refused for exactly one reason, or
    // accepted (the call stops there: collapsible is the furthest stage), so the furthest stage is
    // the largest reason counted. The link conditions are the caller's.
    const auto furthest = [&](const Placement* p, int n, const CollapseOptions& o) {
      std::array<std::uint64_t, kCollapseReasonCount> rejected{};
      if (first_acceptable(mesh, p, n, o, scratch, &rejected, false) >= 0) return static_cast<int>(kCollapsible);
      int stage = kTopology;
      for (int r = 1; r < kCollapseReasonCount; ++r)
        if (rejected[r] != 0) stage = std::max(stage, stage_of(static_cast<CollapseReason>(r)));
      return stage;
    };
    // Moves the placements the engine refused for the tolerance (refused_by_tolerance above: no
    // quality fallback, a surface vertex moves) to `refused`; keeps the others first in `kept` and
    // `placements` and returns their count.
    const auto split_refused = [&](CollapseCandidate* kept, Placement* placements, int m, Placement* refused,
                                   int& n_refused) {
      int rest = 0;
      for (int k = 0; k < m; ++k) {
        if (!kept[k].fallback && kernel.surfaces->on_surface(placements[k].u)) {
          refused[n_refused++] = placements[k];
        } else {
          kept[rest] = kept[k];
          placements[rest++] = placements[k];
        }
      }
      return rest;
    };
    for (std::size_t i = begin; i < end; ++i) {
      const VertId v = static_cast<VertId>(i * stride);
      if (mesh.is_dead_vertex(v) || mesh.is_frozen(v)) continue;
      if (mesh.is_pinned(v)) {
        ++local[kPinnedEnd];
        continue;
      }
      int best = kTopology;  // no edge offers to remove v
      mesh.neighbours(v, nbrs);
      for (const VertId u : nbrs) {
        if (best == kCollapsible) break;
        if (mesh.is_frozen(u)) continue;
        const VertId a = std::min(u, v), b = std::max(u, v);
        Placement placements[kMaxCandidates];
        CollapseCandidate kept[kMaxCandidates];
        int m = placements_removing(mesh, cost, a, b, v, scratch.link, kept, placements);
        if (m == 0) continue;
        // Held by the tolerance already: the placements the engine refused for it cannot raise
        // that (polycrystal 30k: most of the census's edges are skipped so).
        if (refused_by_tolerance && best >= kTolerance) {
          Placement refused[kMaxCandidates];
          int n_refused = 0;
          m = split_refused(kept, placements, m, refused, n_refused);
          if (m == 0) continue;
        }
        // The geometry alone bounds what this edge can give (a placement that passes it reaches
        // at most "collapsible"; one it refuses, exactly its stage): when that is no more than v
        // has already, the edge cannot change v's reason, and its link conditions and tolerance
        // proofs, most of the census on meshes held by the tolerance (polycrystal: 30% of the
        // run), are not needed. Same verdicts.
        if (furthest(placements, m, geometry) <= best) continue;
        if (!gather_stars(mesh, a, b, scratch) ||
            check_link_conditions(mesh, a, b, scratch.star_uv, scratch.link) != LinkResult::kOk)
          continue;  // topology: the link conditions do not depend on the placement
        if (refused_by_tolerance) {
          // The placements the engine refused for the tolerance count so (or by their geometry,
          // as the kernel would: in one call, any that passes it makes the stage the tolerance);
          // the rest (no surface vertex moves, or a quality fallback) go to the kernel below.
          Placement refused[kMaxCandidates];
          int n_refused = 0;
          m = split_refused(kept, placements, m, refused, n_refused);
          if (n_refused > 0 && best < kTolerance)
            best = std::max(best, std::min<int>(kTolerance, furthest(refused, n_refused, geometry)));
          if (m == 0) continue;
        }
        if (field_limit) set_placement_fields(mesh, cost, kept, m, placements, fields);
        // Every placement in one call (they share the stencil's surface and quality); the link
        // conditions passed above, for every placement of this edge: not again.
        best = std::max(best, furthest(placements, m, kernel));
      }
      ++local[best];
      if (best == kTolerance && held_by_tolerance != nullptr) (*held_by_tolerance)[v] = 1;
    }
    for (int k = 0; k < kVerdicts; ++k) counts[k].fetch_add(local[k], std::memory_order_relaxed);
  });
  // The pinned vertices exactly (a flag each); a sample's other verdicts scaled to the unpinned
  // live vertices it was taken from.
  std::uint64_t unpinned = 0, pinned = 0;
  for (VertId v = 0; v < nv; ++v) {
    if (mesh.is_dead_vertex(v)) continue;
    if (!mesh.is_pinned(v)) {
      unpinned += mesh.is_frozen(v) ? 0 : 1;
      continue;
    }
    pinned += mesh.is_frozen(v) ? 0 : 1;
    const std::uint8_t s = mesh.vertex_states[v];
    if (s & vertex_state::kCorner) ++d.pinned_corners;
    else if (s & vertex_state::kRequired) ++d.pinned_required;
    else if (s & vertex_state::kFeatureCorner) ++d.pinned_features;
    else ++d.pinned_other;
  }
  std::uint64_t asked = 0;
  for (int k = 0; k < kVerdicts; ++k)
    if (k != kPinnedEnd) asked += counts[k];
  const double scale = stride == 1 || asked == 0 ? 1.0 : static_cast<double>(unpinned) / static_cast<double>(asked);
  const auto scaled = [&](int k) {
    return stride == 1 ? counts[k].load() : static_cast<std::uint64_t>(std::llround(scale * static_cast<double>(counts[k])));
  };
  d.topology = scaled(kTopology);
  d.pinned = stride == 1 ? counts[kPinnedEnd].load() : pinned;
  d.inversion = scaled(kInversion);
  d.quality = scaled(kQuality);
  d.tolerance = scaled(kTolerance);
  d.field_error = scaled(kFieldError);
  d.collapsible = scaled(kCollapsible);
  d.vertices = d.topology + d.pinned + d.inversion + d.quality + d.tolerance + d.field_error + d.collapsible;

  if (d.vertices == 0) return scale;
  const std::uint64_t fixed = d.topology + d.pinned_corners + d.pinned_required;
  d.beyond_reach = fixed >= target;
  // The reasons, the ones an option relaxes first (ties go to the first).
  struct Reason {
    const char* name;
    const char* who;
    std::uint64_t count;
  };
  const Reason reasons[] = {{"tolerance", "the tolerance", d.tolerance},
                            {"quality", "the quality floor", d.quality},
                            {"field_error", "the field error limit", d.field_error},
                            {"pinned", "pinned vertices", d.pinned},
                            {"inversion", "inverted tets", d.inversion},
                            {"topology", "the topology", d.topology},
                            {"collapsible", "nothing", d.collapsible}};
  const auto share_of = [&](const Reason& r) { return static_cast<double>(r.count) / static_cast<double>(d.vertices); };
  const auto held = [&](const Reason& r) { return std::string(r.who) + " held " + percent(share_of(r)) + " of the vertices left"; };
  // What an option changes for reason r, with its predicted effect; empty when no option does.
  const bool features_pin = d.pinned_features > 0 && d.pinned_features >= d.pinned_corners + d.pinned_required + d.pinned_other;
  const auto advice = [&](const Reason& r) -> std::string {
    const std::string effect = "; it can free up to " + percent(share_of(r)) + " of them";
    const std::string name = r.name;
    if (name == "tolerance") {
      const double diagonal = bounding_box_diagonal(mesh);
      const double rel = diagonal > 0.0 ? report.tolerance / diagonal : options.tolerance_rel;
      return "--tolerance-rel " + number(2.0 * rel) + " (SimplifyOptions::tolerance_rel, twice H = " +
             number(report.tolerance) + ") is the next step" + effect;
    }
    // The floors as the run used them (relaxed ones included: Report::min_dihedral_used).
    if (name == "quality" && report.min_dihedral_used > 0.0)
      return "--min-dihedral " + number(report.min_dihedral_used / 2.0) + " or --min-quality " +
             number(report.min_quality_used / 2.0) +
             " (SimplifyOptions::min_dihedral, min_quality: half a floor) is the next step" + effect +
             ", with flatter tets";
    if (name == "quality")
      return "--min-quality " + number(report.min_quality_used / 2.0) +
             " (SimplifyOptions::min_quality, half the floor) is the next step" + effect + ", with flatter tets";
    if (name == "field_error")
      return (options.max_field_error_rel > 0.0 ? "--max-field-error-rel " + number(2.0 * options.max_field_error_rel)
                                                : "--max-field-error " + number(2.0 * options.max_field_error)) +
             " (twice the limit) is the next step" + effect;
    if (name == "pinned" && features_pin)
      return "--feature-angle " + number(std::min(180.0, options.feature_angle + 30.0)) +
             " (SimplifyOptions::feature_angle; 180 = no features) is the next step" + effect;
    return {};
  };
  const Reason* top = &reasons[0];
  for (const Reason& r : reasons)
    if (r.count > top->count) top = &r;
  d.dominant = top->name;
  d.dominant_share = share_of(*top);
  const std::string dominant = d.dominant;
  std::string why;
  if (dominant == "pinned" && !features_pin)
    why = " (" + std::to_string(d.pinned_corners) + " listed corners, " + std::to_string(d.pinned_required) +
          " required vertices: the input pins them; no option moves them)";
  else if (dominant == "inversion")
    why = " (every placement that removes them, an endpoint, the midpoint or the quadric's optimum, folds a tet; "
          "no option relaxes that)";
  else if (dominant == "topology")
    why = " (they join or end curves of the substructures, or every collapse that removes them would change the "
          "topology of the mesh or of a substructure; no option changes that)";
  else if (dominant == "collapsible")
    why = " (they can go now: a new run from this output continues)";
  std::string step = advice(*top);
  if (step.empty()) {  // the largest reason an option relaxes, if it holds a fair share
    const Reason* next = nullptr;
    for (const Reason& r : reasons)
      if (!advice(r).empty() && (next == nullptr || r.count > next->count)) next = &r;
    if (next != nullptr && share_of(*next) >= 0.05) step = held(*next) + ": " + advice(*next);
  }
  d.suggestion = held(*top) + why + (step.empty() ? "" : (advice(*top).empty() ? "; " : ": ") + step);
  if (d.beyond_reach)
    d.suggestion += "; the topology and the vertices the input pins alone hold " + std::to_string(fixed) +
                    " vertices, the target is " + std::to_string(target) + ": no option reaches it";
  return scale;
}

bool tolerance_frees(const MeshModel& mesh, const CollapseOptions& kernel, CostModel& cost, double h,
                     const std::vector<std::uint8_t>& held_by_tolerance, std::uint64_t wanted, std::size_t sample) {
  std::vector<VertId> held;
  for (std::size_t v = 0; v < held_by_tolerance.size(); ++v)
    if (held_by_tolerance[v] != 0) held.push_back(static_cast<VertId>(v));
  if (wanted == 0) return true;
  if (held.empty() || sample == 0) return false;
  const std::size_t stride = (held.size() + sample - 1) / sample;  // every stride-th: at most `sample`
  const std::size_t asked = (held.size() + stride - 1) / stride;
  // The sample's share of `wanted`, rounded up: freed * held / asked >= wanted.
  const std::uint64_t wanted_asked = (wanted * asked + held.size() - 1) / held.size();
  CollapseOptions looser = kernel;
  looser.tolerance = h;
  // The coverage (the reverse half of the proof) keeps its own H, which only grows: the forward
  // proof alone, an upper bound of what the engine will find.
  looser.coverage = nullptr;
  const bool field_limit = kernel.field_bounds != nullptr && kernel.field_bounds->has_limit();
  std::atomic<std::uint64_t> freed{0};
  // The count stops once it reaches wanted_asked: the answer is the same whichever vertices got there.
  parallel::for_range<std::size_t>(0, asked, 8, "tolerance_frees", [&](std::size_t begin, std::size_t end) {
    CollapseScratch scratch;
    const ReuseClassifications reuse(scratch.link);  // the mesh is read only
    std::vector<VertId> nbrs;
    std::vector<double> fields;
    for (std::size_t i = begin; i < end && freed.load(std::memory_order_relaxed) < wanted_asked; ++i) {
      const VertId v = held[i * stride];
      mesh.neighbours(v, nbrs);
      for (const VertId u : nbrs) {
        if (mesh.is_frozen(u)) continue;
        Placement placements[kMaxCandidates];
        CollapseCandidate kept[kMaxCandidates];
        const int m = placements_removing(mesh, cost, std::min(u, v), std::max(u, v), v, scratch.link, kept, placements);
        if (m == 0) continue;
        if (field_limit) set_placement_fields(mesh, cost, kept, m, placements, fields);
        if (first_acceptable(mesh, placements, m, looser, scratch, nullptr, true) >= 0) {
          freed.fetch_add(1, std::memory_order_relaxed);
          break;
        }
      }
    }
  });
  return freed.load() >= wanted_asked;
}

}  // namespace topotet::detail
