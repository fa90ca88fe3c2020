// Per-tet bounds of the field error (paper 003's "maximal deviation" per tet), kept exact at the
// original vertex samples.
//
// What is guaranteed. Every original vertex w (used by a tet of the input) is a *sample* that
// belongs to exactly one live tet T at any time; bound(T, c) >= |f_c(w) - f~_c(w)| for every
// component c and every sample w of T, where f is the original field at w and f~ the simplified
// field: T's linear interpolant at w when w lies in T, else (w outside the simplified mesh:
// the boundary moved) T's value at the point of T closest to w, as metrics/field_error.h
// measures it. The bound is the maximum itself, plus a rounding slack (kSlack below), rounded
// up to float: it is tight, not an estimate. Corollary: an original tet whose four vertices are
// samples of one simplified tet T lies inside T (convexity), f - f~ is affine on it, so the
// error at EVERY point of it is at most bound(T, c). An original tet whose vertices are spread
// over several simplified tets has no such guarantee between its vertices: the simplified field
// bends inside it (measured in tests/unit_field_bounds.cpp and docs/performance.md "Field error bounds").
//
// Why samples by default and not paper 003's accumulation rule: the paper bounds the error over
// the whole tet by adding, at every intersection point of the old and new tets, the interpolants'
// difference to the old bound, so the bounds only grow (each collapse adds to the last: measured,
// the 50k cube-sphere stopped at 67% of its vertices at a 2% limit). Samples are exact where the
// field is defined (the metrics measure at the same points), never accumulate slack, and cost one
// point location per sample of the stencil. The bound everywhere (below) is exact too, for a price.
//
// How they are kept. At a collapse u <- v (collapse.h), the samples of St(u) ∪ St(v) are
// located in the new star (u at p with its new values): first in the tet that held them (most
// samples stay there), else the tet of the new star with the largest smallest barycentric
// coordinate (ties to the smaller tet id: the result does not depend on the order the star was
// gathered in), as metrics/field_error.cpp does. A sample outside every tet of the new star (the
// boundary moved inward past it) goes to the closest tet of the new star (exact point-tet
// distance). The new star's tets get the exact maximum over their samples. Everything read and
// written lies in the collapse's stencil (its tets' sample lists, their samples), so collapses
// with disjoint stencils may run concurrently and the result is the same for every schedule.
//
// Samples outside the mesh. Without a limit (tracking only) a sample outside stays with the tet
// it was closest to when its stencil last collapsed; a later collapse next to it (not through its
// tet), or a concave corner, may make another tet closer, and the measurement (which takes the
// globally closest tet) then interpolates another tet than the bound did: measured on LOX, up to
// 10x the bound at such vertices. So under a limit a collapse that would leave an original vertex
// outside its new star (outside the mesh: the star's outer faces are the only ones that move) is
// refused like one that exceeds the limit: every sample then stays inside the mesh and the bound
// holds at every original vertex. The price: a convex curved boundary cannot retreat past the
// original vertices on it (flat boundaries and concave ones simplify freely).
//
// Everywhere (set_everywhere, SimplifyOptions::field_bound_mode): the bound of a tet holds at
// every point of it inside the input domain, not only at the samples. Every live tet lists the
// ORIGINAL tets it overlaps (at the start, itself). At a collapse, for each new tet T' and each
// original tet τ listed by the old stencil St(u) ∪ St(v), the error f - f~ is affine on the cell
// T' ∩ τ (f is affine on τ, f~ on T'), so its largest |value| there is at a vertex of the cell: a
// corner of τ inside T', a corner of T' inside τ, or a crossing of an edge of one with a face of
// the other (each an intersection of three of the eight face planes). bound(T') = the largest over
// those vertices (and at least the samples' bound), and T' lists the τ whose cell has a vertex.
// The cells tile T' when the stencil's region does not change, so then the bound covers all of T':
// a collapse whose boundary faces through u or v are neither left in place (their moving corner
// already at p) nor all in one plane with p is refused (evaluate() returns false). Unlike paper
// 003's rule (the old bound plus |f~old - f~new| at the overlay of the old and new stars), nothing
// accumulates. Under a limit each cell is first bounded cheaply (the error at τ's four corners,
// and on the box τ's and T''s boxes share: the cell lies in both) and its vertices are found only
// where both exceed the limit; check and commit take the same path, so the bound stored is the
// one the check accepted (a bound everywhere, within the limit; without a limit: the exact
// maximum). With exact_commits() (a run recording a hierarchy, whose levels are chosen by the
// bounds it stores) the commit finds the cells' vertices always: the stored bound is the exact
// maximum, at most the estimate the check accepted. Everything read and written is in the stencil (the lists are per tet), so
// collapses with disjoint stencils still commute. Not with carried samples (out of core: the
// passes do not carry the original tets).
//
// Memory: per tet one list head and one float per component; per original vertex its position,
// its values and a list link: (4 + 4k) bytes per tet + (28 + 8k) bytes per vertex. Carried from
// run to run (FieldBoundSamples, out of core) a sample keeps its tet instead of its link.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "mesh/mesh_model.h"
#include "topotet/simplify.h"

namespace topotet {

// A tet of the new star of a collapse: its id and the local corner that moves to p.
struct BoundStarTet {
  TetId tet;
  std::uint8_t corner;
};

// Per-thread working memory; keeps capacity between calls.
struct FieldBoundsScratch {
  std::vector<BoundStarTet> star;
  std::vector<std::array<glm::dvec3, 4>> corners;   // [star tet] positions, the moving one at p
  std::vector<std::array<const double*, 4>> values;  // [star tet] field values of the corners
  std::vector<std::uint32_t> samples;                // gathered sample ids
  std::vector<std::uint32_t> home;                   // [sample] star index of its tet, or kInvalid
  std::vector<std::uint32_t> lands;                  // [sample] star index where it lands
  std::vector<double> bounds;                        // [star index * k + c]
  // Everywhere (overlay_bounds): the old stencil's tets and their affine barycentric functions.
  struct AffineTet {
    std::array<glm::dvec3, 4> corner;
    std::array<const double*, 4> values;
    std::array<glm::dvec3, 4> gradient;  // lambda_i(x) = dot(gradient[i], x - corner[i + 1 mod 4])
    std::array<double, 4> gradient_length;
    glm::dvec3 lo, hi;                   // bounding box
    glm::dvec3 centre;                   // and a bounding sphere
    double radius;
    TetId tet;
    bool flat;                           // no barycentric functions (zero volume)
  };
  std::vector<AffineTet> old_tets, new_tets, originals;
  std::vector<std::uint32_t> candidates;                  // original tets of the old stencil
  std::vector<std::vector<std::uint32_t>> new_overlaps;   // [star index] original tets it overlaps
  std::vector<std::array<VertId, 3>> faces;  // faces through a moving vertex, sorted corners
};

class FieldBounds {
 public:
  // Takes the samples (every vertex used by a live tet: bound 0 in the first tet of its star).
  // Limits per component: max_abs (field units) and max_rel (times the component's range); 0 =
  // none, both given = the smaller. A mesh without fields has nothing to bound.
  FieldBounds() = default;  // nothing to bound
  FieldBounds(const MeshModel& mesh, double max_abs, double max_rel);
  // Takes carried samples (topotet/simplify.h FieldBoundSamples, their tets in the mesh's current
  // ids, checked by the caller: check_field_samples) and moves them in; their range and magnitude
  // are the whole input's.
  FieldBounds(const MeshModel& mesh, FieldBoundSamples&& samples, double max_abs, double max_rel);
  // Moves the samples and bounds out, the live tets numbered in the order compact() keeps (by
  // id); a sample no tet holds (an unused vertex) is dropped. Leaves this object empty.
  void release(const MeshModel& mesh, FieldBoundSamples& out);

  // The bounds hold everywhere from now on (the header's "Everywhere"): call before the first
  // collapse, on the mesh the samples were taken from. Otherwise at the samples only.
  // Throws std::invalid_argument with carried samples (out of core: the original tets are not
  // carried between passes).
  void set_everywhere(const MeshModel& mesh);
  // For the tests' planted fault only: the overlay then skips the crossings of edges with faces
  // (the corners alone), which under-estimates the bounds (tests/unit_field_bounds.cpp).
  void plant_fault_skip_crossings() { skip_crossings_ = true; }
  // Everywhere under a limit: commits store the exact maxima, not the cheap estimates the check
  // may have accepted (the header's "Everywhere"). For a collapse log: its levels at bounds below
  // the limit select collapses by the bounds stored (an estimate can be many times the maximum:
  // cube-sphere 197k, limit 0.05: the level at 0.005 kept 35,426 of 35,937 vertices on the
  // estimates, 15,828 on the maxima; the run takes 1.24x the time).
  void exact_commits() { exact_commits_ = true; }
  bool everywhere() const { return everywhere_; }
  int components() const { return k_; }
  // Range (max - min over the samples) of component c; 1 for a constant component.
  double range(int c) const { return range_[static_cast<std::size_t>(c)]; }
  double limit(int c) const { return limit_[static_cast<std::size_t>(c)]; }  // +inf = none
  // Some component has a limit: only then can a collapse be refused, and only then does the
  // kernel check placements (without one the bounds are just kept, at each applied collapse).
  bool has_limit() const { return has_limit_; }
  float bound(TetId t, int c) const { return bound_[static_cast<std::size_t>(t) * k_ + c]; }

  // The bounds the new star would have after collapse u <- v: `s.star` (filled by the caller)
  // lists its tets with their moving corner, `removed` the tets of St(uv). `fields_at_p` are u's
  // new values (nullptr: u's current values). Pure (reads the mesh and the bounds). With
  // `stop_at_limit`, returns false as soon as one bound would exceed its limit or one sample would
  // end up outside the new star (everywhere: or the stencil's boundary would move); otherwise
  // always true. The result is left in `s` for commit().
  bool evaluate(const MeshModel& mesh, std::span<const TetId> removed, VertId u, const glm::dvec3& p,
                const double* fields_at_p, FieldBoundsScratch& s, bool stop_at_limit) const;

  // Stores what the last full evaluate() (stop_at_limit = false) left in `s`: the samples'
  // new tets and the star's bounds. Writes only the lists and bounds of the stencil's tets.
  // Returns the largest bound of the new star relative to its component's range (over every
  // component): the collapse's error bound, for a hierarchy of collapses.
  float commit(std::span<const TetId> removed, FieldBoundsScratch& s);

  // Every live tet's bounds, the tets in the order compact() keeps (by id): [tet * k + c].
  std::vector<float> live_bounds(const MeshModel& mesh) const;
  // Largest bound over the live tets, per component (field units), and relative to the range.
  std::vector<double> max_bounds(const MeshModel& mesh) const;
  double max_bound_rel(const MeshModel& mesh) const;

  // Which tet holds each sample, for the tests: samples of tet t.
  template <class F>
  void for_each_sample(TetId t, F&& f) const {
    for (std::uint32_t w = head_[t]; w != kInvalid; w = next_[w]) f(w, sample_position(w), &sample_values_[w * k_]);
  }

  std::size_t memory_bytes() const;

 private:
  void set_limits(double max_abs, double max_rel);  // from range_ and magnitude_
  // Everywhere: raises s.bounds to the overlay's bounds (header); false when the stencil's boundary
  // would move (with stop_at_limit, also when a bound would exceed its limit).
  bool overlay_bounds(const MeshModel& mesh, std::span<const TetId> removed, const glm::dvec3& p,
                      FieldBoundsScratch& s, bool stop_at_limit) const;
  glm::dvec3 sample_position(std::uint32_t w) const {
    return {sample_xyz_[3 * std::size_t{w}], sample_xyz_[3 * std::size_t{w} + 1], sample_xyz_[3 * std::size_t{w} + 2]};
  }

  int k_ = 0;
  bool has_limit_ = false;
  bool everywhere_ = false;
  bool carried_ = false;
  bool skip_crossings_ = false;
  bool exact_commits_ = false;  // plant_fault_skip_crossings  // samples from an earlier pass: their tets are not the original ones
  // Everywhere: the original tets (sample ids), and per live tet the original tets it overlaps
  // (a superset: a touching one may be listed). Each tet's list is written by its own stencil's
  // collapse only.
  std::vector<std::array<std::uint32_t, 4>> originals_;
  std::vector<std::vector<std::uint32_t>> overlaps_;
  std::size_t overlaps_bytes() const;
  std::vector<double> range_, magnitude_, limit_, slack_;  // [component]
  std::vector<float> bound_;                     // [tet * k + c]
  std::vector<std::uint32_t> head_;              // [tet] first sample, kInvalid = none
  std::vector<std::uint32_t> next_;              // [sample] next sample of the same tet
  std::vector<double> sample_xyz_;               // [sample * 3] original position
  std::vector<double> sample_values_;            // [sample * k + c] original values
};

}  // namespace topotet
