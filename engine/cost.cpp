#include "cost.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "parallel/for_range.h"

namespace topotet {
namespace {

constexpr std::uint8_t kStale = 0xFF;
constexpr double kLengthTieBreak = 1e-6;

enum Placement : int { kAtU = 0, kMidpoint = 1, kOptimum = 2 };

}  // namespace

CostModel::CostModel(const TetMesh& mesh, const SimplifyOptions& options)
    : stride_(mesh.field_stride()), vertex_count_(mesh.positions.size()) {
  n_ = 3 + std::min(stride_, kMaxQuadricDim - 3);
  const std::size_t nv = mesh.positions.size();
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  field_min_.assign(n_ - 3, std::numeric_limits<double>::max());
  std::vector<double> field_max(n_ - 3, -std::numeric_limits<double>::max());
  for (std::size_t v = 0; v < nv; ++v) {
    if (mesh.is_dead_vertex(static_cast<VertId>(v))) continue;
    lo = glm::min(lo, mesh.positions[v]);
    hi = glm::max(hi, mesh.positions[v]);
    for (int c = 0; c < n_ - 3; ++c) {
      const double f = mesh.field_values[v * stride_ + c];
      field_min_[c] = std::min(field_min_[c], f);
      field_max[c] = std::max(field_max[c], f);
    }
  }
  origin_ = lo;
  const double diag = glm::length(hi - lo);
  inv_diag_ = diag > 0.0 ? 1.0 / diag : 1.0;
  field_scale_.resize(n_ - 3);
  for (int c = 0; c < n_ - 3; ++c) {
    const double range = field_max[c] - field_min_[c];
    field_scale_[c] = range > 0.0 ? 1.0 / range : 1.0;  // a constant field stays constant anyway
  }

  orders_ = std::make_unique<std::atomic<std::uint8_t>[]>(nv);
  const int qs = quadric_size(n_);
  quadrics_.assign(nv * qs, 0.0);
  parallel::for_range<std::size_t>(0, nv, 512, "init_quadrics", [&](std::size_t begin, std::size_t end) {
    LinkScratch scratch;
    double pts[4 * kMaxQuadricDim];
    for (std::size_t vi = begin; vi < end; ++vi) {
      const VertId a = static_cast<VertId>(vi);
      if (mesh.is_dead_vertex(a)) {
        orders_[a].store(kStale, std::memory_order_relaxed);
        continue;
      }
      double* q = &quadrics_[vi * qs];
      mesh.for_each_tet_of(a, [&](TetId t) {
        for (int k = 0; k < 4; ++k) normalise(mesh, mesh.tets[t][k], pts + k * n_);
        const glm::dvec3 p0(pts[0], pts[1], pts[2]), p1(pts[n_], pts[n_ + 1], pts[n_ + 2]),
            p2(pts[2 * n_], pts[2 * n_ + 1], pts[2 * n_ + 2]), p3(pts[3 * n_], pts[3 * n_ + 1], pts[3 * n_ + 2]);
        const double volume = std::fabs(glm::dot(p1 - p0, glm::cross(p2 - p0, p3 - p0))) / 6.0;
        if (n_ > 3) quadric_add_simplex(q, n_, pts, 4, volume);  // in 3D a tet's hull is all of space
      });
      LinkScratch::VertexData& data = scratch.a;
      const VertexOrders orders = classify_vertex(mesh, a, data, scratch);
      orders_[a].store(orders.ktilde, std::memory_order_relaxed);
      normalise(mesh, a, pts);
      for (const auto& face : data.special) {
        normalise(mesh, face.x, pts + n_);
        normalise(mesh, face.y, pts + 2 * n_);
        const glm::dvec3 p0(pts[0], pts[1], pts[2]), p1(pts[n_], pts[n_ + 1], pts[n_ + 2]),
            p2(pts[2 * n_], pts[2 * n_ + 1], pts[2 * n_ + 2]);
        const double area = 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
        quadric_add_simplex_positions(q, n_, pts, 3, area * options.boundary_weight);
      }
      for (const auto& nb : data.neighbours) {
        if (!nb.polyline) continue;
        normalise(mesh, nb.x, pts + n_);
        const double length = glm::length(glm::dvec3(pts[n_] - pts[0], pts[n_ + 1] - pts[1], pts[n_ + 2] - pts[2]));
        quadric_add_simplex_positions(q, n_, pts, 2, length * options.polyline_weight);
      }
    }
  });
}

void CostModel::normalise(const TetMesh& mesh, VertId v, double* x) const {
  const glm::dvec3 p = (mesh.positions[v] - origin_) * inv_diag_;
  x[0] = p.x;
  x[1] = p.y;
  x[2] = p.z;
  const double* f = mesh.field_values.data() + static_cast<std::size_t>(v) * stride_;
  for (int c = 0; c < n_ - 3; ++c) x[3 + c] = (f[c] - field_min_[c]) * field_scale_[c];
}

std::uint8_t CostModel::order(const TetMesh& mesh, VertId v, LinkScratch& scratch) {
  std::uint8_t o = orders_[v].load(std::memory_order_relaxed);
  if (o == kStale) {
    o = classify_vertex(mesh, v, scratch.b, scratch).ktilde;
    // Relaxed: the value is a pure function of the (unchanging during evaluation) mesh.
    orders_[v].store(o, std::memory_order_relaxed);
  }
  return o;
}

int CostModel::candidates(const TetMesh& mesh, VertId a, VertId b, CollapseCandidate out[4], LinkScratch& scratch) {
  const bool pa = mesh.is_pinned(a), pb = mesh.is_pinned(b);
  if (pa && pb) return 0;
  const std::uint8_t oa = order(mesh, a, scratch), ob = order(mesh, b, scratch);
  if (oa == 3 && ob == 3 && !(pa || pb)) return 0;

  const int qs = quadric_size(n_);
  double q[quadric_size(kMaxQuadricDim)];
  std::copy_n(&quadrics_[static_cast<std::size_t>(a) * qs], qs, q);
  quadric_add(q, &quadrics_[static_cast<std::size_t>(b) * qs], n_);
  double xa[kMaxQuadricDim], xb[kMaxQuadricDim];
  normalise(mesh, a, xa);
  normalise(mesh, b, xb);
  const double length = glm::length(mesh.positions[a] - mesh.positions[b]) * inv_diag_;
  const double tie = kLengthTieBreak * length * length * length;

  int count = 0;
  auto add = [&](VertId u, VertId v, const double* x, int placement) {
    CollapseCandidate& c = out[count++];
    c.u = u;
    c.v = v;
    c.placement = placement;
    std::copy_n(x, n_, c.x);
    c.p = placement == kAtU ? mesh.positions[u]
          : placement == kMidpoint ? 0.5 * (mesh.positions[a] + mesh.positions[b])
                                   : origin_ + glm::dvec3(x[0], x[1], x[2]) / inv_diag_;
    // Where the position is constrained (an endpoint, the midpoint), the field values need not
    // be: take the ones the merged quadric likes best at that position. Keeping an endpoint's
    // values instead let the greedy order wipe out narrow field features for free. A pinned
    // vertex keeps its values exactly (see fields_at).
    if (placement != kOptimum && !(placement == kAtU && mesh.is_pinned(u))) quadric_minimize_fields(q, n_, c.x);
    c.cost = quadric_eval(q, n_, c.x) + tie;
  };
  // A pinned end, or the end of higher order, stays where it is.
  if (pa || (!pb && oa > ob)) {
    add(a, b, xa, kAtU);
    return count;
  }
  if (pb || ob > oa) {
    add(b, a, xb, kAtU);
    return count;
  }
  add(a, b, xa, kAtU);
  add(b, a, xb, kAtU);
  double xm[kMaxQuadricDim];
  for (int i = 0; i < n_; ++i) xm[i] = 0.5 * (xa[i] + xb[i]);
  add(a, b, xm, kMidpoint);
  double xo[kMaxQuadricDim];
  if (oa == 0 && quadric_minimize(q, n_, xo)) {
    // Trust the optimum only near the edge: far-away minima come from nearly flat quadrics.
    const glm::dvec3 po(xo[0], xo[1], xo[2]), pm(xm[0], xm[1], xm[2]);
    if (glm::length(po - pm) <= length) add(a, b, xo, kOptimum);
  }
  // Cheapest first; ties keep the order above (deterministic).
  std::stable_sort(out, out + count, [](const CollapseCandidate& l, const CollapseCandidate& r) { return l.cost < r.cost; });
  return count;
}

void CostModel::fields_at(const TetMesh& mesh, const CollapseCandidate& c, double* out) const {
  const double* fu = mesh.field_values.data() + static_cast<std::size_t>(c.u) * stride_;
  const double* fv = mesh.field_values.data() + static_cast<std::size_t>(c.v) * stride_;
  // The quadric's field coordinates (optimal for the placement, see candidates()); components
  // beyond the quadric's (more than 16) are interpolated. A pinned vertex keeps its own values.
  const bool keep_u = c.placement == kAtU && mesh.is_pinned(c.u);
  for (int k = 0; k < stride_; ++k) {
    if (keep_u) {
      out[k] = fu[k];
    } else if (k < n_ - 3) {
      out[k] = c.x[3 + k] / field_scale_[k] + field_min_[k];
    } else if (c.placement == kAtU) {
      out[k] = fu[k];
    } else {
      out[k] = 0.5 * (fu[k] + fv[k]);
    }
  }
}

void CostModel::on_collapse(const TetMesh& mesh, VertId u, VertId v, const std::vector<TetId>& star_uv) {
  const int qs = quadric_size(n_);
  quadric_add(&quadrics_[static_cast<std::size_t>(u) * qs], &quadrics_[static_cast<std::size_t>(v) * qs], n_);
  // Which orders can change? u's star changed wholesale. A vertex x outside the removed tets St(uv)
  // is adjacent to u or to v but not both: its faces and edges through v are only renamed to u
  // (no face or edge of x merges, since a merge needs a removed tet uvxy), so the special faces,
  // polyline edges and labels around x form the same configuration and its order is unchanged.
  // Only the vertices of St(uv) (the link of uv) see faces merge or vanish, and of those only the
  // ones on a feature: an interior vertex (order 0: no special face or edge, not pinned) has no
  // special simplex to merge, and every special simplex after the collapse is the image of one
  // before it, so it stays interior. Most vertices are interior: this spares their reclassification.
  orders_[u].store(kStale, std::memory_order_relaxed);
  for (TetId t : star_uv)
    for (VertId x : mesh.tets[t])
      if (x != v && orders_[x].load(std::memory_order_relaxed) != 0) orders_[x].store(kStale, std::memory_order_relaxed);
}

std::size_t CostModel::memory_bytes() const {
  return quadrics_.capacity() * sizeof(double) + vertex_count_ * sizeof(std::atomic<std::uint8_t>) +
         (field_min_.capacity() + field_scale_.capacity()) * sizeof(double);
}

}  // namespace topotet
