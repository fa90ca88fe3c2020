// Face and edge swaps (see swap.h).
#include "optimize/swap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <functional>
#include <queue>
#include <tuple>
#include <vector>

#include <glm/common.hpp>

#include "mesh/moved_corner.h"
#include "mesh/orient.h"
#include "optimize/input_samples.h"
#include "parallel/for_range.h"
#include "parallel/scratch.h"

namespace topotet {

namespace {

using FaceKey = std::array<VertId, 3>;
using EdgeKey = std::array<VertId, 2>;

FaceKey face_key(VertId a, VertId b, VertId c) {
  FaceKey k{a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}
EdgeKey edge_key(VertId a, VertId b) { return a < b ? EdgeKey{a, b} : EdgeKey{b, a}; }

// The flagged faces and edges of the tets a flip replaces, with their refs: every one of them is a
// face or an edge of the new tets (swap.h), which take them back by their vertices.
struct RegionFlags {
  std::vector<std::pair<FaceKey, std::int32_t>> faces;
  std::vector<std::tuple<EdgeKey, std::int32_t, bool>> edges;  // key, ref, MEDIT ridge

  void clear() {
    faces.clear();
    edges.clear();
  }
  void add(const MeshModel& m, TetId t) {
    const TetFlags fl = m.flags[t];
    if (!(fl & (tet_flag::kSurfaceFaces | tet_flag::kPolylineEdges))) return;
    const SubstructureRefs& r = m.refs_table[m.tet_refs_slot[t]];
    const auto& tv = m.tets[t];
    for (int f = 0; f < 4; ++f)
      if (is_surface_face(fl, f))
        faces.emplace_back(face_key(tv[kTetFaces[f][0]], tv[kTetFaces[f][1]], tv[kTetFaces[f][2]]), r.face[f]);
    for (int e = 0; e < 6; ++e)
      if (is_polyline_edge(fl, e))
        edges.emplace_back(edge_key(tv[kTetEdges[e][0]], tv[kTetEdges[e][1]]), r.edge[e], (r.ridge_mask >> e) & 1u);
  }
};

// Writes tet v (positively oriented) into `slot` (an old tet's, or one past the end: appended),
// with the flags and refs its faces and edges had in the region.
void write_tet(MeshModel& m, TetId slot, const std::array<VertId, 4>& v, std::int32_t material, const RegionFlags& region) {
  TetFlags fl = 0;
  SubstructureRefs refs{};
  for (int f = 0; f < 4; ++f) {
    const FaceKey k = face_key(v[kTetFaces[f][0]], v[kTetFaces[f][1]], v[kTetFaces[f][2]]);
    for (const auto& [key, ref] : region.faces)
      if (key == k) {
        fl |= static_cast<TetFlags>(1u << (tet_flag::kSurfaceFaceShift + f));
        refs.face[static_cast<std::size_t>(f)] = ref;
        break;
      }
  }
  for (int e = 0; e < 6; ++e) {
    const EdgeKey k = edge_key(v[kTetEdges[e][0]], v[kTetEdges[e][1]]);
    for (const auto& [key, ref, ridge] : region.edges)
      if (key == k) {
        fl |= static_cast<TetFlags>(1u << (tet_flag::kPolylineEdgeShift + e));
        refs.edge[static_cast<std::size_t>(e)] = ref;
        if (ridge) refs.ridge_mask |= static_cast<std::uint8_t>(1u << e);
        break;
      }
  }
  if (slot == m.tets.size()) {
    m.tets.push_back(v);
    m.material.push_back(material);
    m.flags.push_back(fl);
    m.tet_refs_slot.push_back(kInvalid);
  } else {
    m.tets[slot] = v;
    m.material[slot] = material;
    m.flags[slot] = fl;
  }
  std::uint32_t& refs_slot = m.tet_refs_slot[slot];
  if (fl == 0) {
    refs_slot = kInvalid;  // an old slot stays unused until compact() packs the table
  } else if (refs_slot != kInvalid) {
    m.refs_table[refs_slot] = refs;  // the old tet's own record: it is gone
  } else {
    refs_slot = static_cast<std::uint32_t>(m.refs_table.size());
    m.refs_table.push_back(refs);
  }
}

bool positive(const MeshModel& m, const std::array<VertId, 4>& v) {
  const auto& P = m.positions;
  return orient3d_sign(P[v[0]], P[v[1]], P[v[2]], P[v[3]]) > 0;
}

double quality(const MeshModel& m, const std::array<VertId, 4>& v) {
  const auto& P = m.positions;
  return mean_ratio_cubed(P[v[0]], P[v[1]], P[v[2]], P[v[3]]);
}

bool contains(const std::array<VertId, 4>& tv, VertId x) {
  return tv[0] == x || tv[1] == x || tv[2] == x || tv[3] == x;
}

// Edge removal handles rings of up to this many tets (Catalan(5) = 42 triangulations of the ring's
// heptagon, searched by dynamic programming): longer rings are rare around the bad tets.
constexpr int kMaxRing = 7;

// One flip: the tets it replaces and the tets it makes (edge removal n -> 2n - 4, or 2 -> 3).
struct Flip {
  std::array<TetId, kMaxRing> old{};
  int old_count = 0;
  std::array<std::array<VertId, 4>, 2 * kMaxRing - 4> made{};
  int made_count = 0;
  double quality = 0.0;  // the worst (mean ratio)^3 of the tets it makes
};

// Applies a flip: writes the new tets into the old slots (appending the extra ones, killing the
// unused ones), with the flags of the region, and stamps every vertex of the region with `batch`.
void apply_flip(MeshModel& m, const Flip& f, RegionFlags& region, std::vector<std::uint32_t>& flipped_in,
                std::uint32_t batch) {
  region.clear();
  const std::int32_t material = m.material[f.old[0]];
  for (int i = 0; i < f.old_count; ++i) {
    region.add(m, f.old[static_cast<std::size_t>(i)]);
    for (VertId x : m.tets[f.old[static_cast<std::size_t>(i)]]) {
      flipped_in[x] = batch;
      m.vertex_states[x] |= vertex_state::kReshaped;  // the region's new tets are not the input's
    }
  }
  for (int i = 0; i < f.made_count; ++i) {
    const TetId slot = i < f.old_count ? f.old[static_cast<std::size_t>(i)] : static_cast<TetId>(m.tets.size());
    write_tet(m, slot, f.made[static_cast<std::size_t>(i)], material, region);
  }
  for (int i = f.made_count; i < f.old_count; ++i) {
    const TetId t = f.old[static_cast<std::size_t>(i)];
    m.flags[t] = tet_flag::kDead;
    m.tet_refs_slot[t] = kInvalid;
  }
}

// The tets of each vertex, kept exact through every flip (the mesh's own incidence has no room for
// a star that grows), so that one pass can flip next to an earlier flip.
using Stars = std::vector<std::vector<TetId>>;

// Finds the best flip that removes a tet. Reads the mesh and the stars only.
class FlipFinder {
 public:
  FlipFinder(const MeshModel& m, const Stars& stars, const InputSamples* samples, const SwapOptions& options)
      : m_(m), stars_(stars), samples_(samples), growth_(options.max_sample_error_growth), floor_(options.dihedral_floor) {
    // Each field component's range over the live vertices: the unit of max_field_change.
    const int k = m.field_stride();
    std::vector<double> lo(static_cast<std::size_t>(k), std::numeric_limits<double>::infinity());
    std::vector<double> hi(static_cast<std::size_t>(k), -std::numeric_limits<double>::infinity());
    for (VertId v = 0; v < m.vertex_capacity(); ++v) {
      if (m.is_dead_vertex(v)) continue;
      for (int c = 0; c < k; ++c) {
        const double f = m.field_values[static_cast<std::size_t>(v) * k + c];
        lo[static_cast<std::size_t>(c)] = std::min(lo[static_cast<std::size_t>(c)], f);
        hi[static_cast<std::size_t>(c)] = std::max(hi[static_cast<std::size_t>(c)], f);
      }
    }
    for (int c = 0; c < k; ++c) {
      const double range = hi[static_cast<std::size_t>(c)] - lo[static_cast<std::size_t>(c)];
      allowed_.push_back(range > 0.0 ? options.max_field_change * range : 0.0);
    }
  }

  // The best flip that removes tet t (worst quality q), if one beats q.
  bool best_flip(TetId t, double q, Flip& best) {
    const auto& tv = m_.tets[t];
    for (VertId x : tv)
      if (m_.is_frozen(x)) return false;
    // Every flip that lifts the worst tet, then the field's test from the best down: the test
    // costs more than the search, and the best usually passes.
    int count = 0;
    for (int e = 0; e < 6; ++e)
      if (edge_flip(t, tv[kTetEdges[e][0]], tv[kTetEdges[e][1]], q, candidates_[static_cast<std::size_t>(count)])) ++count;
    for (int k = 0; k < 4; ++k)
      if (face_flip(t, k, q, candidates_[static_cast<std::size_t>(count)])) ++count;
    std::array<int, 10> order{};
    for (int i = 0; i < count; ++i) order[static_cast<std::size_t>(i)] = i;
    // Stable: equal qualities keep the search's order (edges, then faces), as before.
    std::stable_sort(order.begin(), order.begin() + count, [&](int a, int b) {
      return candidates_[static_cast<std::size_t>(a)].quality > candidates_[static_cast<std::size_t>(b)].quality;
    });
    for (int i = 0; i < count; ++i) {
      const Flip& f = candidates_[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])];
      if (dihedral_kept(f) && field_kept(f)) {
        best = f;
        return true;
      }
    }
    return false;
  }

 private:
  // The smallest sin^2 of a dihedral angle over tets the floor's screen does not clear (1 if none).
  double smallest_dihedral(const std::array<VertId, 4>& tv) const {
    const auto& P = m_.positions;
    if (std::fabs(quality(m_, tv)) >= floor_.screen_q3) return 1.0;
    return min_dihedral_sine_sq(P[tv[0]], P[tv[1]], P[tv[2]], P[tv[3]]);
  }

  // Does the flip keep the dihedral floor: the made tets' smallest angle at least min(floor, the
  // smallest of the tets it replaces)?
  bool dihedral_kept(const Flip& f) const {
    if (!floor_.active()) return true;
    double made = 1.0;
    for (int i = 0; i < f.made_count; ++i) made = std::min(made, smallest_dihedral(f.made[static_cast<std::size_t>(i)]));
    if (made >= floor_.sine_sq) return true;
    double old = 1.0;
    for (int i = 0; i < f.old_count; ++i) old = std::min(old, smallest_dihedral(m_.tets[f.old[static_cast<std::size_t>(i)]]));
    return made >= std::min(floor_.sine_sq, old);
  }

  // Is the flip's change of the interpolated field acceptable? Two tests, component by component:
  // - at the input's vertices inside the region (InputSamples: where the output's field error is
  //   measured), the sum of the squared errors (in units of each component's range) must not grow
  //   by more than SwapOptions::max_sample_error_growth;
  // - everywhere, the change is at most SwapOptions::max_field_change of the range. The difference
  //   of the old and new interpolants is piecewise linear over their common refinement, largest
  //   where their edges cross the other's faces; it is measured at the centroids and edge midpoints
  //   of the old and the new tets (each located in the other triangulation), which include the
  //   midpoint of the edge a flip removes or makes and the centroid of the face it removes or makes.
  //   This bounds the change where no input vertex is left to say (a region the collapses did not
  //   thin out, or one between the samples).
  bool field_kept(const Flip& f) {
    const int k = m_.field_stride();
    if (k == 0) return true;
    before_.clear();
    after_.clear();
    for (int i = 0; i < f.old_count; ++i) before_.push_back(field_tet(m_, m_.tets[f.old[static_cast<std::size_t>(i)]], k));
    for (int i = 0; i < f.made_count; ++i) after_.push_back(field_tet(m_, f.made[static_cast<std::size_t>(i)], k));
    if (!change_bounded(before_, after_, k) || !change_bounded(after_, before_, k)) return false;
    if (samples_ == nullptr) return true;
    samples_->inside(m_, before_, kInvalid, inside_);
    return samples_->errors_after(m_, after_, inside_) <= inside_.error * (1.0 + growth_) + kRoundingError;
  }

  // The change at the centroid, the edge midpoints and the face centroids of each tet of `from`
  // (whose barycentric coordinates there are known), located in `to`.
  bool change_bounded(std::span<const FieldTet> from, std::span<const FieldTet> to, int k) {
    static const std::vector<std::array<double, 4>> kPoints = [] {
      std::vector<std::array<double, 4>> points{{0.25, 0.25, 0.25, 0.25}};
      for (const auto& e : kTetEdges) {
        std::array<double, 4> l{};
        l[static_cast<std::size_t>(e[0])] = l[static_cast<std::size_t>(e[1])] = 0.5;
        points.push_back(l);
      }
      for (const auto& face : kTetFaces) {
        std::array<double, 4> l{};
        for (int j : face) l[static_cast<std::size_t>(j)] = 1.0 / 3.0;
        points.push_back(l);
      }
      return points;
    }();
    in_to_.reset(to);
    for (const FieldTet& t : from)
      for (const auto& la : kPoints) {
        const glm::dvec3 x = la[0] * t.p[0] + la[1] * t.p[1] + la[2] * t.p[2] + la[3] * t.p[3];
        std::size_t b = 0;
        std::array<double, 4> lb{};
        in_to_.locate(x, b, lb);
        for (int c = 0; c < k; ++c)
          if (std::fabs(interpolate(t, la, c) - interpolate(to[b], lb, c)) > allowed_[static_cast<std::size_t>(c)]) return false;
      }
    return true;
  }

  // Squared errors in units of the range: rounding of the interpolation, never a real change.
  static constexpr double kRoundingError = 1e-24;

  // Edge removal around edge ab of tet t (3 -> 2 is its smallest case): ab has n <= kMaxRing tets,
  // one material, a closed ring r_0 .. r_{n-1} of vertices, and neither ab nor a face through it is
  // flagged. The ring polygon is triangulated (no diagonal may already be an edge of the mesh) and
  // each triangle pqr gives the tets pqra and qprb: the triangulation with the best worst tet wins
  // (dynamic programming over sub-polygons, as in Shewchuk's edge removal).
  // Only triangulations whose worst tet beats `floor` count (a tet at or below it is not even
  // tested for orientation: most candidate tets are, and that saves the robust predicate).
  bool edge_flip(TetId t, VertId a, VertId b, double floor, Flip& f) {
    ring_.clear();
    bool ok = true;
    for (TetId s : stars_[a])
      if (ok && contains(m_.tets[s], b)) {
        if (ring_.size() == kMaxRing) ok = false;
        else ring_.push_back(s);
      }
    const int n = static_cast<int>(ring_.size());
    if (!ok || n < 3) return false;
    // Each ring tet gives one edge of the ring polygon (its two vertices other than a and b).
    std::array<std::array<VertId, 2>, kMaxRing> sides{};
    for (int i = 0; i < n; ++i) {
      const TetId s = ring_[static_cast<std::size_t>(i)];
      if (m_.material[s] != m_.material[t]) return false;
      const auto& sv = m_.tets[s];
      const TetFlags fl = m_.flags[s];
      int la = -1, lb = -1;
      for (int k = 0; k < 4; ++k) {
        if (sv[k] == a) la = k;
        if (sv[k] == b) lb = k;
      }
      if (is_polyline_edge(fl, local_edge_index(la, lb))) return false;
      int m = 0;
      for (int k = 0; k < 4; ++k) {
        if (k == la || k == lb) continue;
        if (is_surface_face(fl, k)) return false;  // face k holds a and b: it disappears
        sides[static_cast<std::size_t>(i)][static_cast<std::size_t>(m++)] = sv[k];
      }
    }
    // Chain the sides into a cycle; an open fan (ab on the boundary) or a pinched ring fails.
    std::array<VertId, kMaxRing> r{};
    std::array<std::uint8_t, kMaxRing> used{};
    r[0] = sides[0][0];
    r[1] = sides[0][1];
    used[0] = 1;
    for (int k = 2; k <= n; ++k) {
      bool found = false;
      for (int i = 0; i < n && !found; ++i) {
        if (used[static_cast<std::size_t>(i)]) continue;
        const auto& sd = sides[static_cast<std::size_t>(i)];
        const VertId last = r[static_cast<std::size_t>(k - 1)];
        if (sd[0] != last && sd[1] != last) continue;
        used[static_cast<std::size_t>(i)] = 1;
        const VertId next = sd[0] == last ? sd[1] : sd[0];
        if (k == n) {
          if (next != r[0]) return false;
        } else {
          r[static_cast<std::size_t>(k)] = next;
        }
        found = true;
      }
      if (!found) return false;
    }
    for (int i = 0; i < n; ++i) {
      const VertId x = r[static_cast<std::size_t>(i)];
      if (m_.is_frozen(x)) return false;
      for (int j = 0; j < i; ++j)
        if (r[static_cast<std::size_t>(j)] == x) return false;
    }
    // The ring's direction: a on the positive side of the triangles taken in ring order.
    const auto& P = m_.positions;
    const int side = orient3d_sign(P[r[0]], P[r[1]], P[r[2]], P[a]);
    if (side == 0) return false;
    if (side < 0) std::reverse(r.begin(), r.begin() + n);
    // A diagonal that is already an edge of the mesh cannot be used. Finding them scans stars, so
    // the triangulations are first searched as if none were: most edges have no triangulation
    // that beats the floor at all (then none with fewer diagonals has either), and only an edge
    // that has one pays for the scan and the second search.
    std::array<std::array<std::uint8_t, kMaxRing>, kMaxRing> joined{};
    std::array<std::array<double, kMaxRing>, kMaxRing> best{};
    std::array<std::array<std::int8_t, kMaxRing>, kMaxRing> apex{};
    if (!(triangulate(r, n, a, b, floor, joined, best, apex) > kNoTriangulation)) return false;
    bool any_joined = false;
    for (int i = 0; i < n; ++i)
      for (int j = i + 2; j < n; ++j) {
        if (i == 0 && j == n - 1) continue;  // a side
        const VertId x = r[static_cast<std::size_t>(i)], y = r[static_cast<std::size_t>(j)];
        bool e = false;
        for (TetId s : stars_[x]) e = e || contains(m_.tets[s], y);
        joined[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = e ? 1 : 0;
        any_joined = any_joined || e;
      }
    if (any_joined && !(triangulate(r, n, a, b, floor, joined, best, apex) > kNoTriangulation)) return false;
    const double q = best[0][static_cast<std::size_t>(n - 1)];
    f.old_count = n;
    for (int i = 0; i < n; ++i) f.old[static_cast<std::size_t>(i)] = ring_[static_cast<std::size_t>(i)];
    f.made_count = 0;
    emit(r, apex, 0, n - 1, a, b, f);
    f.quality = q;
    return true;
  }

  static constexpr double kNoTriangulation = -1.0;

  // best[i][j]: the best worst tet over the triangulations of the sub-polygon r_i .. r_j (j > i + 1)
  // that use no joined diagonal, apex[i][j] the apex of its triangle on side ij; returns
  // best[0][n - 1] (kNoTriangulation: none beats `floor`).
  double triangulate(const std::array<VertId, kMaxRing>& r, int n, VertId a, VertId b, double floor,
                     const std::array<std::array<std::uint8_t, kMaxRing>, kMaxRing>& joined,
                     std::array<std::array<double, kMaxRing>, kMaxRing>& best,
                     std::array<std::array<std::int8_t, kMaxRing>, kMaxRing>& apex) const {
    for (int len = 2; len < n; ++len)
      for (int i = 0; i + len < n; ++i) {
        const int j = i + len;
        double& bq = best[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
        bq = kNoTriangulation;
        if (len < n - 1 && joined[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]) continue;
        for (int k = i + 1; k < j; ++k) {
          const double left = k == i + 1 ? 1.0 : best[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
          const double right = k == j - 1 ? 1.0 : best[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)];
          if (!(left > kNoTriangulation) || !(right > kNoTriangulation)) continue;
          const std::array<VertId, 4> up{r[static_cast<std::size_t>(i)], r[static_cast<std::size_t>(k)],
                                         r[static_cast<std::size_t>(j)], a};
          const std::array<VertId, 4> down{r[static_cast<std::size_t>(k)], r[static_cast<std::size_t>(i)],
                                           r[static_cast<std::size_t>(j)], b};
          const double q = std::min({left, right, quality(m_, up), quality(m_, down)});
          if (!(q > floor) || !positive(m_, up) || !positive(m_, down)) continue;
          if (q > bq) {
            bq = q;
            apex[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = static_cast<std::int8_t>(k);
          }
        }
      }
    return best[0][static_cast<std::size_t>(n - 1)];
  }

  // The tets of the chosen triangulation of sub-polygon r_i .. r_j.
  void emit(const std::array<VertId, kMaxRing>& r, const std::array<std::array<std::int8_t, kMaxRing>, kMaxRing>& apex,
            int i, int j, VertId a, VertId b, Flip& f) {
    if (j < i + 2) return;
    const int k = apex[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
    const VertId ri = r[static_cast<std::size_t>(i)], rk = r[static_cast<std::size_t>(k)], rj = r[static_cast<std::size_t>(j)];
    f.made[static_cast<std::size_t>(f.made_count++)] = {ri, rk, rj, a};
    f.made[static_cast<std::size_t>(f.made_count++)] = {rk, ri, rj, b};
    emit(r, apex, i, k, a, b, f);
    emit(r, apex, k, j, a, b, f);
  }

  // 2 -> 3 through face k of tet t (opposite its corner k): an unflagged face between two tets of
  // one material, whose apexes a and b are not yet joined by an edge.
  bool face_flip(TetId t, int k, double floor, Flip& f) {
    const auto& tv = m_.tets[t];
    if (is_surface_face(m_.flags[t], k)) return false;
    VertId x = tv[kTetFaces[k][0]], y = tv[kTetFaces[k][1]], z = tv[kTetFaces[k][2]];
    const VertId a = tv[k];
    TetId nb = kInvalid;
    for (TetId s : stars_[x])
      if (s != t && contains(m_.tets[s], y) && contains(m_.tets[s], z)) nb = s;
    if (nb == kInvalid || m_.material[nb] != m_.material[t]) return false;
    VertId b = kInvalid;
    for (VertId w : m_.tets[nb])
      if (w != x && w != y && w != z) b = w;
    if (m_.is_frozen(b)) return false;
    bool joined = false;
    for (TetId s : stars_[a]) joined = joined || contains(m_.tets[s], b);
    if (joined) return false;
    const auto& P = m_.positions;
    const int side = orient3d_sign(P[x], P[y], P[z], P[a]);
    if (side == 0) return false;
    if (side < 0) std::swap(y, z);
    // Each new tet is (x, y, z, a) with one face vertex replaced by b: positive iff ab crosses the face.
    f.old[0] = t;
    f.old[1] = nb;
    f.old_count = 2;
    f.made[0] = {b, y, z, a};
    f.made[1] = {x, b, z, a};
    f.made[2] = {x, y, b, a};
    f.made_count = 3;
    f.quality = 1.0;
    for (int i = 0; i < 3; ++i) {
      f.quality = std::min(f.quality, quality(m_, f.made[static_cast<std::size_t>(i)]));
      if (!(f.quality > floor) || !positive(m_, f.made[static_cast<std::size_t>(i)])) return false;
    }
    return true;
  }

  const MeshModel& m_;
  const Stars& stars_;
  std::vector<double> allowed_;    // [field component] the largest change a flip may make
  const InputSamples* samples_;
  double growth_;
  DihedralFloor floor_;
  std::vector<TetId> ring_;
  std::vector<FieldTet> before_, after_;
  std::array<Flip, 10> candidates_{};  // 6 edges, 4 faces
  RegionLocator in_to_;
  InputSamples::Inside inside_;
};

}  // namespace

SwapStats swap_bad_tets(MeshModel& mesh, const SwapOptions& options, const InputSamples* samples) {
  SwapStats stats;
  const double target3 = options.target_quality * options.target_quality * options.target_quality;
  compact_tets(mesh);  // dense tets: the collapses left ~90% of them dead
  Stars stars(mesh.vertex_capacity());
  for (TetId t = 0; t < mesh.tets.size(); ++t)
    for (VertId x : mesh.tets[t]) stars[x].push_back(t);
  // Worst tet first: a min-heap of (quality, tet, version); a slot a flip rewrote has a new version,
  // so its old entries are stale. Sequential and keyed by quality and id: deterministic.
  using Entry = std::tuple<double, TetId, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  std::vector<std::uint32_t> version(mesh.tets.size(), 0);
  auto push_if_bad = [&](TetId t) {
    if (!mesh.is_reshaped_tet(t)) return;  // an input tet the collapses left alone (swap.h)
    const double q = quality(mesh, mesh.tets[t]);
    if (q < target3) heap.emplace(q, t, version[t]);
  };
  for (TetId t = 0; t < mesh.tets.size(); ++t) push_if_bad(t);
  // A tet that found no flip is looked at again only after a flip next to it (its options changed);
  // every flip lifts the worst tet of its region, so this ends, and the cap bounds the work.
  std::uint64_t budget = 16 * heap.size() + 1024;
  // Batches of the heap's next tets searched in parallel, flipped in heap order (swap.h). A tet a
  // flip of its own batch touched (a vertex of it in that flip's region: the rings and faces its
  // search read may have changed) is searched again on the changed mesh.
  const FlipFinder prototype(mesh, stars, samples, options);
  parallel::PerThread<FlipFinder> finders([&] { return prototype; });
  constexpr std::size_t kBatch = 64;
  struct Pending {
    TetId t;
    std::uint32_t version;
    double q;
    bool found;
    Flip flip;
  };
  std::vector<Pending> batch;
  std::vector<std::uint32_t> flipped_in(mesh.vertex_capacity(), 0);  // [vertex] last batch whose flip touched it
  std::uint32_t batch_id = 0;
  RegionFlags region;
  for (int pass = 0; pass < options.max_passes && !heap.empty(); ++pass) {
    std::uint64_t applied = 0;
    const std::uint32_t pass_start = batch_id;  // the vertices a flip of this pass touched: flipped_in > pass_start
    while (!heap.empty() && budget > 0) {
      batch.clear();
      while (!heap.empty() && budget > 0 && batch.size() < kBatch) {
        const auto [q, t, v] = heap.top();
        heap.pop();
        if (v != version[t] || mesh.is_dead_tet(t)) continue;
        --budget;
        batch.push_back({t, v, q, false, Flip{}});
      }
      parallel::for_range<std::size_t>(0, batch.size(), 1, "swap_search", [&](std::size_t b, std::size_t e) {
        FlipFinder& finder = finders.local();
        for (std::size_t i = b; i < e; ++i) batch[i].found = finder.best_flip(batch[i].t, batch[i].q, batch[i].flip);
      });
      ++batch_id;
      for (Pending& p : batch) {
        if (p.version != version[p.t] || mesh.is_dead_tet(p.t)) continue;  // an earlier flip replaced it
        const auto& tv = mesh.tets[p.t];
        if (flipped_in[tv[0]] == batch_id || flipped_in[tv[1]] == batch_id || flipped_in[tv[2]] == batch_id ||
            flipped_in[tv[3]] == batch_id)
          p.found = finders.local().best_flip(p.t, p.q, p.flip);
        if (!p.found) continue;
        const Flip& flip = p.flip;
        // The stars of the region's vertices lose the old tets and gain the new ones.
        for (int k = 0; k < flip.old_count; ++k) {
          const TetId old = flip.old[static_cast<std::size_t>(k)];
          for (VertId x : mesh.tets[old]) std::erase(stars[x], old);
          ++version[old];
        }
        const std::size_t first_new = mesh.tets.size();
        apply_flip(mesh, flip, region, flipped_in, batch_id);
        version.resize(mesh.tets.size(), 0);
        for (int k = 0; k < flip.made_count; ++k) {
          const TetId made = k < flip.old_count ? flip.old[static_cast<std::size_t>(k)]
                                                : static_cast<TetId>(first_new + static_cast<std::size_t>(k - flip.old_count));
          for (VertId x : mesh.tets[made]) stars[x].push_back(made);
          push_if_bad(made);
        }
        ++(flip.old_count == 2 ? stats.flips_23 : stats.edge_removals);
        ++applied;
      }
    }
    if (applied == 0) break;
    stats.passes = pass + 1;
    // The bad tets next to a flip of this pass (a vertex of theirs touched) may have a flip now.
    for (TetId t = 0; t < mesh.tets.size(); ++t) {
      if (mesh.is_dead_tet(t)) continue;
      const auto& tv = mesh.tets[t];
      if (std::max({flipped_in[tv[0]], flipped_in[tv[1]], flipped_in[tv[2]], flipped_in[tv[3]]}) > pass_start)
        push_if_bad(t);
    }
  }
  compact_tets(mesh);
  return stats;
}

}  // namespace topotet
