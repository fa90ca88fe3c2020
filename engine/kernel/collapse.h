// The collapse kernel: "may edge uv collapse to position p?" and "collapse it".
//
//      before                         after (v merged into u, u moved to p)
//   x-----u-----y                   x-----p-----y
//    \   / \   /                     \   |   /
//     \ /   \ /          ==>          \  |  /
//      v-----z                          \ | /
//                                         z
// The tets of St(uv) disappear; every other tet of St(v) has v renamed to u. Faces and edges
// that were on a substructure keep their flags and refs, renamed; faces that merge (uxy and vxy of
// a removed tet uvxy) keep the union of their flags.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "guarantees/field_bounds.h"
#include "kernel/link_condition.h"
#include "guarantees/surface_coverage.h"
#include "guarantees/surface_tolerance.h"
#include "mesh/dihedral.h"
#include "mesh/mesh_model.h"
#include "mesh/moved_corner.h"

namespace topotet {

enum class CollapseReason : std::uint8_t {
  kOk,
  kLinkK,       // would change the topology of the mesh itself (its link conditions fail)
  kLinkKtilde,  // would change the topology of a substructure (the extended complex's conditions fail)
  kPinned,      // v is pinned (it would disappear) or u is pinned and p is not u's position
  kInversion,   // a tet of the new star would be inverted or degenerate
  kQuality,     // a tet of the new star would fall below the quality floor
  kTolerance,   // a surface or polyline around p would leave the tolerance (surface_tolerance.h)
  kFieldError,  // a tet of the new star would exceed the field error limit (field_bounds.h)
};
inline constexpr int kCollapseReasonCount = 8;
const char* to_string(CollapseReason reason);

struct CollapseOptions {
  // The worst mean ratio of the new star may not fall below min(quality_floor, worst of the old).
  double quality_floor = 0.05;
  // Nor may its smallest dihedral angle fall below min(floor, the smallest of the old star's)
  // (mesh/dihedral.h; inactive by default).
  DihedralFloor dihedral_floor;
  // Optional geometric tolerance (surface_tolerance.h): with a reference, the surfaces and
  // polylines around p must stay within `tolerance` of the original ones. Checked last; the
  // reference is immutable, so the check is thread-safe.
  const SurfaceReference* surfaces = nullptr;
  double tolerance = 0.0;
  // With the reference, the original surfaces' items (surface_coverage.h): a placement must find
  // a new face for each item it moves. Read by the check, updated by collapse(), which the
  // engines give this same pointer.
  SurfaceCoverage* coverage = nullptr;
  // false: the tolerance check only applies its cheap rule (an interior vertex may not absorb a
  // surface vertex) and leaves the proof and the coverage to a later full check. The parallel
  // engine verifies its candidates so and proves only the round's winners (rounds.cpp): most
  // verified candidates lose their reservation and are verified again, and the proof is the
  // dearest check of a surface collapse.
  bool prove_tolerance = true;
  // Screen placements with a few point queries before the proof (placement_within_tolerance):
  // worth it where most placements that reach the proof fail it, not where most pass (a winner's
  // proof after a verification without it).
  bool screen_tolerance = true;
  // With prove_tolerance: the screen and the reverse check only (placement_within_tolerance
  // without its proofs), no coverage: refuses most of what the proof refuses, at a few point
  // queries. A placement that passes is not proved: the parallel engine verifies so where the
  // tolerance binds and proves the round's winners (cost/proposals.h).
  bool screen_only = false;
  // Optional field error bounds (field_bounds.h): with them, a placement whose new star would have
  // a bound above its limit is refused (kFieldError). Checked after everything else (it locates
  // every sample of the stencil), and only when a limit is set; read-only here, updated by
  // collapse().
  const FieldBounds* field_bounds = nullptr;
};

// Per-thread scratch; keeps capacity between calls so that steady-state calls do not allocate.
struct CollapseScratch {
  std::vector<TetId> star_u, star_v, star_uv;  // sorted tet ids
  // first_acceptable gathers a star only when it needs it: an endpoint placement moves only the
  // other end's star, and most of them fail there. gather_stars (and a successful
  // first_acceptable) leaves both.
  bool have_u = false, have_v = false;
  // The tets that survive the collapse (St(u) ∪ St(v) minus St(uv)) with the corner that moves to
  // p (where u or v sits): the same for both directions of the edge and every placement, so the
  // geometric tests of all placements share it. Appended star by star as they are gathered.
  struct NewStarTet {
    TetId tet;
    std::uint8_t corner;  // local index of the corner that moves to p
    VertId at;            // the vertex there now (u or v)
  };
  std::vector<NewStarTet> new_star;
  // The same tets seen from the moving corner, with everything that does not depend on p
  // precomputed (mesh/moved_corner.h): a placement then costs ~30 flops per tet.
  // Filled on demand by the geometric test (moved[i] is ready when prepared[i]; gather_stars resets).
  std::vector<MovedCorner> moved;
  std::vector<std::uint8_t> prepared;
  LinkScratch link;
  // Flagged faces and edges through u after the collapse (v renamed to u), keyed by their other
  // vertices (a face by its two other vertices packed low/high).
  struct FlaggedFace {
    std::uint64_t key;
    std::int32_t ref;
    bool operator<(const FlaggedFace& o) const { return key != o.key ? key < o.key : ref > o.ref; }
  };
  struct FlaggedEdge {
    VertId key;
    std::int32_t ref;
    bool ridge;
    bool operator<(const FlaggedEdge& o) const { return key != o.key ? key < o.key : ref > o.ref; }
  };
  std::vector<FlaggedFace> faces;
  std::vector<FlaggedEdge> edges;
  std::vector<TetId> merged;
  std::vector<VertId> link_vertices;  // vertices of St(uv) other than u, v
  SurfaceStencil surface;  // the tolerance check's faces and edges at u, v
  CoverageScratch coverage;
  // The placement the last successful coverage check was for (u = kInvalid: none): collapse()
  // commits that result instead of computing it again when it applies the same placement. Valid
  // only while the stencil is unchanged: the sequential engine applies right after the check, and
  // the parallel engine clears it at every round (rounds.cpp), whose winners were checked in it.
  struct CoverageFor {
    VertId u = kInvalid, v = kInvalid;
    glm::dvec3 p{0.0};
  } coverage_for;
  FieldBoundsScratch bounds;
  // Why the last first_acceptable refused every placement, when the refusal is bound to repeat:
  // each placement tried was pinned, or refused by one of `witness` (at most two tets) alone: the
  // tet inverts, or falls below a quality or dihedral floor that the old star was above (then the
  // floor, not the old star, set the bar). Either depends only on the three corners of that tet
  // that stay and on the placement, so the same placements of the same edge are refused again
  // while those tets keep their corners (for a floor: while no tet worse than the witness enters
  // the stars, which collapses make rare; first_acceptable says why). The engine keeps such an
  // edge banned through collapses that do not touch its witnesses (cost/proposals.h).
  // certified = false: some placement was refused for another reason (links, tolerance, field
  // error, the old star's own worst tet), or by more than two tets.
  struct Refusal {
    bool certified = false;
    std::uint8_t count = 0;
    std::array<TetId, 2> witness{kInvalid, kInvalid};
  } refusal;
};

// One way to collapse an edge: v merges into u, which moves to p with field values `fields`
// (field_stride() of them; nullptr: u keeps its values). Only the field error check reads them.
// A quality fallback (CollapseCandidate::fallback) is tried only when a placement before it in the
// same call was refused by a quality floor; otherwise it is skipped, and counts as no rejection.
struct Placement {
  VertId u, v;
  glm::dvec3 p;
  const double* fields = nullptr;
  bool quality_fallback = false;
};

// Fills scratch.star_u, star_v, star_uv. Returns false if uv is not an edge.
bool gather_stars(const MeshModel& mesh, VertId u, VertId v, CollapseScratch& scratch);

// May v be merged into u, with u moved to p? Pure: reads the mesh only. Checks, cheapest first:
// pinned, inversion and quality (one pass over the tets that move), the link conditions of K and
// K~, then the tolerance (options.surfaces). When both inversion and a link condition fail, the
// reason is inversion.
// On success scratch.star_u/star_v/star_uv hold the stars for collapse().
CollapseReason may_collapse(const MeshModel& mesh, VertId u, VertId v, const glm::dvec3& p,
                            const CollapseOptions& options, CollapseScratch& scratch);

// Tries `count` placements of ONE edge in order and returns the index of the first acceptable
// one, or -1. The link conditions do not depend on the placement, so they are evaluated at most
// once. Each rejected placement adds one to (*rejected)[reason] when `rejected` is given.
// With check_topology = false the link conditions are skipped: a cheap geometric pre-filter for
// callers that re-check the chosen placement in full before applying it.
int first_acceptable(const MeshModel& mesh, const Placement* placements, int count, const CollapseOptions& options,
                     CollapseScratch& scratch, std::array<std::uint64_t, kCollapseReasonCount>* rejected,
                     bool check_topology = true);

// Applies the collapse (the caller has checked may_collapse with the same scratch stars). Writes
// only the tets of St(u) ∪ St(v), the vertices u and v, and the incidence chains of the vertices of
// St(uv), so collapses with disjoint stencils may run concurrently. `fields_at_p` gives u's new
// field values (field_stride() doubles); nullptr keeps u's values.
// Needs mesh.refs_table headroom for |St(u)| + |St(v)| new slots (see reserve_refs_headroom),
// taken through `refs_used` with an atomic increment.
// With `bounds`, the samples of the stencil move to the new star and its tets get their new
// bounds (inside the stencil too); returns the largest of them relative to its component's range
// (FieldBounds::commit), 0 without bounds.
// With `coverage`, the original surface items held by faces through u or v move to the new faces
// (surface_coverage.h); the check must have accepted the placement with the same coverage.
float collapse(MeshModel& mesh, VertId u, VertId v, const glm::dvec3& p, const double* fields_at_p,
               CollapseScratch& scratch, std::uint32_t& refs_used, FieldBounds* bounds = nullptr,
               SurfaceCoverage* coverage = nullptr);

// Grows mesh.refs_table so that `count` more slots can be taken after `refs_used`.
void reserve_refs_headroom(MeshModel& mesh, std::uint32_t refs_used, std::size_t count);

}  // namespace topotet
