// Relaxing the limits that would stop a run before its target (issue #23; SimplifyOptions::
// relax_tolerance, relax_quality, relax_features): the driver's RelaxStep (engines.h).
#pragma once

#include <functional>

#include "cost/cost.h"
#include "guarantees/surface_coverage.h"
#include "kernel/collapse.h"
#include "mesh/mesh_model.h"
#include "topotet/simplify.h"

namespace topotet::detail {

// Called when no legal collapse is left before the target. Takes the census of the vertices left
// (diagnose_stop, into report.stop; first on a sample of them when they are many, relax_limits.cpp)
// and, if the tolerance, the quality floors or the feature
// corners hold enough of them, no fewer than any other limit an option sets, and the options let
// that limit relax, relaxes the one that holds more: H doubled (kernel and coverage; quadrupled or
// multiplied by 8 when a look-ahead finds that 2H would free less than an eighth of the excess of
// the vertices left over the target, and the larger value does: relax_limits.cpp), or the
// dihedral and mean-ratio floors halved (to 0 once below 1/256 of the asked ones), or the feature
// curves lower than 2H, 4H or 8H dropped and H raised to that scale (drop_features_below; `cost`
// forgets its orders, the coverage the curves' segments).
// Records it in report (tolerance, min_quality_used, min_dihedral_used, features_dropped,
// relaxations), clears report.stop and returns true; else leaves report.stop filled (it is the
// run's stop diagnosis) and returns false. Deterministic: the census is (diagnose_stop).
//
// Why relaxing keeps the guarantees, with the relaxed values: every collapse was proved under
// the H it was made with, which is at most the last H, and the coverage invariant (every original
// point within H of its face) only gets looser; every tet was accepted above the floor of its time,
// which is at least the last floor. Dropped features were curves of our own making, not of the
// input: the surfaces they lay on keep their labels, topology and tolerance. The topology,
// inversion, listed or required vertices and field error limits are never relaxed.
//
// `flip` (may be empty): where the census says inverted tets hold at least as many of the vertices
// left as every limit an option sets (and at least min(excess, 1% of them)), flip() is asked first
// (the driver's flip_at_stall, flip_at_stall.h: it changes the stars that fold, at no guarantee's
// price); true: the run goes on with every limit as it was. False (no flip, or no collapse since
// the last flips): the limits are looked at as above.
bool relax_limits(MeshModel& mesh, const SimplifyOptions& options, CollapseOptions& kernel, SurfaceCoverage* coverage,
                  CostModel& cost, std::uint64_t target, Report& report, const std::function<bool()>& flip = {});

// The rule above on a census alone, shared with topotet::mpi (whose ranks add up the censuses of
// their parts): which limit relaxes, given which of them can (`may_*`), with `live` vertices left
// for `target`. A limit relaxes when it holds at least min(excess, 1% of the live vertices) and no
// fewer than any other limit an option sets (the tolerance, the floors, a field error limit, the
// feature corners); ties go to the tolerance, then the floors, then the features.
enum class RelaxChoice : std::uint8_t { kNone, kTolerance, kFloors, kFeatures };
RelaxChoice choose_relaxation(const StopDiagnosis& census, std::uint64_t live, std::uint64_t target, bool may_tolerance,
                              bool may_floors, bool may_features);
// Inverted tets hold at least min(excess, 1% of the live vertices) and no fewer than any limit an
// option sets: relax_limits flips first then.
bool inversion_holds_most(const StopDiagnosis& census, std::uint64_t live, std::uint64_t target);
// Both quality floors the run uses (Report::min_dihedral_used, min_quality_used) halved, each to 0
// once below 1/256 of the asked one (`asked`), and never below its lowest (Report::
// min_dihedral_lowest, min_quality_lowest; a floor already there stays), each step recorded in
// Report::relaxations with `live` vertices left and the `share` of them the floors held. The
// caller puts the new floors in its kernel (relax_limits) or its parts' options (topotet::mpi).
void halve_floors(const SimplifyOptions& asked, std::uint64_t live, double share, Report& report);
// How far the floors may relax, from the input (call before the first collapse): min(asked floor,
// the worst of the mesh's live tets), into Report::min_quality_lowest and min_dihedral_lowest.
// Relaxing a floor below the input's own worst tet would let the run make tets worse than any the
// input has: an output of slivers, which solvers cannot use (issue #50).
void lowest_floors(const MeshModel& mesh, const SimplifyOptions& asked, Report& report);
void lowest_floors(const MeshData& mesh, const SimplifyOptions& asked, Report& report);  // a part's (MPI)
// The census the relaxation rule compares (choose_relaxation, inversion_holds_most): the floors
// relax last, so once relax_quality brought them to their lowest, what they hold is left out (it
// counts 0) and no longer keeps the tolerance, the feature curves or the flips from relaxing for
// the vertices those hold. Floors given as options (relax_quality false) hold as asked and keep
// counting: a limit the user set is not outweighed.
StopDiagnosis floors_at_lowest(const StopDiagnosis& census, bool relax_quality, const Report& report);

}  // namespace topotet::detail
