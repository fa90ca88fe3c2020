// The Embree scene of the surface distance, private to metrics/ (surface_distance.cpp): both sides
// of a comparison in one scene, and exact closest-primitive queries restricted to one label.
//
// Geometry 2s holds side s's triangles, 2s + 1 its segments (a user geometry). Every query starts
// with a radius that is already an upper bound (the distance to a primitive known to be close, or
// at worst to the label's first primitive), so the traversal stays in the neighbourhood of the
// point and meets few primitives of other labels, which the callback skips.
#pragma once

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include "mesh/glm_convert.h"
#include "parallel/for_range.h"
#include "surface_primitives.h"

namespace topotet::metrics::detail {

inline double squared_distance_to_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  const glm::dvec3 d = p - (a + ab * t);
  return glm::dot(d, d);
}

// Closest point on a triangle by its barycentric region (Ericson, Real-Time Collision Detection 5.1.5).
inline double squared_distance_to_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
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

// One side of the comparison: its primitives and, for each, the index of its label in the run's
// sorted label list (shared by both sides).
struct SurfaceSide {
  const std::vector<std::array<double, 3>>& positions;
  SurfacePrimitives prims;
  std::vector<std::uint32_t> triangle_label, segment_label;
  std::vector<std::size_t> label_primitives;  // [label] primitive count
  std::vector<std::uint32_t> label_first;     // [label] its first primitive (a query's last-resort seed)
};

// Both sides in one Embree scene: geometry 2s holds side s's triangles, 2s + 1 its segments (a
// user geometry). A query names a side and a label; primitives of other labels are skipped in the
// callback.
class SurfaceScene {
 public:
  explicit SurfaceScene(const std::array<const SurfaceSide*, 2>& sides) : sides_(sides) {
    double max_abs = 0.0;
    for (int s = 0; s < 2; ++s) {
      const auto& P = sides[s]->positions;
      vertices_[s].assign(3 * P.size() + 1, 0.0f);  // +1: padding for Embree's wide loads
      for (std::size_t i = 0; i < P.size(); ++i)
        for (int k = 0; k < 3; ++k) {
          vertices_[s][3 * i + k] = static_cast<float>(P[i][k]);
          max_abs = std::max(max_abs, std::abs(P[i][k]));
        }
    }
    slack_ = 8.0 * FLT_EPSILON * std::max(max_abs, 1e-30);
    // One builder thread in the TSan build (parallel::kStdThreads), as in surface_tolerance.cpp.
    device_ = rtcNewDevice(parallel::kStdThreads ? "threads=1" : nullptr);
    if (device_ == nullptr) throw std::runtime_error("Embree: cannot create a device");
    scene_ = rtcNewScene(device_);
    for (int s = 0; s < 2; ++s) {
      const SurfacePrimitives& prims = sides[s]->prims;
      if (!prims.triangles.empty()) {
        RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices_[s].data(), 0,
                                   3 * sizeof(float), sides[s]->positions.size());
        indices_[s].reserve(3 * prims.triangles.size() + 1);
        for (const auto& t : prims.triangles) indices_[s].insert(indices_[s].end(), t.begin(), t.end());
        indices_[s].push_back(0);  // padding, as for the vertices
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices_[s].data(), 0,
                                   3 * sizeof(std::uint32_t), prims.triangles.size());
        attach(geom, 2 * s);
      }
      if (!prims.segments.empty()) {
        RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(geom, static_cast<unsigned>(prims.segments.size()));
        segment_users_[s] = {this, s};
        rtcSetGeometryUserData(geom, &segment_users_[s]);
        rtcSetGeometryBoundsFunction(geom, &SurfaceScene::segment_bounds, nullptr);
        attach(geom, 2 * s + 1);
      }
    }
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw std::runtime_error("Embree: building the scene failed");
  }
  ~SurfaceScene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  SurfaceScene(const SurfaceScene&) = delete;
  SurfaceScene& operator=(const SurfaceScene&) = delete;

  struct Closest {
    double distance;      // +infinity if side s has no primitive of this label
    std::uint32_t index;  // the closest primitive: a triangle, or a segment for a polyline label
  };

  // The closest primitive of side s with label g to p. `known` is a primitive of that label
  // already known to be at squared distance known2 (known2 = infinity: none, then the label's
  // first primitive serves): the search only looks for closer ones, so it stays in the
  // neighbourhood of p and rarely meets primitives of other labels.
  Closest closest(int s, std::uint32_t g, bool polyline, const glm::dvec3& p, double known2,
                  std::uint32_t known) const {
    if (sides_[s]->label_primitives[g] == 0) return {std::numeric_limits<double>::infinity(), 0};
    if (!std::isfinite(known2)) {
      known = sides_[s]->label_first[g];
      known2 = squared_distance(s, polyline, known, p);
    }
    Query q{this, s, g, polyline, p, known2, known};
    RTCPointQuery query;
    query.x = static_cast<float>(p.x);
    query.y = static_cast<float>(p.y);
    query.z = static_cast<float>(p.z);
    query.time = 0.0f;
    query.radius = radius_for(known2);
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(scene_, &query, &context, &SurfaceScene::on_primitive, &q);
    return {std::sqrt(q.best2), q.best_index};
  }

  // Squared distance from p to primitive `index` of side s (a segment when `polyline`).
  double squared_distance(int s, bool polyline, std::uint32_t index, const glm::dvec3& p) const {
    const auto& P = sides_[s]->positions;
    if (polyline) {
      const auto& e = sides_[s]->prims.segments[index];
      return squared_distance_to_segment(p, to_glm(P[e[0]]), to_glm(P[e[1]]));
    }
    const auto& t = sides_[s]->prims.triangles[index];
    return squared_distance_to_triangle(p, to_glm(P[t[0]]), to_glm(P[t[1]]), to_glm(P[t[2]]));
  }

 private:
  struct Query {
    const SurfaceScene* scene;
    int side;
    std::uint32_t label;
    bool polyline;
    glm::dvec3 p;
    double best2;
    std::uint32_t best_index;
  };
  struct SegmentUser {  // user data of a segment geometry
    const SurfaceScene* scene;
    int side;
  };

  void attach(RTCGeometry geom, unsigned id) {
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(scene_, geom, id);
    rtcReleaseGeometry(geom);
  }

  // Embree's float bounds and query point differ from the double geometry by rounding: widen.
  float radius_for(double d2) const {
    return std::nextafter(static_cast<float>(std::sqrt(d2) + slack_), std::numeric_limits<float>::infinity());
  }

  static void segment_bounds(const RTCBoundsFunctionArguments* args) {
    const auto* user = static_cast<const SegmentUser*>(args->geometryUserPtr);
    const auto& e = user->scene->sides_[user->side]->prims.segments[args->primID];
    const float* a = &user->scene->vertices_[user->side][3 * std::size_t{e[0]}];
    const float* b = &user->scene->vertices_[user->side][3 * std::size_t{e[1]}];
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
    if (args->geomID != static_cast<unsigned>(2 * q->side + (q->polyline ? 1 : 0))) return false;
    const SurfaceSide& side = *q->scene->sides_[q->side];
    const auto& labels = q->polyline ? side.segment_label : side.triangle_label;
    if (labels[args->primID] != q->label) return false;  // another label
    const double d2 = q->scene->squared_distance(q->side, q->polyline, args->primID, q->p);
    if (!(d2 < q->best2)) return false;
    q->best2 = d2;
    q->best_index = args->primID;
    args->query->radius = q->scene->radius_for(d2);
    return true;
  }

  std::array<const SurfaceSide*, 2> sides_;
  std::array<std::vector<float>, 2> vertices_;
  std::array<std::vector<std::uint32_t>, 2> indices_;
  std::array<SegmentUser, 2> segment_users_{};
  double slack_ = 0.0;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

}  // namespace topotet::metrics::detail
