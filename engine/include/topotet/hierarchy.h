// The collapse hierarchy: one simplification run, recorded, serves every level of detail.
//
//   topotet::Hierarchy h;
//   topotet::Report report = topotet::simplify_with_hierarchy(mesh, options, h);  // mesh -> base
//   topotet::write_hierarchy("h.tth", h);
//   std::vector<std::uint8_t> applied = topotet::select_by_error(h, 1e-3);       // a uniform level
//   topotet::MeshData level = topotet::extract(h, applied);
//
// What is recorded. A collapse u <- v kills the tets of St(uv), renames v to u in the other tets
// of St(v) and moves u (position and field values). No tet is ever created, so a level is fully
// described by WHICH collapses are applied: a tet of the original mesh is alive iff its vertices,
// each replaced by its representative (follow "v merged into u" through the applied collapses),
// are still four distinct vertices, and a vertex sits where the last applied collapse that moved
// it put it. Records use the ids of `Hierarchy::original` (the mesh as simplify received it).
//
// Dependencies (paper 000 §5.2's DAG, as in the MT library). A collapse replaces the patch
// St(u) ∪ St(v) (the tets it reads) by the new star (those tets, changed). Collapse i depends on
// the collapses that last changed a tet of its patch. Applying any DOWNWARD-CLOSED set of
// collapses (every parent of a member is a member) in recording order gives each member exactly
// the patch and the positions the engine verified (argument in engine/hierarchy/hierarchy_log.cpp; checked with
// the kernel itself in tests/property_hierarchy.cpp), and the kernel's checks (link conditions,
// orientation, quality, tolerance) read nothing else, so every such set gives a valid mesh with
// the topology of the original, substructures included.
//
// The parallel engine records its rounds winner by winner (their stencils are disjoint, so any
// order within a round is a valid sequence); the records are identical for every thread count.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "topotet/mesh_data.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"

namespace topotet {

struct Hierarchy {
  // The mesh the records refer to: TetMesh::to_mesh_data() of the mesh simplify_with_hierarchy
  // received. Extracting with no collapse applied gives it back exactly.
  MeshData original;
  int field_stride = 0;  // doubles per vertex in the field arrays below (sum of the components)

  // One entry per collapse, in recording order (a valid application order).
  std::vector<VertId> u, v;                 // v merges into u
  std::vector<std::array<double, 3>> u_before, u_after;  // u's position before and after
  std::vector<std::array<double, 3>> v_position;         // where v was when it was removed
  std::vector<double> fields_before, fields_after;  // u's field values, [i * field_stride + k]
  std::vector<double> cost;                 // the collapse's cost (SimplifyOptions::max_cost units)
  // A monotone error value for uniform levels, so every prefix of the records is "all collapses
  // with error <= e" for some e: the running maximum of `error_bound` up to and including
  // collapse i when the bounds were tracked, else the running maximum of `cost`.
  std::vector<double> error;
  // Per collapse: the largest field error bound of the tets of its new star, relative to each
  // component's range (engine/guarantees/field_bounds.h: exact at the original vertices each tet holds). Any
  // mesh extracted from a closed set of collapses has every tet's bound <= the largest error_bound
  // of the applied collapses (a tet's bound was set by the last collapse that changed it, on the
  // same stencil). NaN when the run did not track bounds (SimplifyOptions::track_field_bounds, a
  // field error limit, or no fields).
  std::vector<float> error_bound;
  // Dependencies as CSR: the parents of collapse i are parents[parent_offsets[i] ..
  // parent_offsets[i + 1]), each < i, sorted, distinct.
  std::vector<std::uint32_t> parent_offsets{0};
  std::vector<std::uint32_t> parents;

  std::size_t collapse_count() const { return u.size(); }
};

// simplify() that also records every accepted collapse into `hierarchy` (cleared first). The mesh
// ends as simplify() leaves it (the base mesh). Same options, same result, same report.
Report simplify_with_hierarchy(TetMesh& mesh, const SimplifyOptions& options, Hierarchy& hierarchy) noexcept;

// Checks the internal consistency of a hierarchy (array sizes, id ranges, parents before their
// child, each vertex removed at most once); throws InputError naming `label` and the first fault.
void validate_hierarchy(const Hierarchy& hierarchy, const std::string& label);

// ---- selections: which collapses are applied (one byte per collapse, 1 = applied) ----
// Every selection returned is downward closed, so extract() gives a valid mesh.

// The first `count` collapses (a uniform level).
std::vector<std::uint8_t> select_prefix(const Hierarchy& hierarchy, std::size_t count);
// The longest prefix leaving at least `vertices` vertices (the whole hierarchy if fewer).
std::size_t prefix_for_vertices(const Hierarchy& hierarchy, std::size_t vertices);
// The longest prefix whose error (Hierarchy::error) is <= max_error.
std::size_t prefix_for_error(const Hierarchy& hierarchy, double max_error);
// A collapse's own error: its error_bound when the hierarchy has bounds, else its cost.
double collapse_error(const Hierarchy& hierarchy, std::size_t i);
// Uniform level by error: every collapse whose own error is <= max_error and whose parents are all
// applied (the largest closed subset). With bounds, every tet of the level then has a field error
// bound <= max_error; it applies at least the collapses of prefix_for_error's prefix, and usually
// many more (the collapses' order follows their cost, not their bound).
std::vector<std::uint8_t> select_error(const Hierarchy& hierarchy, double max_error);

// A volume of interest: a box or a sphere.
struct Voi {
  enum class Kind : std::uint8_t { kBox, kSphere } kind = Kind::kBox;
  std::array<double, 3> lo{}, hi{};  // box
  std::array<double, 3> centre{};    // sphere
  double radius = 0.0;
  bool contains(const std::array<double, 3>& p) const;
  Voi moved(const std::array<double, 3>& by) const;
  double size() const;  // box: its diagonal; sphere: its diameter
};
// "box:x0,y0,z0,x1,y1,z1" or "sphere:x,y,z,r". Throws InputError with the text on bad syntax.
Voi parse_voi(const std::string& text);

// Selective level: collapse i is wanted iff its own error (collapse_error) is <= inside_error when it touches the VOI
// (u before, v, or u after inside it), else <= outside_error. The wanted set is rarely closed (a
// coarse collapse outside may depend on a fine one inside), and `closure` decides which side
// gives way:
//  - kKeepFine: the largest closed subset of the wanted set: i is applied iff wanted and all its
//    parents are applied. No collapse above inside_error is ever applied in the VOI (it stays
//    fine), and the coarsening outside stops where it would need one.
//  - kReachCoarse: the smallest closed superset: the wanted collapses and all their ancestors.
//    Everything outside reaches outside_error, and the VOI gets the collapses that needs.
// Either way the transition conforms by construction (the set is closed).
enum class VoiClosure : std::uint8_t { kKeepFine, kReachCoarse };
std::vector<std::uint8_t> select_voi(const Hierarchy& hierarchy, const Voi& voi, double inside_error,
                                     double outside_error, VoiClosure closure = VoiClosure::kKeepFine);

// The mesh after applying the selected collapses (which must be downward closed; checked, throws
// InputError otherwise). Vertices are the original's that remain, in original order; tets the
// original's that remain, in original order; listed triangles and segments are renamed, those
// that became degenerate dropped, repeats kept once (first occurrence); fields, refs, corners,
// required vertices, ridges and group names carried.
MeshData extract(const Hierarchy& hierarchy, const std::vector<std::uint8_t>& applied);

// Incremental extraction for a viewer: keeps the current selection and the vertex positions and
// fields it gives; moving to another selection undoes and applies only the difference (undo in
// decreasing order, apply in increasing order, so the state is always that of a downward closed
// set).
class HierarchyCursor {
 public:
  explicit HierarchyCursor(const Hierarchy& hierarchy);  // nothing applied: the original mesh
  // Returns how many collapses were undone plus applied.
  std::size_t move_to(const std::vector<std::uint8_t>& applied);
  const std::vector<std::uint8_t>& applied() const { return applied_; }
  MeshData mesh() const;  // the current level, as extract() gives it

 private:
  const Hierarchy& h_;
  std::vector<std::uint8_t> applied_;
  std::vector<std::array<double, 3>> positions_;  // [original vertex]
  std::vector<double> fields_;         // [original vertex * field_stride + k]
};

// ---- the .tth file (docs/formats.md) ----
void write_hierarchy(const std::string& path, const Hierarchy& hierarchy);
// Throws InputError naming the file and the byte offset of the fault on a bad or truncated file.
Hierarchy read_hierarchy(const std::string& path);
// Bytes of the file's collapse section (the records and dependencies; the rest is the original mesh).
std::uint64_t hierarchy_collapse_bytes(const Hierarchy& hierarchy);

}  // namespace topotet
