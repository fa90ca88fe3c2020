#include "cost/cost.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "parallel/for_range.h"
#include "mesh/prefetch.h"
#include "cost/quadric.h"
#include "cost/field_pins.h"

namespace topotet {
namespace {

constexpr std::uint8_t kStale = 0xFF;         // unknown
constexpr std::uint8_t kStaleFeature = 0xFE;  // unknown, but it was not 0: skip the interior test
constexpr double kLengthTieBreak = 1e-6;
// The size term's unit (SimplifyOptions::size_weight; cost.h): an edge of length l weighs
// size_weight x kSizeUnit x l^3, about the quadric error of a relative field error
// sqrt(size_weight) over the ~20 tets of edge length l around it (each input tet counted at its 4
// vertices: 4 x 20 / (6 sqrt 2) = 9.43).
constexpr double kSizeUnit = 80.0 / (6.0 * 1.4142135623730951);
// A feature face's field term weighs this many tets (cost.h).
constexpr double kFeatureFieldWeight = 3.0;
// The new vertex's field value: this much of the mesh's field at its position, the rest the
// quadric's (cost.h).
constexpr double kFieldBlend = 0.25;

enum Placement : int { kAtU = 0, kMidpoint = 1, kOptimum = 2, kAlong = 3 };

}  // namespace

CostModel::CostModel(const MeshModel& mesh, const SimplifyOptions& options, const SurfaceReference* surfaces)
    : stride_(mesh.field_stride()), surfaces_(surfaces), vertex_count_(mesh.positions.size()) {
  // The quadric's field coordinates: every component of a field with a positive weight, in mesh
  // order, at most kMaxQuadricDim - 3 of them.
  std::vector<double> component_weight;
  for (std::size_t f = 0, offset = 0; f < mesh.fields.size(); offset += mesh.fields[f].components, ++f) {
    const auto it = options.field_weights.find(mesh.fields[f].name);
    const double w = it == options.field_weights.end() ? 1.0 : it->second;
    for (int c = 0; c < mesh.fields[f].components; ++c)
      if (w > 0.0 && static_cast<int>(component_.size()) < kMaxQuadricDim - 3) {
        component_.push_back(static_cast<int>(offset) + c);
        component_weight.push_back(w);
      }
  }
  const int k = static_cast<int>(component_.size());
  n_ = 3 + k;
  // The size term (cost.h); auto: on where only the geometry steers the cost (SimplifyOptions).
  const double size_weight = options.size_weight >= 0.0 ? options.size_weight : k == 0 ? kAutoSizeWeight : 0.0;
  length_weight_ = kLengthTieBreak + size_weight * kSizeUnit;
  compute_field_pins(mesh, options.isosurfaces, pins_);  // checked by simplify() (driver.cpp)
  const std::size_t nv = mesh.positions.size();
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  field_min_.assign(k, std::numeric_limits<double>::max());
  std::vector<double> field_max(k, -std::numeric_limits<double>::max());
  for (std::size_t v = 0; v < nv; ++v) {
    if (mesh.is_dead_vertex(static_cast<VertId>(v))) continue;
    lo = glm::min(lo, mesh.positions[v]);
    hi = glm::max(hi, mesh.positions[v]);
    for (int c = 0; c < k; ++c) {
      const double f = mesh.field_values[v * stride_ + component_[c]];
      field_min_[c] = std::min(field_min_[c], f);
      field_max[c] = std::max(field_max[c], f);
    }
  }
  const CostUnits* units = options.cost_units;  // the caller's units (checked by simplify)
  if (units != nullptr) {
    lo = glm::dvec3(units->origin[0], units->origin[1], units->origin[2]);
    hi = lo + glm::dvec3(units->diagonal, 0.0, 0.0);
    for (int c = 0; c < k; ++c) {
      field_min_[c] = units->field_min[component_[c]];
      field_max[c] = field_min_[c] + units->field_range[component_[c]];
    }
  }
  origin_ = lo;
  const double diag = glm::length(hi - lo);
  inv_diag_ = diag > 0.0 ? 1.0 / diag : 1.0;
  field_scale_.resize(k);
  for (int c = 0; c < k; ++c) {
    const double range = field_max[c] - field_min_[c];
    field_scale_[c] = range > 0.0 ? 1.0 / range : 1.0;  // a constant field stays constant anyway
  }

  // The reference volume: the mean tet volume (normalised), summed in fixed blocks (deterministic).
  constexpr std::size_t kBlock = 1 << 16;
  const std::size_t nt = mesh.tets.size(), blocks = (nt + kBlock - 1) / kBlock;
  std::vector<double> block_volume(blocks, 0.0);
  std::vector<std::size_t> block_count(blocks, 0);
  parallel::for_range<std::size_t>(0, blocks, 1, "mean_volume", [&](std::size_t begin, std::size_t end) {
    for (std::size_t bi = begin; bi < end; ++bi)
      for (std::size_t t = bi * kBlock; t < std::min(nt, (bi + 1) * kBlock); ++t) {
        if (mesh.is_dead_tet(static_cast<TetId>(t))) continue;
        const auto& tv = mesh.tets[t];
        const glm::dvec3 p0 = mesh.positions[tv[0]];
        block_volume[bi] += std::fabs(glm::dot(mesh.positions[tv[1]] - p0, glm::cross(mesh.positions[tv[2]] - p0,
                                                                                    mesh.positions[tv[3]] - p0)));
        ++block_count[bi];
      }
  });
  double total_volume = 0.0;
  std::size_t tet_count = 0;
  for (std::size_t bi = 0; bi < blocks; ++bi) total_volume += block_volume[bi], tet_count += block_count[bi];
  const double v_ref = units != nullptr ? units->mean_tet_volume * inv_diag_ * inv_diag_ * inv_diag_
                      : tet_count ? total_volume / 6.0 / static_cast<double>(tet_count) * inv_diag_ * inv_diag_ * inv_diag_
                                  : 1.0;
  const double e_ref = std::cbrt(6.0 * std::sqrt(2.0) * v_ref);  // the regular tet of volume v_ref
  const double a_ref = std::sqrt(3.0) / 4.0 * e_ref * e_ref;

  orders_ = std::make_unique<std::atomic<std::uint8_t>[]>(nv);
  curved_ = std::make_unique<std::uint8_t[]>(nv);  // zeroed: interior and dead vertices are not curved
  record_size_ = static_cast<std::size_t>(quadric_size(n_) + n_);
  records_.assign(nv * record_size_, 0.0);
  parallel::for_range<std::size_t>(0, nv, 4096, "normalise", [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) normalise(mesh, static_cast<VertId>(v), coordinates(static_cast<VertId>(v)));
  });
  if (k > 0) add_star_field_quadrics(mesh, v_ref, component_weight);
  parallel::for_range<std::size_t>(0, nv, 512, "init_quadrics", [&](std::size_t begin, std::size_t end) {
    LinkScratch scratch;
    double pts[4 * kMaxQuadricDim], tet_pts[4 * kMaxQuadricDim], weights[kMaxQuadricDim];
    for (std::size_t vi = begin; vi < end; ++vi) {
      const VertId a = static_cast<VertId>(vi);
      if (mesh.is_dead_vertex(a)) {
        orders_[a].store(kStale, std::memory_order_relaxed);
        continue;
      }
      double* q = quadric(a);
      // Most vertices are interior: no special face or polyline edge to add, order 0.
      if (is_interior(mesh, a)) {
        orders_[a].store(0, std::memory_order_relaxed);
        continue;
      }
      LinkScratch::VertexData& data = scratch.a;
      const VertexOrders orders = classify_vertex(mesh, a, data, scratch);
      orders_[a].store(orders.ktilde, std::memory_order_relaxed);
      normalise(mesh, a, pts);
      double fan_area = 0.0;
      glm::dvec3 first_normal(0.0);
      bool flat = true;
      for (const auto& face : data.special) {
        normalise(mesh, face.x, pts + n_);
        normalise(mesh, face.y, pts + 2 * n_);
        const glm::dvec3 p0(pts[0], pts[1], pts[2]), p1(pts[n_], pts[n_ + 1], pts[n_ + 2]),
            p2(pts[2 * n_], pts[2 * n_ + 1], pts[2 * n_ + 2]);
        const glm::dvec3 normal = glm::cross(p1 - p0, p2 - p0);
        fan_area += 0.5 * glm::length(normal);
        // Every face of the fan contains a, so parallel normals mean one plane. The bound is far
        // below any real curvature and far above the rounding of coordinates on a tilted plane.
        if (first_normal == glm::dvec3(0.0)) first_normal = normal;
        else if (glm::length(glm::cross(first_normal, normal)) > 1e-9 * glm::length(first_normal) * glm::length(normal))
          flat = false;
      }
      curved_[a] = !flat;
      const double mean_area = data.special.empty() ? 0.0 : fan_area / static_cast<double>(data.special.size());
      const double plane_scale = !(mean_area > 0.0) ? 1.0 : (a_ref / mean_area) * (a_ref / mean_area);
      const double field_per_area = fan_area > 0.0 ? kFeatureFieldWeight * v_ref * static_cast<double>(data.special.size()) / fan_area : 0.0;
      for (const auto& face : data.special) {
        normalise(mesh, face.x, pts + n_);
        normalise(mesh, face.y, pts + 2 * n_);
        const glm::dvec3 p0(pts[0], pts[1], pts[2]), p1(pts[n_], pts[n_ + 1], pts[n_ + 2]),
            p2(pts[2 * n_], pts[2 * n_ + 1], pts[2 * n_ + 2]);
        const double area = 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
        quadric_add_simplex_positions(q, n_, pts, 3, area * plane_scale * options.boundary_weight);
        if (k > 0 && field_per_area > 0.0) {
          // The field term of the face is the error against the linear interpolant of a tet
          // through it (the first in a's chain), not the face's own interpolant: that one is
          // constant along the face's normal, so a vertex off the face's plane (a curved or
          // jittered boundary, a midpoint across a fold) would pay for, and take, a linear
          // field's normal slope as error. With the tet's interpolant a linear field costs
          // nothing anywhere. Weighted by the face's area (measure / volume cancels the tet's).
          TetId through = kInvalid;
          mesh.for_each_tet_of(a, [&](TetId t) {
            const auto& tv = mesh.tets[t];
            const auto has = [&](VertId x) { return tv[0] == x || tv[1] == x || tv[2] == x || tv[3] == x; };
            if (through == kInvalid && has(face.x) && has(face.y)) through = t;
          });
          if (through != kInvalid) {
            for (int j = 0; j < 4; ++j) std::copy_n(coordinates(mesh.tets[through][j]), n_, tet_pts + j * n_);
            const glm::dvec3 t0(tet_pts[0], tet_pts[1], tet_pts[2]), t1(tet_pts[n_], tet_pts[n_ + 1], tet_pts[n_ + 2]),
                t2(tet_pts[2 * n_], tet_pts[2 * n_ + 1], tet_pts[2 * n_ + 2]),
                t3(tet_pts[3 * n_], tet_pts[3 * n_ + 1], tet_pts[3 * n_ + 2]);
            const double volume = std::fabs(glm::dot(t1 - t0, glm::cross(t2 - t0, t3 - t0))) / 6.0;
            if (volume > 0.0) {
              for (int c = 0; c < k; ++c) weights[c] = field_per_area * area / volume * component_weight[c];
              quadric_add_field_simplex(q, n_, tet_pts, 4, weights);  // x volume
            }
          }
        }
      }
      double fan_length = 0.0;
      int polyline_edges = 0;
      for (const auto& nb : data.neighbours) {
        if (!nb.polyline) continue;
        normalise(mesh, nb.x, pts + n_);
        fan_length += glm::length(glm::dvec3(pts[n_] - pts[0], pts[n_ + 1] - pts[1], pts[n_ + 2] - pts[2]));
        ++polyline_edges;
      }
      const double mean_length = polyline_edges ? fan_length / polyline_edges : 0.0;
      const double line_scale = !(mean_length > 0.0) ? 1.0 : std::pow(e_ref / mean_length, 3);
      for (const auto& nb : data.neighbours) {
        if (!nb.polyline) continue;
        normalise(mesh, nb.x, pts + n_);
        const double length = glm::length(glm::dvec3(pts[n_] - pts[0], pts[n_ + 1] - pts[1], pts[n_ + 2] - pts[2]));
        quadric_add_simplex_positions(q, n_, pts, 2, length * line_scale * options.polyline_weight);
      }
    }
  });
  // A pass of a run in passes starts from the quadrics the last pass ended with (simplify.h),
  // indexed like this mesh's vertices, but for those marked NaN, built above from this mesh; the
  // orders and curvature flags above are this mesh's.
  if (options.quadrics_in != nullptr) {
    const std::size_t qs = static_cast<std::size_t>(quadric_size(n_));
    if (options.quadrics_in->size() != nv * qs)
      throw std::invalid_argument("quadrics_in holds " + std::to_string(options.quadrics_in->size()) +
                                  " values, not " + std::to_string(qs) + " for each of " + std::to_string(nv) + " vertices");
    for (std::size_t v = 0; v < nv; ++v) {
      const double* carried = options.quadrics_in->data() + v * qs;
      if (!mesh.is_dead_vertex(static_cast<VertId>(v)) && !std::isnan(carried[0]))
        std::copy_n(carried, qs, quadric(static_cast<VertId>(v)));
    }
  }
}

// The field part of every vertex's quadric: every tet of the star stands for one sample (weight
// v_ref); the star's total weight is shared among its tets by volume, so that slivers, whose
// gradients are unreliable, count little: Q = (tets x v_ref / star volume) x sum of volume x tet
// quadric. Each tet's quadric is computed once, not once per corner (it was a quarter of the
// set-up), block by block of tets so that the scratch stays small (kBlock x quadric_size
// doubles: 7 MB with three field components; a scratch for all tets raised LOX's peak by 10%),
// and added to its corners' sums in each star's own tet order (the incidence chains are sorted
// by tet id and the blocks are id ranges): the sums, and so the quadrics, are the same bits as a
// per-corner computation gives, for any thread count. A star meets few blocks (the tets are in
// locality order), so a vertex is visited only for the blocks between its first and last tet.
void CostModel::add_star_field_quadrics(const MeshModel& mesh, double v_ref, const std::vector<double>& weights) {
  constexpr std::size_t kBlock = std::size_t{1} << 15;
  const std::size_t nt = mesh.tets.size(), nv = mesh.positions.size();
  const std::size_t qs = static_cast<std::size_t>(quadric_size(n_));
  std::vector<double> tet_quadric(std::min(nt, kBlock) * qs), tet_volume(std::min(nt, kBlock));
  std::vector<double> star_volume(nv, 0.0);
  std::vector<TetId> first(nv, kInvalid), last(nv, 0);  // the star's smallest and largest tet id
  parallel::for_range<std::size_t>(0, nv, 4096, "star_tet_range", [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v)
      if (!mesh.is_dead_vertex(static_cast<VertId>(v)))
        mesh.for_each_tet_of(static_cast<VertId>(v), [&](TetId t) {
          first[v] = std::min(first[v], t);
          last[v] = std::max(last[v], t);
        });
  });
  for (std::size_t lo = 0; lo < nt; lo += kBlock) {
    const std::size_t hi = std::min(nt, lo + kBlock);
    parallel::for_range<std::size_t>(lo, hi, 1024, "tet_field_quadrics", [&](std::size_t begin, std::size_t end) {
      double pts[4 * kMaxQuadricDim];
      for (std::size_t t = begin; t < end; ++t) {
        double* qt = &tet_quadric[(t - lo) * qs];
        std::fill_n(qt, qs, 0.0);
        tet_volume[t - lo] = 0.0;
        if (mesh.is_dead_tet(static_cast<TetId>(t))) continue;
        for (int j = 0; j < 4; ++j) std::copy_n(coordinates(mesh.tets[t][j]), n_, pts + j * n_);
        tet_volume[t - lo] = quadric_add_field_simplex(qt, n_, pts, 4, weights.data());
      }
    });
    parallel::for_range<std::size_t>(0, nv, 512, "star_field_quadrics", [&](std::size_t begin, std::size_t end) {
      for (std::size_t v = begin; v < end; ++v) {
        if (mesh.is_dead_vertex(static_cast<VertId>(v)) || first[v] == kInvalid || last[v] < lo || first[v] >= hi) continue;
        double* q = quadric(static_cast<VertId>(v));  // zero so far: it holds the star's sum
        mesh.for_each_tet_of(static_cast<VertId>(v), [&](TetId t) {
          if (t < lo || t >= hi) return;
          const double* qt = &tet_quadric[(t - lo) * qs];
          for (std::size_t i = 0; i < qs; ++i) q[i] += qt[i];
          star_volume[v] += tet_volume[t - lo];
        });
      }
    });
  }
  parallel::for_range<std::size_t>(0, nv, 4096, "scale_field_quadrics", [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) {
      if (mesh.is_dead_vertex(static_cast<VertId>(v))) continue;
      double* q = quadric(static_cast<VertId>(v));
      if (!(star_volume[v] > 0.0)) {
        std::fill_n(q, qs, 0.0);  // a flat star adds nothing
        continue;
      }
      const double scale = v_ref * static_cast<double>(mesh.v2t_count[v]) / star_volume[v];
      for (std::size_t i = 0; i < qs; ++i) q[i] = 0.0 + scale * q[i];  // 0.0 +: a -0.0 becomes +0.0, as before
    }
  });
}

void CostModel::normalise(const MeshModel& mesh, VertId v, double* x) const {
  const glm::dvec3 p = (mesh.positions[v] - origin_) * inv_diag_;
  x[0] = p.x;
  x[1] = p.y;
  x[2] = p.z;
  const double* f = mesh.field_values.data() + static_cast<std::size_t>(v) * stride_;
  for (int c = 0; c < n_ - 3; ++c) x[3 + c] = (f[component_[c]] - field_min_[c]) * field_scale_[c];
}

std::uint8_t CostModel::order(const MeshModel& mesh, VertId v, LinkScratch& scratch) {
  std::uint8_t o = orders_[v].load(std::memory_order_relaxed);
  if (o == kStale || o == kStaleFeature) {
    o = o == kStale && is_interior(mesh, v) ? 0 : classify_vertex(mesh, v, scratch.b, scratch).ktilde;
    // Relaxed: the value is a pure function of the (unchanging during evaluation) mesh.
    orders_[v].store(o, std::memory_order_relaxed);
  }
  return o;
}

void CostModel::forget_orders() {
  for (std::size_t v = 0; v < vertex_count_; ++v) {
    const std::uint8_t o = orders_[v].load(std::memory_order_relaxed);
    if (o != 0 && o != kStale) orders_[v].store(kStaleFeature, std::memory_order_relaxed);
  }
}

bool CostModel::pins_conflict(const MeshModel& mesh, VertId a, VertId b) const {
  if (pins_.empty()) return false;
  std::uint32_t both = pins_[a] & pins_[b];
  const double* fa = mesh.field_values.data() + static_cast<std::size_t>(a) * stride_;
  const double* fb = mesh.field_values.data() + static_cast<std::size_t>(b) * stride_;
  for (; both != 0; both &= both - 1) {
    const int k = std::countr_zero(both);
    if (fa[k] != fb[k]) return true;
  }
  return false;
}

int CostModel::candidates(const MeshModel& mesh, VertId a, VertId b, CollapseCandidate out[kMaxCandidates], LinkScratch& scratch) {
  if (pins_conflict(mesh, a, b)) return 0;
  // The hot path of both engines: the quadric arithmetic is instantiated for the common
  // dimensions (positions plus up to 4 field components) so that its loops unroll.
  switch (n_) {
    case 3: return candidates_n<3>(mesh, a, b, out, scratch);
    case 4: return candidates_n<4>(mesh, a, b, out, scratch);
    case 5: return candidates_n<5>(mesh, a, b, out, scratch);
    case 6: return candidates_n<6>(mesh, a, b, out, scratch);
    case 7: return candidates_n<7>(mesh, a, b, out, scratch);
    default: return candidates_n<0>(mesh, a, b, out, scratch);
  }
}

double CostModel::edge_cost(const MeshModel& mesh, VertId a, VertId b, LinkScratch& scratch) {
  if (pins_conflict(mesh, a, b)) return std::numeric_limits<double>::infinity();
  switch (n_) {
    case 3: return edge_cost_n<3>(mesh, a, b, scratch);
    case 4: return edge_cost_n<4>(mesh, a, b, scratch);
    case 5: return edge_cost_n<5>(mesh, a, b, scratch);
    case 6: return edge_cost_n<6>(mesh, a, b, scratch);
    case 7: return edge_cost_n<7>(mesh, a, b, scratch);
    default: return edge_cost_n<0>(mesh, a, b, scratch);
  }
}

// The merged quadric of an edge ab and what every placement of it needs.
template <int kN>
struct CostModel::EdgeQuadric {
  static constexpr int kQ = quadric_size(kN > 0 ? kN : kMaxQuadricDim);
  int n;
  double q[kQ];
  double xa[kMaxQuadricDim], xb[kMaxQuadricDim], xm[kMaxQuadricDim];
  double length, tie;

  EdgeQuadric(const CostModel& model, VertId a, VertId b) : n(quadric_detail::dim<kN>(model.n_)) {
    // One record per end: quadric and normalised coordinates side by side (few cache lines).
    std::copy_n(model.quadric(a), quadric_size(n), q);
    quadric_detail::add<kN>(q, model.quadric(b), n);
    std::copy_n(model.coordinates(a), n, xa);
    std::copy_n(model.coordinates(b), n, xb);
    for (int i = 0; i < n; ++i) xm[i] = 0.5 * (xa[i] + xb[i]);
    length = glm::length(glm::dvec3(xa[0] - xb[0], xa[1] - xb[1], xa[2] - xb[2]));
    tie = model.length_weight_ * length * length * length;  // the tie break and the size term (cost.h)
  }

  // Cost at x (normalised). Where the position is constrained (an endpoint, the midpoint), the
  // field values need not be: x's field part becomes the values the merged quadric likes best at
  // that position. Keeping an endpoint's values instead let the greedy order wipe out narrow
  // field features for free. A pinned vertex keeps its values exactly (see fields_at).
  double placement_cost(double* x, bool free_fields) const {
    if (free_fields) quadric_detail::minimize_fields<kN>(q, n, x);
    return quadric_detail::eval<kN>(q, n, x) + tie;
  }

  // Cost at the optimum x (A x = -b there, so Q(x) = b.x + c): one dot product instead of the
  // whole form.
  double optimum_cost(const double* x) const {
    const double* b = q + n * (n + 1) / 2;
    double s = b[n];
    for (int i = 0; i < n; ++i) s += b[i] * x[i];
    return (s > 0.0 ? s : 0.0) + tie;
  }

  // The optimum, when the quadric is well conditioned and its minimum lies near the edge
  // (far-away minima come from nearly flat quadrics).
  bool optimum(double* xo) const {
    if (!quadric_detail::minimize<kN>(q, n, xo)) return false;
    const glm::dvec3 po(xo[0], xo[1], xo[2]), pm(xm[0], xm[1], xm[2]);
    return glm::length(po - pm) <= length;
  }
};

template <int kN>
int CostModel::candidates_n(const MeshModel& mesh, VertId a, VertId b, CollapseCandidate out[kMaxCandidates], LinkScratch& scratch) {
  if (mesh.is_frozen(a) || mesh.is_frozen(b)) return 0;  // no collapse touches a frozen vertex
  const std::uint8_t oa = order(mesh, a, scratch), ob = order(mesh, b, scratch);
  if (oa == 3 && ob == 3) return 0;  // link condition (I); pinned vertices have order 3
  const bool pa = oa == 3 && mesh.is_pinned(a), pb = ob == 3 && mesh.is_pinned(b);
  const EdgeQuadric<kN> e(*this, a, b);
  const int n = e.n;

  CollapseCandidate found[4];
  int count = 0;
  auto add = [&](VertId u, VertId v, const double* x, int placement) {
    CollapseCandidate& c = found[count++];
    c.u = u;
    c.v = v;
    c.placement = placement;
    std::copy_n(x, n, c.x);
    c.fallback = false;
    c.p = placement == kAtU ? mesh.positions[u]
          : placement == kMidpoint ? 0.5 * (mesh.positions[a] + mesh.positions[b])
                                   : origin_ + glm::dvec3(x[0], x[1], x[2]) / inv_diag_;
    c.cost = placement == kOptimum ? e.optimum_cost(c.x) : e.placement_cost(c.x, !(placement == kAtU && mesh.is_pinned(u)));
  };
  // A pinned end, or the end of higher order, stays where it is.
  if (pa || (!pb && oa > ob)) {
    add(a, b, e.xa, kAtU);
  } else if (pb || ob > oa) {
    add(b, a, e.xb, kAtU);
  } else {
    add(a, b, e.xa, kAtU);
    add(b, a, e.xb, kAtU);
    add(a, b, e.xm, kMidpoint);
    double xo[kMaxQuadricDim];
    if (optimum_allowed(a, b, oa) && e.optimum(xo)) add(a, b, xo, kOptimum);
  }
  // Cheapest first; ties keep the order above (deterministic). Sorted by index: a candidate is
  // large (its quadric coordinates), and only the winner order matters.
  int order_of[4] = {0, 1, 2, 3};
  for (int i = 1; i < count; ++i)
    for (int j = i; j > 0 && found[order_of[j]].cost < found[order_of[j - 1]].cost; --j)
      std::swap(order_of[j], order_of[j - 1]);
  for (int i = 0; i < count; ++i) {
    const CollapseCandidate& c = found[order_of[i]];
    CollapseCandidate& o = out[i];
    o.u = c.u;
    o.v = c.v;
    o.p = c.p;
    o.cost = c.cost;
    o.placement = c.placement;
    o.fallback = false;
    std::copy_n(c.x, n, o.x);
  }
  // The quality fallbacks (issue #26: where a quality floor refuses every placement above, try
  // others before refusing the edge): the points at 1/4 and 3/4 of the edge, where its two ends
  // may both move. They lie wherever the midpoint does (on the edge: on a flat face's plane, on a
  // polyline's segment), so the same rules hold; the kernel checks them like any placement. Not
  // ranked with the others: the edge's rank stays its cheapest placement's (edge_cost), and a
  // fallback is said to cost at least as much as the dearest placement before it, so the list
  // stays sorted (the engines rely on it: a verified proposal may only get dearer when its proof
  // moves on to a later placement; rounds.cpp).
  if (count >= 3) {
    double dearest = out[count - 1].cost;
    const glm::dvec3 end_a = mesh.positions[a], end_b = mesh.positions[b];
    for (const double t : {0.25, 0.75}) {
      CollapseCandidate& o = out[count++];
      o.u = a;
      o.v = b;
      o.placement = kAlong;
      o.fallback = true;
      o.p = end_a + t * (end_b - end_a);
      for (int i = 0; i < n; ++i) o.x[i] = e.xa[i] + t * (e.xb[i] - e.xa[i]);
      o.cost = dearest = std::max(e.placement_cost(o.x, true), dearest);
    }
  }
  return count;
}

template <int kN>
double CostModel::edge_cost_n(const MeshModel& mesh, VertId a, VertId b, LinkScratch& scratch) {
  constexpr double kForbidden = std::numeric_limits<double>::infinity();
  if (mesh.is_frozen(a) || mesh.is_frozen(b)) return kForbidden;  // no collapse touches a frozen vertex
  const std::uint8_t oa = order(mesh, a, scratch), ob = order(mesh, b, scratch);
  if (oa == 3 && ob == 3) return kForbidden;  // link condition (I); pinned vertices have order 3
  const bool pa = oa == 3 && mesh.is_pinned(a), pb = ob == 3 && mesh.is_pinned(b);
  const EdgeQuadric<kN> e(*this, a, b);
  double x[kMaxQuadricDim];
  // The same placements as candidates_n, in the same arithmetic; only the cheapest cost is kept.
  if (pa || (!pb && oa > ob)) {
    std::copy_n(e.xa, e.n, x);
    return e.placement_cost(x, !pa);
  }
  if (pb || ob > oa) {
    std::copy_n(e.xb, e.n, x);
    return e.placement_cost(x, !pb);
  }
  // The optimum minimises the quadric over all positions and field values, so when it is a
  // candidate it is the cheapest one: the three others need not be evaluated.
  if (optimum_allowed(a, b, oa) && e.optimum(x)) return e.optimum_cost(x);
  double best = kForbidden;
  for (const double* start : {e.xa, e.xb, e.xm}) {
    std::copy_n(start, e.n, x);
    best = std::min(best, e.placement_cost(x, true));
  }
  return best;
}

void CostModel::fields_at(const MeshModel& mesh, const CollapseCandidate& c, double* out) const {
  if (stride_ == 0) return;
  const double* fu = mesh.field_values.data() + static_cast<std::size_t>(c.u) * stride_;
  if (c.placement == kAtU) {  // a vertex that stays where it is (pinned or not) keeps its own values
    std::copy_n(fu, stride_, out);
    apply_pins(mesh, c.u, c.v, out);  // v's pins too (u may gain them)
    return;
  }
  // The mesh's current field at p: at an endpoint its values, at the midpoint the mean of the two;
  // elsewhere linear in the tet of St(u) ∪ St(v) that contains p (the first one found whose
  // barycentric coordinates are all >= 0, else the one whose smallest is largest).
  const double* fv = mesh.field_values.data() + static_cast<std::size_t>(c.v) * stride_;
  if (c.placement == kAtU) {
    std::copy_n(fu, stride_, out);
  } else if (c.placement == kMidpoint) {
    for (int k = 0; k < stride_; ++k) out[k] = 0.5 * (fu[k] + fv[k]);
  } else {
    TetId best = kInvalid;
    double best_min = -std::numeric_limits<double>::infinity(), bary[4] = {1.0, 0.0, 0.0, 0.0};
    const auto test = [&](TetId t) {
      if (best_min >= 0.0) return;  // found
      const auto& tv = mesh.tets[t];
      const glm::dvec3 a = mesh.positions[tv[0]] - c.p, b = mesh.positions[tv[1]] - c.p,
                       cc = mesh.positions[tv[2]] - c.p, d = mesh.positions[tv[3]] - c.p;
      double l[4] = {glm::dot(b, glm::cross(cc, d)), -glm::dot(a, glm::cross(cc, d)), glm::dot(a, glm::cross(b, d)),
                     -glm::dot(a, glm::cross(b, cc))};
      const double total = l[0] + l[1] + l[2] + l[3];
      if (!(total > 0.0)) return;
      for (double& x : l) x /= total;
      const double m = std::min({l[0], l[1], l[2], l[3]});
      if (m > best_min) best_min = m, best = t, std::copy_n(l, 4, bary);
    };
    // The tets around uv first: p is near the edge (cost.h), so one of them usually holds it.
    const auto has = [&](TetId t, VertId x) {
      const auto& tv = mesh.tets[t];
      return tv[0] == x || tv[1] == x || tv[2] == x || tv[3] == x;
    };
    // The other tets are walked only when none of those holds p (the walk itself costs: it was
    // most of this function's time, on every collapse).
    mesh.for_each_tet_of(c.u, [&](TetId t) { if (has(t, c.v)) test(t); });
    if (best_min < 0.0) {
      mesh.for_each_tet_of(c.u, [&](TetId t) { if (!has(t, c.v)) test(t); });
      mesh.for_each_tet_of(c.v, [&](TetId t) { if (!has(t, c.u)) test(t); });
    }
    // Outside every tet (rare: the optimum lies near the edge) the nearest tet's interpolant is
    // extended linearly rather than clamped onto the tet: a linear field stays exact.
    const double* corner[4] = {fu, fu, fu, fu};
    if (best != kInvalid)
      for (int i = 0; i < 4; ++i) corner[i] = mesh.field_values.data() + static_cast<std::size_t>(mesh.tets[best][i]) * stride_;
    for (int k = 0; k < stride_; ++k)
      out[k] = bary[0] * corner[0][k] + bary[1] * corner[1][k] + bary[2] * corner[2][k] + bary[3] * corner[3][k];
  }
  // The quadric's components: mostly its value (the best fit over the vertex's region), pulled
  // toward the field at p by kFieldBlend (see cost.h).
  for (int q = 0; q < n_ - 3; ++q) {
    const int k = component_[q];
    out[k] = (1.0 - kFieldBlend) * (c.x[3 + q] / field_scale_[q] + field_min_[q]) + kFieldBlend * out[k];
  }
  apply_pins(mesh, c.u, c.v, out);
}

void CostModel::apply_pins(const MeshModel& mesh, VertId u, VertId v, double* out) const {
  if (pins_.empty()) return;
  // u's pins first: where both ends pin a component they agree (pins_conflict refused the rest).
  for (const VertId w : {v, u})
    for (std::uint32_t bits = pins_[w]; bits != 0; bits &= bits - 1) {
      const int k = std::countr_zero(bits);
      out[k] = mesh.field_values[static_cast<std::size_t>(w) * stride_ + k];
    }
}

void CostModel::fields_at_point(const MeshModel& mesh, VertId v, const glm::dvec3& p, double* out) const {
  if (stride_ == 0) return;
  // A "collapse" of v with itself at p: every tet of St(v) is searched for p, and the quadric's
  // best field values at p (v's current ones where its field block cannot be trusted) are blended in.
  CollapseCandidate c;
  c.u = v;
  c.v = v;
  c.p = p;
  c.placement = kOptimum;
  best_at_point(mesh, v, p, c.x);
  fields_at(mesh, c, out);
}

double CostModel::point_cost(const MeshModel& mesh, VertId v, const glm::dvec3& p) const {
  double x[kMaxQuadricDim];
  best_at_point(mesh, v, p, x);
  return quadric_eval(quadric(v), n_, x);
}

void CostModel::best_at_point(const MeshModel& mesh, VertId v, const glm::dvec3& p, double* x) const {
  normalise(mesh, v, x);  // v's own field values, kept where the quadric's field block is untrustworthy
  const glm::dvec3 y = (p - origin_) * inv_diag_;
  x[0] = y.x;
  x[1] = y.y;
  x[2] = y.z;
  quadric_minimize_fields(quadric(v), n_, x);
}

void CostModel::prefetch(VertId v) const {
  const double* record = quadric(v);
  for (std::size_t offset = 0; offset < record_size_; offset += 8) topotet::prefetch(record + offset);  // 64-byte lines
  topotet::prefetch(&orders_[v]);
}

void CostModel::on_collapse(const MeshModel& mesh, VertId u, VertId v) {
  quadric_add(quadric(u), quadric(v), n_);
  if (!pins_.empty()) pins_[u] |= pins_[v];  // u is on every level triangle v was on (field_pins.h)
  curved_[u] = curved_[u] | curved_[v];  // u's region holds v's: curved if either part was
  normalise(mesh, u, coordinates(u));  // u moved and took new field values
  // Which orders can change? Only u's: its star changed wholesale (unless u was interior: then so
  // was v, since the cost model keeps the end of higher order; every tet of St(u) ∪ St(v) had one
  // material and no special face or edge at u or v, and the merged faces stay interior).
  // Every other vertex x keeps its order. Outside the removed tets St(uv), x's faces and edges
  // through v are only renamed to u. Inside, x is in the link of uv and the collapse acts on Lk(x)
  // as the contraction of its edge uv, which the link conditions keep from changing the special
  // structure there: xu and xv both special (on a surface) imply that uvx is special (E), so u and v
  // are neighbours on the special cycle (or curve) of Lk(x) and the contraction shortens it by one
  // edge; faces xuy and xvy that merge are never both special (F), so no sheet folds onto another;
  // xu and xv are never both on a curve (H); labels and pinning go with the faces, edges and
  // vertices. So the cycle or curve shape that gave x its order, and its labels, are the same after.
  // Measured before relying on it: 0 of 190,000 reclassifications of such vertices changed an
  // order (the families at 2% and every mesh of ../shared/data); property_fast_paths asserts it
  // after every collapse it takes. And the cached order steers only the placement (which end
  // stays, whether the optimum may be used): the kernel classifies both ends of an edge afresh.
  // Reclassifying the link (what this did before) was 14% of a 1M slab run on one thread.
  const std::uint8_t o = orders_[u].load(std::memory_order_relaxed);
  if (o != 0) orders_[u].store(o == kStale ? kStale : kStaleFeature, std::memory_order_relaxed);
}

std::size_t CostModel::memory_bytes() const {
  return records_.capacity() * sizeof(double) + vertex_count_ * (sizeof(std::atomic<std::uint8_t>) + 1) +
         (field_min_.capacity() + field_scale_.capacity()) * sizeof(double);
}

void set_placement_fields(const MeshModel& mesh, const CostModel& cost, const CollapseCandidate* cands, int n,
                          topotet::Placement* placements, std::vector<double>& storage) {
  const std::size_t stride = static_cast<std::size_t>(mesh.field_stride());
  storage.resize(stride * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    double* out = storage.data() + stride * static_cast<std::size_t>(i);
    cost.fields_at(mesh, cands[i], out);
    placements[i].fields = out;
  }
}

}  // namespace topotet
