// Simplification by topology-preserving edge collapses: options in, report out, never throws.
//
//   topotet::TetMesh mesh = topotet::build_tet_mesh(topotet::read_mesh("in.mesh"));
//   topotet::SimplifyOptions options;
//   options.target_vertex_ratio = 0.1;
//   topotet::Report report = topotet::simplify(mesh, options);
//   if (report.status == topotet::Status::kInvalidInput) { /* report.message says why */ }
//   topotet::write_mesh("out.mesh", mesh.to_mesh_data());
//
// Every accepted collapse keeps the topology of the mesh and of every substructure (surfaces,
// material interfaces, polylines, pinned vertices) and inverts no tet. The library never prints;
// progress goes through on_progress, which may also cancel. There is no global state: two calls
// on two meshes may run concurrently.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "topotet/isosurface.h"
#include "topotet/tet_mesh.h"

namespace topotet {

struct RoundStats;  // topotet/round_log.h

// The field error bounds of a mesh carried from one run to the next (SimplifyOptions::field_samples):
// out of core, a piece's samples travel with it through the levels, so that its bounds stay exact
// over the input's vertices (engine/guarantees/field_bounds.h) instead of restarting at 0 against
// an already simplified piece. A sample is an original vertex: its position and field values,
// and the tet of the mesh that holds it. Every component's range and largest magnitude are the
// whole input's (the limits and the rounding slack are in its units, not a piece's).
struct FieldBoundSamples {
  int components = 0;                     // field_stride() of the mesh
  std::vector<double> range, magnitude;   // [component] max - min (1 if constant), max |value|
  std::vector<double> positions;          // [sample * 3]
  std::vector<double> values;             // [sample * components + c]
  std::vector<std::uint32_t> tet;         // [sample] the tet holding it (the mesh's tet order)
  std::vector<float> bounds;              // [tet * components + c] the tet's bound (field units)
  std::size_t size() const { return tet.size(); }
};

enum class Status : std::uint8_t {
  kOk,            // target reached
  kStoppedEarly,  // mesh valid; no legal collapse was left (topology or error bounds stopped us)
  kInvalidInput,  // mesh untouched; see Report::message
  kOutOfMemory,   // mesh valid, possibly partly simplified
  kCancelled,     // on_progress returned false; mesh valid
  kInternalError,  // a bug or an unexpected exception: mesh valid but unfinished; see Report::message
};
const char* to_string(Status status);

enum class Engine : std::uint8_t {
  kParallel,    // deterministic rounds of independent collapses (engine/rounds.cpp)
  kSequential,  // the reference: one lazy priority queue (engine/sequential.cpp)
};

// Mesh improvement after the collapses (issue #26): the interior vertices of stars with a tet below
// a mean ratio, and those inside flat sheets in an axis plane (in the plane), move to better places
// (engine/optimize/smooth.h), and 2-3 flips and edge removals replace such tets inside one material
// (engine/optimize/swap.h); both say why every guarantee holds. none; light = tets below mean
// ratio 0.4 that the collapses made or moved (input tets they left alone stay), 4 smoothing passes,
// then 3 passes of flips;
// full = 6 rounds of 2 smoothing passes and the flips (engine/optimize/optimize.cpp).
enum class Optimize : std::uint8_t { kNone, kLight, kFull };
const char* to_string(Optimize optimize);  // "none", "light", "full"

// What a field error bound covers (SimplifyOptions::field_bound_mode; engine/guarantees/field_bounds.h):
// kVertices: the original vertices (exact there; between them the simplified field may bend past
// it); kEverywhere: every point of the input domain that the simplified mesh covers (paper 003's
// rule, in 3D), for a price: a boundary that is not flat around a collapse cannot move.
enum class FieldBoundMode : std::uint8_t { kVertices, kEverywhere };
const char* to_string(FieldBoundMode mode);  // "vertices", "everywhere"

// The default geometric tolerance, relative to the bounding box diagonal (SimplifyOptions).
inline constexpr double kDefaultToleranceRel = 0.004;
// SimplifyOptions::size_weight: any negative value means "auto", which is kAutoSizeWeight when no
// field steers the cost (the mesh has none, or all weigh 0) and 0 (the error alone) when one does.
inline constexpr double kSizeWeightAuto = -1.0;
inline constexpr double kAutoSizeWeight = 3e-4;

// Why the kernel refused a collapse placement (engine/kernel/collapse.h has the checks). The values
// index Report::rejected; read the counters with Report::rejected_by.
enum class RejectReason : std::uint8_t {
  kLinkK = 1,      // would change the topology of the mesh itself (its link conditions fail)
  kLinkKtilde,     // would change the topology of a substructure (surfaces, interfaces, polylines)
  kPinned,         // would remove a pinned vertex or move it
  kInversion,      // a tet of the new star would be inverted or degenerate
  kQuality,        // a tet of the new star would fall below min_quality or min_dihedral
  kTolerance,      // a surface or polyline would leave the geometric tolerance
  kFieldError,     // a tet's field error bound would exceed max_field_error(_rel)
};
inline constexpr RejectReason kRejectReasons[] = {RejectReason::kLinkK,     RejectReason::kLinkKtilde,
                                                  RejectReason::kPinned,    RejectReason::kInversion,
                                                  RejectReason::kQuality,   RejectReason::kTolerance,
                                                  RejectReason::kFieldError};
const char* to_string(RejectReason reason);  // "link_K", "link_Ktilde", "pinned", ..., "field_error"

// The units costs are normalised in (engine/cost/cost.h). By default the mesh's own: its bounding box
// (origin = the low corner, diagonal), each field component's min and range over its vertices, and
// its mean tet volume. A caller that simplifies the parts of one mesh separately (topotet::mpi)
// passes the whole mesh's, so that the parts' costs are in the same units and compare.
struct CostUnits {
  double origin[3] = {0.0, 0.0, 0.0};
  double diagonal = 0.0;         // > 0
  double mean_tet_volume = 0.0;  // > 0, mesh units
  std::vector<double> field_min, field_range;  // [field component, field_stride() order]
};

struct SimplifyOptions {
  // Stop when the live vertex count reaches target_vertex_ratio * input vertices, or
  // target_vertices if non-zero (it wins over the ratio).
  double target_vertex_ratio = 0.25;
  std::uint64_t target_vertices = 0;
  // Stop when the cheapest candidate costs more than this (quadric error in normalised units: the
  // bounding box diagonal is 1, every field component spans [0, 1], and each input tet the
  // collapse affects counts as a tet of the mean volume; engine/cost/cost.h); 0 = no limit.
  double max_cost = 0.0;
  // Reject collapses whose new star would have a tet below min(min_quality, worst of the old star)
  // (mean ratio, 1 = regular tet).
  double min_quality = 0.05;
  // Nor a tet with a dihedral angle below min(min_dihedral, the smallest of the old star), in
  // degrees (or above 180 - min_dihedral: the floor is on the angle's sine); 0 = no floor. The
  // optimisation (optimize) keeps it too, so no output tet is below min(min_dihedral, the input's
  // smallest dihedral angle), and where the input is worse its slivers are not made worse. 5 by
  // default (issue #26: slivers cost a solver; measured in docs/performance.md, "The dihedral
  // floor"); where a floor refuses every placement, points at 1/4 and 3/4 of the edge are tried.
  double min_dihedral = 5.0;
  // Weight of the size term in the ranking of collapses (issue #26, item 5; engine/cost/cost.h):
  // every edge ab costs size_weight x 80 / (6 sqrt 2) x |ab|^3 (|ab| relative to the bounding box
  // diagonal) on top of its quadric error, about what a relative field error of sqrt(size_weight)
  // at every input vertex around the edge costs. Short edges go first wherever the error is small,
  // so flat surfaces and smooth regions coarsen evenly instead of being left dense while the
  // interior empties; where the field or the shape needs vertices the quadric still wins. Placements,
  // the kernel's checks and every guarantee are the same; max_cost bounds the ranking cost, size
  // term included. 0 = rank by the error alone (the smallest edges first only among equal errors):
  // the most field accuracy for a vertex count, for visualisation. Negative = auto (the default):
  // kAutoSizeWeight without a field in the cost, 0 with one, because the term evens sizes and
  // removes slivers at no measured cost where only the geometry steers the collapses, but costs
  // field accuracy where a field does (LOX at 10%: field RMS +45% at 1e-4; docs/performance.md
  // "Even sizes"). Must be finite.
  double size_weight = kSizeWeightAuto;
  // Weight of boundary/surface (plane) and polyline (line) quadrics relative to tet quadrics.
  double boundary_weight = 100.0;
  double polyline_weight = 100.0;
  // Weight of each field in the cost, by name; a field not listed weighs 1. The cost adds up, over
  // every component of every field, weight x (error relative to the component's range)^2 at the
  // input vertices the collapse affects (engine/cost/cost.h), so by default every component counts
  // alike whatever its units. With several fields the vertices are shared: raise a field's weight
  // to keep it closer at the others' expense. 0: the field is carried along (interpolated at new
  // vertices) but does not steer the collapses. Weights must be finite and >= 0 and every name a
  // field of the mesh, else the call returns kInvalidInput. Scaling by range, not by standard
  // deviation or not at all: the cost then adds up exactly the errors the reports print (relative
  // to the range); unscaled, the balance would follow the fields' units; by standard deviation it
  // follows their distributions, and moves vertices from the geometry to fields with a few extreme
  // values (docs/performance.md, "Field accuracy", has the measurements).
  std::map<std::string, double> field_weights;
  // Geometric tolerance (like MMG's -hausd): a collapse is refused (reason "tolerance") when the
  // boundary, interface, listed surfaces or polylines around the moved vertex would leave a
  // distance H of the ORIGINAL ones of the same label (ref and material pair). H = tolerance (mesh
  // units) if > 0, else tolerance_rel * bounding box diagonal; both 0 = unchecked. Checked at the
  // new vertex, the centroid and edge midpoints of every new surface triangle, and at the removed
  // vertex (engine/guarantees/surface_tolerance.h says what is guaranteed); measure the result with
  // metrics/surface_distance.h. The reference is the mesh as passed to this call. On by default
  // (kDefaultToleranceRel, chosen in docs/performance.md "Default runs"); tolerance_rel = 0 turns it off.
  double tolerance = 0.0;
  double tolerance_rel = kDefaultToleranceRel;
  // What a run does when the tolerance or the quality floors (min_quality, min_dihedral) would stop
  // it before its target (issue #23: a default that stops short of what the user asked is the wrong
  // default). true (the default): when no legal collapse is left, the limit that holds more of the
  // vertices left (Report::stop's census) is relaxed, H doubled (4H or 8H where a look-ahead finds
  // that 2H would free too few: relax_limits.h) or both floors halved, and the run
  // goes on, as often as needed; it never relaxes the topology, inversion, pinned vertices or a
  // field error limit. A floor never goes below the input's own worst tet (min(asked floor, the
  // input's smallest dihedral angle or mean ratio): Report::min_dihedral_lowest,
  // min_quality_lowest), and the floors relax last: once there, what they hold no longer keeps
  // the tolerance, the feature curves or the flips from relaxing; where nothing else frees the
  // vertices left the run stops and Report::stop says the floors hold them (a solver cannot use
  // an output of slivers; to reach a count whatever the shape, lower the floors themselves:
  // min_dihedral = min_quality = 0). The output then holds the guarantees with the relaxed values, which the
  // Report gives (tolerance, min_quality_used, min_dihedral_used, relaxations): the tolerance proof
  // covers every collapse with the H it was made under, so the whole output is within the last H.
  // false: the limit holds as given and the run stops early (Report::stop says why). `topotet
  // simplify` sets them false for a limit given on its command line (and --hard-limits for both).
  bool relax_tolerance = true;
  bool relax_quality = true;
  // The same for the feature curves (feature_angle), which are judged at the scale of H: where
  // their pinned corners hold more of the vertices left than the tolerance and the floors, once H
  // was relaxed, they are judged again at that H on the simplified surfaces and those lower than
  // it are dropped (Relaxation "features"): generated staircases and voxel creases go, a box's
  // edges and corners stay (the surfaces around dropped curves stay within H).
  bool relax_features = true;
  // Field error bounds (paper 003; engine/guarantees/field_bounds.h says exactly what is bounded): every tet
  // carries, per field component, the largest |original - simplified| over the original vertices
  // that lie in it (exact, kept through every collapse). A collapse that would give a tet a bound
  // above max_field_error (field units, every component) or max_field_error_rel x the component's
  // range (max - min over the input vertices) is refused (reason "field_error"), so the run stops
  // before any bound exceeds the limit; both given = the smaller per component. 0 = no limit.
  // With a limit or track_field_bounds, the report gives the achieved bounds. Off by default: the
  // bounds cost memory and time (docs/performance.md, "Field error bounds"). A mesh without fields has
  // nothing to bound (the limits are then ignored).
  double max_field_error = 0.0;
  double max_field_error_rel = 0.0;
  bool track_field_bounds = false;
  // kEverywhere: each tet's bound holds at every point of it inside the input domain, not only at
  // the original vertices (paper 003 §3.1: at a collapse, the new tets' bounds are the largest
  // old bound plus |old field - new field| over the vertices of the overlay of the old and new
  // stars). Needs a limit (max_field_error or max_field_error_rel): a collapse that would move a
  // boundary that is not flat around it is refused, which only a check can do.
  FieldBoundMode field_bound_mode = FieldBoundMode::kVertices;
  // The bounds are kept: a limit or track_field_bounds (and the mesh has fields).
  bool keeps_field_bounds() const { return max_field_error > 0.0 || max_field_error_rel > 0.0 || track_field_bounds; }
  // Runs in passes (out of core) carry the bounds (FieldBoundSamples above). When set and the
  // bounds are kept: the run starts from these samples (the mesh passed, in its tet order) instead
  // of taking the mesh's vertices as samples at bound 0 (empty samples, components 0: it takes
  // them, as without), moves them out, and leaves the output's here (its tets in output order).
  // Samples that do not fit the mesh (components, a tet out of range, sizes): kInvalidInput, the
  // samples left as given; after an internal error or running out of memory they are lost.
  FieldBoundSamples* field_samples = nullptr;
  Engine engine = Engine::kParallel;
  // Smoothing and flips of badly shaped stars after the collapses (Optimize above).
  // Not run when the collapses are recorded for a hierarchy (simplify_with_hierarchy): its levels
  // are collapse sequences, and a moved vertex would make the finest level differ from the output.
  Optimize optimize = Optimize::kLight;
  int num_threads = 0;  // 0 = the caller's current task arena; the output is identical for every value
  // Parallel rounds: about this fraction of the cheapest proposals is verified and competes in
  // one round, divided by the share of the last round's that passed the verification (at most
  // 16x), so that it is about this fraction of the legal collapses. Smaller means closer to the
  // greedy order and fewer verified proposals that lose to a neighbour (their check is wasted),
  // but more rounds. Measured (1 thread, 10%, one run each on
  // a loaded machine): cube-sphere 1M, 0.01 / 0.015 / 0.03: 1.75 / 1.89 / 2.32 kernel checks per
  // collapse, 8.9 / 8.1 / 9.6 s, field error and dihedral spread within 1%; polycrystal 300k: 17.2
  // / 18.2 / 19.7 checks, 6.0 / 5.2 / 6.6 s; LOX to 2%: 0.01 / 0.03: 7.7 / 9.3 checks.
  double round_fraction = 0.015;
  // Called now and then with the fraction done (0..1). Return false to cancel. May run on any
  // thread, never concurrently with itself.
  std::function<bool(double done_fraction)> on_progress;
  // Sharp features (topotet/features.h): before the first collapse, every surface edge whose two
  // faces turn by more than this angle (degrees, between the face normals) and that is a feature
  // at the scale of the tolerance H (the surface around it departs from a plane by more than H/2:
  // voxel staircases and other creases lower than H are left to the tolerance) becomes a feature
  // curve kept like a listed polyline; its junctions, ends and sharp turns are pinned, its other
  // vertices slide along it. 180 = off. Like Mmg's -ar (45 by default there too).
  double feature_angle = 45.0;
  // Diagnostics (topotet/round_log.h): with a vector here, the parallel engine appends the work and
  // times of every round to it (bench/bench_simplify's scaling model, `topotet simplify -vv`).
  std::vector<RoundStats>* round_log = nullptr;
  // Non-null: normalise costs in these units instead of the mesh's own (CostUnits above); field
  // vectors must have field_stride() entries, else the call returns kInvalidInput.
  const CostUnits* cost_units = nullptr;
  // Runs in passes (out of core, topotet/out_of_core.h: the levels of pieces) keep the collapses'
  // error memory from one pass to the next: each vertex's quadric sums those of the original
  // vertices merged into it, and a pass that rebuilt them from its own, already simplified input
  // would measure its errors against that input, not the original (on the cube-sphere, four
  // passes instead of one cost +41% field RMS). quadrics_out, when set, receives the quadrics of
  // the output's vertices, in its order, the same number of doubles each (left empty when the run
  // fails); quadrics_in, when set, gives those of the mesh passed, in its vertex order, and the
  // run starts from them instead of building them (another count: kInternalError), except for the
  // vertices whose first value is NaN, built from the mesh. Meaningful only with the same
  // cost_units, fields and weights in every pass.
  const std::vector<double>* quadrics_in = nullptr;
  std::vector<double>* quadrics_out = nullptr;
  // Isosurfaces embedded by embed_isosurfaces (topotet/isosurface.h; pass its report's levels):
  // every vertex of a triangle listed with a level's ref keeps that field component at exactly
  // the level, through every collapse (engine/cost/field_pins.h). Their topology and position are
  // kept like any listed surface's; they are not searched for sharp features (feature_angle): their
  // creases are the interpolation's, not a shape to keep. The call returns kInvalidInput when a field or component is
  // unknown, a pinned component is past the 32nd of the interleaved field values, or such a vertex
  // does not have the level's value at the start.
  std::vector<IsoLevel> isosurfaces;
};

// Why a run stopped before its target, and what to change (issue #23): Report::stop. Filled when
// simplify() returns kStoppedEarly with vertices left above the target. A census of the vertices
// left: each is counted under the reason that refuses every collapse that would remove it, the
// furthest any of them gets in the kernel's order (a placement refused by the tolerance passed
// the pinning, inversion, quality and topology checks before it). So each share answers "what
// would have to give for these vertices to go".
struct StopDiagnosis {
  bool is_filled = false;
  std::uint64_t vertices = 0;  // live vertices examined (frozen ones are left out)
  // Vertices by reason. pinned: the vertex is pinned; topology: no edge offers to remove it (it
  // joins or ends curves, order 3) or the link conditions of K or K~ fail on every edge that
  // does; inversion, quality, tolerance, field_error: the best placement fails that check;
  // collapsible: a placement passes now (the run's bans were not lifted for it; rare).
  std::uint64_t topology = 0, pinned = 0, inversion = 0, quality = 0, tolerance = 0, field_error = 0,
                collapsible = 0;
  // Live pinned vertices by why: listed corners (MEDIT Corners, Gmsh points), required vertices,
  // feature corners (detect_features), other (pinned by the caller).
  std::uint64_t pinned_corners = 0, pinned_required = 0, pinned_features = 0, pinned_other = 0;
  // The topology and the vertices the input pins (listed corners, required) alone hold at least
  // as many vertices as the target: no option reaches it from here (the suggestion says so).
  bool beyond_reach = false;
  const char* dominant = "";  // the reason with most vertices: "topology", "pinned", "inversion", ...
  double dominant_share = 0.0;  // its share of the vertices, 0..1
  // One change to try, with its predicted effect, in words (an option of `topotet simplify` and
  // of SimplifyOptions); empty when nothing the options control stands in the way.
  std::string suggestion;
};

// One relaxation of a limit that would have stopped the run before its target
// (SimplifyOptions::relax_tolerance, relax_quality): which, from and to what value, with how many
// vertices left, and the share of them it held (Report::stop's census at that point).
struct Relaxation {
  // "tolerance" (H, mesh units), "min_dihedral" (degrees), "min_quality" (mean ratio) or
  // "features" (the feature edges before and after they were judged at the relaxed H)
  const char* limit = "";
  double from = 0.0, to = 0.0;
  std::uint64_t vertices_left = 0;
  double share = 0.0;
};

struct Report {
  Status status = Status::kOk;
  std::string message;  // empty when status == kOk
  std::uint64_t vertices_before = 0, vertices_after = 0;
  std::uint64_t tets_before = 0, tets_after = 0;
  std::uint64_t collapses = 0;        // accepted collapses
  std::uint64_t evaluations = 0;      // candidate cost evaluations
  std::uint64_t legality_checks = 0;  // calls of the kernel's may_collapse
  // Rejections by reason: read them with rejected_by(RejectReason) (entry 0 is unused).
  std::array<std::uint64_t, 8> rejected{};
  std::uint64_t rejected_by(RejectReason reason) const { return rejected[static_cast<std::size_t>(reason)]; }
  std::uint64_t rounds = 0;  // parallel engine: rounds run
  double seconds = 0.0;
  double max_cost = 0.0;  // largest accepted collapse cost
  double tolerance = 0.0;                // H used (mesh units); 0 = no tolerance check
  // The limits as asked, and as they held for the output (different when the run relaxed them to
  // reach its target: SimplifyOptions::relax_tolerance, relax_quality), and each relaxation.
  double tolerance_asked = 0.0;
  double min_quality_used = 0.0, min_dihedral_used = 0.0;
  // How far the floors may relax (SimplifyOptions::relax_quality): min(asked floor, the input's
  // worst tet), the smallest mean ratio and dihedral angle (degrees) of the input's tets.
  double min_quality_lowest = 0.0, min_dihedral_lowest = 0.0;
  // Whether a floor is still above its lowest (relax_quality may halve it again).
  bool floors_may_relax() const { return min_quality_used > min_quality_lowest || min_dihedral_used > min_dihedral_lowest; }
  std::vector<Relaxation> relaxations;
  double relax_seconds = 0.0;  // the censuses that chose them (included in `seconds`)
  std::uint64_t features_dropped = 0;  // feature edges relaxations dropped (relax_features)
  // Flips made where the collapses stalled with inverted tets holding the most of the vertices
  // left (the flips of the optimisation, on the mesh the collapses left: engine/flip_at_stall.h),
  // and their time (included in `seconds`). Only with optimize != kNone.
  std::uint64_t stall_flips = 0;
  double stall_flip_seconds = 0.0;
  double tolerance_setup_seconds = 0.0;  // building the Embree scene of the original surfaces
  // Wall time per phase (evaluate, select, apply: parallel engine; compact: both, the final
  // renumbering of the live vertices and tets), seconds.
  std::array<double, 4> phase_seconds{};
  double evaluate_seconds() const { return phase_seconds[0]; }
  double select_seconds() const { return phase_seconds[1]; }
  double apply_seconds() const { return phase_seconds[2]; }
  double compact_seconds() const { return phase_seconds[3]; }
  std::uint64_t feature_edges = 0;    // edges detect_features flagged (SimplifyOptions::feature_angle)
  std::uint64_t feature_corners = 0;  // vertices it pinned (feature_turns included)
  std::uint64_t feature_candidates = 0;  // creases sharper than the angle, before the scale test
  std::uint64_t feature_turns = 0;       // inner curve points pinned because the curve turns there
  double feature_scale = 0.0;  // the scale H features were judged at (topotet/features.h), mesh units
  double feature_seconds = 0.0;
  // The run stopped before its target (kStoppedEarly: no legal collapse left) and the tolerance
  // had refused collapses: the tolerance may be what stopped it (the message says so). Whether it
  // was, and not the topology or the features, only a run without it tells (measured on the
  // cube-sphere at 2%: features alone stop at 5.1%, the same as with the tolerance).
  bool tolerance_limited = false;
  // Field error bounds (SimplifyOptions::max_field_error): the largest bound over the output's
  // tets per field component (fields in order, then components; field units), and the largest
  // relative to the component's range. Empty / 0 when the bounds were not kept.
  bool field_bounds = false;
  FieldBoundMode field_bound_mode = FieldBoundMode::kVertices;  // what they cover (SimplifyOptions)
  std::vector<double> field_bound;
  double field_bound_rel = 0.0;
  // Per output tet (the simplified mesh's numbering) and component: [tet * field_stride() + c].
  std::vector<float> tet_field_bound;
  std::uint64_t field_bounds_bytes = 0;  // memory the bounds took (field_bounds.h)
  double field_bounds_setup_seconds = 0.0;
  // The optimisation after the collapses (SimplifyOptions::optimize): vertices moved, passes run,
  // movable vertices of bad stars it started from, face and edge flips made, and its time (included
  // in `seconds`).
  std::uint64_t optimize_moves = 0, optimize_candidates = 0, optimize_flips = 0;
  int optimize_passes = 0;
  double optimize_seconds = 0.0;
  StopDiagnosis stop;  // why a run stopped before its target (above)
};

// Simplifies in place. The mesh is valid on return for every status.
Report simplify(TetMesh& mesh, const SimplifyOptions& options = {}) noexcept;

// The same, and fills `vertex_map` with one entry per vertex of `mesh` as passed: the output
// vertex that input vertex i became or merged into (a solver transfers its fields back with it).
// Every input vertex referenced by a tet maps to a live output vertex; a vertex referenced by no
// tet (dead since build_tet_mesh) maps to kInvalid. The map is identical for every thread count.
// On kInvalidInput the mesh is untouched and the map is the identity.
Report simplify(TetMesh& mesh, const SimplifyOptions& options, std::vector<VertId>& vertex_map) noexcept;

}  // namespace topotet
