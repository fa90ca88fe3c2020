// surface_distance: label the special faces and polylines of both meshes, put each side in an
// Embree scene (one geometry per label), sample the other side and query.
//
// The checker keeps its own Embree scene and distance code rather than the simplifier's
// (engine/surface_tolerance.h): it is the independent measurement of what that check promises.
#include "topotet/metrics/surface_distance.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include "parallel/for_range.h"
#include "topotet/error.h"

namespace topotet {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// (ref, m0, m1) for faces; (ref, polyline marker, 0) for polylines: one key type for both.
using Label = std::array<std::int32_t, 3>;
constexpr std::int32_t kPolylineMarker = INT32_MAX;

struct Primitives {
  std::vector<std::array<VertId, 3>> triangles;
  std::vector<Label> triangle_label;
  std::vector<std::array<VertId, 2>> segments;
  std::vector<Label> segment_label;
};

// The special faces (each once) and the listed segments of a mesh, with their labels.
Primitives special_primitives(const MeshData& m, const char* which) {
  const std::size_t nv = m.vertex_count();
  auto check = [&](VertId x) {
    if (x >= nv) throw InputError(std::string("surface_distance: ") + which + ": vertex index out of range");
  };
  struct Rec {
    std::array<VertId, 3> key;
    std::uint32_t owner;  // tet id, or tets + listed triangle id
    bool operator<(const Rec& o) const { return key != o.key ? key < o.key : owner < o.owner; }
  };
  const std::size_t nt = m.tet_count();
  std::vector<Rec> recs(4 * nt + m.triangles.size());
  parallel::for_range<std::size_t>(0, nt, 4096, "surface_faces", [&](std::size_t b, std::size_t e) {
    for (std::size_t t = b; t < e; ++t)
      for (int f = 0; f < 4; ++f) {
        std::array<VertId, 3> k{};
        for (int j = 0, n = 0; j < 4; ++j)
          if (j != f) k[n++] = m.tets[t][j];
        std::sort(k.begin(), k.end());
        recs[4 * t + f] = {k, static_cast<std::uint32_t>(t)};
      }
  });
  for (const auto& tet : m.tets)
    for (VertId x : tet) check(x);
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    std::array<VertId, 3> k = m.triangles[i].v;
    for (VertId x : k) check(x);
    std::sort(k.begin(), k.end());
    recs[4 * nt + i] = {k, static_cast<std::uint32_t>(nt + i)};
  }
  parallel::sort(recs.begin(), recs.end());
  const auto material = [&](std::size_t t) { return m.tet_material.empty() ? 0 : m.tet_material[t]; };

  Primitives out;
  for (std::size_t i = 0; i < recs.size();) {
    std::size_t j = i + 1;
    while (j < recs.size() && recs[j].key == recs[i].key) ++j;
    std::int32_t ref = kSurfaceUnlistedRef;
    bool listed = false;
    std::vector<std::int32_t> mats;
    for (std::size_t k = i; k < j; ++k) {
      if (recs[k].owner >= nt) {
        const std::int32_t r = m.triangles[recs[k].owner - nt].ref;
        ref = listed ? std::max(ref, r) : r;
        listed = true;
      } else {
        mats.push_back(material(recs[k].owner));
      }
    }
    Label label{};
    bool special = listed;
    if (mats.empty()) {
      label = {ref, kSurfaceNoMaterial, kSurfaceNoMaterial};
    } else if (mats.size() == 1) {
      label = {ref, kSurfaceOutside, mats[0]};  // kSurfaceOutside is the smallest int32
      special = true;
    } else {
      label = {ref, std::min(mats[0], mats[1]), std::max(mats[0], mats[1])};
      special = special || mats[0] != mats[1];
    }
    if (special) {
      out.triangles.push_back(recs[i].key);
      out.triangle_label.push_back(label);
    }
    i = j;
  }
  // Segments: each (edge, ref) once.
  std::vector<std::pair<std::array<VertId, 2>, std::int32_t>> segs;
  for (const Segment& s : m.segments) {
    check(s.v[0]);
    check(s.v[1]);
    segs.push_back({{std::min(s.v[0], s.v[1]), std::max(s.v[0], s.v[1])}, s.ref});
  }
  std::sort(segs.begin(), segs.end());
  segs.erase(std::unique(segs.begin(), segs.end()), segs.end());
  for (const auto& [v, ref] : segs) {
    out.segments.push_back(v);
    out.segment_label.push_back({ref, kPolylineMarker, 0});
  }
  return out;
}

double squared_distance_to_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  const glm::dvec3 d = p - (a + ab * t);
  return glm::dot(d, d);
}

// Closest point on a triangle by its barycentric region (Ericson, Real-Time Collision Detection 5.1.5).
double squared_distance_to_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                    const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  auto sq = [&](const glm::dvec3& q) { return glm::dot(p - q, p - q); };
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return sq(a);
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return sq(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return sq(a + ab * (d1 / (d1 - d3)));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return sq(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return sq(a + ac * (d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return sq(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denom = va + vb + vc;
  if (!(denom > 0.0))
    return std::min({squared_distance_to_segment(p, a, b), squared_distance_to_segment(p, b, c),
                     squared_distance_to_segment(p, a, c)});
  return sq(a + ab * (vb / denom) + ac * (vc / denom));
}

// One side's primitives in an Embree scene; geometry g = label index g (triangles) or
// face labels + polyline index (segments, as a user geometry).
class Scene {
 public:
  Scene(const std::vector<glm::dvec3>& positions, const Primitives& prims, const std::vector<Label>& labels)
      : positions_(positions), prims_(prims) {
    double max_abs = 0.0;
    vertices_.resize(3 * positions.size() + 1, 0.0f);
    for (std::size_t i = 0; i < positions.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        vertices_[3 * i + k] = static_cast<float>(positions[i][k]);
        max_abs = std::max(max_abs, std::abs(positions[i][k]));
      }
    slack_ = 8.0 * FLT_EPSILON * std::max(max_abs, 1e-30);
    const auto geometry_of = [&](const Label& l) {
      return static_cast<std::uint32_t>(std::lower_bound(labels.begin(), labels.end(), l) - labels.begin());
    };
    primitives_.assign(labels.size(), {});
    indices_.assign(labels.size(), {});
    is_segment_.assign(labels.size(), false);
    for (std::uint32_t t = 0; t < prims.triangles.size(); ++t) {
      const std::uint32_t g = geometry_of(prims.triangle_label[t]);
      primitives_[g].push_back(t);
      for (VertId x : prims.triangles[t]) indices_[g].push_back(x);
    }
    for (std::uint32_t s = 0; s < prims.segments.size(); ++s) {
      const std::uint32_t g = geometry_of(prims.segment_label[s]);
      primitives_[g].push_back(s);
      is_segment_[g] = true;
    }
    segment_users_.reserve(labels.size());  // no reallocation: Embree keeps the pointers
    device_ = rtcNewDevice(nullptr);
    if (device_ == nullptr) throw std::runtime_error("Embree: cannot create a device");
    scene_ = rtcNewScene(device_);
    for (std::uint32_t g = 0; g < labels.size(); ++g) {
      RTCGeometry geom;
      if (!is_segment_[g]) {
        geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices_.data(), 0,
                                   3 * sizeof(float), positions.size());
        indices_[g].push_back(0);  // padding for Embree's wide loads
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices_[g].data(), 0,
                                   3 * sizeof(std::uint32_t), primitives_[g].size());
      } else {
        geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(geom, static_cast<unsigned>(primitives_[g].size()));
        rtcSetGeometryUserData(geom, &segment_users_.emplace_back(SegmentUser{this, g}));
        rtcSetGeometryBoundsFunction(geom, &Scene::segment_bounds, nullptr);
      }
      rtcCommitGeometry(geom);
      rtcAttachGeometryByID(scene_, geom, g);
      rtcReleaseGeometry(geom);
    }
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw std::runtime_error("Embree: building the scene failed");
  }
  ~Scene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  bool has(std::uint32_t g) const { return g < primitives_.size() && !primitives_[g].empty(); }

  struct Closest {
    double distance;      // +infinity if geometry g has no primitive
    std::uint32_t index;  // the closest primitive: its index in the geometry
  };
  // The closest primitive of geometry g to p.
  Closest closest(const glm::dvec3& p, std::uint32_t g) const {
    if (!has(g)) return {kInfinity, 0};
    Query q{this, g, p, kInfinity, 0};
    RTCPointQuery query;
    query.x = static_cast<float>(p.x);
    query.y = static_cast<float>(p.y);
    query.z = static_cast<float>(p.z);
    query.time = 0.0f;
    query.radius = std::numeric_limits<float>::infinity();
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(scene_, &query, &context, &Scene::on_primitive, &q);
    return {std::sqrt(q.best2), q.best_index};
  }

  // Distance from p to primitive `index` of geometry g.
  double distance_to(const glm::dvec3& p, std::uint32_t g, std::uint32_t index) const {
    return std::sqrt(squared_distance(p, g, primitives_[g][index]));
  }

 private:
  struct Query {
    const Scene* scene;
    std::uint32_t geometry;
    glm::dvec3 p;
    double best2;
    std::uint32_t best_index;
  };

  double squared_distance(const glm::dvec3& p, std::uint32_t g, std::uint32_t k) const {
    const auto& P = positions_;
    if (is_segment_[g]) {
      const auto& e = prims_.segments[k];
      return squared_distance_to_segment(p, P[e[0]], P[e[1]]);
    }
    const auto& t = prims_.triangles[k];
    return squared_distance_to_triangle(p, P[t[0]], P[t[1]], P[t[2]]);
  }

  struct SegmentUser {  // user data of one segment geometry
    const Scene* scene;
    std::uint32_t geometry;
  };

  static void segment_bounds(const RTCBoundsFunctionArguments* args) {
    const auto* user = static_cast<const SegmentUser*>(args->geometryUserPtr);
    const Scene& s = *user->scene;
    const auto& e = s.prims_.segments[s.primitives_[user->geometry][args->primID]];
    const float* a = &s.vertices_[3 * std::size_t{e[0]}];
    const float* b = &s.vertices_[3 * std::size_t{e[1]}];
    RTCBounds* o = args->bounds_o;
    o->lower_x = std::min(a[0], b[0]);
    o->lower_y = std::min(a[1], b[1]);
    o->lower_z = std::min(a[2], b[2]);
    o->upper_x = std::max(a[0], b[0]);
    o->upper_y = std::max(a[1], b[1]);
    o->upper_z = std::max(a[2], b[2]);
  }

  static bool on_primitive(RTCPointQueryFunctionArguments* args) {
    auto* q = static_cast<Query*>(args->userPtr);
    if (args->geomID != q->geometry) return false;  // another label
    const Scene& s = *q->scene;
    const double d2 = s.squared_distance(q->p, q->geometry, s.primitives_[q->geometry][args->primID]);
    if (!(d2 < q->best2)) return false;
    q->best2 = d2;
    q->best_index = args->primID;
    args->query->radius =
        std::nextafter(static_cast<float>(std::sqrt(d2) + s.slack_), std::numeric_limits<float>::infinity());
    return true;
  }

  const std::vector<glm::dvec3>& positions_;
  const Primitives& prims_;
  std::vector<float> vertices_;
  std::vector<std::vector<std::uint32_t>> primitives_, indices_;
  std::vector<bool> is_segment_;
  std::vector<SegmentUser> segment_users_;
  double slack_ = 0.0;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

// Adaptive sampling. Two upper bounds of the distance d to the other side over a piece (triangle
// or segment) of a primitive, from its corners c_i with closest primitives Q_i:
//   convex     d(x) <= dist(x, Q_i) for any i, and dist(., Q_i) is convex (Q_i is convex), so
//              d <= min_i max_j dist(c_j, Q_i) on the piece: tight wherever one primitive of the
//              other side covers the piece (the common case: flat and well-matched regions);
//   Lipschitz  d is 1-Lipschitz and every point of a triangle is within L / sqrt(3) of a corner
//              (L its longest edge; L / 2 on a segment): d <= max_i d(c_i) + L / sqrt(3).
// A piece is split at its edge midpoints (4 triangles, 2 segments) while both bounds exceed the
// largest value already reached (the label's largest corner value, or this primitive's best) by
// more than the sampling error e = spacing / sqrt(3), and while it is longer than `spacing`. So
// the reported maximum is at most e below the true supremum, and never above it.
constexpr double kInvSqrt3 = 0.57735026918962576;

struct Refiner {
  const Scene& to;
  std::uint32_t geometry;
  double spacing, floor;
  double best = 0.0;
  std::size_t samples = 0;

  struct Sample {
    glm::dvec3 x;
    double d;
    std::uint32_t q;  // closest primitive of the other side
  };
  Sample at(const glm::dvec3& x) {
    ++samples;
    const Scene::Closest c = to.closest(x, geometry);
    return {x, c.distance, c.index};
  }
  bool settled(const Sample* c, int n, double longest) {
    double top = 0.0;
    for (int i = 0; i < n; ++i) top = std::max(top, c[i].d);
    best = std::max(best, top);
    const double known = std::max(floor, best) + spacing * kInvSqrt3;
    if (longest <= spacing || top + longest * (n == 3 ? kInvSqrt3 : 0.5) <= known) return true;
    if (!std::isfinite(top)) return true;  // no primitive of this label on the other side
    for (int i = 0; i < n; ++i) {
      double convex = c[i].d;
      for (int j = 0; j < n && convex <= known; ++j)
        if (j != i) convex = std::max(convex, to.distance_to(c[j].x, geometry, c[i].q));
      if (convex <= known) return true;
    }
    return false;
  }
  void triangle(const Sample& a, const Sample& b, const Sample& c) {
    const Sample corners[3] = {a, b, c};
    const double longest = std::max({glm::length(b.x - a.x), glm::length(c.x - b.x), glm::length(a.x - c.x)});
    if (settled(corners, 3, longest)) return;
    const Sample ab = at(0.5 * (a.x + b.x)), bc = at(0.5 * (b.x + c.x)), ca = at(0.5 * (c.x + a.x));
    triangle(a, ab, ca);
    triangle(ab, b, bc);
    triangle(ca, bc, c);
    triangle(ab, bc, ca);
  }
  void segment(const Sample& a, const Sample& b) {
    const Sample ends[2] = {a, b};
    if (settled(ends, 2, glm::length(b.x - a.x))) return;
    const Sample m = at(0.5 * (a.x + b.x));
    segment(a, m);
    segment(m, b);
  }
};

struct Directional {
  std::vector<double> max;            // [label]
  std::vector<std::size_t> samples;   // [label]
};

// Samples every primitive of `from` and measures the distance to `to` of the same label. Two
// passes keep the result independent of the thread count: the corners first (their maximum per
// label is the pruning floor), then the refinement of each primitive on its own.
Directional one_side(const std::vector<glm::dvec3>& from_positions, const Primitives& from, const Scene& to,
                     const std::vector<Label>& labels, double spacing) {
  const auto geometry_of = [&](const Label& l) {
    return static_cast<std::uint32_t>(std::lower_bound(labels.begin(), labels.end(), l) - labels.begin());
  };
  const std::size_t nt = from.triangles.size(), n = nt + from.segments.size();
  const auto& P = from_positions;
  const auto corners = [&](std::size_t i, VertId out[3]) {
    if (i < nt) {
      for (int k = 0; k < 3; ++k) out[k] = from.triangles[i][k];
      return 3;
    }
    out[0] = from.segments[i - nt][0];
    out[1] = from.segments[i - nt][1];
    return 2;
  };
  const auto label_of = [&](std::size_t i) {
    return geometry_of(i < nt ? from.triangle_label[i] : from.segment_label[i - nt]);
  };
  std::vector<std::array<Refiner::Sample, 3>> corner(n);
  parallel::for_range<std::size_t>(0, n, 512, "surface_distance_corners", [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      VertId c[3];
      const int k = corners(i, c);
      Refiner r{to, label_of(i), spacing, 0.0};
      for (int j = 0; j < k; ++j) corner[i][j] = r.at(P[c[j]]);
    }
  });
  std::vector<double> floor(labels.size(), 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t g = label_of(i);
    for (int j = 0; j < (i < nt ? 3 : 2); ++j)
      if (std::isfinite(corner[i][j].d)) floor[g] = std::max(floor[g], corner[i][j].d);
  }
  std::vector<double> prim_max(n, 0.0);
  std::vector<std::size_t> prim_samples(n, 0);
  parallel::for_range<std::size_t>(0, n, 64, "surface_distance_refine", [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      Refiner r{to, label_of(i), spacing, floor[label_of(i)]};
      r.samples = i < nt ? 3 : 2;
      if (i < nt)
        r.triangle(corner[i][0], corner[i][1], corner[i][2]);
      else
        r.segment(corner[i][0], corner[i][1]);
      prim_max[i] = r.best;
      prim_samples[i] = r.samples;
    }
  });
  Directional d{std::vector<double>(labels.size(), 0.0), std::vector<std::size_t>(labels.size(), 0)};
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t g = label_of(i);
    d.max[g] = std::max(d.max[g], prim_max[i]);
    d.samples[g] += prim_samples[i];
  }
  return d;
}

double diagonal_of(const std::vector<glm::dvec3>& positions) {
  if (positions.empty()) return 0.0;
  glm::dvec3 lo = positions[0], hi = positions[0];
  for (const glm::dvec3& p : positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return glm::length(hi - lo);
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
  SurfaceDistance result;
  result.diagonal = diagonal_of(original.positions);
  result.sample_spacing = options.sample_spacing_rel * result.diagonal;
  if (!(result.sample_spacing > 0.0)) result.sample_spacing = 1.0;
  result.sampling_error = result.sample_spacing / std::sqrt(3.0);

  const Primitives a = special_primitives(original, "original");
  const Primitives b = special_primitives(simplified, "simplified");
  std::vector<Label> labels;
  for (const Primitives* p : {&a, &b}) {
    labels.insert(labels.end(), p->triangle_label.begin(), p->triangle_label.end());
    labels.insert(labels.end(), p->segment_label.begin(), p->segment_label.end());
  }
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());

  const Scene scene_a(original.positions, a, labels), scene_b(simplified.positions, b, labels);
  const Directional ab = one_side(original.positions, a, scene_b, labels, result.sample_spacing);
  const Directional ba = one_side(simplified.positions, b, scene_a, labels, result.sample_spacing);

  for (std::size_t g = 0; g < labels.size(); ++g) {
    LabelDistance d;
    d.polyline = labels[g][1] == kPolylineMarker;
    d.ref = labels[g][0];
    if (!d.polyline) {
      d.material_low = labels[g][1];
      d.material_high = labels[g][2];
    }
    const auto count = [&](const Primitives& p) {
      return static_cast<std::size_t>(std::count(p.triangle_label.begin(), p.triangle_label.end(), labels[g]) +
                                      std::count(p.segment_label.begin(), p.segment_label.end(), labels[g]));
    };
    d.original_primitives = count(a);
    d.simplified_primitives = count(b);
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
