// The original surfaces as an Embree scene, and the kernel's tolerance check (see surface_tolerance.h).
#include "guarantees/surface_tolerance.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include "guarantees/facet_cover.h"
#include "guarantees/flat_patches.h"
#include "mesh/probe_set.h"
#include "mesh/special_faces.h"
#include "parallel/for_range.h"

namespace topotet {

// ---------------------------------------------------------------- exact distances

// Ericson, Real-Time Collision Detection, 5.1.5: the closest point by Voronoi regions.
double squared_distance_to_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                    const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  auto sq = [&](const glm::dvec3& q) { return glm::dot(p - q, p - q); };
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
  if (!(denom > 0.0)) {  // degenerate triangle: the closest of its edges
    return std::min({squared_distance_to_segment(p, a, b), squared_distance_to_segment(p, b, c),
                     squared_distance_to_segment(p, a, c)});
  }
  return sq(a + ab * (vb / denom) + ac * (vc / denom));
}

glm::dvec3 crease_normal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& o1, const glm::dvec3& o2) {
  const glm::dvec3 ab = b - a;
  const double ab2 = glm::dot(ab, ab);
  if (!(ab2 > 0.0)) return glm::dvec3(0.0);
  const auto inward = [&](const glm::dvec3& o) {
    const glm::dvec3 w = (o - a) - ab * (glm::dot(o - a, ab) / ab2);
    const double l = glm::length(w);
    return l > 0.0 ? w / l : glm::dvec3(0.0);
  };
  return inward(o1) - inward(o2);
}

double squared_distance_to_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  double t = len2 > 0.0 ? glm::dot(p - a, ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const glm::dvec3 d = p - (a + ab * t);
  return glm::dot(d, d);
}

// ---------------------------------------------------------------- Embree scene

namespace {

struct SegmentGeometry {  // user data of one polyline geometry
  const std::vector<float>* vertices;
  const std::vector<std::array<VertId, 2>>* segments;
  const std::vector<std::uint32_t>* primitives;
};

}  // namespace

struct SurfaceReference::Embree {
  RTCDevice device = nullptr;
  // A label (geometry) with many primitives has a scene of its own, so that its queries visit
  // its primitives only: in one shared scene a query also visited every coincident or nearby
  // primitive of the other labels to filter it out (a listed surface on an interface: 56% of the
  // visits on sphere3). The small labels share one scene: a scene costs some kilobytes however
  // small (polycrystal 1M, thousands of grain interfaces: +17 bytes per tet with a scene each).
  std::vector<RTCScene> scenes;
  std::vector<std::uint32_t> scene_index;  // [label] index into scenes
  std::vector<unsigned> geometry_id;       // [label] its geometry's id in that scene
  RTCScene scene_of(int label) const { return scenes[scene_index[static_cast<std::size_t>(label)]]; }
  unsigned geometry_id_of(int label) const { return geometry_id[static_cast<std::size_t>(label)]; }
  std::vector<float> vertices;                        // xyz per vertex, +1 float of padding
  std::vector<std::vector<std::uint32_t>> indices;    // [face label] triangle vertex triples
  std::vector<std::vector<std::uint32_t>> primitives; // [geometry] primID -> soup triangle/segment
  std::vector<SegmentGeometry> segment_data;          // [polyline label] user data
  // Flat patches (build_flat_patches): their boundary edges as one user geometry in a scene of
  // their own, filtered by patch in the callback.
  RTCScene patch_scene = nullptr;
  std::vector<std::vector<std::uint32_t>> patch_primitives;  // [0] primID -> boundary edge
  std::vector<SegmentGeometry> patch_data;
  ~Embree() {
    if (patch_scene != nullptr) rtcReleaseScene(patch_scene);
    for (RTCScene s : scenes)
      if (s != nullptr) rtcReleaseScene(s);
    if (device != nullptr) rtcReleaseDevice(device);
  }
};

namespace {

void segment_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* g = static_cast<const SegmentGeometry*>(args->geometryUserPtr);
  const auto& s = (*g->segments)[(*g->primitives)[args->primID]];
  const float* a = &(*g->vertices)[3 * std::size_t{s[0]}];
  const float* b = &(*g->vertices)[3 * std::size_t{s[1]}];
  RTCBounds* o = args->bounds_o;
  o->lower_x = std::min(a[0], b[0]);
  o->lower_y = std::min(a[1], b[1]);
  o->lower_z = std::min(a[2], b[2]);
  o->upper_x = std::max(a[0], b[0]);
  o->upper_y = std::max(a[1], b[1]);
  o->upper_z = std::max(a[2], b[2]);
}

// The shadow of a piece of a new triangle on a patch plane, in 2D coordinates of the plane (see
// SurfaceReference::within_by_patch): does a segment's shadow enter it deeper than eps?
struct ShadowTriangle {
  glm::dvec3 origin, e1, e2;              // the plane's frame
  std::array<std::array<double, 2>, 3> t;  // the piece's corners, counter-clockwise
  std::array<std::array<double, 3>, 3> edge;  // unit inward normal (x, y) and offset per edge
  double eps;
  std::array<double, 2> to2d(const glm::dvec3& x) const {
    return {glm::dot(x - origin, e1), glm::dot(x - origin, e2)};
  }
  // Clips the segment to the triangle shrunk by eps (Cyrus-Beck): anything left enters it.
  bool entered_by(const glm::dvec3& a3, const glm::dvec3& b3) const {
    const auto a = to2d(a3), b = to2d(b3);
    double lo = 0.0, hi = 1.0;
    for (const auto& e : edge) {
      const double da = e[0] * a[0] + e[1] * a[1] - e[2] - eps;  // >= 0 inside
      const double db = e[0] * b[0] + e[1] * b[1] - e[2] - eps;
      if (da < 0.0 && db < 0.0) return false;
      if (da < 0.0) lo = std::max(lo, da / (da - db));
      if (db < 0.0) hi = std::min(hi, da / (da - db));
      if (lo > hi) return false;
    }
    return true;
  }
};

// State of one query, on the caller's stack (this is what makes queries thread-safe).
struct Query {
  const SurfaceSoup* soup;
  const std::vector<std::vector<std::uint32_t>>* primitives;
  unsigned geometry;  // the label: index into `primitives`
  bool is_segment;
  glm::dvec3 p;
  double best2;        // squared distance to beat (within: h^2, inclusive)
  double slack;
  bool stop_at_first;  // within(): any hit answers the question
  bool found = false;
  std::uint32_t best_primitive = kInvalid;  // soup triangle (segment) of the best hit
  // Patch boundary queries: the segments are the patches' boundary edges, only those of `patch`.
  const std::vector<std::array<VertId, 2>>* segments = nullptr;
  const std::vector<std::uint32_t>* segment_patch = nullptr;
  std::uint32_t patch = 0;
  // within_by_patch: a boundary edge counts only if its shadow enters the piece's shadow.
  const struct ShadowTriangle* shadow = nullptr;
  // within_one(): the primitive must be within sqrt(best2) of each of these points, not of p.
  const glm::dvec3* corners = nullptr;
  int corner_count = 0;
  unsigned geometry_id = 0;  // the label's geometry id in the scene searched (others are filtered out)
};

float radius_for(double distance, double slack) {
  return std::nextafter(static_cast<float>(distance + slack), std::numeric_limits<float>::infinity());
}

bool on_primitive(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<Query*>(args->userPtr);
  if (args->geomID != q->geometry_id) return false;  // another label sharing the scene
  const std::uint32_t k = (*q->primitives)[q->geometry][args->primID];
  const auto& P = q->soup->positions;
  if (q->segment_patch != nullptr && (*q->segment_patch)[k] != q->patch) return false;
  if (q->shadow != nullptr) {
    const auto& sg = (*q->segments)[k];
    if (!q->shadow->entered_by(P[sg[0]], P[sg[1]])) return false;
    q->found = true;
    args->query->radius = 0.0f;
    return true;
  }
  if (q->corners != nullptr) {
    for (int i = 0; i < q->corner_count; ++i) {
      double d2;
      if (q->is_segment) {
        const auto& sg = q->soup->segments[k];
        d2 = squared_distance_to_segment(q->corners[i], P[sg[0]], P[sg[1]]);
      } else {
        const auto& t = q->soup->triangles[k];
        d2 = squared_distance_to_triangle(q->corners[i], P[t[0]], P[t[1]], P[t[2]]);
      }
      if (d2 > q->best2) return false;
    }
    q->found = true;
    args->query->radius = 0.0f;
    return true;
  }
  double d2;
  if (q->is_segment) {
    const auto& s = (q->segments != nullptr ? *q->segments : q->soup->segments)[k];
    d2 = squared_distance_to_segment(q->p, P[s[0]], P[s[1]]);
  } else {
    const auto& t = q->soup->triangles[k];
    d2 = squared_distance_to_triangle(q->p, P[t[0]], P[t[1]], P[t[2]]);
  }
  // Ties go to the lower primitive index: the nearest primitive is then one function of the query
  // (the lexicographic minimum of distance and index), whatever the visiting order or a hint.
  if (d2 > q->best2 || (q->found && d2 == q->best2 && k >= q->best_primitive)) return false;
  q->best2 = d2;
  q->found = true;
  q->best_primitive = k;
  args->query->radius = q->stop_at_first ? 0.0f : radius_for(std::sqrt(d2), q->slack);
  return true;
}

}  // namespace

SurfaceReference::SurfaceReference(SurfaceSoup soup) : soup_(std::move(soup)), embree_(std::make_unique<Embree>()) {
  if (face_labels_.size() < soup_.face_labels) face_labels_.resize(soup_.face_labels, SurfaceLabel{0, 0, 0});
  if (polyline_refs_.size() < soup_.polyline_labels) polyline_refs_.resize(soup_.polyline_labels, 0);
  double max_abs = 0.0;
  Embree& e = *embree_;
  e.vertices.resize(3 * soup_.positions.size() + 1, 0.0f);
  for (std::size_t i = 0; i < soup_.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      e.vertices[3 * i + k] = static_cast<float>(soup_.positions[i][k]);
      max_abs = std::max(max_abs, std::abs(soup_.positions[i][k]));
    }
  // Rounding of the vertices and of the query point to float, with a wide margin.
  slack_ = 8.0 * FLT_EPSILON * std::max(max_abs, 1e-30);

  const std::uint32_t geometries = soup_.face_labels + soup_.polyline_labels;
  e.indices.assign(soup_.face_labels, {});
  e.primitives.assign(geometries, {});
  {  // exact sizes: these buffers live as long as the reference
    std::vector<std::size_t> count(geometries, 0);
    for (std::uint32_t g : soup_.triangle_label) ++count[g];
    for (std::uint32_t g : soup_.segment_label) ++count[soup_.face_labels + g];
    for (std::uint32_t g = 0; g < geometries; ++g) {
      e.primitives[g].reserve(count[g]);
      if (g < soup_.face_labels) e.indices[g].reserve(3 * count[g] + 1);  // + Embree's padding
    }
  }
  for (std::uint32_t t = 0; t < soup_.triangles.size(); ++t) {
    const std::uint32_t g = soup_.triangle_label[t];
    e.primitives[g].push_back(t);
    for (VertId x : soup_.triangles[t]) e.indices[g].push_back(x);
  }
  for (std::uint32_t s = 0; s < soup_.segments.size(); ++s)
    e.primitives[soup_.face_labels + soup_.segment_label[s]].push_back(s);

  // One builder thread in the TSan build (parallel::kStdThreads): Embree's own TBB workers are
  // invisible to TSan there. Elsewhere Embree builds in the caller's task arena.
  e.device = rtcNewDevice(parallel::kStdThreads ? "threads=1" : nullptr);
  if (e.device == nullptr) throw std::runtime_error("Embree: cannot create a device");
  // Labels with at least this many primitives get a scene of their own (Embree::scenes).
  constexpr std::size_t kOwnScene = 1024;
  e.scene_index.assign(geometries, 0);
  e.geometry_id.assign(geometries, 0);
  e.scenes.push_back(rtcNewScene(e.device));  // [0]: the small labels
  rtcSetSceneFlags(e.scenes[0], RTC_SCENE_FLAG_COMPACT);  // about half the BVH memory (measured: same speed here)
  e.segment_data.reserve(soup_.polyline_labels);  // no reallocation: Embree keeps pointers
  for (std::uint32_t g = 0; g < geometries; ++g) {
    RTCGeometry geom;
    if (g < soup_.face_labels) {
      geom = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_TRIANGLE);
      rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, e.vertices.data(), 0,
                                 3 * sizeof(float), soup_.positions.size());
      e.indices[g].push_back(0);  // padding: Embree may read 4 bytes past the last triple
      rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, e.indices[g].data(), 0,
                                 3 * sizeof(std::uint32_t), e.primitives[g].size());
    } else {
      geom = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_USER);
      SegmentGeometry& user = e.segment_data.emplace_back(SegmentGeometry{&e.vertices, &soup_.segments, &e.primitives[g]});
      rtcSetGeometryUserPrimitiveCount(geom, static_cast<unsigned>(e.primitives[g].size()));
      rtcSetGeometryUserData(geom, &user);
      rtcSetGeometryBoundsFunction(geom, segment_bounds, nullptr);
    }
    rtcCommitGeometry(geom);
    if (e.primitives[g].size() >= kOwnScene) {
      e.scene_index[g] = static_cast<std::uint32_t>(e.scenes.size());
      e.scenes.push_back(rtcNewScene(e.device));
      rtcSetSceneFlags(e.scenes.back(), RTC_SCENE_FLAG_COMPACT);
    }
    e.geometry_id[g] = rtcAttachGeometry(e.scenes[e.scene_index[g]], geom);
    rtcReleaseGeometry(geom);
  }
  for (RTCScene scene : e.scenes) rtcCommitScene(scene);
  if (rtcGetDeviceError(e.device) != RTC_ERROR_NONE) throw std::runtime_error("Embree: building the scene failed");
}

SurfaceReference::~SurfaceReference() = default;

int SurfaceReference::face_label_id(const SurfaceLabel& label) const {
  auto it = std::lower_bound(face_labels_.begin(), face_labels_.end(), label);
  return it != face_labels_.end() && *it == label ? static_cast<int>(it - face_labels_.begin()) : -1;
}

int SurfaceReference::polyline_label_id(std::int32_t ref) const {
  auto it = std::lower_bound(polyline_refs_.begin(), polyline_refs_.end(), ref);
  return it != polyline_refs_.end() && *it == ref
             ? static_cast<int>(face_labels_.size()) + static_cast<int>(it - polyline_refs_.begin())
             : -1;
}

namespace {

double run_query(const SurfaceSoup& soup, const std::vector<std::vector<std::uint32_t>>& primitives, RTCScene scene,
                 unsigned geometry_id, const glm::dvec3& p, int label, double radius, double slack, bool stop_at_first, bool* found,
                 const glm::dvec3* corners = nullptr, int corner_count = 0, double search_radius = 0.0) {
  Query q{&soup, &primitives, static_cast<unsigned>(label), label >= static_cast<int>(soup.face_labels), p,
          radius * radius, slack, stop_at_first};
  q.corners = corners;
  q.corner_count = corner_count;
  q.geometry_id = geometry_id;
  RTCPointQuery query;
  query.x = static_cast<float>(p.x);
  query.y = static_cast<float>(p.y);
  query.z = static_cast<float>(p.z);
  query.time = 0.0f;
  query.radius = radius_for(corners != nullptr ? search_radius : radius, slack);
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene, &query, &context, on_primitive, &q);
  *found = q.found;
  return q.best2;
}

}  // namespace

bool SurfaceReference::within(const glm::dvec3& p, int label, double h) const {
  return any_within(p, label, h) != kInvalid;
}

std::uint32_t SurfaceReference::any_within(const glm::dvec3& p, int label, double h) const {
  if (label < 0 || static_cast<std::size_t>(label) >= embree_->primitives.size()) return kInvalid;
  Query q{&soup_, &embree_->primitives, static_cast<unsigned>(label), label >= static_cast<int>(soup_.face_labels), p,
          h * h, slack_, true};
  q.geometry_id = embree_->geometry_id_of(label);
  RTCPointQuery query{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z), 0.0f,
                      radius_for(h, slack_)};
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(embree_->scene_of(label), &query, &context, on_primitive, &q);
  return q.found ? q.best_primitive : kInvalid;
}

bool SurfaceReference::within_one(const glm::dvec3* corners, int count, int label, double h) const {
  if (label < 0 || static_cast<std::size_t>(label) >= embree_->primitives.size() || count <= 0) return false;
  glm::dvec3 centre(0.0);
  for (int i = 0; i < count; ++i) centre += corners[i];
  centre /= static_cast<double>(count);
  double r2 = 0.0;
  for (int i = 0; i < count; ++i) r2 = std::max(r2, glm::dot(corners[i] - centre, corners[i] - centre));
  // A primitive within h of every corner is within h + r of the centre.
  bool found = false;
  run_query(soup_, embree_->primitives, embree_->scene_of(label), embree_->geometry_id_of(label), centre, label, h, slack_, true, &found, corners, count,
            h + std::sqrt(r2));
  return found;
}

double SurfaceReference::distance(const glm::dvec3& p, int label, double max_distance) const {
  if (label < 0 || static_cast<std::size_t>(label) >= embree_->primitives.size())
    return std::numeric_limits<double>::infinity();
  bool found = false;
  const double d2 = run_query(soup_, embree_->primitives, embree_->scene_of(label), embree_->geometry_id_of(label), p, label, max_distance, slack_, false, &found);
  return found ? std::sqrt(d2) : std::numeric_limits<double>::infinity();
}

void SurfaceReference::build_flat_patches(double max_deviation) {
  patches_ = std::make_unique<FlatPatches>(find_flat_patches(soup_, max_deviation));
  Embree& e = *embree_;
  if (e.patch_scene != nullptr) rtcReleaseScene(e.patch_scene);
  e.patch_scene = rtcNewScene(e.device);
  e.patch_primitives.assign(1, {});
  e.patch_primitives[0].resize(patches_->boundary.size());
  for (std::uint32_t i = 0; i < patches_->boundary.size(); ++i) e.patch_primitives[0][i] = i;
  e.patch_data.assign(1, SegmentGeometry{&e.vertices, &patches_->boundary, &e.patch_primitives[0]});
  RTCGeometry geom = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(geom, static_cast<unsigned>(patches_->boundary.size()));
  rtcSetGeometryUserData(geom, &e.patch_data[0]);
  rtcSetGeometryBoundsFunction(geom, segment_bounds, nullptr);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(e.patch_scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(e.patch_scene);
  if (rtcGetDeviceError(e.device) != RTC_ERROR_NONE) throw std::runtime_error("Embree: building the patch scene failed");
}

std::uint32_t SurfaceReference::nearest_triangle(const glm::dvec3& p, int label, double max_distance,
                                                double* distance, std::uint32_t hint) const {
  if (label < 0 || static_cast<std::uint32_t>(label) >= soup_.face_labels) return kInvalid;
  Query near{&soup_, &embree_->primitives, static_cast<unsigned>(label), false, p, max_distance * max_distance, slack_,
             false};
  near.geometry_id = embree_->geometry_id_of(label);
  // A hint near p starts the search with a small radius, so the traversal prunes more. The answer
  // does not depend on it (ties go to the lower index, on_primitive).
  if (hint != kInvalid && soup_.triangle_label[hint] == static_cast<std::uint32_t>(label)) {
    const auto& t = soup_.triangles[hint];
    const auto& P = soup_.positions;
    const double d2 = squared_distance_to_triangle(p, P[t[0]], P[t[1]], P[t[2]]);
    if (d2 <= near.best2) {
      near.best2 = d2;
      near.found = true;
      near.best_primitive = hint;
    }
  }
  RTCPointQuery query{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z), 0.0f,
                      radius_for(near.found ? std::sqrt(near.best2) : max_distance, slack_)};
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(embree_->scene_of(label), &query, &context, on_primitive, &near);
  if (!near.found) return kInvalid;
  if (distance != nullptr) *distance = std::sqrt(near.best2);
  return near.best_primitive;
}

bool SurfaceReference::triangle_holds(std::uint32_t k, const std::array<glm::dvec3, 3>& q, double h) const {
  const auto& t = soup_.triangles[k];
  const auto& P = soup_.positions;
  for (const glm::dvec3& x : q)
    if (squared_distance_to_triangle(x, P[t[0]], P[t[1]], P[t[2]]) > h * h) return false;
  return true;
}

bool SurfaceReference::within_by_patch(const std::array<glm::dvec3, 3>& q, int label, double h,
                                       std::uint32_t nearest) const {
  if (!patches_ || label < 0 || static_cast<std::uint32_t>(label) >= soup_.face_labels || nearest == kInvalid)
    return false;
  const glm::dvec3 c = (q[0] + q[1] + q[2]) / 3.0;
  double r2 = 0.0;
  for (const glm::dvec3& x : q) r2 = std::max(r2, glm::dot(x - c, x - c));
  // The original triangle nearest to the centre gives the patch to project on.
  const std::uint32_t pid = patches_->patch_of[nearest];
  const FlatPatches::Patch& patch = patches_->patches[pid];
  if (!(patch.deviation < h)) return false;
  // The bound: distance to the plane (convex: its largest value is at a corner) plus deviation
  // (plus the rim allowance below).
  // The piece's shadow must lie in the patch's shadow. The patch does not fold (flat_patches.h),
  // so the boundary of its shadow lies in the shadow of its boundary edges: it is enough that one
  // point of the piece's shadow (the centre's) lies in the shadow of a patch triangle (the
  // nearest one) and that no boundary edge's shadow enters the piece's shadow. "Enters" means
  // deeper than eps: an edge that runs along the piece's own edge (a piece touching the rim of a
  // box face) does not count, and the points this leaves unproved lie within eps / sin(a / 2)
  // (a: the smallest angle of the shadow) of proved ones, which the bound pays for below.
  ShadowTriangle shadow;
  shadow.origin = c - (glm::dot(patch.normal, c) - patch.offset) * patch.normal;
  shadow.e1 = glm::normalize(std::abs(patch.normal.x) < 0.9 ? glm::cross(patch.normal, glm::dvec3(1, 0, 0))
                                                             : glm::cross(patch.normal, glm::dvec3(0, 1, 0)));
  shadow.e2 = glm::cross(patch.normal, shadow.e1);
  for (int k = 0; k < 3; ++k) shadow.t[k] = shadow.to2d(q[k]);
  const double area2 = (shadow.t[1][0] - shadow.t[0][0]) * (shadow.t[2][1] - shadow.t[0][1]) -
                       (shadow.t[2][0] - shadow.t[0][0]) * (shadow.t[1][1] - shadow.t[0][1]);
  if (!(std::abs(area2) > 0.0)) return false;
  if (area2 < 0.0) std::swap(shadow.t[1], shadow.t[2]);
  double min_sin_half = 1.0, longest = 0.0;
  for (int k = 0; k < 3; ++k) {
    const auto& a = shadow.t[k];
    const auto& b = shadow.t[(k + 1) % 3];
    const double dx = b[0] - a[0], dy = b[1] - a[1], len = std::sqrt(dx * dx + dy * dy);
    if (!(len > 0.0)) return false;
    longest = std::max(longest, len);
    shadow.edge[k] = {-dy / len, dx / len, (-dy * a[0] + dx * a[1]) / len};  // inward (left) normal
  }
  for (int k = 0; k < 3; ++k) {  // sin of half the angle at each corner
    const auto& a = shadow.t[k];
    const auto& b = shadow.t[(k + 1) % 3];
    const auto& o = shadow.t[(k + 2) % 3];
    const double ux = b[0] - a[0], uy = b[1] - a[1], vx = o[0] - a[0], vy = o[1] - a[1];
    const double cosine = (ux * vx + uy * vy) / std::sqrt((ux * ux + uy * uy) * (vx * vx + vy * vy));
    min_sin_half = std::min(min_sin_half, std::sqrt(std::max(0.0, 0.5 * (1.0 - cosine))));
  }
  shadow.eps = 1e-9 * std::max(h, longest);
  const double unproved = shadow.eps / std::max(min_sin_half, 1e-300);
  for (const glm::dvec3& x : q)
    if (std::abs(glm::dot(patch.normal, x) - patch.offset) + patch.deviation + unproved > h) return false;
  // The centre's shadow in the shadow of the nearest triangle.
  const auto& t = soup_.triangles[nearest];
  const auto& P = soup_.positions;
  {
    const auto c2 = shadow.to2d(c);
    std::array<std::array<double, 2>, 3> tt{shadow.to2d(P[t[0]]), shadow.to2d(P[t[1]]), shadow.to2d(P[t[2]])};
    double sign = 0.0;
    for (int k = 0; k < 3; ++k) {
      const auto& a = tt[k];
      const auto& b = tt[(k + 1) % 3];
      const double cr = (b[0] - a[0]) * (c2[1] - a[1]) - (b[1] - a[1]) * (c2[0] - a[0]);
      if (cr == 0.0) continue;
      if (sign == 0.0) sign = cr;
      if ((cr > 0.0) != (sign > 0.0)) return false;
    }
  }
  // Every boundary edge whose shadow could reach the piece's: within sqrt(r^2 + deviation^2).
  const double radius = std::sqrt(r2 + patch.deviation * patch.deviation);
  Query edge{&soup_, &embree_->patch_primitives, 0, true, shadow.origin, radius * radius, slack_, true};
  edge.segments = &patches_->boundary;
  edge.segment_patch = &patches_->boundary_patch;
  edge.patch = pid;
  edge.shadow = &shadow;
  RTCPointQuery query{static_cast<float>(shadow.origin.x), static_cast<float>(shadow.origin.y),
                      static_cast<float>(shadow.origin.z), 0.0f, radius_for(radius, slack_)};
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(embree_->patch_scene, &query, &context, on_primitive, &edge);
  return !edge.found;
}

bool SurfaceReference::within_by_facets(const std::array<glm::dvec3, 3>& q, double h, std::uint32_t nearest) const {
  return patches_ && topotet::within_by_facets(soup_, patches_->neighbour, q, h, nearest);
}

bool SurfaceReference::within_by_crease(const std::array<glm::dvec3, 3>& q, int label, double h,
                                        std::uint32_t nearest) const {
  if (!patches_ || label < 0 || static_cast<std::uint32_t>(label) >= soup_.face_labels || nearest == kInvalid)
    return false;
  const auto& P = soup_.positions;
  const std::uint32_t t1 = nearest;
  const auto& f1 = soup_.triangles[t1];
  const double h2 = h * h;
  auto within_facet = [&](const glm::dvec3& x, const std::array<VertId, 3>& f) {
    return squared_distance_to_triangle(x, P[f[0]], P[f[1]], P[f[2]]) <= h2;
  };
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t t2 = patches_->neighbour[3 * std::size_t{t1} + k];
    if (t2 == kInvalid) continue;
    const auto& f2 = soup_.triangles[t2];
    const glm::dvec3 a = P[f1[k]], b = P[f1[(k + 1) % 3]];
    VertId o2 = f2[0];
    for (VertId x : f2)
      if (x != f1[k] && x != f1[(k + 1) % 3]) o2 = x;
    // The cutting plane holds the edge and bisects the crease: it separates the facets. Any plane
    // would do for the proof (each side is checked against its facet); this one puts the cut
    // where the nearest facet changes. Its normal points towards facet 1.
    const glm::dvec3 nb = crease_normal(a, b, P[f1[(k + 2) % 3]], P[o2]);
    if (!(glm::dot(nb, nb) > 1e-12)) continue;  // a degenerate edge (or facet)
    auto side = [&](const glm::dvec3& x) { return glm::dot(nb, x - a); };
    std::array<double, 3> s{side(q[0]), side(q[1]), side(q[2])};
    bool ok = true;
    for (int i = 0; i < 3 && ok; ++i) ok = within_facet(q[i], s[i] >= 0.0 ? f1 : f2);
    // Where an edge of the piece crosses the plane, the crossing point belongs to both parts.
    for (int i = 0; i < 3 && ok; ++i) {
      const int j = (i + 1) % 3;
      if ((s[i] > 0.0 && s[j] < 0.0) || (s[i] < 0.0 && s[j] > 0.0)) {
        const glm::dvec3 x = q[i] + (q[j] - q[i]) * (s[i] / (s[i] - s[j]));
        ok = within_facet(x, f1) && within_facet(x, f2);
      }
    }
    if (ok) return true;
  }
  return false;
}

// ---------------------------------------------------------------- from a MeshModel

namespace {

int local_of(const std::array<VertId, 4>& v, VertId a) {
  for (int k = 0; k < 4; ++k)
    if (v[k] == a) return k;
  return -1;
}

std::int32_t normalised_ref(std::int32_t ref) { return ref == kImplicitInterfaceRef ? kUnlistedRef : ref; }

struct LabelledFace {
  std::array<VertId, 3> v;
  SurfaceLabel label;
  TetId tet;            // the tet the face was taken from, and its local index there
  std::uint8_t local;
};
struct LabelledEdge {
  std::array<VertId, 2> v;
  std::int32_t ref;
  TetId tet;  // a tet that has the edge, and the edge's local index there (the smallest such tet)
  std::uint8_t local;
  bool operator<(const LabelledEdge& o) const {
    if (v != o.v) return v < o.v;
    return ref != o.ref ? ref < o.ref : tet < o.tet;
  }
  bool operator==(const LabelledEdge& o) const { return v == o.v && ref == o.ref; }
};

}  // namespace

std::unique_ptr<SurfaceReference> SurfaceReference::from_mesh(const MeshModel& mesh, double tolerance) {
  return from_mesh(mesh, tolerance, find_special_faces(mesh));
}

std::unique_ptr<SurfaceReference> SurfaceReference::from_mesh(const MeshModel& mesh, double tolerance,
                                                              const SpecialFaces& special) {
  constexpr std::size_t kBlock = 4096;
  // Each special face with its label, as seen from its smaller tet (the order of `special`).
  std::vector<LabelledFace> faces(special.faces.size());
  parallel::for_range<std::size_t>(0, special.faces.size(), 4096, "surface_reference", [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const SpecialFace& sf = special.faces[i];
      const TetId t = sf.tet, o = sf.other;
      const int f = sf.local;
      const bool flagged_here = is_surface_face(mesh.flags[t], f);
      bool flagged = flagged_here;
      std::int32_t ref = flagged_here ? normalised_ref(mesh.refs_table[mesh.tet_refs_slot[t]].face[f]) : kUnlistedRef;
      std::int32_t m_other = kOutsideMaterial;
      if (o != kInvalid) {
        m_other = mesh.material[o];
        if (is_surface_face(mesh.flags[o], sf.other_local)) {
          const std::int32_t r = normalised_ref(mesh.refs_table[mesh.tet_refs_slot[o]].face[sf.other_local]);
          ref = flagged ? std::max(ref, r) : r;
        }
      }
      const std::int32_t m = mesh.material[t];
      const auto& tv = mesh.tets[t];
      faces[i] = {{tv[kTetFaces[f][0]], tv[kTetFaces[f][1]], tv[kTetFaces[f][2]]},
                  SurfaceLabel{ref, std::min(m, m_other), std::max(m, m_other)}, t, static_cast<std::uint8_t>(f)};
    }
  });

  // Polyline edges: flagged edges of flagged tets, in tet order.
  const std::size_t nt = mesh.tet_capacity();
  const std::size_t tet_blocks = (nt + 8 * kBlock - 1) / (8 * kBlock);
  std::vector<std::vector<LabelledEdge>> block_edges(tet_blocks);
  parallel::for_range<std::size_t>(0, tet_blocks, 1, "surface_reference_edges", [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b)
      for (std::size_t ti = b * 8 * kBlock; ti < std::min(nt, (b + 1) * 8 * kBlock); ++ti) {
        const TetId t = static_cast<TetId>(ti);
        const TetFlags fl = mesh.flags[t];
        if (!(fl & tet_flag::kPolylineEdges) || mesh.is_dead_tet(t)) continue;
        const auto& tv = mesh.tets[t];
        const SubstructureRefs& refs = mesh.refs_table[mesh.tet_refs_slot[t]];
        for (int e = 0; e < 6; ++e) {
          if (!is_polyline_edge(fl, e)) continue;
          const VertId x = tv[kTetEdges[e][0]], y = tv[kTetEdges[e][1]];
          block_edges[b].push_back({{std::min(x, y), std::max(x, y)}, refs.edge[e], t, static_cast<std::uint8_t>(e)});
        }
      }
  });

  SurfaceSoup soup;
  std::vector<SurfaceLabel> labels;
  std::vector<std::int32_t> polyline_refs;
  std::vector<LabelledEdge> edges;
  for (const LabelledFace& f : faces) labels.push_back(f.label);
  for (const auto& be : block_edges) edges.insert(edges.end(), be.begin(), be.end());
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const LabelledEdge& e : edges) polyline_refs.push_back(e.ref);
  std::sort(polyline_refs.begin(), polyline_refs.end());
  polyline_refs.erase(std::unique(polyline_refs.begin(), polyline_refs.end()), polyline_refs.end());

  soup.face_labels = static_cast<std::uint32_t>(labels.size());
  // Polyline geometries, then one border geometry per face label.
  soup.polyline_labels = static_cast<std::uint32_t>(polyline_refs.size() + labels.size());
  std::vector<std::uint8_t> on_surface(mesh.vertex_capacity(), 0);
  std::vector<FaceHolder> holders;
  for (const LabelledFace& f : faces) {
    soup.triangles.push_back(f.v);
    holders.push_back({f.tet, f.local});
    soup.triangle_label.push_back(static_cast<std::uint32_t>(
        std::lower_bound(labels.begin(), labels.end(), f.label) - labels.begin()));
    for (VertId x : f.v) on_surface[x] = 1;
  }
  std::vector<FaceHolder> segment_holders;
  for (const LabelledEdge& e : edges) {
    soup.segments.push_back(e.v);
    segment_holders.push_back({e.tet, e.local});
    soup.segment_label.push_back(static_cast<std::uint32_t>(
        std::lower_bound(polyline_refs.begin(), polyline_refs.end(), e.ref) - polyline_refs.begin()));
    for (VertId x : e.v) on_surface[x] = 1;
  }
  // The soup holds the surfaces' vertices only, numbered in the mesh's order (so that every order
  // by id stays the same): it and Embree's float copy then cost bytes per surface vertex, not per
  // mesh vertex.
  {
    std::vector<VertId> soup_id(mesh.vertex_capacity(), kInvalid);
    for (std::size_t x = 0; x < on_surface.size(); ++x)
      if (on_surface[x]) {
        soup_id[x] = static_cast<VertId>(soup.positions.size());
        soup.positions.push_back(mesh.positions[x]);
      }
    for (auto& t : soup.triangles)
      for (VertId& x : t) x = soup_id[x];
    for (auto& e : soup.segments)
      for (VertId& x : e) x = soup_id[x];
  }
  // Border edges: the edges with exactly one face of their label.
  std::vector<std::pair<std::array<VertId, 2>, std::uint32_t>> face_edges;  // (edge, label id)
  for (std::size_t t = 0; t < soup.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const VertId x = soup.triangles[t][k], y = soup.triangles[t][(k + 1) % 3];
      face_edges.push_back({{std::min(x, y), std::max(x, y)}, soup.triangle_label[t]});
    }
  parallel::sort(face_edges.begin(), face_edges.end());
  for (std::size_t i = 0; i < face_edges.size();) {
    std::size_t j = i + 1;
    while (j < face_edges.size() && face_edges[j] == face_edges[i]) ++j;
    if (j - i == 1) {
      soup.segments.push_back(face_edges[i].first);
      soup.segment_label.push_back(static_cast<std::uint32_t>(polyline_refs.size()) + face_edges[i].second);
    }
    i = j;
  }
  faces = {};
  // Kept for the whole run: without the slack of their growth.
  soup.positions.shrink_to_fit();
  soup.triangles.shrink_to_fit();
  soup.triangle_label.shrink_to_fit();
  soup.segments.shrink_to_fit();
  soup.segment_label.shrink_to_fit();
  holders.shrink_to_fit();
  segment_holders.shrink_to_fit();

  auto reference = std::make_unique<SurfaceReference>(std::move(soup));
  reference->face_labels_ = std::move(labels);
  reference->polyline_refs_ = std::move(polyline_refs);
  reference->on_surface_ = std::move(on_surface);
  reference->holders_ = std::move(holders);
  reference->segment_holders_ = std::move(segment_holders);
  // Patches within h / 2 of a plane: a large new triangle over one is proved in one step, at the
  // price of half of h for the patch's own curvature. On a coarse curved surface (original
  // triangles several h across) a patch of h / 4 is about one triangle and proves nothing the
  // triangle alone does not; h / 2 doubles its area (simnibs sphere3: 8% fewer instructions,
  // 16.2% -> 15.8% of the vertices reached; the families and the 1M meshes are unchanged).
  if (tolerance > 0.0) reference->build_flat_patches(0.5 * tolerance);
  return reference;
}

// ---------------------------------------------------------------- the kernel check

namespace {

// A face through u (table 0) or through v but not u (table 1), keyed by its two other vertices (a
// face through both: v and the third). The two tets of a face through u are both in St(u), so the
// key names the face among the records.
struct FaceKey {
  int table;
  std::uint64_t key;
};
FaceKey face_key(const std::array<VertId, 3>& f, VertId u, VertId v) {
  const VertId pivot = (f[0] == u || f[1] == u || f[2] == u) ? u : v;
  VertId o[2];
  int n = 0;
  for (VertId x : f)
    if (x != pivot && n < 2) o[n++] = x;
  return {pivot == u ? 0 : 1, (std::uint64_t{o[0]} << 32) | o[1]};  // f is sorted: o[0] < o[1]
}

}  // namespace

void gather_surface_stencil(const MeshModel& mesh, const SurfaceReference& reference, VertId u, VertId v,
                            const std::vector<TetId>& star_u, const std::vector<TetId>& star_v,
                            const std::vector<TetId>& star_uv, SurfaceStencil& out) {
  out.recs.clear();
  out.faces.clear();
  out.edges.clear();
  auto add = [&](TetId t) {
    const auto& tv = mesh.tets[t];
    const int iu = local_of(tv, u), iv = local_of(tv, v);
    for (int f = 0; f < 4; ++f) {
      if ((iu < 0 || iu == f) && (iv < 0 || iv == f)) continue;  // the face has neither u nor v
      std::array<VertId, 3> key{tv[kTetFaces[f][0]], tv[kTetFaces[f][1]], tv[kTetFaces[f][2]]};
      std::sort(key.begin(), key.end());
      out.recs.push_back({key, t, static_cast<std::uint8_t>(f)});
    }
    const TetFlags fl = mesh.flags[t];
    if (!(fl & tet_flag::kPolylineEdges)) return;
    const SubstructureRefs& refs = mesh.refs_table[mesh.tet_refs_slot[t]];
    for (int e = 0; e < 6; ++e) {
      if (!is_polyline_edge(fl, e)) continue;
      const int a = kTetEdges[e][0], b = kTetEdges[e][1];
      if (a != iu && b != iu && a != iv && b != iv) continue;
      const VertId x = tv[a], y = tv[b];
      const bool keeps = !std::binary_search(star_uv.begin(), star_uv.end(), t);
      out.edges.push_back({{std::min(x, y), std::max(x, y)}, reference.polyline_label_id(refs.edge[e]),
                           keeps ? FaceHolder{t, static_cast<std::uint8_t>(e)} : FaceHolder{kInvalid, 0}});
    }
  };
  for (TetId t : star_u) add(t);
  for (TetId t : star_v)
    if (!std::binary_search(star_uv.begin(), star_uv.end(), t)) add(t);

  // Group the records of each face in two probe tables (about one probe a record; sorting the
  // ~130 records by their three vertices was a tenth of a surface collapse's time).
  const std::size_t n = out.recs.size();
  out.next_rec.assign(n, kInvalid);
  out.group_head.clear();
  for (int k = 0; k < 2; ++k) {
    out.face_slots[k].resize(probe_slots_for(n));
    out.slot_group[k].resize(out.face_slots[k].size());
  }
  ProbeSet<std::uint64_t> tables[2] = {ProbeSet<std::uint64_t>(out.face_slots[0]),
                                       ProbeSet<std::uint64_t>(out.face_slots[1])};
  for (std::uint32_t i = 0; i < n; ++i) {
    const FaceKey k = face_key(out.recs[i].key, u, v);
    const auto [slot, fresh] = tables[k.table].insert(k.key);
    if (fresh) {
      out.slot_group[k.table][slot] = static_cast<std::uint32_t>(out.group_head.size());
      out.group_head.push_back(i);
    } else {
      std::uint32_t& head = out.group_head[out.slot_group[k.table][slot]];
      out.next_rec[i] = head;
      head = i;
    }
  }
  const auto outside_star_uv = [&](TetId t) { return !std::binary_search(star_uv.begin(), star_uv.end(), t); };
  // The record of the lowest tet outside St(uv) among a face's (kInvalid: none).
  const auto keeper = [&](std::uint32_t head) {
    std::uint32_t best = kInvalid;
    for (std::uint32_t r = head; r != kInvalid; r = out.next_rec[r])
      if (outside_star_uv(out.recs[r].tet) && (best == kInvalid || out.recs[r].tet < out.recs[best].tet)) best = r;
    return best;
  };
  for (std::uint32_t head : out.group_head) {
    bool flagged = false;
    std::int32_t ref = kUnlistedRef;
    int count = 0;
    TetId low = kInvalid, second = kInvalid;  // the face's two lowest tets
    for (std::uint32_t r = head; r != kInvalid; r = out.next_rec[r]) {
      const SurfaceStencil::FaceRec& rec = out.recs[r];
      ++count;
      if (rec.tet < low) {
        second = low;
        low = rec.tet;
      } else if (rec.tet < second) {
        second = rec.tet;
      }
      if (!is_surface_face(mesh.flags[rec.tet], rec.local_face)) continue;
      const std::int32_t fr = normalised_ref(mesh.refs_table[mesh.tet_refs_slot[rec.tet]].face[rec.local_face]);
      ref = flagged ? std::max(ref, fr) : fr;
      flagged = true;
    }
    const bool boundary = count == 1;
    if (!boundary && !flagged) continue;
    const std::int32_t m0 = mesh.material[low];
    const std::int32_t m1 = boundary ? kOutsideMaterial : mesh.material[second];
    const std::uint32_t keep = keeper(head);
    const FaceHolder holder = keep == kInvalid ? FaceHolder{kInvalid, 0}
                                               : FaceHolder{out.recs[keep].tet, out.recs[keep].local_face};
    out.faces.push_back(
        {out.recs[head].key, reference.face_label_id({ref, std::min(m0, m1), std::max(m0, m1)}), holder});
  }
  // In the order of their vertices, as a sort of the records gave them (the tolerance proof and
  // the coverage visit the faces in this order).
  std::sort(out.faces.begin(), out.faces.end(), [](const SurfaceStencil::Face& a, const SurfaceStencil::Face& b) {
    if (a.v[0] != b.v[0]) return a.v[0] < b.v[0];
    if (a.v[1] != b.v[1]) return a.v[1] < b.v[1];
    return a.v[2] < b.v[2];
  });
  // A face through u (v) whose only tets die with St(uv) lives on in the face it merges with: the
  // same face through v (u), in a tet that survives (a boundary face uxy of a removed tet uvxy
  // becomes the face vxy of its neighbour, renamed). That tet holds it after the collapse.
  for (SurfaceStencil::Face& f : out.faces) {
    if (f.holder.tet != kInvalid) continue;
    const bool has_u = f.v[0] == u || f.v[1] == u || f.v[2] == u;
    const bool has_v = f.v[0] == v || f.v[1] == v || f.v[2] == v;
    if (has_u == has_v) continue;
    std::array<VertId, 3> partner = f.v;
    for (VertId& x : partner)
      if (x == (has_u ? u : v)) x = has_u ? v : u;
    std::sort(partner.begin(), partner.end());
    const FaceKey k = face_key(partner, u, v);
    const std::uint32_t slot = tables[k.table].find(k.key);
    if (slot == ProbeSet<std::uint64_t>::kNotFound) continue;
    const std::uint32_t keep = keeper(out.group_head[out.slot_group[k.table][slot]]);
    if (keep != kInvalid) f.holder = {out.recs[keep].tet, out.recs[keep].local_face};
  }
  // The same for polyline edges: the edge ux (vx) lives on in vx (ux) of a surviving tet.
  for (SurfaceStencil::Edge& e : out.edges) {
    if (e.holder.tet != kInvalid) continue;
    const bool has_u = e.v[0] == u || e.v[1] == u, has_v = e.v[0] == v || e.v[1] == v;
    if (has_u == has_v) continue;
    const VertId other = e.v[0] == (has_u ? u : v) ? e.v[1] : e.v[0];
    const VertId partner = has_u ? v : u;
    auto find_in = [&](const std::vector<TetId>& star) {
      for (TetId t : star) {
        if (std::binary_search(star_uv.begin(), star_uv.end(), t)) continue;
        const int a = local_of(mesh.tets[t], partner), b = local_of(mesh.tets[t], other);
        if (a >= 0 && b >= 0) {
          e.holder = {t, static_cast<std::uint8_t>(local_edge_index(a, b))};
          return true;
        }
      }
      return false;
    };
    if (!find_in(star_u)) find_in(star_v);
  }
  // Equal edges: the first one kept has a holder if any has (kInvalid sorts last).
  std::sort(out.edges.begin(), out.edges.end(), [](const auto& a, const auto& b) {
    if (a.v != b.v) return a.v < b.v;
    return a.label != b.label ? a.label < b.label : a.holder.tet < b.holder.tet;
  });
  out.edges.erase(std::unique(out.edges.begin(), out.edges.end(),
                              [](const auto& a, const auto& b) { return a.v == b.v && a.label == b.label; }),
                  out.edges.end());
}

namespace {

bool contains(const std::array<VertId, 3>& f, VertId x) { return f[0] == x || f[1] == x || f[2] == x; }
bool contains(const std::array<VertId, 2>& e, VertId x) { return e[0] == x || e[1] == x; }

// Is `old` within h of the new triangles (segments) of label `label` around p? True when there
// are none (the label left this neighbourhood entirely; nothing local to compare with).
template <class Prims, class Dist>
bool old_point_covered(const glm::dvec3& old, int label, double h2, const Prims& prims, Dist&& dist2) {
  bool any = false;
  for (const auto& prim : prims) {
    if (prim.label != label) continue;
    any = true;
    if (dist2(old, prim) <= h2) return true;
  }
  return !any;
}

// The forward check of a whole new triangle (segment): is EVERY point of it within h of the
// original surface (polyline, border curve) of `label`? The distance to a fixed set is
// 1-Lipschitz, so a piece whose centre c is within h - r, r the distance from c to the piece's
// farthest corner, lies within h everywhere. A piece that fails this test is refused at once when
// c itself is farther than h (a point of the new surface is out), and otherwise split (a triangle
// in four at its edge midpoints, a segment in two), coarse pieces before fine ones. The split
// stops at pieces of r < h / 8 (kFinestPiece) or after kPieceBudget pieces: the placement is then
// refused. So "yes" is always a proof; the price is refusing a few placements whose surface comes
// within h / 8 of the limit, and the work per triangle is bounded. Most triangles pass at once or
// after one split: on coarse levels a triangle is a few h long and lies much closer than h.
constexpr double kFinestPiece = 1.0 / 8.0;
constexpr int kPieceBudget = 64;
// SurfaceStencil::found_triangles keeps this many (polycrystal 30k at 10%: 4, 8, 16 ran -8.6%,
// -9.1%, -9.3% instructions).
constexpr std::size_t kFoundTriangles = 8;

bool triangle_within(const SurfaceReference& reference, const glm::dvec3& a, const glm::dvec3& b,
                     const glm::dvec3& c, int label, double h, std::uint32_t& hint) {
  std::array<std::array<glm::dvec3, 3>, kPieceBudget> pieces;  // a FIFO: coarse pieces first
  std::array<std::uint32_t, kPieceBudget> parent_nearest;      // [piece] its parent's nearest triangle
  int head = 0, tail = 0;
  parent_nearest[tail] = kInvalid;
  pieces[tail++] = {a, b, c};
  while (head < tail) {
    const std::uint32_t tried = parent_nearest[head];
    const auto& piece = pieces[head++];
    // A piece of a split usually lies within h of its parent's nearest triangle alone: three
    // distances then prove it, without a search.
    if (tried != kInvalid && reference.triangle_holds(tried, piece, h)) continue;
    const auto [x, y, z] = piece;
    const glm::dvec3 centre = (x + y + z) / 3.0;
    const double r = std::sqrt(std::max({glm::dot(x - centre, x - centre), glm::dot(y - centre, y - centre),
                                         glm::dot(z - centre, z - centre)}));
    // One query for the nearest original triangle to the centre serves every test: none within h
    // is a violation (refused); within h - r proves the piece by Lipschitz; else that triangle
    // alone (convexity), with a neighbour across a crease, or its flat patch may prove it.
    double d = 0.0;
    const std::uint32_t nearest = reference.nearest_triangle(centre, label, h, &d, hint);
    if (nearest == kInvalid) return false;
    hint = nearest;
    if (d <= h - r) continue;
    if (nearest != tried && reference.triangle_holds(nearest, piece, h)) continue;
    if (reference.within_by_crease(piece, label, h, nearest)) continue;
    if (reference.within_by_patch(piece, label, h, nearest)) continue;
    if (reference.within_by_facets(piece, h, nearest)) continue;
    if (r < kFinestPiece * h || tail + 4 > kPieceBudget) {
      // The last resort, before a refusal: another original triangle within h of every corner. It
      // searches h + r around the centre and almost never succeeds on a coarse piece (sphere3: 42
      // of 215k calls, 15% of the run's instructions), whose children prove themselves instead.
      if (reference.within_one(piece.data(), 3, label, h)) continue;
      return false;
    }
    const glm::dvec3 xy = 0.5 * (x + y), yz = 0.5 * (y + z), zx = 0.5 * (z + x);
    for (int k = 0; k < 4; ++k) parent_nearest[tail + k] = nearest;
    pieces[tail++] = {x, xy, zx};
    pieces[tail++] = {xy, y, yz};
    pieces[tail++] = {zx, yz, z};
    pieces[tail++] = {xy, yz, zx};
  }
  return true;
}

bool segment_within(const SurfaceReference& reference, const glm::dvec3& a, const glm::dvec3& b, int label,
                    double h) {
  std::array<std::array<glm::dvec3, 2>, kPieceBudget> pieces;
  int head = 0, tail = 0;
  pieces[tail++] = {a, b};
  while (head < tail) {
    const auto [x, y] = pieces[head++];
    const glm::dvec3 centre = 0.5 * (x + y);
    const double r = 0.5 * std::sqrt(glm::dot(y - x, y - x));
    if (r < h && reference.within(centre, label, h - r)) continue;
    if (reference.within_one(pieces[head - 1].data(), 2, label, h)) continue;
    if (r < kFinestPiece * h || tail + 2 > kPieceBudget || !reference.within(centre, label, h)) return false;
    pieces[tail++] = {x, centre};
    pieces[tail++] = {centre, y};
  }
  return true;
}

}  // namespace

bool new_surface_around(const MeshModel& mesh, VertId u, VertId v, const glm::dvec3& p, SurfaceStencil& s) {
  const auto& P = mesh.positions;
  s.new_faces.clear();
  s.new_edges.clear();
  for (const SurfaceStencil::Face& f : s.faces) {
    const bool hu = contains(f.v, u), hv = contains(f.v, v);
    if (hu == hv) continue;  // vanishes with St(uv) (or does not move)
    if (f.label < 0) return false;
    SurfaceStencil::NewFace nf{{p, p, p}, {kInvalid, kInvalid}, f.label, f.holder};
    int k = 0;
    for (VertId x : f.v)
      if (x != u && x != v) {
        nf.others[k] = x;
        nf.pts[1 + k++] = P[x];
      }
    s.new_faces.push_back(nf);
  }
  for (const SurfaceStencil::Edge& e : s.edges) {
    const bool hu = contains(e.v, u), hv = contains(e.v, v);
    if (hu == hv) continue;
    if (e.label < 0) return false;
    const VertId other = e.v[0] == u || e.v[0] == v ? e.v[1] : e.v[0];
    s.new_edges.push_back({{p, P[other]}, e.label, other, e.holder});
  }
  return true;
}

bool placement_within_tolerance(const MeshModel& mesh, const SurfaceReference& reference, double h, VertId u,
                                VertId v, const glm::dvec3& p, SurfaceStencil& s, bool screen, bool proofs) {
  if (!new_surface_around(mesh, u, v, p, s)) return false;
  const auto& P = mesh.positions;
  // Is x within h of the original surface of face label `label`? The original triangles held near
  // the stencil first (the last one that answered first: the points asked are close together),
  // then those earlier searches of this stencil answered with, then a search, whose answer joins
  // them. The answer is the search's either way (any original triangle within h proves it).
  const SurfaceSoup& soup = reference.soup();
  std::size_t last_near = 0;
  const auto holds = [&](std::uint32_t t, const glm::dvec3& x, int label) {
    if (soup.triangle_label[t] != static_cast<std::uint32_t>(label)) return false;
    const auto& tv = soup.triangles[t];
    return squared_distance_to_triangle(x, soup.positions[tv[0]], soup.positions[tv[1]], soup.positions[tv[2]]) <= h * h;
  };
  const auto within = [&](const glm::dvec3& x, int label) {
    const std::size_t n = s.near_triangles.size();
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t k = (last_near + i) % n;
      if (holds(s.near_triangles[k], x, label)) {
        last_near = k;
        return true;
      }
    }
    for (const std::uint32_t t : s.found_triangles)
      if (holds(t, x, label)) return true;
    const std::uint32_t found = reference.any_within(x, label, h);
    if (found == kInvalid) return false;
    if (s.found_triangles.size() == kFoundTriangles) s.found_triangles.pop_back();
    s.found_triangles.insert(s.found_triangles.begin(), found);
    return true;
  };

  // Forward: every point of the new surface near the original one. p first, once per label: it
  // refuses most placements with one query.
  int last_label = -1;
  for (const SurfaceStencil::NewFace& f : s.new_faces) {
    if (f.label != last_label && !within(p, f.label)) return false;
    last_label = f.label;
  }
  for (const SurfaceStencil::NewEdge& e : s.new_edges)
    if (!reference.within(p, e.label, h)) return false;
  // A cheap screen before the proofs: a few points of each new triangle (centroid, midpoints of
  // the edges at p) and of each new segment (midpoint). A point beyond h is a real violation, and
  // most refused placements are refused here with a handful of queries.
  for (const SurfaceStencil::NewFace& f : s.new_faces) {
    if (!screen) break;
    const auto& q = f.pts;
    if (!within((q[0] + q[1] + q[2]) / 3.0, f.label) || !within(0.5 * (q[0] + q[1]), f.label) ||
        !within(0.5 * (q[0] + q[2]), f.label))
      return false;
  }
  for (const SurfaceStencil::NewEdge& e : s.new_edges)
    if (screen && !reference.within(0.5 * (e.pts[0] + e.pts[1]), e.label, h)) return false;

  // Reverse: the points that leave the surface (u's and v's old positions) stay near the new one.
  const double h2 = h * h;
  const auto tri2 = [](const glm::dvec3& q, const SurfaceStencil::NewFace& f) {
    return squared_distance_to_triangle(q, f.pts[0], f.pts[1], f.pts[2]);
  };
  const auto seg2 = [](const glm::dvec3& q, const SurfaceStencil::NewEdge& e) {
    return squared_distance_to_segment(q, e.pts[0], e.pts[1]);
  };
  for (const VertId w : {u, v}) {
    if (P[w] == p) continue;
    int checked = -1;  // faces come sorted by vertices, so labels repeat in runs: skip repeats
    for (const SurfaceStencil::Face& f : s.faces) {
      if (!contains(f.v, w) || f.label == checked) continue;
      if (!old_point_covered(P[w], f.label, h2, s.new_faces, tri2)) return false;
      checked = f.label;
    }
    for (const SurfaceStencil::Edge& e : s.edges)
      if (contains(e.v, w) && !old_point_covered(P[w], e.label, h2, s.new_edges, seg2)) return false;
  }

  if (!proofs) return true;
  // The proofs (triangle_within, segment_within), most expensive last. A face (p x y) made by two
  // merging faces (u x y and v x y) is listed twice: proved once.
  std::uint32_t hint = kInvalid;  // the last nearest original triangle: where the next search starts
  for (std::size_t i = 0; i < s.new_faces.size(); ++i) {
    const SurfaceStencil::NewFace& f = s.new_faces[i];
    bool seen = false;
    for (std::size_t j = 0; j < i && !seen; ++j)
      seen = s.new_faces[j].label == f.label && s.new_faces[j].others[0] == f.others[0] &&
             s.new_faces[j].others[1] == f.others[1];
    if (!seen && !triangle_within(reference, f.pts[0], f.pts[1], f.pts[2], f.label, h, hint)) return false;
  }
  for (const SurfaceStencil::NewEdge& e : s.new_edges)
    if (!segment_within(reference, e.pts[0], e.pts[1], e.label, h)) return false;
  // Border edges p-x: every face containing the new edge contains p, so all are in new_faces.
  for (const SurfaceStencil::NewFace& f : s.new_faces)
    for (int k = 0; k < 2; ++k) {
      int count = 0;
      for (const SurfaceStencil::NewFace& g : s.new_faces)
        count += g.label == f.label && (g.others[0] == f.others[k] || g.others[1] == f.others[k]) ? 1 : 0;
      if (count != 1) continue;
      if (!segment_within(reference, p, f.pts[1 + k], reference.border_label_id(f.label), h)) return false;
    }

  return true;
}

}  // namespace topotet
