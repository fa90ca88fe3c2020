// Vertex smoothing (see smooth.h).
#include "optimize/smooth.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>

#include "cost/cost.h"
#include "mesh/moved_corner.h"
#include "optimize/input_samples.h"
#include "parallel/filter.h"
#include "parallel/for_range.h"
#include "parallel/scratch.h"

namespace topotet {

namespace {

int corner_of(const std::array<VertId, 4>& tv, VertId v) {
  for (int k = 0; k < 4; ++k)
    if (tv[k] == v) return k;
  return -1;
}

// Whether and how a vertex may move (smooth.h): kFixed, kFree, or in the axis plane `axis`.
struct Mobility {
  enum Kind : std::uint8_t { kFixed, kFree, kInPlane } kind = kFixed;
  int axis = -1;  // kInPlane: the coordinate the vertex and its sheet's fan share exactly
};

// Label of a sheet face through v: its ref when flagged, kUnflaggedBoundary for a boundary face
// that lists no ref (an unflagged face shared by two tets is not on a sheet).
constexpr std::int32_t kUnflaggedBoundary = INT32_MIN + 1;

struct FaceThrough {
  std::uint64_t key;  // the face's two other vertices (x < y) packed
  std::int32_t label;
  bool flagged;
};

struct Scratch {
  std::vector<TetId> star;
  std::vector<std::uint8_t> corner;  // [star tet] local corner of the vertex
  std::vector<MovedCorner> moved;    // [star tet]
  std::vector<VertId> link;
  std::vector<FaceThrough> through;
  FieldBoundsScratch bounds;
  std::vector<double> values;
  std::vector<FieldTet> before, after;  // the star with v at its place and at a proposed one
  InputSamples::Inside inside;          // the input's vertices inside the star
};

void gather_star(const MeshModel& mesh, VertId v, Scratch& s) {
  s.star.clear();
  s.corner.clear();
  mesh.for_each_tet_of(v, [&](TetId t) {
    s.star.push_back(t);
    s.corner.push_back(static_cast<std::uint8_t>(corner_of(mesh.tets[t], v)));
  });
}

// The one coordinate (0..2) in which v and every vertex of its sheet's fan agree exactly, if
// the sheet faces through v form one loop around it (a disk of one label); -1 otherwise.
int flat_axis_of_sheet(const MeshModel& mesh, VertId v, std::vector<FaceThrough>& faces, std::vector<VertId>& ends) {
  // Sheet faces: on the boundary (listed once) or flagged; the rest appear twice, unflagged.
  ends.clear();
  std::int32_t label = 0;
  bool first = true;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i > 2) return -1;  // not a manifold star
    const bool boundary = j - i == 1;
    const bool flagged = faces[i].flagged || (!boundary && faces[i + 1].flagged);
    if (boundary || flagged) {
      const std::int32_t l = faces[i].flagged ? faces[i].label : (boundary ? kUnflaggedBoundary : faces[i + 1].label);
      if (!first && l != label) return -1;  // two labels meet at v: moving it would shift their seam
      label = l;
      first = false;
      ends.push_back(static_cast<VertId>(faces[i].key >> 32));
      ends.push_back(static_cast<VertId>(faces[i].key & 0xffffffffu));
    }
    i = j;
  }
  if (ends.size() < 6) return -1;  // fewer than 3 sheet faces: no disk around v
  // One loop: the sheet's link edges (x, y) give every link vertex degree 2 and connect them.
  std::vector<VertId> sorted_ends = ends;
  std::sort(sorted_ends.begin(), sorted_ends.end());
  for (std::size_t i = 0; i < sorted_ends.size(); i += 2)
    if (sorted_ends[i] != sorted_ends[i + 1] || (i + 2 < sorted_ends.size() && sorted_ends[i + 2] == sorted_ends[i]))
      return -1;
  const std::size_t edges = ends.size() / 2;
  VertId start = ends[0], at = ends[1];
  std::size_t walked = 1, prev = 0;
  while (at != start && walked <= edges) {
    std::size_t next = edges;
    for (std::size_t e = 0; e < edges; ++e)
      if (e != prev && (ends[2 * e] == at || ends[2 * e + 1] == at)) next = e;
    if (next == edges) return -1;
    at = ends[2 * next] == at ? ends[2 * next + 1] : ends[2 * next];
    prev = next;
    ++walked;
  }
  if (at != start || walked != edges) return -1;  // several loops: v pinches two disks together
  // Flat in an axis plane, exactly: then the vertex can move in it and stay in it to the last bit.
  const glm::dvec3& x = mesh.positions[v];
  for (int axis = 0; axis < 3; ++axis) {
    bool same = true;
    for (VertId w : ends) same = same && mesh.positions[w][axis] == x[axis];
    if (same) return axis;
  }
  return -1;
}

Mobility mobility_of(const MeshModel& mesh, VertId v, Scratch& s) {
  if (mesh.is_dead_vertex(v) || mesh.is_pinned(v) || mesh.is_frozen(v)) return {};
  gather_star(mesh, v, s);
  if (s.star.empty()) return {};
  const std::int32_t material = mesh.material[s.star[0]];
  bool one_material = true, flagged_face = false;
  s.through.clear();
  for (std::size_t i = 0; i < s.star.size(); ++i) {
    const TetId t = s.star[i];
    const int k = s.corner[i];
    one_material = one_material && mesh.material[t] == material;
    const TetFlags fl = mesh.flags[t];
    for (int e = 0; e < 6; ++e)
      if ((kTetEdges[e][0] == k || kTetEdges[e][1] == k) && is_polyline_edge(fl, e)) return {};
    // The faces through v, by their two other vertices.
    const auto& tv = mesh.tets[t];
    for (int f = 0; f < 4; ++f) {
      if (f == k) continue;
      VertId x = kInvalid, y = kInvalid;
      for (int j = 0; j < 4; ++j) {
        if (j == f || j == k) continue;
        (x == kInvalid ? x : y) = tv[j];
      }
      const bool flagged = is_surface_face(fl, f);
      flagged_face = flagged_face || flagged;
      const std::int32_t label = flagged ? mesh.refs_table[mesh.tet_refs_slot[t]].face[f] : 0;
      s.through.push_back({x < y ? (std::uint64_t{x} << 32) | y : (std::uint64_t{y} << 32) | x, label, flagged});
    }
  }
  std::sort(s.through.begin(), s.through.end(), [](const FaceThrough& a, const FaceThrough& b) { return a.key < b.key; });
  bool interior = !flagged_face && one_material;
  for (std::size_t i = 0; interior && i < s.through.size(); i += 2)
    interior = i + 1 < s.through.size() && s.through[i].key == s.through[i + 1].key &&
               (i + 2 >= s.through.size() || s.through[i + 2].key != s.through[i].key);
  if (interior) return {Mobility::kFree, -1};
  const int axis = flat_axis_of_sheet(mesh, v, s.through, s.link);
  if (axis < 0) return {};
  return {Mobility::kInPlane, axis};
}

// The star's worst (mean ratio)^3 with the vertex at x, and which tet; -1 if a tet would invert.
double star_quality(const std::vector<MovedCorner>& moved, const glm::dvec3& x, std::size_t* worst = nullptr) {
  double q = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < moved.size(); ++i) {
    double qi = 0.0;
    if (!moved_corner_quality(moved[i], x, qi)) return -1.0;
    if (qi < q) {
      q = qi;
      if (worst != nullptr) *worst = i;
    }
  }
  return q;
}

// The star's smallest sin^2 of a dihedral angle with the vertex at x, over the tets the floor's
// screen does not clear (1 if none; mesh/dihedral.h).
double star_dihedral(const std::vector<MovedCorner>& moved, const glm::dvec3& x, const DihedralFloor& floor) {
  double worst = 1.0;
  for (const MovedCorner& m : moved) {
    double q3 = 0.0;
    if (moved_corner_quality(m, x, q3) && q3 >= floor.screen_q3) continue;
    worst = std::min(worst, min_dihedral_sine_sq(m.a, x, m.c, m.d));
  }
  return worst;
}

// Does moving the vertex from x0 to x keep the dihedral floor: the new star's smallest angle at
// least min(floor, the old star's)?
bool dihedral_kept(const std::vector<MovedCorner>& moved, const glm::dvec3& x0, const glm::dvec3& x,
                   const DihedralFloor& floor) {
  if (!floor.active()) return true;
  const double now = star_dihedral(moved, x, floor);
  return now >= floor.sine_sq || now >= std::min(floor.sine_sq, star_dihedral(moved, x0, floor));
}

// Gradient of log((mean ratio)^3) of one tet with respect to its moving corner at x:
// q3 = 432 det^2 / S^3, so d log q3 = 2 d(det) / det - 3 dS / S, with d(det) / dx = normal and
// dS / dx = 2 ((x - a) + (x - c) + (x - d)).
glm::dvec3 log_quality_gradient(const MovedCorner& m, const glm::dvec3& x) {
  const double det = glm::dot(x - m.a, m.normal);
  const glm::dvec3 xa = x - m.a, xc = x - m.c, xd = x - m.d;
  const double S = m.fixed_edges_sq + glm::dot(xa, xa) + glm::dot(xc, xc) + glm::dot(xd, xd);
  return (2.0 / det) * m.normal - (6.0 / S) * (xa + xc + xd);
}

// A move is proposed only when it lifts the star's worst (mean ratio)^3 by this factor (the mean
// ratio by 3%): smaller gains kept every vertex of a bad region proposing in every pass.
constexpr double kMinGain = 1.1;
constexpr double kCostBudget = 1.2;
// Quadric errors below this are rounding (the costs are in units of the bounding box's diagonal:
// a distance of 1e-8 of it, squared): a vertex whose quadric is zero at its place (a flat sheet
// without fields) may move where the quadric is zero up to rounding.
constexpr double kRoundingCost = 1e-16;
// Squared field errors in units of the range below this are rounding, not a change (input_samples.h).
constexpr double kRoundingError = 1e-24;

struct Proposal {
  VertId v = kInvalid;
  glm::dvec3 p{0.0};
  double key = 0.0;  // the star's worst quality before the move
};

// The mobility a vertex's `known` byte records: 0 = not yet known, 1 = free, 2 = fixed, 3 + axis
// = in the axis plane. A move keeps the star's combinatorics and a vertex in its plane, so the
// answer holds for the whole call; written only by the thread evaluating v.
constexpr std::uint8_t kUnknown = 0, kKnownFree = 1, kKnownFixed = 2, kKnownInPlane = 3;
std::uint8_t encode(const Mobility& m) {
  return m.kind == Mobility::kFree ? kKnownFree
                                   : (m.kind == Mobility::kFixed ? kKnownFixed : static_cast<std::uint8_t>(kKnownInPlane + m.axis));
}

// The star of v, with each tet's quality as a function of v's place (s.moved) and the link's
// vertices (s.link, with repeats).
void prepare_star(const MeshModel& mesh, VertId v, Scratch& s) {
  gather_star(mesh, v, s);
  const auto& P = mesh.positions;
  s.moved.resize(s.star.size());
  s.link.clear();
  for (std::size_t i = 0; i < s.star.size(); ++i) {
    const auto& tv = mesh.tets[s.star[i]];
    const auto& face = kTetFaces[s.corner[i]];
    s.moved[i] = prepare_moved_corner(P[tv[face[0]]], P[tv[face[1]]], P[tv[face[2]]]);
    for (int j = 0; j < 3; ++j) s.link.push_back(tv[face[j]]);
  }
}

// Does moving v to x (with the values its quadric gives there) keep the squared field errors at
// the input's vertices inside its star within the growth allowed (optimize/input_samples.h)? The
// star is the same point set before and after (v is free, or moves in its flat sheet's plane), so
// the vertices inside it are found once per proposal (s.inside, for s.star as gathered).
bool samples_kept(const MeshModel& mesh, const CostModel& cost, const InputSamples* samples, double growth, VertId v,
                  const glm::dvec3& x, Scratch& s, bool& gathered) {
  const int k = mesh.field_stride();
  if (k == 0 || samples == nullptr || samples->empty()) return true;
  if (!gathered) {
    s.before.clear();
    for (TetId t : s.star) s.before.push_back(field_tet(mesh, mesh.tets[t], k));
    samples->inside(mesh, s.before, v, s.inside);
    gathered = true;
  }
  s.values.resize(static_cast<std::size_t>(k));
  cost.fields_at_point(mesh, v, x, s.values.data());
  s.after = s.before;
  for (std::size_t i = 0; i < s.star.size(); ++i) {
    s.after[i].p[s.corner[i]] = x;
    s.after[i].f[s.corner[i]] = s.values.data();
  }
  return samples->errors_after(mesh, s.after, s.inside) <= s.inside.error * (1.0 + growth) + kRoundingError;
}

// The best point found for movable vertex v, if it lifts the star's worst tet by kMinGain at least.
// A vertex of a flat sheet moves in its axis plane only: every candidate point keeps that
// coordinate exactly.
bool propose(const MeshModel& mesh, const CostModel& cost, VertId v, double target3, const DihedralFloor& floor,
             Scratch& s, std::uint8_t& known, Proposal& out) {
  if (known == kUnknown) known = encode(mobility_of(mesh, v, s));
  if (known == kKnownFixed) return false;
  const int axis = known >= kKnownInPlane ? known - kKnownInPlane : -1;
  const auto in_plane = [&](glm::dvec3 y, const glm::dvec3& x) {
    if (axis >= 0) y[axis] = x[axis];
    return y;
  };
  prepare_star(mesh, v, s);
  const auto& P = mesh.positions;
  const glm::dvec3 x0 = P[v];
  const double q0 = star_quality(s.moved, x0);
  if (!(q0 > 0.0) || q0 >= target3) return false;
  std::sort(s.link.begin(), s.link.end());
  s.link.erase(std::unique(s.link.begin(), s.link.end()), s.link.end());
  glm::dvec3 centroid{0.0};
  double scale = 0.0;
  for (VertId w : s.link) {
    centroid += P[w];
    scale += glm::length(P[w] - x0);
  }
  centroid = in_plane(centroid / static_cast<double>(s.link.size()), x0);
  scale /= static_cast<double>(s.link.size());
  glm::dvec3 x = x0;
  double q = q0;
  if (const double qc = star_quality(s.moved, centroid); qc > q) {
    x = centroid;
    q = qc;
  }
  double step = 0.05 * scale;
  constexpr int kIterations = 6, kHalvings = 6;
  for (int it = 0; it < kIterations; ++it) {
    glm::dvec3 direction{0.0};
    for (const MovedCorner& m : s.moved) {
      double qi = 0.0;
      moved_corner_quality(m, x, qi);
      if (qi > q * 1.01) continue;  // not among the worst
      const glm::dvec3 g = log_quality_gradient(m, x);
      const double n = glm::length(g);
      if (n > 0.0 && std::isfinite(n)) direction += g / n;
    }
    direction = in_plane(direction, glm::dvec3(0.0));
    const double n = glm::length(direction);
    if (!(n > 0.0) || !std::isfinite(n)) break;
    direction /= n;
    bool improved = false;
    for (int h = 0; h < kHalvings; ++h, step *= 0.5) {
      const glm::dvec3 y = in_plane(x + step * direction, x0);
      const double qy = star_quality(s.moved, y);
      if (qy > q) {
        x = y;
        q = qy;
        improved = true;
        step = std::min(step * 2.0, 0.25 * scale);
        break;
      }
    }
    if (!improved) break;
  }
  if (!(q > q0 * kMinGain)) return false;
  // The field (smooth.h): the quadric's error at the new point may exceed the one at the old
  // point by kCostBudget at most; pulled back toward the old point until it does.
  const double limit = std::max(cost.point_cost(mesh, v, x0) * kCostBudget, kRoundingCost);
  double qx = q;
  int tries = 0;
  for (; tries < 8 && cost.point_cost(mesh, v, x) > limit; ++tries) {
    x = in_plane(0.5 * (x0 + x), x0);
    qx = star_quality(s.moved, x);
  }
  if (tries == 8 || !(qx > q0 * kMinGain) || !dihedral_kept(s.moved, x0, x, floor)) return false;
  out = {v, x, q0};
  return true;
}

// The field at the input's vertices, for a proposal that won its pass (checked after the selection,
// as the collapses' winners prove the tolerance: a sixth of the proposals win, and finding the
// input's vertices in a star costs more than the rest of a proposal). Pulled back toward the old
// point until the squared errors there grow by `growth` at most (the quadric's error only falls
// on the way: it is convex, and the old point is within its budget), while the star's worst tet
// still gains kMinGain; false when it does not. Reads the mesh only: the winners' stars share no
// tet, and none of them is a vertex of another's star.
bool keep_samples(const MeshModel& mesh, const CostModel& cost, const InputSamples* samples, double growth,
                  const DihedralFloor& floor, Proposal& pr, Scratch& s) {
  if (samples == nullptr || samples->empty() || mesh.field_stride() == 0) return true;
  prepare_star(mesh, pr.v, s);
  const glm::dvec3 x0 = mesh.positions[pr.v];
  bool gathered = false;
  glm::dvec3 x = pr.p;
  for (int tries = 0; tries < 8; ++tries) {
    if (samples_kept(mesh, cost, samples, growth, pr.v, x, s, gathered) && dihedral_kept(s.moved, x0, x, floor)) {
      pr.p = x;
      return true;
    }
    x = 0.5 * (x0 + x);  // keeps a flat sheet's coordinate: both points have it
    if (!(star_quality(s.moved, x) > pr.key * kMinGain)) return false;
  }
  return false;
}

// Moves v to p with its new field values (and the star's field bounds). False (nothing written)
// when the field bounds' limit refuses the move.
bool apply_move(MeshModel& mesh, const Proposal& pr, CostModel& cost, FieldBounds* bounds, Scratch& s) {
  gather_star(mesh, pr.v, s);
  const int k = mesh.field_stride();
  s.values.resize(static_cast<std::size_t>(k));
  cost.fields_at_point(mesh, pr.v, pr.p, s.values.data());
  if (bounds != nullptr) {
    s.bounds.star.clear();
    for (std::size_t i = 0; i < s.star.size(); ++i) s.bounds.star.push_back({s.star[i], s.corner[i]});
    if (!bounds->evaluate(mesh, {}, pr.v, pr.p, s.values.data(), s.bounds, bounds->has_limit())) return false;
    if (bounds->has_limit()) bounds->evaluate(mesh, {}, pr.v, pr.p, s.values.data(), s.bounds, false);
    bounds->commit({}, s.bounds);
  }
  mesh.positions[pr.v] = pr.p;
  mesh.vertex_states[pr.v] |= vertex_state::kReshaped;  // its own byte: winners' stars share no tet
  for (int c = 0; c < k; ++c) mesh.field_values[static_cast<std::size_t>(pr.v) * k + c] = s.values[static_cast<std::size_t>(c)];
  cost.on_move(mesh, pr.v);
  return true;
}

}  // namespace

bool is_free_vertex(const MeshModel& mesh, VertId v) {
  Scratch s;
  return mobility_of(mesh, v, s).kind == Mobility::kFree;
}

int flat_sheet_axis(const MeshModel& mesh, VertId v) {
  Scratch s;
  const Mobility m = mobility_of(mesh, v, s);
  return m.kind == Mobility::kInPlane ? m.axis : -1;
}

SmoothStats smooth_vertices(MeshModel& mesh, const SmoothOptions& options, CostModel& cost, FieldBounds* bounds,
                            const InputSamples* samples) {
  SmoothStats stats;
  const double target3 = options.target_quality * options.target_quality * options.target_quality;
  const std::size_t nv = mesh.vertex_capacity();
  parallel::PerThread<Scratch> scratch;
  // The start: the movable vertices of the tets below the target that the collapses made or moved
  // (smooth.h: input tets the collapses left alone are left as the input had them), in one pass
  // over the tets, which the collapses left at a tenth of the input or so.
  std::vector<std::uint8_t> bad(nv, 0);
  const auto& P = mesh.positions;
  for (TetId t = 0; t < mesh.tets.size(); ++t) {
    if (mesh.is_dead_tet(t)) continue;
    const auto& tv = mesh.tets[t];
    if (mesh.is_reshaped_tet(t) && mean_ratio_cubed(P[tv[0]], P[tv[1]], P[tv[2]], P[tv[3]]) < target3)
      for (VertId x : tv) bad[x] = 1;
  }
  std::vector<VertId> candidates;
  parallel::filter_map_sparse(
      nv, candidates, [&](std::size_t b, std::size_t e) { return std::find(bad.begin() + b, bad.begin() + e, 1) != bad.begin() + e; },
      [&](std::size_t v) { return bad[v] && mobility_of(mesh, static_cast<VertId>(v), scratch.local()).kind != Mobility::kFixed; },
      [](std::size_t v) { return static_cast<VertId>(v); });
  std::vector<std::uint8_t>().swap(bad);
  stats.candidates = candidates.size();
  // Per vertex: the key of its proposal while undecided (+inf otherwise), and whether it joined.
  std::vector<double> key(nv, std::numeric_limits<double>::infinity());
  std::vector<std::uint8_t> known(nv, kUnknown);
  std::vector<std::uint8_t> joined(nv, 0);
  enum : std::uint8_t { kUndecided, kJoined, kOut };
  std::vector<std::uint8_t> state, decision;
  std::vector<Proposal> proposals;
  std::vector<std::uint8_t> won;
  std::vector<VertId> next;
  for (int pass = 0; pass < options.max_passes && !candidates.empty(); ++pass) {
    // 1. Evaluate (read-only).
    std::vector<Proposal> all(candidates.size());
    std::vector<std::uint8_t> has(candidates.size(), 0);
    parallel::for_range<std::size_t>(0, candidates.size(), 64, "smooth_evaluate", [&](std::size_t b, std::size_t e) {
      Scratch& s = scratch.local();
      for (std::size_t i = b; i < e; ++i) has[i] = propose(mesh, cost, candidates[i], target3, options.dihedral_floor, s, known[candidates[i]], all[i]) ? 1 : 0;
    });
    proposals.clear();
    for (std::size_t i = 0; i < all.size(); ++i)
      if (has[i]) proposals.push_back(all[i]);
    if (proposals.empty()) break;
    stats.passes = pass + 1;
    // 2. Select the greedy independent set in (key, id) order, in parallel sub-rounds: a proposal
    //    joins when no neighbour has joined and it is the smallest of its undecided neighbours;
    //    the neighbours of one that joined drop out. The same set for every thread count.
    for (const Proposal& pr : proposals) key[pr.v] = pr.key;
    // The neighbours that also propose, once per pass (the sub-rounds read them again and again).
    std::vector<std::vector<VertId>> rivals(proposals.size());
    parallel::for_range<std::size_t>(0, proposals.size(), 64, "smooth_rivals", [&](std::size_t b, std::size_t e) {
      Scratch& s = scratch.local();
      for (std::size_t i = b; i < e; ++i) {
        mesh.neighbours(proposals[i].v, s.link);
        for (VertId w : s.link)
          if (key[w] != std::numeric_limits<double>::infinity()) rivals[i].push_back(w);
      }
    });
    state.assign(proposals.size(), kUndecided);
    for (bool undecided = true; undecided;) {
      undecided = false;
      decision.assign(proposals.size(), kUndecided);
      parallel::for_range<std::size_t>(0, proposals.size(), 64, "smooth_select", [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          if (state[i] != kUndecided) continue;
          const Proposal& pr = proposals[i];
          std::uint8_t d = kJoined;
          for (VertId w : rivals[i]) {
            if (joined[w]) {
              d = kOut;
              break;
            }
            if (key[w] < pr.key || (key[w] == pr.key && w < pr.v)) d = kUndecided;  // a smaller one may still join
          }
          decision[i] = d;
        }
      });
      for (std::size_t i = 0; i < proposals.size(); ++i) {
        if (state[i] != kUndecided) continue;
        state[i] = decision[i];
        if (decision[i] == kUndecided) undecided = true;
        if (decision[i] != kUndecided) key[proposals[i].v] = std::numeric_limits<double>::infinity();
        if (decision[i] == kJoined) joined[proposals[i].v] = 1;
      }
    }
    for (const Proposal& pr : proposals) joined[pr.v] = 0;
    won.assign(proposals.size(), 0);
    for (std::size_t i = 0; i < proposals.size(); ++i) won[i] = state[i] == kJoined ? 1 : 0;
    // 3. The winners' field at the input's vertices (read-only), then apply them: their stars share no tet.
    parallel::for_range<std::size_t>(0, proposals.size(), 16, "smooth_samples", [&](std::size_t b, std::size_t e) {
      Scratch& s = scratch.local();
      for (std::size_t i = b; i < e; ++i)
        if (won[i] && !keep_samples(mesh, cost, samples, options.max_sample_error_growth, options.dihedral_floor, proposals[i], s)) won[i] = 0;
    });
    std::vector<std::uint8_t> moved(proposals.size(), 0);
    parallel::for_range<std::size_t>(0, proposals.size(), 16, "smooth_apply", [&](std::size_t b, std::size_t e) {
      Scratch& s = scratch.local();
      for (std::size_t i = b; i < e; ++i)
        if (won[i]) moved[i] = apply_move(mesh, proposals[i], cost, bounds, s) ? 1 : 0;
    });
    // 4. Next: the losers, the movers and the movers' neighbours.
    next.clear();
    Scratch& s = scratch.local();
    for (std::size_t i = 0; i < proposals.size(); ++i) {
      next.push_back(proposals[i].v);
      if (!moved[i]) continue;
      ++stats.moves;
      mesh.neighbours(proposals[i].v, s.link);
      next.insert(next.end(), s.link.begin(), s.link.end());
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    candidates.swap(next);
  }
  return stats;
}

}  // namespace topotet

