// detect_features (topotet/features.h): find the creases of the surfaces that are features at the
// scale of the tolerance, flag them as polyline edges, pin the corners they make.
//
//   candidates <- surface edges whose two faces (one surface label) turn by more than the angle
//   if scale H > 0, keep a candidate only if it is, at that scale,
//     high:  the surface around it departs from its best plane by more than H/2 at the edge;
//     sharp: the mean normals of the surface on its two sides still turn by more than the angle;
//            both measured on a disk of the surface around the edge, of radius
//            max(4H, 1.5 x the edge's face size) (measure_crease below);
//     (or it continues a kept crease straight on: continue_straight, a hysteresis)
//     long:  its chain (kept creases joined at vertices with exactly two of them) is >= 4H long;
//   flag the kept edges as feature curves (polyline edges, ref kFeatureCurveRef)
//   pin the kept edges' vertices that are not inner points of one curve (order 3: junctions of
//   three or more curves, ends, meetings with listed curves) and the inner points where the curve,
//   seen at scale H, turns by more than the angle; every other curve vertex slides along its curve
//
// Why a scale (issue #23). The tolerance keeps every surface within H of the original, whatever
// the features: a crease lower than H (a voxel staircase of a segmented image, the jagged faces of
// a surface digitized on a grid, the facets of a finely meshed curved surface) is already kept to
// within H, and pinning its junctions only sets a floor under the vertex count (a CGAL segmentation
// of a frog stopped at 36% of its vertices with 53,870 pinned corners; the angle alone pins 7,204
// vertices of the liver). A crease that matters at scale H is one the surface cannot lose within
// the tolerance and that a person sees as an edge of the shape:
//   - High. A staircase of step s departs from its mean plane by about s/2 at its edges (the fit
//     of the disk follows the mean slope): steps lower than H are dropped. A straight crease whose
//     faces turn by an angle a departs at the edge by 0.42 r sin(a/2) for two half-disks of radius
//     r (their centroids sit 4r/(3 pi) from the edge): with r = 4H a 45-degree crease departs by
//     0.65H, a box edge by 1.2H.
//   - Sharp. A crease of the shape keeps its angle when each side is averaged over a disk; the
//     creases of a digitized or noisy surface (a tet staircase on a sphere, the bumps of a
//     segmentation) alternate in sign and average out. The disk holds at least the next ring of
//     faces on each side (1.5 x the mean edge length of the crease's faces) so that one jagged
//     facet pair does not decide; a larger disk would wrap around thin tubes (the tori of
//     `generate linked-tori`: 302 corners with 1.5, 2,397 with 3), where the two sides' normals
//     then differ by the tube's own curvature.
//   - Long. A feature curve a person sees runs for a while; isolated short creases (the liver's
//     are 1 to 3 edges long) are noise, and each would add two pinned ends.
//   Measured with the default angle and H (generated meshes of 200k tets): the liver keeps 824 of
//   12,188 creases and pins 422 vertices (7,204 by the angle alone); cube-sphere keeps its box
//   edges and pins 20 (639 by the angle alone); linked-tori 302 (1,336), polycrystal 694 (6,040);
//   a Gmsh L-bracket with a hole and a pocket keeps all of its 394 creases and pins its 20
//   corners. The disk is grown over the surface (faces of one label, across edges with exactly two
//   faces), not in space, so the other side of a thin plate never enters the fit; the faces'
//   normals are oriented consistently as it grows.
// With scale 0 every candidate counts (the angle alone, the rule before issue #23).
//
// Sharp turns. A vertex with two curve edges is an inner point of the curve (order 2): collapses
// along the curve may remove it (a placement on the curve: an endpoint or the midpoint of a curve
// edge, cost.h), so it slides along the curve. That is right for a ridge and wrong at the corner of
// a square hole's rim, where the two edges turn by 90 degrees: the turn is measured between the
// chords to the curve points at distance H on each side (or the last point before a junction), so
// a polygonal circle or a zigzag finer than H is not a turn, and a turn by more than the angle pins
// the vertex.
#include "features/features.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <span>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "kernel/link_condition.h"
#include "parallel/for_range.h"
#include "mesh/probe_set.h"

namespace topotet {
namespace {

constexpr int kKtilde = 1;  // index of the substructure filtration in Neighbour::count / order

// The scale test (file comment), in units of the scale H: the disk's radius, the departure that
// makes a crease high, the length that makes a chain long; and the disk's least radius in edge
// lengths of the crease's faces.
constexpr double kDiskRadius = 4.0;
constexpr double kDepartureFraction = 0.5;
constexpr double kMinChainLength = 4.0;
constexpr double kDiskEdges = 1.5;
// At most this many faces in one disk (a mesh much finer than H): the disk is then the nearest
// part of it, grown in breadth-first order (deterministic), which only shrinks its radius.
constexpr std::size_t kMaxDiskFaces = 4096;

// The angle between the normals of triangles a x y1 and a x y2 is π minus their dihedral angle at
// edge ax, measured between the components of (y - a) orthogonal to ax. A sharp edge has a small
// dihedral angle φ: φ < π - θ, i.e. cos φ > -cos θ. Degenerate triangles decide nothing.
bool is_sharp(const glm::dvec3& a, const glm::dvec3& x, const glm::dvec3& y1, const glm::dvec3& y2,
              double minus_cos_theta) {
  const glm::dvec3 axis = x - a;
  const double len2 = glm::dot(axis, axis);
  if (!(len2 > 0.0)) return false;
  const auto across = [&](const glm::dvec3& y) {
    const glm::dvec3 d = y - a;
    return d - axis * (glm::dot(d, axis) / len2);
  };
  const glm::dvec3 u1 = across(y1), u2 = across(y2);
  const double n1 = glm::length(u1), n2 = glm::length(u2);
  if (!(n1 > 0.0 && n2 > 0.0)) return false;
  return glm::dot(u1, u2) / (n1 * n2) > minus_cos_theta;
}

std::uint64_t edge_key(VertId x, VertId y) {
  return x < y ? (std::uint64_t{x} << 32) | y : (std::uint64_t{y} << 32) | x;
}

// The special faces of the substructure filtration, each once (vertex ids ascending), with their
// label, and the faces of each edge: what the disks of the scale test grow over.
struct Surfaces {
  std::vector<std::array<VertId, 3>> faces;
  std::vector<LinkScratch::Label> labels;                          // [face]
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edge_faces;  // (edge key, face), sorted

  // The faces of edge xy, as a range of edge_faces.
  std::span<const std::pair<std::uint64_t, std::uint32_t>> of_edge(VertId x, VertId y) const {
    const std::uint64_t key = edge_key(x, y);
    const auto lo = std::lower_bound(edge_faces.begin(), edge_faces.end(), std::pair{key, std::uint32_t{0}});
    auto hi = lo;
    while (hi != edge_faces.end() && hi->first == key) ++hi;
    return {lo, hi};
  }
};

// The Surfaces of the special faces found by a parallel scan (in any order: sorted here, so the
// result does not depend on the split).
Surfaces make_surfaces(std::vector<std::pair<std::array<VertId, 3>, LinkScratch::Label>> face_list) {
  std::sort(face_list.begin(), face_list.end(), [](const auto& x, const auto& y) {
    return x.first != y.first ? x.first < y.first : x.second < y.second;
  });
  Surfaces surfaces;
  surfaces.faces.reserve(face_list.size());
  surfaces.labels.reserve(face_list.size());
  for (const auto& [f, label] : face_list) {
    surfaces.faces.push_back(f);
    surfaces.labels.push_back(label);
  }
  std::vector<std::pair<std::array<VertId, 3>, LinkScratch::Label>>().swap(face_list);
  surfaces.edge_faces.reserve(3 * surfaces.faces.size());
  for (std::uint32_t f = 0; f < surfaces.faces.size(); ++f) {
    const auto& v = surfaces.faces[f];
    for (int e = 0; e < 3; ++e) surfaces.edge_faces.push_back({edge_key(v[e], v[(e + 1) % 3]), f});
  }
  std::sort(surfaces.edge_faces.begin(), surfaces.edge_faces.end());
  return surfaces;
}

// A sharp candidate: edge (a, x), a < x, and its two faces' third vertices.
struct Candidate {
  VertId a, x;
  bool operator<(const Candidate& o) const { return a != o.a ? a < o.a : x < o.x; }
};

// The special faces (a, x, y) of classified vertex a with a < x < y: each face once over its vertices.
void append_special_faces(VertId a, const LinkScratch::VertexData& d,
                          std::vector<std::pair<std::array<VertId, 3>, LinkScratch::Label>>& out) {
  for (const auto& s : d.special)
    if (a < s.x && a < s.y) out.push_back({{a, std::min(s.x, s.y), std::max(s.x, s.y)}, s.label});
}

// The candidates at a (edges (a, x) with a < x that are sharp inner edges of one surface), and,
// when `faces` is given, the special faces (a, x, y) with a < x < y.
void scan_vertex(const MeshModel& mesh, VertId a, double minus_cos_theta, LinkScratch& scratch,
                 std::vector<Candidate>& out, std::vector<std::pair<std::array<VertId, 3>, LinkScratch::Label>>* faces,
                 const std::vector<std::int32_t>& skip_refs) {
  LinkScratch::VertexData& d = scratch.a;
  classify_vertex(mesh, a, d, scratch);
  if (faces != nullptr) append_special_faces(a, d, *faces);
  for (const LinkScratch::Neighbour& nb : d.neighbours) {
    if (nb.x < a || nb.polyline || nb.mixed_labels || nb.count[kKtilde] != 2) continue;
    VertId y[2];
    int n = 0;
    bool skipped = false;
    for (const auto& s : d.special) {
      if (s.x == nb.x) y[n++] = s.y;
      else if (s.y == nb.x) y[n++] = s.x;
      else continue;
      skipped = skipped || std::find(skip_refs.begin(), skip_refs.end(), s.label.ref) != skip_refs.end();
      if (n == 2) break;
    }
    if (n == 2 && !skipped && is_sharp(mesh.positions[a], mesh.positions[nb.x], mesh.positions[y[0]], mesh.positions[y[1]],
                           minus_cos_theta))
      out.push_back({a, nb.x});
  }
}

// Per-thread memory of the scale test.
struct DiskScratch {
  std::vector<std::array<VertId, 3>> queue;  // oriented faces, in visiting order
  std::vector<std::uint32_t> queue_ids;
  std::vector<std::uint32_t> slots;  // all empty between calls (cleared slot by slot: 32 KB each)
  std::vector<std::uint32_t> used;   // the slots filled in this call
};

// A crease seen at a scale (measure_crease).
struct CreaseAtScale {
  double departure = 0.0;  // of the edge's midpoint from the disk's plane (mesh units)
  double sides_cos = 1.0;  // cosine of the angle between the mean normals of the two sides
};

// Crease ab on a disk of the surface around it: ab's two faces, and every face of the same label
// reached across edges with exactly two faces that has a vertex within `radius` (at least
// kDiskEdges x the mean edge length of ab's faces) of ab's midpoint. The departure: how far the
// midpoint is from the plane through the area-weighted centroid of the disk's faces, normal to
// their area-weighted (consistently oriented) normal. The sides: a face is on the side of the edge
// face its centroid lies further towards, across the edge.
CreaseAtScale measure_crease(const MeshModel& mesh, const Surfaces& surfaces, VertId a, VertId b, double radius,
                             DiskScratch& s) {
  const auto start = surfaces.of_edge(a, b);
  if (start.size() != 2) return {std::numeric_limits<double>::infinity(), -1.0};
  const glm::dvec3 mid = 0.5 * (mesh.positions[a] + mesh.positions[b]);
  double local = 0.0;  // the mean edge length of the two faces
  for (int k = 0; k < 2; ++k) {
    const auto& f = surfaces.faces[start[k].second];
    for (int e = 0; e < 3; ++e) local += glm::length(mesh.positions[f[e]] - mesh.positions[f[(e + 1) % 3]]);
  }
  local /= 6.0;
  radius = std::max(radius, kDiskEdges * local);
  const double r2 = radius * radius;
  const LinkScratch::Label label = surfaces.labels[start[0].second];
  // The table holds the largest disk, but most disks are a few dozen faces: it is emptied slot by
  // slot after use, not cleared whole before (that memset was 1% of a run's instructions).
  if (s.slots.empty()) s.slots.assign(probe_slots_for(kMaxDiskFaces + 8), ProbeSet<std::uint32_t>::kEmpty);
  ProbeSet<std::uint32_t> seen(s.slots, ProbeSet<std::uint32_t>::AlreadyEmpty{});
  s.used.clear();
  s.queue.clear();
  s.queue_ids.clear();
  // Oriented face: the third vertex of face f opposite edge (p, q), listed so that f runs q -> p
  // (consistent with a neighbour that runs p -> q).
  const auto third = [&](std::uint32_t f, VertId p, VertId q) {
    for (VertId v : surfaces.faces[f])
      if (v != p && v != q) return v;
    return kInvalid;
  };
  const auto push = [&](std::uint32_t f, const std::array<VertId, 3>& oriented) {
    s.used.push_back(seen.insert(f).first);
    s.queue.push_back(oriented);
    s.queue_ids.push_back(f);
  };
  push(start[0].second, {a, b, third(start[0].second, a, b)});
  push(start[1].second, {b, a, third(start[1].second, a, b)});
  const auto near = [&](VertId v) {
    const glm::dvec3 d = mesh.positions[v] - mid;
    return glm::dot(d, d) <= r2;
  };
  for (std::size_t i = 0; i < s.queue.size() && s.queue.size() < kMaxDiskFaces; ++i) {
    const std::array<VertId, 3> f = s.queue[i];
    for (int e = 0; e < 3; ++e) {
      const VertId p = f[e], q = f[(e + 1) % 3];
      const auto across = surfaces.of_edge(p, q);
      if (across.size() != 2) continue;  // a curve of the filtration: the surface ends here
      const std::uint32_t g = across[0].second == s.queue_ids[i] ? across[1].second : across[0].second;
      if (!(surfaces.labels[g] == label) || seen.contains(g)) continue;
      const VertId t = third(g, p, q);
      if (!near(p) && !near(q) && !near(t)) continue;
      push(g, {q, p, t});
      if (s.queue.size() >= kMaxDiskFaces) break;
    }
  }
  seen.erase_slots(s.used);
  const glm::dvec3 pa = mesh.positions[a], axis = mesh.positions[b] - pa;
  const auto across_dir = [&](const glm::dvec3& y) {
    const glm::dvec3 d = y - pa;
    const glm::dvec3 u = d - axis * (glm::dot(d, axis) / glm::dot(axis, axis));
    const double l = glm::length(u);
    return l > 0.0 ? u / l : u;
  };
  const glm::dvec3 u1 = across_dir(mesh.positions[s.queue[0][2]]), u2 = across_dir(mesh.positions[s.queue[1][2]]);
  glm::dvec3 normal(0.0), centroid(0.0), side[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
  double area = 0.0;
  for (std::size_t i = 0; i < s.queue.size(); ++i) {
    const auto& f = s.queue[i];
    const glm::dvec3 p0 = mesh.positions[f[0]], p1 = mesh.positions[f[1]], p2 = mesh.positions[f[2]];
    const glm::dvec3 n = 0.5 * glm::cross(p1 - p0, p2 - p0);
    const double w = glm::length(n);
    const glm::dvec3 c = (p0 + p1 + p2) / 3.0;
    normal += n;
    centroid += w * c;
    area += w;
    side[glm::dot(c - mid, u1) >= glm::dot(c - mid, u2) ? 0 : 1] += n;
  }
  CreaseAtScale out;
  const double l0 = glm::length(side[0]), l1 = glm::length(side[1]);
  out.sides_cos = l0 > 0.0 && l1 > 0.0 ? glm::dot(side[0], side[1]) / (l0 * l1) : 1.0;
  const double n = glm::length(normal);
  if (!(area > 0.0)) return {};  // degenerate faces decide nothing
  out.departure = n > 1e-9 * area ? std::fabs(glm::dot(mid - centroid / area, normal)) / n
                                  : std::numeric_limits<double>::infinity();  // folded onto itself
  return out;
}

// Flags edge ab as a feature curve in every tet that has it (a side table slot is added to tets
// that had none).
void flag_edge(MeshModel& mesh, VertId a, VertId b) {
  mesh.for_each_tet_of(a, [&](TetId t) {
    const auto& v = mesh.tets[t];
    int la = -1, lb = -1;
    for (int k = 0; k < 4; ++k) {
      if (v[k] == a) la = k;
      if (v[k] == b) lb = k;
    }
    if (lb < 0) return;
    const int e = local_edge_index(la, lb);
    if (mesh.tet_refs_slot[t] == kInvalid) {
      mesh.tet_refs_slot[t] = static_cast<std::uint32_t>(mesh.refs_table.size());
      SubstructureRefs r;
      r.face.fill(kImplicitInterfaceRef);
      mesh.refs_table.push_back(r);
    }
    mesh.flags[t] |= TetFlags(1u << (tet_flag::kPolylineEdgeShift + e));
    mesh.refs_table[mesh.tet_refs_slot[t]].edge[e] = kFeatureCurveRef;
  });
}

// The kept feature edges by vertex (both directions, sorted): the curves the turn test walks.
struct Curves {
  std::vector<std::pair<VertId, VertId>> half;  // (from, to), sorted
  std::span<const std::pair<VertId, VertId>> at(VertId v) const {
    const auto lo = std::lower_bound(half.begin(), half.end(), std::pair{v, VertId{0}});
    auto hi = lo;
    while (hi != half.end() && hi->first == v) ++hi;
    return {lo, hi};
  }
};

// Where the curve through v, left towards `next`, is at distance `scale` from v: the first curve
// point at least that far, or the last before a junction or an end (at least `next`).
glm::dvec3 curve_point_at(const MeshModel& mesh, const Curves& curves, VertId v, VertId next, double scale) {
  const glm::dvec3 origin = mesh.positions[v];
  VertId prev = v, cur = next;
  for (int steps = 0; steps < 1024; ++steps) {
    const glm::dvec3 d = mesh.positions[cur] - origin;
    if (glm::dot(d, d) >= scale * scale || cur == v) break;
    const auto out = curves.at(cur);
    if (out.size() != 2) break;
    const VertId after = out[0].second == prev ? out[1].second : out[0].second;
    prev = cur;
    cur = after;
  }
  return mesh.positions[cur];
}

// Both ends of every edge as (vertex, edge index), sorted: the edges at one vertex are adjacent.
std::vector<std::pair<VertId, std::uint32_t>> sorted_ends(const std::vector<Candidate>& edges) {
  std::vector<std::pair<VertId, std::uint32_t>> ends;
  ends.reserve(2 * edges.size());
  for (std::uint32_t i = 0; i < edges.size(); ++i) {
    ends.push_back({edges[i].a, i});
    ends.push_back({edges[i].x, i});
  }
  std::sort(ends.begin(), ends.end());
  return ends;
}

// The total length of the chain of `edges` each edge is on: chains are joined at the vertices
// with exactly two of the edges, and end at the others (ends and junctions). [edge]
std::vector<double> chain_lengths(const MeshModel& mesh, const std::vector<Candidate>& edges) {
  const std::vector<std::pair<VertId, std::uint32_t>> ends = sorted_ends(edges);
  std::vector<std::uint32_t> parent(edges.size());
  for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  const auto root = [&](std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (std::size_t k = 0; k < ends.size();) {
    std::size_t j = k;
    while (j < ends.size() && ends[j].first == ends[k].first) ++j;
    if (j - k == 2) {
      const std::uint32_t r0 = root(ends[k].second), r1 = root(ends[k + 1].second);
      if (r0 != r1) parent[std::max(r0, r1)] = std::min(r0, r1);
    }
    k = j;
  }
  std::vector<double> total(edges.size(), 0.0);
  for (std::uint32_t i = 0; i < edges.size(); ++i)
    total[root(i)] += glm::length(mesh.positions[edges[i].a] - mesh.positions[edges[i].x]);
  std::vector<double> out(edges.size());
  for (std::uint32_t i = 0; i < edges.size(); ++i) out[i] = total[root(i)];
  return out;
}


// Hysteresis (as in Canny's edge detector): a candidate that failed the scale test is kept all
// the same where it continues a kept crease straight on, through a vertex with exactly these two
// candidates that do not turn by more than the angle. Near a corner of the shape the disk takes in
// the third face and the last edge before the corner measures lower and blunter than the rest of
// its crease (the pocket of a machined part: 0.4H and 43 degrees); the curve runs on to the
// corner. Where a staircase meets a real crease of the same surface, its steps near the crease
// measure high too and are continued across: a segmented surface has no such creases, and an
// interface staircase ends on a seam of the boundary (a curve already, not a candidate).
void continue_straight(const MeshModel& mesh, const std::vector<Candidate>& edges, std::vector<char>& keep,
                       double minus_cos_theta) {
  const std::vector<std::pair<VertId, std::uint32_t>> ends = sorted_ends(edges);
  const auto other_end = [&](std::uint32_t e, VertId v) { return edges[e].a == v ? edges[e].x : edges[e].a; };
  std::vector<std::uint32_t> work;
  for (std::uint32_t i = 0; i < edges.size(); ++i)
    if (keep[i]) work.push_back(i);
  while (!work.empty()) {
    const std::uint32_t e = work.back();
    work.pop_back();
    for (VertId v : {edges[e].a, edges[e].x}) {
      const auto lo = std::lower_bound(ends.begin(), ends.end(), std::pair{v, std::uint32_t{0}});
      if (lo + 1 >= ends.end() || lo[1].first != v || (lo + 2 < ends.end() && lo[2].first == v)) continue;
      const std::uint32_t f = lo[0].second == e ? lo[1].second : lo[0].second;
      if (keep[f]) continue;
      const glm::dvec3 p = mesh.positions[v];
      const glm::dvec3 d1 = mesh.positions[other_end(e, v)] - p, d2 = mesh.positions[other_end(f, v)] - p;
      const double l1 = glm::length(d1), l2 = glm::length(d2);
      if (!(l1 > 0.0 && l2 > 0.0) || glm::dot(d1, d2) / (l1 * l2) > minus_cos_theta) continue;  // a turn
      keep[f] = 1;
      work.push_back(f);
    }
  }
}

}  // namespace

FeatureStats detect_features(MeshModel& mesh, double angle_degrees, double scale) {
  return detect_features(mesh, angle_degrees, scale, nullptr);
}

FeatureStats detect_features(MeshModel& mesh, double angle_degrees, double scale,
                             const std::vector<std::uint8_t>* on_special_face, const std::vector<std::int32_t>& skip_refs) {
  FeatureStats stats;
  if (!(angle_degrees < 180.0)) return stats;
  if (!(scale > 0.0) || !std::isfinite(scale)) scale = 0.0;
  const double minus_cos_theta = -std::cos(std::max(angle_degrees, 0.0) * std::numbers::pi / 180.0);
  const std::size_t nv = mesh.vertex_capacity();

  // Found in parallel (reading only), sorted afterwards: the result does not depend on the split.
  std::vector<Candidate> sharp;
  std::vector<std::pair<std::array<VertId, 3>, LinkScratch::Label>> face_list;
  std::mutex merge;
  const bool want_faces = scale > 0.0;
  parallel::for_range<std::size_t>(0, nv, 1024, "detect_features", [&](std::size_t begin, std::size_t end) {
    LinkScratch scratch;
    std::vector<Candidate> local;
    std::vector<std::pair<std::array<VertId, 3>, LinkScratch::Label>> local_faces;
    for (std::size_t i = begin; i < end; ++i) {
      const VertId a = static_cast<VertId>(i);
      if (mesh.is_dead_vertex(a)) continue;
      // Creases are edges between special faces: a vertex on none has no candidate.
      if (on_special_face != nullptr ? !(*on_special_face)[a] : is_interior_vertex(mesh, a)) continue;
      scan_vertex(mesh, a, minus_cos_theta, scratch, local, want_faces ? &local_faces : nullptr, skip_refs);
    }
    const std::lock_guard<std::mutex> lock(merge);
    sharp.insert(sharp.end(), local.begin(), local.end());
    face_list.insert(face_list.end(), local_faces.begin(), local_faces.end());
  });
  std::sort(sharp.begin(), sharp.end());
  stats.candidates = sharp.size();

  // High and sharp at the scale (file comment), in parallel over the candidates.
  if (scale > 0.0 && !sharp.empty()) {
    const Surfaces surfaces = make_surfaces(std::move(face_list));
    std::vector<char> keep(sharp.size(), 0);
    const double radius = kDiskRadius * scale, least = kDepartureFraction * scale;
    parallel::for_range<std::size_t>(0, sharp.size(), 64, "feature_scale", [&](std::size_t begin, std::size_t end) {
      DiskScratch disk;
      for (std::size_t i = begin; i < end; ++i) {
        const CreaseAtScale c = measure_crease(mesh, surfaces, sharp[i].a, sharp[i].x, radius, disk);
        keep[i] = c.departure > least && c.sides_cos < -minus_cos_theta;  // high and sharp
      }
    });
    continue_straight(mesh, sharp, keep, minus_cos_theta);
    std::size_t kept = 0;
    for (std::size_t i = 0; i < sharp.size(); ++i)
      if (keep[i]) sharp[kept++] = sharp[i];
    sharp.resize(kept);
    // Long: drop the chains shorter than kMinChainLength x H. Dropping a chain can only join
    // others (a junction it left may become an inner point), so repeat until none is dropped.
    for (;;) {
      const std::vector<double> length = chain_lengths(mesh, sharp);
      kept = 0;
      for (std::size_t i = 0; i < sharp.size(); ++i)
        if (length[i] >= kMinChainLength * scale) sharp[kept++] = sharp[i];
      if (kept == sharp.size()) break;
      sharp.resize(kept);
    }
  }
  for (const Candidate& c : sharp) flag_edge(mesh, c.a, c.x);
  stats.edges = sharp.size();

  // Corners: the vertices of the new curves that the classification cannot take as an inner
  // curve point (order 3). They would not move anyway (the end of higher order stays); pinning
  // makes it a promise that no later change of their neighbourhood can undo. Then the inner
  // points where the curve turns sharply at the scale (file comment).
  Curves curves;
  curves.half.reserve(2 * sharp.size());
  for (const Candidate& c : sharp) {
    curves.half.push_back({c.a, c.x});
    curves.half.push_back({c.x, c.a});
  }
  std::sort(curves.half.begin(), curves.half.end());
  std::vector<VertId> ends;
  ends.reserve(curves.half.size());
  for (const auto& h : curves.half)
    if (ends.empty() || ends.back() != h.first) ends.push_back(h.first);
  std::vector<char> corner(ends.size(), 0);  // 1 = not an inner curve point, 2 = a sharp turn
  parallel::for_range<std::size_t>(0, ends.size(), 256, "feature_corners", [&](std::size_t begin, std::size_t end) {
    LinkScratch scratch;
    for (std::size_t i = begin; i < end; ++i) {
      const VertId v = ends[i];
      if (mesh.is_pinned(v)) continue;
      if (vertex_orders(mesh, v, scratch).ktilde == 3) {
        corner[i] = 1;
        continue;
      }
      const auto out = curves.at(v);
      if (out.size() != 2) continue;
      const glm::dvec3 p = mesh.positions[v];
      const glm::dvec3 d1 = curve_point_at(mesh, curves, v, out[0].second, scale) - p;
      const glm::dvec3 d2 = curve_point_at(mesh, curves, v, out[1].second, scale) - p;
      const double l1 = glm::length(d1), l2 = glm::length(d2);
      // Straight on: d1 = -d2. A turn by more than the angle: cos(d1, d2) > -cos(angle).
      if (l1 > 0.0 && l2 > 0.0 && glm::dot(d1, d2) / (l1 * l2) > minus_cos_theta) corner[i] = 2;
    }
  });
  for (std::size_t i = 0; i < ends.size(); ++i) {
    if (!corner[i]) continue;
    mesh.vertex_states[ends[i]] |= vertex_state::kPinned | vertex_state::kFeatureCorner;
    ++stats.corners;
    if (corner[i] == 2) ++stats.turns;
  }
  return stats;
}

FeatureStats detect_features(MeshModel& mesh, double angle_degrees) { return detect_features(mesh, angle_degrees, 0.0); }

FeatureDrop drop_features_below(MeshModel& mesh, double angle_degrees, const std::vector<double>& scales) {
  FeatureDrop out;
  const double minus_cos_theta = -std::cos(std::max(angle_degrees, 0.0) * std::numbers::pi / 180.0);
  // The feature edges now, each once (a < x): none, and there is nothing to judge (no scan).
  std::vector<Candidate> edges;
  for (TetId t = 0; t < mesh.tets.size(); ++t) {
    if ((mesh.flags[t] & tet_flag::kDead) || mesh.tet_refs_slot[t] == kInvalid) continue;
    const SubstructureRefs& r = mesh.refs_table[mesh.tet_refs_slot[t]];
    for (int e = 0; e < 6; ++e)
      if (is_polyline_edge(mesh.flags[t], e) && r.edge[e] == kFeatureCurveRef) {
        const VertId x = mesh.tets[t][kTetEdges[e][0]], y = mesh.tets[t][kTetEdges[e][1]];
        edges.push_back({std::min(x, y), std::max(x, y)});
      }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end(), [](const Candidate& p, const Candidate& q) { return p.a == q.a && p.x == q.x; }),
              edges.end());
  out.edges_before = out.edges_after = edges.size();
  if (edges.empty() || scales.empty()) return out;
  // The special faces the disks grow over, found once for every scale tried.
  std::vector<std::pair<std::array<VertId, 3>, LinkScratch::Label>> face_list;
  std::mutex merge;
  parallel::for_range<std::size_t>(0, mesh.vertex_capacity(), 1024, "features_below", [&](std::size_t begin, std::size_t end) {
    LinkScratch scratch;
    std::vector<std::pair<std::array<VertId, 3>, LinkScratch::Label>> local_faces;
    for (std::size_t i = begin; i < end; ++i) {
      const VertId a = static_cast<VertId>(i);
      if (mesh.is_dead_vertex(a) || is_interior_vertex(mesh, a)) continue;
      classify_vertex(mesh, a, scratch.a, scratch);
      append_special_faces(a, scratch.a, local_faces);
    }
    const std::lock_guard<std::mutex> lock(merge);
    face_list.insert(face_list.end(), local_faces.begin(), local_faces.end());
  });
  const Surfaces surfaces = make_surfaces(std::move(face_list));
  const std::vector<double> chain = chain_lengths(mesh, edges);
  // The scale test of detect_features on the mesh as it is, which is within the tolerance of the
  // original: high and sharp on a disk of radius 4H, continued straight on. Two changes, for the
  // curves of a shape smaller than 4H (a box whose edges are a few H long): the disk is at most
  // half the curve's chain long (a larger one wraps around the box's other faces, whose normals
  // then cancel), and a curve that was long at the asked H is not judged on its length again.
  // A staircase of steps s stays as high as s / 2 on any disk, so it goes once H > s; a box edge
  // departs by 0.3 r on a disk of radius r, so it stays until H > 0.6 x its chain's half length.
  // Each scale in turn, until one drops some: nothing changes the mesh before that.
  std::vector<Candidate> kept;
  for (const double scale : scales) {
    std::vector<char> keep(edges.size(), 0);
    const double least = kDepartureFraction * scale;
    parallel::for_range<std::size_t>(0, edges.size(), 64, "features_below_scale", [&](std::size_t begin, std::size_t end) {
      DiskScratch disk;
      for (std::size_t i = begin; i < end; ++i) {
        const double radius = std::min(kDiskRadius * scale, 0.5 * chain[i]);
        const CreaseAtScale c = measure_crease(mesh, surfaces, edges[i].a, edges[i].x, radius, disk);
        keep[i] = c.departure > least && c.sides_cos < -minus_cos_theta;
      }
    });
    continue_straight(mesh, edges, keep, minus_cos_theta);
    kept.clear();
    for (std::size_t i = 0; i < edges.size(); ++i)
      if (keep[i]) kept.push_back(edges[i]);
    if (kept.size() != edges.size()) {
      out.scale = scale;
      break;
    }
  }
  out.edges_after = kept.size();
  if (kept.size() == edges.size()) return out;
  // Unflag the others; unpin the feature corners no kept edge touches (a kept curve keeps its
  // corners: its ends and junctions are where they were).
  const auto is_kept = [&](VertId x, VertId y) {
    const Candidate c{std::min(x, y), std::max(x, y)};
    return std::binary_search(kept.begin(), kept.end(), c);
  };
  std::vector<std::uint8_t> on_kept(mesh.vertex_capacity(), 0);
  for (const Candidate& c : kept) on_kept[c.a] = on_kept[c.x] = 1;
  parallel::for_range<std::size_t>(0, mesh.tets.size(), 4096, "features_below_drop", [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const TetId t = static_cast<TetId>(i);
      if ((mesh.flags[t] & tet_flag::kDead) || mesh.tet_refs_slot[t] == kInvalid) continue;
      const SubstructureRefs& r = mesh.refs_table[mesh.tet_refs_slot[t]];
      for (int e = 0; e < 6; ++e)
        if (is_polyline_edge(mesh.flags[t], e) && r.edge[e] == kFeatureCurveRef &&
            !is_kept(mesh.tets[t][kTetEdges[e][0]], mesh.tets[t][kTetEdges[e][1]]))
          // The flags are the truth (is_polyline_edge): the side table's ref of a cleared edge is
          // left as it is, nothing reads the ref of an edge that is not a polyline edge.
          mesh.flags[t] &= static_cast<TetFlags>(~(TetFlags(1u) << (tet_flag::kPolylineEdgeShift + e)));
    }
  });
  for (VertId v = 0; v < mesh.vertex_capacity(); ++v) {
    std::uint8_t& st = mesh.vertex_states[v];
    if (!(st & vertex_state::kFeatureCorner) || (st & vertex_state::kDead) || on_kept[v]) continue;
    st &= static_cast<std::uint8_t>(~vertex_state::kFeatureCorner);
    // detect_features pins only vertices that were not pinned: unless also listed (kCorner,
    // kRequired), a feature corner was pinned for that reason alone.
    if (!(st & (vertex_state::kCorner | vertex_state::kRequired))) {
      st &= static_cast<std::uint8_t>(~vertex_state::kPinned);
      ++out.unpinned;
    }
  }
  return out;
}

double feature_scale(const MeshModel& mesh, const SimplifyOptions& options) {
  if (options.tolerance > 0.0) return options.tolerance;
  const double diagonal = bounding_box_diagonal(mesh);
  return (options.tolerance_rel > 0.0 ? options.tolerance_rel : kDefaultToleranceRel) * diagonal;
}

}  // namespace topotet
