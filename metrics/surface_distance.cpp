// surface_distance: label the special faces and polylines of both meshes (surface_primitives.cpp),
// put both sides in one Embree scene, sample each side and query the other side's primitives of
// the same label.
//
// The checker keeps its own Embree scene and distance code rather than the simplifier's
// (engine/guarantees/surface_tolerance.h): it is the independent measurement of what that check promises.
//
// Cost. One scene per run (surface_scene.h): a triangle geometry and a segment (user) geometry per
// side, every primitive tagged with its label; every query is seeded with a close primitive (for
// a midpoint, the closest primitives of its piece's corners). Corners are queried once per
// (vertex, label), not once per primitive.
#include "topotet/metrics/surface_distance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>

#include "parallel/for_range.h"
#include "surface_primitives.h"
#include "surface_scene.h"
#include "topotet/error.h"

namespace topotet {
namespace {

using metrics::detail::kPolylineMarker;
using metrics::detail::special_primitives;
using metrics::detail::SurfaceLabel;
using metrics::detail::SurfacePrimitives;
using Side = metrics::detail::SurfaceSide;
using Scene = metrics::detail::SurfaceScene;

constexpr double kInfinity = std::numeric_limits<double>::infinity();


// Adaptive sampling. Two upper bounds of the distance d to the other side over a piece (triangle
// or segment) of a primitive, from its corners c_i with closest primitives Q_i:
//   convex     d(x) <= dist(x, Q_i) for any i, and dist(., Q_i) is convex (Q_i is convex), so
//              d <= min_i max_j dist(c_j, Q_i) on the piece: tight wherever one primitive of the
//              other side covers the piece (the common case: flat and well-matched regions);
//   Lipschitz  d is 1-Lipschitz and every point of a triangle is within L / sqrt(3) of a corner
//              (L its longest edge; L / 2 on a segment): d <= max_i d(c_i) + L / sqrt(3).
// A piece is split at its edge midpoints (4 triangles, 2 segments) while both bounds exceed the
// floor (the largest corner value of the label, or of every label; see surface_distance.h) or
// this primitive's best value by more than the sampling error e = spacing / sqrt(3), and while it
// is longer than `spacing`. So every point's distance is at most e above a reported value (the
// label's, or the overall one), and no reported value exceeds a true distance.
constexpr double kInvSqrt3 = 0.57735026918962576;

struct Sample {
  glm::dvec3 x;
  double d;         // distance to the other side's primitives of the label
  std::uint32_t q;  // the closest of them
};

struct Refiner {
  const Scene& scene;
  int to_side;
  std::uint32_t label;
  bool polyline;
  double spacing, floor;
  double best = 0.0;
  std::size_t samples = 0;

  // The sample at x, a point of the piece whose corners are `near`: their closest primitives
  // bound the search.
  Sample at(const glm::dvec3& x, const Sample* near, int n) {
    ++samples;
    double known2 = kInfinity;
    std::uint32_t known = 0;
    for (int i = 0; i < n; ++i) {
      if (!std::isfinite(near[i].d)) continue;
      const double d2 = scene.squared_distance(to_side, polyline, near[i].q, x);
      if (d2 < known2) known2 = d2, known = near[i].q;
    }
    const Scene::Closest c = scene.closest(to_side, label, polyline, x, known2, known);
    return {x, c.distance, c.index};
  }
  bool settled(const Sample* c, int n, double longest) {
    double top = 0.0;
    for (int i = 0; i < n; ++i) top = std::max(top, c[i].d);
    best = std::max(best, top);
    const double reached = std::max(floor, best) + spacing * kInvSqrt3;
    if (longest <= spacing || top + longest * (n == 3 ? kInvSqrt3 : 0.5) <= reached) return true;
    if (!std::isfinite(top)) return true;  // no primitive of this label on the other side
    const double reached2 = reached * reached;
    for (int i = 0; i < n; ++i) {
      double convex2 = c[i].d * c[i].d;
      for (int j = 0; j < n && convex2 <= reached2; ++j)
        if (j != i) convex2 = std::max(convex2, scene.squared_distance(to_side, polyline, c[i].q, c[j].x));
      if (convex2 <= reached2) return true;
    }
    return false;
  }
  void triangle(const Sample& a, const Sample& b, const Sample& c) {
    const Sample corners[3] = {a, b, c};
    const double longest = std::max({glm::length(b.x - a.x), glm::length(c.x - b.x), glm::length(a.x - c.x)});
    if (settled(corners, 3, longest)) return;
    const Sample ab = at(0.5 * (a.x + b.x), corners, 3), bc = at(0.5 * (b.x + c.x), corners, 3),
                 ca = at(0.5 * (c.x + a.x), corners, 3);
    triangle(a, ab, ca);
    triangle(ab, b, bc);
    triangle(ca, bc, c);
    triangle(ab, bc, ca);
  }
  void segment(const Sample& a, const Sample& b) {
    const Sample ends[2] = {a, b};
    if (settled(ends, 2, glm::length(b.x - a.x))) return;
    const Sample m = at(0.5 * (a.x + b.x), ends, 2);
    segment(a, m);
    segment(m, b);
  }
};

struct Directional {
  std::vector<double> max;           // [label]
  std::vector<std::size_t> samples;  // [label]
};

// Consecutive corner queries of one block seed each other (they are mostly neighbours); blocks
// are fixed, so the answers do not depend on the thread count.
constexpr std::size_t kCornerBlock = 64;

// Samples every primitive of side `from` and measures the distance to the other side's primitives
// of the same label. Separate passes keep the result independent of the thread count: the
// corners, each (vertex, label) once, and the centres of the primitives first (their maxima are
// the pruning floors), then the refinement of each primitive on its own.
Directional one_side(const Scene& scene, const Side& from, int to_side, const std::vector<bool>& is_polyline,
                     double spacing, bool per_label_floor) {
  const std::size_t label_count = is_polyline.size();
  const std::size_t nt = from.prims.triangles.size(), n = nt + from.prims.segments.size();
  const auto label_of = [&](std::size_t i) { return i < nt ? from.triangle_label[i] : from.segment_label[i - nt]; };
  const auto corners = [&](std::size_t i, VertId out[3]) {
    if (i < nt) {
      for (int k = 0; k < 3; ++k) out[k] = from.prims.triangles[i][k];
      return 3;
    }
    out[0] = from.prims.segments[i - nt][0];
    out[1] = from.prims.segments[i - nt][1];
    return 2;
  };

  // Distinct (label, vertex) corners, sorted.
  std::vector<std::uint64_t> keys;
  keys.reserve(3 * nt + 2 * (n - nt));
  for (std::size_t i = 0; i < n; ++i) {
    VertId c[3];
    const int k = corners(i, c);
    for (int j = 0; j < k; ++j) keys.push_back(std::uint64_t{label_of(i)} << 32 | c[j]);
  }
  parallel::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<Sample> corner(keys.size());
  const std::size_t blocks = (keys.size() + kCornerBlock - 1) / kCornerBlock;
  parallel::for_range<std::size_t>(0, blocks, 1, "surface_distance_corners", [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b)
      for (std::size_t k = b * kCornerBlock; k < std::min(keys.size(), (b + 1) * kCornerBlock); ++k) {
        const auto g = static_cast<std::uint32_t>(keys[k] >> 32);
        Refiner r{scene, to_side, g, is_polyline[g], spacing, 0.0};
        const bool has_seed = k > b * kCornerBlock && (keys[k - 1] >> 32) == g;
        corner[k] = r.at(to_glm(from.positions[static_cast<VertId>(keys[k])]), has_seed ? &corner[k - 1] : nullptr,
                         has_seed ? 1 : 0);
      }
  });
  const auto corner_samples = [&](std::size_t i, Sample s[3]) {
    const std::uint32_t g = label_of(i);
    VertId c[3];
    const int k = corners(i, c);
    for (int j = 0; j < k; ++j) {
      const std::uint64_t key = std::uint64_t{g} << 32 | c[j];
      s[j] = corner[static_cast<std::size_t>(std::lower_bound(keys.begin(), keys.end(), key) - keys.begin())];
    }
    return k;
  };

  std::vector<double> floor(label_count, 0.0);
  double overall_floor = 0.0;
  const auto raise_floor = [&](std::uint32_t g, double d) {
    if (!std::isfinite(d)) return;
    floor[g] = std::max(floor[g], d);
    overall_floor = std::max(overall_floor, d);
  };
  for (std::size_t k = 0; k < keys.size(); ++k) raise_floor(static_cast<std::uint32_t>(keys[k] >> 32), corner[k].d);

  // The centre of every primitive that its corners do not settle: where a piece that cuts a
  // corner of the other side is farthest, so the floors get close to the final maxima before the
  // refinement, and little needs refining. (Settled on its corners: the primitive is done.)
  const std::vector<double> corner_floor = floor;
  const double corner_overall_floor = overall_floor;
  constexpr double kNoCentre = -1.0;
  std::vector<Sample> centre(n, Sample{glm::dvec3(0.0), kNoCentre, 0});
  parallel::for_range<std::size_t>(0, n, 256, "surface_distance_centres", [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      Sample s[3];
      const int k = corner_samples(i, s);
      const std::uint32_t g = label_of(i);
      Refiner r{scene, to_side, g, is_polyline[g], spacing, per_label_floor ? corner_floor[g] : corner_overall_floor};
      const double longest = k == 3 ? std::max({glm::length(s[1].x - s[0].x), glm::length(s[2].x - s[1].x),
                                                glm::length(s[0].x - s[2].x)})
                                    : glm::length(s[1].x - s[0].x);
      if (r.settled(s, k, longest)) continue;
      const glm::dvec3 x = k == 3 ? (s[0].x + s[1].x + s[2].x) / 3.0 : 0.5 * (s[0].x + s[1].x);
      centre[i] = r.at(x, s, k);
    }
  });
  for (std::size_t i = 0; i < n; ++i)
    if (centre[i].d != kNoCentre) raise_floor(label_of(i), centre[i].d);

  std::vector<double> prim_max(n, 0.0);
  std::vector<std::size_t> prim_samples(n, 0);
  parallel::for_range<std::size_t>(0, n, 16, "surface_distance_refine", [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const std::uint32_t g = label_of(i);
      Refiner r{scene, to_side, g, is_polyline[g], spacing, per_label_floor ? floor[g] : overall_floor};
      Sample s[3];
      const int k = corner_samples(i, s);
      if (centre[i].d == kNoCentre) {  // settled on its corners
        for (int j = 0; j < k; ++j) r.best = std::max(r.best, s[j].d);
        prim_max[i] = r.best;
        continue;
      }
      r.best = centre[i].d;  // a sample of this primitive: part of its reported maximum
      r.samples = 1;
      if (k == 3)
        r.triangle(s[0], s[1], s[2]);
      else
        r.segment(s[0], s[1]);
      prim_max[i] = r.best;
      prim_samples[i] = r.samples;
    }
  });
  Directional d{std::vector<double>(label_count, 0.0), std::vector<std::size_t>(label_count, 0)};
  for (std::size_t k = 0; k < keys.size(); ++k) ++d.samples[keys[k] >> 32];
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t g = label_of(i);
    d.max[g] = std::max(d.max[g], prim_max[i]);
    d.samples[g] += prim_samples[i];
  }
  return d;
}

double diagonal_of(const std::vector<std::array<double, 3>>& positions) {
  if (positions.empty()) return 0.0;
  glm::dvec3 lo = to_glm(positions[0]), hi = lo;
  for (const std::array<double, 3>& p : positions) {
    lo = glm::min(lo, to_glm(p));
    hi = glm::max(hi, to_glm(p));
  }
  return glm::length(hi - lo);
}

// The spacing: sample_spacing_rel x diagonal, and with pieces_per_triangle > 0 at least the side
// of a square of 1 / pieces_per_triangle of the original's mean special-triangle area.
double sample_spacing(const SurfacePrimitives& original, const std::vector<std::array<double, 3>>& positions, double diagonal,
                      const SurfaceDistanceOptions& options) {
  double spacing = options.sample_spacing_rel * diagonal;
  if (!(spacing > 0.0)) spacing = 1.0;
  if (!(options.pieces_per_triangle > 0.0) || original.triangles.empty()) return spacing;
  double area = 0.0;
  for (const auto& t : original.triangles) {
    const glm::dvec3 a = to_glm(positions[t[0]]), b = to_glm(positions[t[1]]), c = to_glm(positions[t[2]]);
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  const double mean_area = area / static_cast<double>(original.triangles.size());
  const double resolution = std::sqrt(mean_area / options.pieces_per_triangle);
  return std::isfinite(resolution) ? std::max(spacing, resolution) : spacing;
}

// Label index of every primitive, and the primitive count of each label.
void assign_labels(Side& side, const std::vector<SurfaceLabel>& labels) {
  const auto index_of = [&](const SurfaceLabel& l) {
    return static_cast<std::uint32_t>(std::lower_bound(labels.begin(), labels.end(), l) - labels.begin());
  };
  side.label_primitives.assign(labels.size(), 0);
  side.label_first.assign(labels.size(), 0);
  for (const auto* from : {&side.prims.triangle_label, &side.prims.segment_label}) {
    auto& to = from == &side.prims.triangle_label ? side.triangle_label : side.segment_label;
    to.resize(from->size());
    for (std::size_t i = 0; i < from->size(); ++i) {
      to[i] = index_of((*from)[i]);
      if (side.label_primitives[to[i]]++ == 0) side.label_first[to[i]] = static_cast<std::uint32_t>(i);
    }
  }
}

}  // namespace

std::string LabelDistance::name() const {
  const auto ref_text = [&] { return ref == kSurfaceUnlistedRef ? std::string() : "ref " + std::to_string(ref) + " "; };
  if (polyline) return "polyline ref " + std::to_string(ref);
  if (material_low == kSurfaceOutside) return "boundary " + ref_text() + "(material " + std::to_string(material_high) + ")";
  if (material_low == kSurfaceNoMaterial) return "surface " + ref_text() + "(no tet)";
  if (material_low == material_high) return "surface " + ref_text() + "(in material " + std::to_string(material_low) + ")";
  return "interface " + ref_text() + "(materials " + std::to_string(material_low) + "|" + std::to_string(material_high) + ")";
}

SurfaceDistance surface_distance(const MeshData& original, const MeshData& simplified,
                                 const SurfaceDistanceOptions& options) {
  Side a{original.positions, special_primitives(original, "original"), {}, {}, {}};
  Side b{simplified.positions, special_primitives(simplified, "simplified"), {}, {}, {}};
  SurfaceDistance result;
  result.diagonal = diagonal_of(original.positions);
  result.sample_spacing = sample_spacing(a.prims, original.positions, result.diagonal, options);
  result.sampling_error = result.sample_spacing / std::sqrt(3.0);

  std::vector<SurfaceLabel> labels;
  for (const Side* s : {&a, &b}) {
    labels.insert(labels.end(), s->prims.triangle_label.begin(), s->prims.triangle_label.end());
    labels.insert(labels.end(), s->prims.segment_label.begin(), s->prims.segment_label.end());
  }
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  assign_labels(a, labels);
  assign_labels(b, labels);
  std::vector<bool> is_polyline(labels.size());
  for (std::size_t g = 0; g < labels.size(); ++g) is_polyline[g] = labels[g][1] == kPolylineMarker;

  const Scene scene({&a, &b});
  const Directional ab = one_side(scene, a, 1, is_polyline, result.sample_spacing, options.per_label_accuracy);
  const Directional ba = one_side(scene, b, 0, is_polyline, result.sample_spacing, options.per_label_accuracy);

  for (std::size_t g = 0; g < labels.size(); ++g) {
    LabelDistance d;
    d.polyline = is_polyline[g];
    d.ref = labels[g][0];
    if (!d.polyline) {
      d.material_low = labels[g][1];
      d.material_high = labels[g][2];
    }
    d.original_primitives = a.label_primitives[g];
    d.simplified_primitives = b.label_primitives[g];
    d.original_samples = ab.samples[g];
    d.simplified_samples = ba.samples[g];
    const bool matched = d.original_primitives != 0 && d.simplified_primitives != 0;
    d.original_to_simplified = matched ? ab.max[g] : kInfinity;
    d.simplified_to_original = matched ? ba.max[g] : kInfinity;
    d.hausdorff = std::max(d.original_to_simplified, d.simplified_to_original);
    result.unmatched_labels += matched ? 0 : 1;
    result.original_to_simplified = std::max(result.original_to_simplified, d.original_to_simplified);
    result.simplified_to_original = std::max(result.simplified_to_original, d.simplified_to_original);
    result.samples += d.original_samples + d.simplified_samples;
    result.labels.push_back(d);
  }
  result.hausdorff = std::max(result.original_to_simplified, result.simplified_to_original);
  return result;
}

}  // namespace topotet
