// compare_fields: locate each mesh's vertices in the other mesh, interpolate, accumulate errors.
//
// Point location is an Embree hierarchy of the tets' boxes (TetLocator below): among the tets
// whose box holds the point, the one with the largest minimum barycentric coordinate wins (ties
// to the smaller tet id), and it contains the point if that coordinate is >= -kInsideTolerance.
// Otherwise the point is outside the mesh and a closest-point query over the same hierarchy finds
// the closest tet exactly.
//
// Determinism: queries are independent; sums over samples run in fixed-size blocks whose partial
// sums are combined in block order, so results do not depend on the thread count.
#include "topotet/metrics/field_error.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "mesh/glm_convert.h"
#include "parallel/for_range.h"
#include "parallel/scratch.h"
#include "topotet/error.h"

namespace topotet {
namespace {

// Barycentric slack accepted as "inside": points on shared faces or on a boundary that coincides
// up to rounding. Barycentric coordinates are scale-free, so one constant serves every mesh.
constexpr double kInsideTolerance = 1e-9;
constexpr std::size_t kBlock = 4096;

using Bary = std::array<double, 4>;

struct Location {
  TetId tet = kInvalid;
  Bary bary{};                  // in [0, 1], summing to 1
  bool outside = false;         // found by the closest-tet search
  double outside_distance = 0.0;
};

double det3(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return glm::dot(a, glm::cross(b, c));
}

// Barycentric coordinates of q in tet p: l_i = V_i / sum V_j, V_i the signed volume of the tet
// with vertex i replaced by q, each evaluated from the vectors p_j - q. At a vertex p_k of the
// tet one of those vectors is exactly zero in every V_i with i != k, so the answer is exactly the
// unit vector e_k and identical meshes compare with no rounding error at all. False for a tet of
// zero volume.
bool barycentric(const std::array<glm::dvec3, 4>& p, const glm::dvec3& q, Bary& l) {
  const double d = det3(p[1] - p[0], p[2] - p[0], p[3] - p[0]);
  if (d == 0.0 || !std::isfinite(d)) return false;
  const glm::dvec3 a = p[0] - q, b = p[1] - q, c = p[2] - q, e = p[3] - q;
  // Moving q to the front of (p0, .., q, .., p3) takes i transpositions: sign (-1)^i.
  l[0] = det3(b, c, e);
  l[1] = -det3(a, c, e);
  l[2] = det3(a, b, e);
  l[3] = -det3(a, b, c);
  const double sum = l[0] + l[1] + l[2] + l[3];  // = d up to rounding
  if (sum == 0.0 || !std::isfinite(sum)) return false;
  for (double& x : l) x /= sum;
  return true;
}

// Parameter of the point of segment [a, b] closest to p, in [0, 1].
double closest_on_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  if (!(len2 > 0.0)) return 0.0;
  return std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0);
}

// Barycentric coordinates (of a, b, c) of the point of triangle abc closest to p, by Voronoi
// regions (Ericson, Real-Time Collision Detection, 5.1.5). Degenerate triangles fall back to
// the closest point of their three edges.
std::array<double, 3> closest_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                          const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {1.0, 0.0, 0.0};
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return {0.0, 1.0, 0.0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) {
    const double v = d1 / (d1 - d3);
    return {1.0 - v, v, 0.0};
  }
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 0.0, 1.0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) {
    const double w = d2 / (d2 - d6);
    return {1.0 - w, 0.0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0.0, 1.0 - w, w};
  }
  const double sum = va + vb + vc;
  if (sum > 0.0 && std::isfinite(sum)) {
    const double v = vb / sum, w = vc / sum;
    return {1.0 - v - w, v, w};
  }
  // Degenerate (collinear or coincident corners): best of the three edges.
  const double s_ab = closest_on_segment(p, a, b), s_bc = closest_on_segment(p, b, c),
               s_ca = closest_on_segment(p, c, a);
  const std::array<std::array<double, 3>, 3> cand = {{{1.0 - s_ab, s_ab, 0.0},
                                                      {0.0, 1.0 - s_bc, s_bc},
                                                      {s_ca, 0.0, 1.0 - s_ca}}};
  std::array<double, 3> best = cand[0];
  double best_d2 = std::numeric_limits<double>::infinity();
  for (const auto& w : cand) {
    const glm::dvec3 x = w[0] * a + w[1] * b + w[2] * c;
    const double dist2 = glm::dot(x - p, x - p);
    if (dist2 < best_d2) best_d2 = dist2, best = w;
  }
  return best;
}

// Squared distance from q to tet p and the barycentric coordinates of the closest point.
double closest_in_tet(const std::array<glm::dvec3, 4>& p, const glm::dvec3& q, Bary& out) {
  Bary l;
  if (barycentric(p, q, l) && std::min({l[0], l[1], l[2], l[3]}) >= 0.0) {
    out = l;
    return 0.0;
  }
  // Outside (or flat): the closest point lies on a face. Face i is the one opposite vertex i.
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {
    const int a = (i + 1) % 4, b = (i + 2) % 4, c = (i + 3) % 4;
    const auto w = closest_on_triangle(q, p[a], p[b], p[c]);
    const glm::dvec3 x = w[0] * p[a] + w[1] * p[b] + w[2] * p[c];
    const double d2 = glm::dot(x - q, x - q);
    if (d2 < best) {
      best = d2;
      out = {};
      out[a] = w[0];
      out[b] = w[1];
      out[c] = w[2];
    }
  }
  return best;
}

// A bounding volume hierarchy (Embree) over the tets of one mesh, for point location. The tets
// are a user geometry whose boxes are rounded outwards to float and widened, so that every tet
// that may hold a point within kInsideTolerance has a box within the query radius of it; the
// callbacks then decide in double. Unlike a uniform grid, the hierarchy adapts to graded meshes
// (tets of very different sizes, as in LOX), where a grid's cells hold thousands of tets.
class TetLocator {
 public:
  explicit TetLocator(const MeshData& mesh) : mesh_(mesh) {
    double max_abs = 0.0;
    for (const auto& p : mesh.positions) max_abs = std::max({max_abs, std::abs(p[0]), std::abs(p[1]), std::abs(p[2])});
    // Coordinates of about 1e38 or more have no float: no box could hold them.
    if (!(max_abs < 1e37)) throw InputError("compare_fields: vertex coordinates beyond the float range");
    slack_ = 8.0 * FLT_EPSILON * std::max(max_abs, 1e-30);
    compute_boxes();
    // One builder thread in the TSan build (parallel::kStdThreads), as in surface_tolerance.cpp:
    // Embree's own TBB workers are invisible to TSan there.
    device_ = rtcNewDevice(parallel::kStdThreads ? "threads=1" : nullptr);
    if (device_ == nullptr) throw std::runtime_error("Embree: cannot create a device");
    scene_ = rtcNewScene(device_);
    // A Morton-code build: several times faster to build than the default SAH one, and each
    // point's query only descends to the boxes holding it, which a lower-quality tree hardly slows.
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_LOW);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_LOW);
    rtcSetGeometryUserPrimitiveCount(geom, static_cast<unsigned>(mesh.tets.size()));
    rtcSetGeometryUserData(geom, this);
    rtcSetGeometryBoundsFunction(geom, &TetLocator::tet_bounds, nullptr);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw std::runtime_error("Embree: building the tet hierarchy failed");
  }
  ~TetLocator() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  TetLocator(const TetLocator&) = delete;
  TetLocator& operator=(const TetLocator&) = delete;

  // Among the tets whose box holds q: the largest minimum barycentric coordinate wins (ties to the
  // smaller tet id); it holds q if that coordinate is >= -kInsideTolerance. Otherwise q is outside
  // the mesh and the closest tet (exact point-tet distance, ties to the smaller id) is used.
  Location locate(const glm::dvec3& q) const {
    Search inside{this, q};
    inside.best = -std::numeric_limits<double>::infinity();
    query(inside, static_cast<float>(slack_), &TetLocator::on_inside);
    if (inside.loc.tet != kInvalid && inside.best >= -kInsideTolerance) {
      if (inside.best < 0.0) {  // on a face up to rounding: snap onto it
        double sum = 0.0;
        for (double& x : inside.loc.bary) sum += (x = std::max(x, 0.0));
        for (double& x : inside.loc.bary) x /= sum;
      }
      return inside.loc;
    }
    Search nearest{this, q};
    nearest.best = std::numeric_limits<double>::infinity();  // squared distance
    nearest.loc.outside = true;
    query(nearest, std::numeric_limits<float>::infinity(), &TetLocator::on_nearest);
    nearest.loc.outside_distance = std::sqrt(nearest.best);
    return nearest.loc;
  }

 private:
  struct Search {
    const TetLocator* locator;
    glm::dvec3 q;
    double best = 0.0;
    Location loc;
  };

  std::array<glm::dvec3, 4> points(TetId t) const {
    const auto& tv = mesh_.tets[t];
    const auto& P = mesh_.positions;
    return {to_glm(P[tv[0]]), to_glm(P[tv[1]]), to_glm(P[tv[2]]), to_glm(P[tv[3]])};
  }

  void query(Search& search, float radius, RTCPointQueryFunction callback) const {
    RTCPointQuery query;
    query.x = static_cast<float>(search.q.x);
    query.y = static_cast<float>(search.q.y);
    query.z = static_cast<float>(search.q.z);
    query.time = 0.0f;
    query.radius = radius;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(scene_, &query, &context, callback, &search);
  }

  // Each tet's box, computed once (Embree's builder asks for a box several times).
  // A point whose barycentric coordinates are >= -kInsideTolerance is within 4 kInsideTolerance
  // times the tet's diameter of it: widen by more. The widening also exceeds slack_, which bounds
  // the error of rounding a coordinate to float, so the float box holds the double one.
  void compute_boxes() {
    boxes_.resize(mesh_.tets.size());
    parallel::for_range<std::size_t>(0, mesh_.tets.size(), 4096, "tet_boxes", [&](std::size_t b, std::size_t e) {
      for (std::size_t t = b; t < e; ++t) {
        const auto p = points(static_cast<TetId>(t));
        glm::dvec3 lo = p[0], hi = p[0];
        for (int i = 1; i < 4; ++i) lo = glm::min(lo, p[i]), hi = glm::max(hi, p[i]);
        const glm::dvec3 extent = hi - lo;
        const double widen = 1e-8 * std::max({extent.x, extent.y, extent.z}) + 2.0 * slack_;
        boxes_[t] = {static_cast<float>(lo.x - widen), static_cast<float>(lo.y - widen), static_cast<float>(lo.z - widen),
                     static_cast<float>(hi.x + widen), static_cast<float>(hi.y + widen), static_cast<float>(hi.z + widen)};
      }
    });
  }

  static void tet_bounds(const RTCBoundsFunctionArguments* args) {
    const auto& box = static_cast<const TetLocator*>(args->geometryUserPtr)->boxes_[args->primID];
    RTCBounds* o = args->bounds_o;
    o->lower_x = box[0], o->lower_y = box[1], o->lower_z = box[2];
    o->upper_x = box[3], o->upper_y = box[4], o->upper_z = box[5];
  }

  static bool on_inside(RTCPointQueryFunctionArguments* args) {
    auto* s = static_cast<Search*>(args->userPtr);
    const TetId t = args->primID;
    Bary l;
    if (!barycentric(s->locator->points(t), s->q, l)) return false;
    const double m = std::min({l[0], l[1], l[2], l[3]});
    if (m > s->best || (m == s->best && t < s->loc.tet)) s->best = m, s->loc.tet = t, s->loc.bary = l;
    return false;  // the radius stays: every tet whose box holds q is seen
  }

  static bool on_nearest(RTCPointQueryFunctionArguments* args) {
    auto* s = static_cast<Search*>(args->userPtr);
    const TetId t = args->primID;
    Bary l;
    const double d2 = closest_in_tet(s->locator->points(t), s->q, l);
    if (!(d2 < s->best || (d2 == s->best && t < s->loc.tet))) return false;
    s->best = d2, s->loc.tet = t, s->loc.bary = l;
    args->query->radius = std::nextafter(static_cast<float>(std::sqrt(d2) + s->locator->slack_),
                                         std::numeric_limits<float>::infinity());
    return true;
  }

  const MeshData& mesh_;
  double slack_ = 0.0;
  std::vector<std::array<float, 6>> boxes_;  // [tet] lower x, y, z, upper x, y, z
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

void check_tets(const MeshData& m, const char* which) {
  const std::size_t nv = m.positions.size();
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (const VertId v : m.tets[t])
      if (v >= nv)
        throw InputError(std::string(which) + " tet " + std::to_string(t) + ": vertex index " +
                         std::to_string(v) + " out of range [0, " + std::to_string(nv) + ")");
  for (const auto& tet : m.tets)
    for (const VertId v : tet)
      if (!std::isfinite(m.positions[v][0]) || !std::isfinite(m.positions[v][1]) || !std::isfinite(m.positions[v][2]))
        throw InputError("compare_fields: a tet has a non-finite vertex coordinate");
}

void check_field(const MeshData& m, const VertexField& f, const char* which) {
  if (f.components < 1 || f.values.size() != m.positions.size() * static_cast<std::size_t>(f.components))
    throw InputError(std::string(which) + " field '" + f.name + "': " + std::to_string(f.values.size()) +
                     " values for " + std::to_string(m.positions.size()) + " vertices of " +
                     std::to_string(f.components) + " components");
}

// Vertices used by at least one tet, in increasing order.
std::vector<VertId> used_vertices(const MeshData& m) {
  std::vector<std::uint8_t> used(m.positions.size(), 0);
  for (const auto& tv : m.tets)
    for (const VertId v : tv) used[v] = 1;
  std::vector<VertId> out;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) out.push_back(static_cast<VertId>(v));
  return out;
}

// Locates `queries` (vertices of `from`) in `in`.
std::vector<Location> locate_all(const MeshData& from, const std::vector<VertId>& queries, const TetLocator& locator) {
  std::vector<Location> loc(queries.size());
  parallel::for_range<std::size_t>(0, queries.size(), 512, "locate", [&](std::size_t q0, std::size_t q1) {
    for (std::size_t q = q0; q < q1; ++q) loc[q] = locator.locate(to_glm(from.positions[queries[q]]));
  });
  return loc;
}

// Below this many queries per tet, a sweep over the tets beats building a hierarchy over them.
constexpr std::size_t kSweepTetsPerQuery = 4;

// The same answers as locate_all for few points in a big mesh (simplified vertices in the
// original): one pass over the tets, each testing the points that a uniform grid over the points
// puts in its widened box (as TetLocator's: every tet that may hold a point within
// kInsideTolerance is tested), so nothing is built over the big mesh. The best tet of each point
// is kept per thread and merged with the same order-free rule (largest minimum barycentric
// coordinate, ties to the smaller id); points inside no tet go to `fallback()`, a TetLocator.
template <class Fallback>
std::vector<Location> locate_by_sweep(const MeshData& from, const std::vector<VertId>& queries, const MeshData& in,
                                      Fallback&& fallback) {
  const std::size_t nq = queries.size();
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const VertId v : queries) lo = glm::min(lo, to_glm(from.positions[v])), hi = glm::max(hi, to_glm(from.positions[v]));
  const glm::dvec3 extent = glm::max(hi - lo, glm::dvec3(0.0));
  const double longest = std::max({extent.x, extent.y, extent.z});
  // About one point per cell (cells of side h), at most 1024 cells per axis.
  double volume = 1.0;
  int flat_axes = 0;
  for (int a = 0; a < 3; ++a) {
    if (extent[a] > 1e-9 * longest) {
      volume *= extent[a];
    } else {
      ++flat_axes;
    }
  }
  const double h = longest > 0.0 ? std::pow(volume / static_cast<double>(nq), 1.0 / (3 - std::min(flat_axes, 2))) : 1.0;
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a)
    dims[a] = h > 0.0 ? static_cast<int>(std::clamp(std::ceil(extent[a] / h), 1.0, 1024.0)) : 1;
  const auto cell_of = [&](double x, int a) {  // clamped before the cast: a big tet's box reaches far
    const double f = extent[a] > 0.0 ? (x - lo[a]) / extent[a] * dims[a] : 0.0;
    return static_cast<int>(std::clamp(f, 0.0, static_cast<double>(dims[a] - 1)));
  };
  const std::size_t cell_count = static_cast<std::size_t>(dims[0]) * dims[1] * dims[2];
  const auto cell_index = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) + static_cast<std::size_t>(dims[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims[1]) * k);
  };
  std::vector<std::uint32_t> start(cell_count + 1, 0), points(nq);
  std::vector<std::size_t> point_cell(nq);
  for (std::size_t q = 0; q < nq; ++q) {
    const glm::dvec3 x = to_glm(from.positions[queries[q]]);
    point_cell[q] = cell_index(cell_of(x.x, 0), cell_of(x.y, 1), cell_of(x.z, 2));
    ++start[point_cell[q] + 1];
  }
  for (std::size_t c = 0; c < cell_count; ++c) start[c + 1] += start[c];
  {
    std::vector<std::uint32_t> cursor(start.begin(), start.end() - 1);
    for (std::size_t q = 0; q < nq; ++q) points[cursor[point_cell[q]]++] = static_cast<std::uint32_t>(q);
  }

  struct Best {
    double m = -std::numeric_limits<double>::infinity();
    TetId tet = kInvalid;
    Bary bary{};
  };
  parallel::PerThread<std::vector<Best>> per_thread([nq] { return std::vector<Best>(nq); });
  const auto& P = in.positions;
  parallel::for_range<std::size_t>(0, in.tets.size(), 4096, "locate_sweep", [&](std::size_t t0, std::size_t t1) {
    std::vector<Best>& best = per_thread.local();
    for (std::size_t t = t0; t < t1; ++t) {
      const auto& tv = in.tets[t];
      const std::array<glm::dvec3, 4> p = {to_glm(P[tv[0]]), to_glm(P[tv[1]]), to_glm(P[tv[2]]), to_glm(P[tv[3]])};
      glm::dvec3 blo = p[0], bhi = p[0];
      for (int i = 1; i < 4; ++i) blo = glm::min(blo, p[i]), bhi = glm::max(bhi, p[i]);
      const glm::dvec3 size = bhi - blo;
      const glm::dvec3 widen(1e-8 * std::max({size.x, size.y, size.z}));
      blo -= widen;
      bhi += widen;
      if (blo.x > hi.x || blo.y > hi.y || blo.z > hi.z || bhi.x < lo.x || bhi.y < lo.y || bhi.z < lo.z) continue;
      for (int k = cell_of(blo.z, 2); k <= cell_of(bhi.z, 2); ++k)
        for (int j = cell_of(blo.y, 1); j <= cell_of(bhi.y, 1); ++j)
          for (int i = cell_of(blo.x, 0); i <= cell_of(bhi.x, 0); ++i) {
            const std::size_t c = cell_index(i, j, k);
            for (std::uint32_t s = start[c]; s < start[c + 1]; ++s) {
              const std::uint32_t q = points[s];
              const glm::dvec3 x = to_glm(from.positions[queries[q]]);
              if (x.x < blo.x || x.y < blo.y || x.z < blo.z || x.x > bhi.x || x.y > bhi.y || x.z > bhi.z) continue;
              Bary l;
              if (!barycentric(p, x, l)) continue;
              const double m = std::min({l[0], l[1], l[2], l[3]});
              Best& b = best[q];
              if (m > b.m || (m == b.m && t < b.tet)) b = {m, static_cast<TetId>(t), l};
            }
          }
    }
  });

  std::vector<Best> merged(nq);
  for (const std::vector<Best>& best : per_thread)
    for (std::size_t q = 0; q < nq; ++q)
      if (best[q].m > merged[q].m || (best[q].m == merged[q].m && best[q].tet < merged[q].tet)) merged[q] = best[q];
  std::vector<Location> loc(nq);
  for (std::size_t q = 0; q < nq; ++q) {
    if (merged[q].tet == kInvalid || merged[q].m < -kInsideTolerance) {
      loc[q] = fallback().locate(to_glm(from.positions[queries[q]]));  // outside the mesh: the closest tet
      continue;
    }
    loc[q].tet = merged[q].tet;
    loc[q].bary = merged[q].bary;
    if (merged[q].m < 0.0) {  // on a face up to rounding: snap onto it, as TetLocator does
      double sum = 0.0;
      for (double& x : loc[q].bary) sum += (x = std::max(x, 0.0));
      for (double& x : loc[q].bary) x /= sum;
    }
  }
  return loc;
}

LocationStats location_stats(const std::vector<Location>& loc) {
  LocationStats s;
  s.points = loc.size();
  for (const Location& l : loc)
    if (l.outside) ++s.outside, s.max_outside_distance = std::max(s.max_outside_distance, l.outside_distance);
  return s;
}

// Sum of squared and max absolute differences, at the query vertices (of some mesh), between
// their own value of component c (from_field) and `in`'s field interpolated at their location.
struct ErrorSums {
  double sum_sq = 0.0;
  double max_abs = 0.0;
};

ErrorSums direction_error(const VertexField& from_field, const std::vector<VertId>& queries,
                          const std::vector<Location>& loc, const MeshData& in, const VertexField& in_field, int c) {
  const std::size_t n = queries.size();
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  const std::size_t fk = static_cast<std::size_t>(from_field.components);
  const std::size_t ik = static_cast<std::size_t>(in_field.components);
  std::vector<ErrorSums> part(blocks);
  parallel::for_range<std::size_t>(0, blocks, 1, "field_error", [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) {
      ErrorSums s;
      for (std::size_t q = b * kBlock; q < std::min(n, (b + 1) * kBlock); ++q) {
        const auto& tv = in.tets[loc[q].tet];
        double interp = 0.0;
        for (int i = 0; i < 4; ++i) interp += loc[q].bary[i] * in_field.values[tv[i] * ik + c];
        const double d = from_field.values[queries[q] * fk + c] - interp;
        s.sum_sq += d * d;
        s.max_abs = std::max(s.max_abs, std::abs(d));
      }
      part[b] = s;
    }
  });
  // Neumaier-compensated sum of the block sums, in block order.
  ErrorSums total;
  double comp = 0.0;
  for (const ErrorSums& s : part) {
    const double t = total.sum_sq + s.sum_sq;
    comp += std::abs(total.sum_sq) >= std::abs(s.sum_sq) ? (total.sum_sq - t) + s.sum_sq : (s.sum_sq - t) + total.sum_sq;
    total.sum_sq = t;
    total.max_abs = std::max(total.max_abs, s.max_abs);
  }
  total.sum_sq += comp;
  return total;
}

DirectionalError finish(const ErrorSums& s, std::size_t n, double scale) {
  DirectionalError e;
  e.samples = n;
  if (n == 0) return e;
  e.rms = std::sqrt(s.sum_sq / static_cast<double>(n));
  e.max_abs = s.max_abs;
  e.rms_rel = e.rms / scale;
  e.max_rel = e.max_abs / scale;
  return e;
}

}  // namespace

// The original's checked tets, used vertices and (built on first need) point locator.
struct FieldErrorReference::Prepared {
  explicit Prepared(const MeshData& mesh) : original(mesh) {
    check_tets(original, "original");
    used = used_vertices(original);
  }
  const TetLocator& locator() const {
    std::call_once(locator_built, [&] { locator_ = std::make_unique<TetLocator>(original); });
    return *locator_;
  }

  const MeshData& original;
  std::vector<VertId> used;

 private:
  mutable std::once_flag locator_built;
  mutable std::unique_ptr<TetLocator> locator_;
};

FieldErrorReference::FieldErrorReference(const MeshData& original) : prepared_(std::make_unique<Prepared>(original)) {}
FieldErrorReference::~FieldErrorReference() = default;

FieldError FieldErrorReference::compare(const MeshData& simplified) const {
  const MeshData& original = prepared_->original;
  check_tets(simplified, "simplified");

  FieldError out;
  // Match by name: the first field of each name in each mesh.
  auto find = [](const MeshData& m, const std::string& name) -> const VertexField* {
    for (const auto& f : m.fields)
      if (f.name == name) return &f;
    return nullptr;
  };
  std::vector<std::pair<const VertexField*, const VertexField*>> pairs;
  auto note_unmatched = [&](const std::string& name) {
    if (std::find(out.unmatched_fields.begin(), out.unmatched_fields.end(), name) == out.unmatched_fields.end())
      out.unmatched_fields.push_back(name);
  };
  for (const auto& f : original.fields) {
    if (find(original, f.name) != &f) continue;  // a later duplicate name
    const VertexField* g = find(simplified, f.name);
    if (g && g->components == f.components) {
      check_field(original, f, "original");
      check_field(simplified, *g, "simplified");
      pairs.emplace_back(&f, g);
    } else {
      note_unmatched(f.name);
    }
  }
  for (const auto& g : simplified.fields) {
    const VertexField* f = find(original, g.name);
    if (!f || f->components != g.components) note_unmatched(g.name);
  }
  if (pairs.empty() || original.tets.empty() || simplified.tets.empty()) return out;

  const std::vector<VertId>& orig_q = prepared_->used;
  const std::vector<VertId> simp_q = used_vertices(simplified);
  const std::vector<Location> orig_loc = locate_all(original, orig_q, TetLocator(simplified));
  const std::vector<Location> simp_loc =
      simp_q.size() * kSweepTetsPerQuery < original.tets.size()
          ? locate_by_sweep(simplified, simp_q, original, [&]() -> const TetLocator& { return prepared_->locator(); })
          : locate_all(simplified, simp_q, prepared_->locator());
  out.original_in_simplified = location_stats(orig_loc);
  out.simplified_in_original = location_stats(simp_loc);

  for (const auto& [f, g] : pairs)
    for (int c = 0; c < f->components; ++c) {
      ComponentError e;
      e.field = f->name;
      e.component = c;
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const VertId v : orig_q) {
        const double x = f->values[v * static_cast<std::size_t>(f->components) + c];
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
      e.range = hi - lo;
      const double scale = e.range > 0.0 ? e.range : 1.0;
      const ErrorSums a = direction_error(*f, orig_q, orig_loc, simplified, *g, c);
      const ErrorSums b = direction_error(*g, simp_q, simp_loc, original, *f, c);
      e.original_to_simplified = finish(a, orig_q.size(), scale);
      e.simplified_to_original = finish(b, simp_q.size(), scale);
      e.rms_both = std::sqrt((a.sum_sq + b.sum_sq) / static_cast<double>(orig_q.size() + simp_q.size()));
      e.rms_both_rel = e.rms_both / scale;
      out.worst_rms_rel = std::max(out.worst_rms_rel, e.rms_both_rel);
      out.worst_max_rel = std::max({out.worst_max_rel, e.original_to_simplified.max_rel, e.simplified_to_original.max_rel});
      out.components.push_back(std::move(e));
    }
  return out;
}

FieldError compare_fields(const MeshData& original, const MeshData& simplified) {
  return FieldErrorReference(original).compare(simplified);
}

DenseBoundCheck check_bounds_densely(const MeshData& original, const MeshData& simplified, const std::vector<float>& tet_bounds,
                                     std::uint64_t points, std::uint64_t seed) {
  check_tets(original, "original");
  check_tets(simplified, "simplified");
  // The matched components: (original field, simplified field, component, offset in the bounds).
  struct Match {
    const VertexField* orig;
    const VertexField* simp;
    int component;
    std::size_t offset;
    double range;
  };
  std::vector<Match> matches;
  std::size_t stride = 0;
  for (const VertexField& f : simplified.fields) stride += static_cast<std::size_t>(f.components);
  std::size_t offset = 0;
  const std::vector<VertId> used = used_vertices(original);
  for (const VertexField& f : simplified.fields) {
    const VertexField* o = nullptr;
    for (const VertexField& g : original.fields)
      if (g.name == f.name && g.components == f.components && o == nullptr) o = &g;
    if (o != nullptr) {
      check_field(original, *o, "original");
      check_field(simplified, f, "simplified");
      for (int c = 0; c < f.components; ++c) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (VertId x : used) {
          const double v = o->values[x * static_cast<std::size_t>(o->components) + c];
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
        matches.push_back({o, &f, c, offset + static_cast<std::size_t>(c), hi > lo ? hi - lo : 1.0});
      }
    }
    offset += static_cast<std::size_t>(f.components);
  }
  if (tet_bounds.size() != simplified.tets.size() * stride)
    throw std::invalid_argument("check_bounds_densely: " + std::to_string(tet_bounds.size()) + " bounds for " +
                                std::to_string(simplified.tets.size()) + " tets of " + std::to_string(stride) + " components");
  DenseBoundCheck out;
  if (matches.empty() || original.tets.empty() || simplified.tets.empty()) return out;
  const TetLocator locator(simplified);
  std::vector<std::pair<TetId, int>> corner_of(original.positions.size(), {kInvalid, 0});  // a tet of each vertex
  for (TetId t = original.tets.size(); t-- > 0;)
    for (int k = 0; k < 4; ++k) corner_of[original.tets[t][k]] = {t, k};
  const std::uint64_t total = points + used.size();
  const std::size_t blocks = static_cast<std::size_t>((total + kBlock - 1) / kBlock);
  std::vector<DenseBoundCheck> part(blocks);
  const auto orig_points = [&](TetId t) {
    const auto& tv = original.tets[t];
    const auto& P = original.positions;
    return std::array<glm::dvec3, 4>{to_glm(P[tv[0]]), to_glm(P[tv[1]]), to_glm(P[tv[2]]), to_glm(P[tv[3]])};
  };
  parallel::for_range<std::size_t>(0, blocks, 1, "dense_bounds", [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) {
      DenseBoundCheck& r = part[b];
      std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + b);  // one stream per block: any thread count
      std::uniform_real_distribution<double> uniform(0.0, 1.0);
      for (std::uint64_t i = b * kBlock; i < std::min<std::uint64_t>(total, (b + 1) * kBlock); ++i) {
        // The point, its original tet and its barycentric coordinates there.
        TetId t;
        Bary w{};
        if (i < points) {
          t = static_cast<TetId>(i % original.tets.size());
          double sum = 0.0;
          for (double& x : w) sum += (x = -std::log(1.0 - uniform(rng)));  // uniform in the tet (Dirichlet(1,1,1,1))
          for (double& x : w) x /= sum;
        } else {
          // An original vertex: as a corner of the first tet that has it.
          const auto [s, k] = corner_of[used[i - points]];
          t = s;
          w[static_cast<std::size_t>(k)] = 1.0;
        }
        const auto p = orig_points(t);
        const glm::dvec3 q = w[0] * p[0] + w[1] * p[1] + w[2] * p[2] + w[3] * p[3];
        const Location loc = locator.locate(q);
        if (loc.outside) {
          ++r.outside;
          continue;
        }
        ++r.points;
        const auto& ov = original.tets[t];
        const auto& sv = simplified.tets[loc.tet];
        for (const Match& m : matches) {
          const std::size_t ok = static_cast<std::size_t>(m.orig->components), sk = static_cast<std::size_t>(m.simp->components);
          double f = 0.0, g = 0.0;
          for (int k = 0; k < 4; ++k) {
            f += w[k] * m.orig->values[ov[k] * ok + m.component];
            g += loc.bary[k] * m.simp->values[sv[k] * sk + m.component];
          }
          const double error = std::abs(f - g);
          const double bound = tet_bounds[loc.tet * stride + m.offset];
          r.worst_error_rel = std::max(r.worst_error_rel, error / m.range);
          r.worst_excess_rel = std::max(r.worst_excess_rel, (error - bound) / m.range);
          if (error > bound * (1.0 + 1e-9) + 1e-12 * m.range) {
            if (r.violations++ == 0)
              r.first_violation = m.simp->name + "[" + std::to_string(m.component) + "] error " + std::to_string(error) +
                                  " at (" + std::to_string(q.x) + ", " + std::to_string(q.y) + ", " + std::to_string(q.z) +
                                  ") in tet " + std::to_string(loc.tet) + ", bound " + std::to_string(bound);
          }
        }
      }
    }
  });
  for (const DenseBoundCheck& r : part) {  // in block order: the first violation is the same for any thread count
    out.points += r.points;
    out.outside += r.outside;
    if (out.violations == 0 && r.violations > 0) out.first_violation = r.first_violation;
    out.violations += r.violations;
    out.worst_error_rel = std::max(out.worst_error_rel, r.worst_error_rel);
    out.worst_excess_rel = std::max(out.worst_excess_rel, r.worst_excess_rel);
  }
  return out;
}

std::vector<std::string> field_bound_violations(const FieldError& measured, const std::vector<double>& bounds) {
  std::vector<std::string> violations;
  for (std::size_t c = 0; c < bounds.size() && c < measured.components.size(); ++c) {
    const ComponentError& m = measured.components[c];
    const double error = m.original_to_simplified.max_abs;
    if (error > bounds[c] * (1.0 + 1e-9) + 1e-12 * m.range)
      violations.push_back(m.field + "[" + std::to_string(m.component) + "] measured " + std::to_string(error) +
                           " at an original vertex, bound " + std::to_string(bounds[c]));
  }
  return violations;
}

}  // namespace topotet
