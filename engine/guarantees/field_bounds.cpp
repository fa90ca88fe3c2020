// Per-tet field error bounds at the original vertex samples (see field_bounds.h).
#include "guarantees/field_bounds.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace topotet {
namespace {

using Bary = std::array<double, 4>;

// Barycentric slack accepted as "inside", and the barycentric and closest-point formulas: the same
// as metrics/field_error.cpp, so that the bound interpolates where the measurement does.
constexpr double kInsideTolerance = 1e-9;

double det3(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) { return glm::dot(a, glm::cross(b, c)); }

bool barycentric(const std::array<glm::dvec3, 4>& p, const glm::dvec3& q, Bary& l) {
  const glm::dvec3 a = p[0] - q, b = p[1] - q, c = p[2] - q, e = p[3] - q;
  l[0] = det3(b, c, e);
  l[1] = -det3(a, c, e);
  l[2] = det3(a, b, e);
  l[3] = -det3(a, b, c);
  const double sum = l[0] + l[1] + l[2] + l[3];
  if (sum == 0.0 || !std::isfinite(sum)) return false;
  for (double& x : l) x /= sum;
  return true;
}

double closest_on_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  if (!(len2 > 0.0)) return 0.0;
  return std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0);
}

// Barycentric coordinates (of a, b, c) of the point of triangle abc closest to p (Ericson 5.1.5).
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
  const double s_ab = closest_on_segment(p, a, b), s_bc = closest_on_segment(p, b, c), s_ca = closest_on_segment(p, c, a);
  const std::array<std::array<double, 3>, 3> cand = {{{1.0 - s_ab, s_ab, 0.0}, {0.0, 1.0 - s_bc, s_bc}, {s_ca, 0.0, 1.0 - s_ca}}};
  std::array<double, 3> best = cand[0];
  double best_d2 = std::numeric_limits<double>::infinity();
  for (const auto& w : cand) {
    const glm::dvec3 x = w[0] * a + w[1] * b + w[2] * c;
    const double dist2 = glm::dot(x - p, x - p);
    if (dist2 < best_d2) best_d2 = dist2, best = w;
  }
  return best;
}

// Squared distance from q to tet p (q outside it) and the barycentric coordinates of the closest point.
double closest_in_tet(const std::array<glm::dvec3, 4>& p, const glm::dvec3& q, Bary& out) {
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

double smallest(const Bary& l) { return std::min(std::min(l[0], l[1]), std::min(l[2], l[3])); }

// The float at or above x: a bound stays a bound when stored in 4 bytes.
float round_up(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

// Some component's bound, stored as a float, would exceed its limit (the refusal test).
bool above_limit(const double* bound, const double* limit, std::size_t k) {
  for (std::size_t c = 0; c < k; ++c)
    if (static_cast<double>(round_up(bound[c])) > limit[c]) return true;
  return false;
}

// Where sample q lands in the new star: the index and the barycentric coordinates to interpolate
// with (field_bounds.h says which tet).
std::uint32_t locate(const FieldBoundsScratch& s, const glm::dvec3& q, std::uint32_t home, Bary& lambda, bool& outside) {
  outside = false;
  if (home != kInvalid && barycentric(s.corners[home], q, lambda) && smallest(lambda) >= -kInsideTolerance) return home;
  const std::size_t n = s.star.size();
  std::uint32_t best = kInvalid;
  double best_min = -std::numeric_limits<double>::infinity();
  Bary l;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!barycentric(s.corners[i], q, l)) continue;
    const double m = smallest(l);
    if (best == kInvalid || m > best_min || (m == best_min && s.star[i].tet < s.star[best].tet)) {
      best = i;
      best_min = m;
      lambda = l;
    }
  }
  if (best != kInvalid && best_min >= -kInsideTolerance) return best;
  outside = true;
  double best_d2 = std::numeric_limits<double>::infinity();
  best = kInvalid;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double d2 = closest_in_tet(s.corners[i], q, l);
    if (best == kInvalid || d2 < best_d2 || (d2 == best_d2 && s.star[i].tet < s.star[best].tet)) {
      best = i;
      best_d2 = d2;
      lambda = l;
    }
  }
  return best;
}

// --- everywhere (field_bounds.h) ----------------------------------------------------------------

using AffineTet = FieldBoundsScratch::AffineTet;

// A tet's barycentric functions, lambda_i(x) = dot(gradient[i], x - corner[i + 1]) (the opposite
// face's first corner as origin: relative coordinates keep them accurate far from the origin).
void make_affine(AffineTet& a) {
  a.lo = a.hi = a.corner[0];
  for (const glm::dvec3& x : a.corner) {
    a.lo = glm::min(a.lo, x);
    a.hi = glm::max(a.hi, x);
  }
  a.centre = 0.25 * (a.corner[0] + a.corner[1] + a.corner[2] + a.corner[3]);
  a.radius = 0.0;
  for (const glm::dvec3& x : a.corner) a.radius = std::max(a.radius, glm::length(x - a.centre));
  a.flat = false;
  for (int i = 0; i < 4; ++i) {
    const glm::dvec3& x = a.corner[(i + 1) % 4];
    const glm::dvec3 n = glm::cross(a.corner[(i + 2) % 4] - x, a.corner[(i + 3) % 4] - x);
    const double d = glm::dot(n, a.corner[i] - x);
    if (!(std::fabs(d) > 0.0) || !std::isfinite(d)) {
      a.flat = true;
      return;
    }
    a.gradient[i] = n / d;
    a.gradient_length[i] = glm::length(a.gradient[i]);
  }
}

double lambda(const AffineTet& a, int i, const glm::dvec3& x) { return glm::dot(a.gradient[i], x - a.corner[(i + 1) % 4]); }

// Raises out[c] (new tet n's bounds) to |original - new| + slack at every vertex of the cell
// o ∩ n, o an original tet (field_bounds.h, "Everywhere"): corners of either tet inside the other,
// and the crossings of either's edges with the other's face planes that lie inside it.
// Barycentric coordinates down to -kInsideTolerance count as inside: a vertex of the cell a
// rounding away is taken with the cell's (the difference is affine on the cell, so this changes
// the result by rounding only, which the slack covers). Returns whether the cell has a vertex
// (o is then one of n's original tets). With `limit` (a run under a limit: a bound is only asked
// to be a bound within it), two cheap bounds are tried first: the difference at o's four corners
// (the cell lies in o, where the difference is affine) and at the box the tets' boxes share; the
// cell's own vertices are found only when both exceed the limit. The check and the commit of a
// placement take the same path, so the bound stored is the one the check accepted. With
// `stop_at_limit` (a check), the search stops at the first cell vertex above the limit.
bool raise_by_cell(const AffineTet& o, const AffineTet& n, std::size_t k, const double* slack, const double* limit,
                   bool stop_at_limit, bool skip_crossings, double* out) {
  // o's bounding sphere beyond a face plane of n: disjoint (most pairs whose boxes meet).
  for (int j = 0; j < 4; ++j)
    if (lambda(n, j, o.centre) < -(o.radius * n.gradient_length[j] + kInsideTolerance)) return false;
  double in_n[4][4], in_o[4][4];  // in_n[i][j]: lambda^n_j at o's corner i; in_o the other way
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) in_n[i][j] = lambda(n, j, o.corner[i]);
  // A face plane of one tet with every corner of the other beyond it separates them (l[i][j]: the
  // first's barycentric coordinate j at the other's corner i).
  const auto separated = [](const double (*l)[4]) {
    for (int j = 0; j < 4; ++j)
      if (l[0][j] < -kInsideTolerance && l[1][j] < -kInsideTolerance && l[2][j] < -kInsideTolerance && l[3][j] < -kInsideTolerance)
        return true;
    return false;
  };
  if (separated(in_n)) return false;
  const auto new_at_o = [&](int i, std::size_t c) {
    return in_n[i][0] * n.values[0][c] + in_n[i][1] * n.values[1][c] + in_n[i][2] * n.values[2][c] + in_n[i][3] * n.values[3][c];
  };
  // The largest error at o's corners (o holds the cell, and the error is affine on o).
  const auto at_corners = [&](std::size_t c) {
    double e = 0.0;
    for (int i = 0; i < 4; ++i) e = std::max(e, std::fabs(o.values[i][c] - new_at_o(i, c)));
    return e + slack[c];
  };
  // The cell lies in the box common to both tets' boxes too: on it |d| <= |d(centre)| + the
  // gradient of d against the half-extents (d = f_o - f_n is affine). Tighter where the tets
  // overlap in a corner only, where o's corners lie far outside n.
  const glm::dvec3 box_lo = glm::max(o.lo, n.lo), box_hi = glm::min(o.hi, n.hi);
  const glm::dvec3 centre = 0.5 * (box_lo + box_hi), half = 0.5 * (box_hi - box_lo);
  double at_centre_o[4], at_centre_n[4];
  for (int j = 0; j < 4; ++j) at_centre_o[j] = lambda(o, j, centre), at_centre_n[j] = lambda(n, j, centre);
  const auto in_box = [&](std::size_t c) {
    double d = 0.0;
    glm::dvec3 g(0.0);
    for (int j = 0; j < 4; ++j) {
      d += o.values[j][c] * at_centre_o[j] - n.values[j][c] * at_centre_n[j];
      g += o.values[j][c] * o.gradient[j] - n.values[j][c] * n.gradient[j];
    }
    return std::fabs(d) + std::fabs(g.x) * half.x + std::fabs(g.y) * half.y + std::fabs(g.z) * half.z + slack[c];
  };
  const auto either = [&](std::size_t c) { return std::min(at_corners(c), in_box(c)); };
  if (limit != nullptr) {
    bool within = true;
    for (std::size_t c = 0; c < k && within; ++c) within = either(c) <= limit[c];
    if (within) {
      for (std::size_t c = 0; c < k; ++c) out[c] = std::max(out[c], either(c));
      return true;
    }
  }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) in_o[i][j] = lambda(o, j, n.corner[i]);
  if (separated(in_o)) return false;
  bool found = false;
  const auto raise = [&](auto&& old_value, auto&& new_value) {
    found = true;
    for (std::size_t c = 0; c < k; ++c) {
      const double e = std::fabs(old_value(c) - new_value(c)) + slack[c];
      if (e > out[c]) out[c] = e;
    }
  };
  // A check stops at the first cell vertex above the limit (the placement is refused).
  const auto over = [&] { return stop_at_limit && limit != nullptr && above_limit(out, limit, k); };
  const auto inside = [](const double* l) { return std::min(std::min(l[0], l[1]), std::min(l[2], l[3])) >= -kInsideTolerance; };
  for (int i = 0; i < 4; ++i) {
    if (inside(in_n[i])) raise([&](std::size_t c) { return o.values[i][c]; }, [&](std::size_t c) { return new_at_o(i, c); });
    if (inside(in_o[i]))
      raise([&](std::size_t c) { return in_o[i][0] * o.values[0][c] + in_o[i][1] * o.values[1][c] + in_o[i][2] * o.values[2][c] + in_o[i][3] * o.values[3][c]; },
            [&](std::size_t c) { return n.values[i][c]; });
  }
  if (over()) return true;
  // Edges of `a` crossing the face planes of `b` (l[i][j]: lambda^b_j at a's corner i).
  const auto crossings = [&](const AffineTet& a, const AffineTet& b, const double (*l)[4], bool a_is_old) {
    for (const auto& e : kTetEdges) {
      const int x = e[0], y = e[1];
      for (int f = 0; f < 4; ++f) {
        const double lx = l[x][f], ly = l[y][f];
        if (!((lx < 0.0 && ly > 0.0) || (lx > 0.0 && ly < 0.0))) continue;
        const double t = lx / (lx - ly);
        double at[4];
        for (int j = 0; j < 4; ++j) at[j] = j == f ? 0.0 : l[x][j] + t * (l[y][j] - l[x][j]);
        if (!inside(at)) continue;
        const auto on_edge = [&](std::size_t c) { return (1.0 - t) * a.values[x][c] + t * a.values[y][c]; };
        const auto in_b = [&](std::size_t c) { return at[0] * b.values[0][c] + at[1] * b.values[1][c] + at[2] * b.values[2][c] + at[3] * b.values[3][c]; };
        if (a_is_old)
          raise(on_edge, in_b);
        else
          raise(in_b, on_edge);
        if (over()) return;
      }
    }
  };
  if (!skip_crossings) {
    crossings(o, n, in_n, true);
    if (!over()) crossings(n, o, in_o, false);
  }
  return found;
}

}  // namespace

FieldBounds::FieldBounds(const MeshModel& mesh, double max_abs, double max_rel) : k_(mesh.field_stride()) {
  const std::size_t nv = mesh.vertex_capacity(), nt = mesh.tets.size(), k = static_cast<std::size_t>(k_);
  head_.assign(nt, kInvalid);
  next_.assign(nv, kInvalid);
  bound_.assign(nt * k, 0.0f);
  sample_xyz_.resize(3 * nv);
  for (std::size_t x = 0; x < nv; ++x)
    for (int d = 0; d < 3; ++d) sample_xyz_[3 * x + d] = mesh.positions[x][d];
  sample_values_ = mesh.field_values;
  // Each used vertex is a sample of the first tet (by id) that has it: there the error is 0.
  std::vector<std::uint8_t> taken(nv, 0);
  for (TetId t = 0; t < nt; ++t) {
    if (mesh.flags[t] & tet_flag::kDead) continue;
    for (VertId x : mesh.tets[t]) {
      if (taken[x]) continue;
      taken[x] = 1;
      next_[x] = head_[t];
      head_[t] = x;
    }
  }
  std::vector<double> lo(k, std::numeric_limits<double>::infinity()), hi(k, -std::numeric_limits<double>::infinity()),
      max_magnitude(k, 0.0);
  for (VertId x = 0; x < nv; ++x) {
    if (!taken[x]) continue;
    for (std::size_t c = 0; c < k; ++c) {
      const double f = sample_values_[x * k + c];
      lo[c] = std::min(lo[c], f);
      hi[c] = std::max(hi[c], f);
      max_magnitude[c] = std::max(max_magnitude[c], std::fabs(f));
    }
  }
  range_.resize(k);
  for (std::size_t c = 0; c < k; ++c) range_[c] = hi[c] > lo[c] ? hi[c] - lo[c] : 1.0;  // a constant component divides by 1 (as the metrics do)
  magnitude_ = std::move(max_magnitude);
  set_limits(max_abs, max_rel);
}

FieldBounds::FieldBounds(const MeshModel& mesh, FieldBoundSamples&& samples, double max_abs, double max_rel)
    : k_(mesh.field_stride()) {
  const std::size_t nt = mesh.tets.size(), n = samples.size(), k = static_cast<std::size_t>(k_);
  range_ = std::move(samples.range);
  magnitude_ = std::move(samples.magnitude);
  sample_xyz_ = std::move(samples.positions);
  sample_values_ = std::move(samples.values);
  bound_ = std::move(samples.bounds);
  bound_.resize(nt * k, 0.0f);
  head_.assign(nt, kInvalid);
  next_.assign(n, kInvalid);
  // Pushed in reverse so that each list is in sample order, as given.
  for (std::size_t w = n; w-- > 0;) {
    const TetId t = samples.tet[w];
    next_[w] = head_[t];
    head_[t] = static_cast<std::uint32_t>(w);
  }
  samples = FieldBoundSamples{};
  carried_ = true;
  set_limits(max_abs, max_rel);
}

void FieldBounds::release(const MeshModel& mesh, FieldBoundSamples& out) {
  const std::size_t k = static_cast<std::size_t>(k_);
  out = FieldBoundSamples{};
  out.components = k_;
  out.bounds = live_bounds(mesh);
  std::vector<std::uint32_t> tet_of(next_.size(), kInvalid);
  std::uint32_t o = 0;
  for (TetId t = 0; t < mesh.tets.size(); ++t) {
    if (mesh.flags[t] & tet_flag::kDead) continue;
    for (std::uint32_t w = head_[t]; w != kInvalid; w = next_[w]) tet_of[w] = o;
    ++o;
  }
  // Dropping the samples no live tet holds, in place (the kept ones keep their order).
  std::size_t kept = 0;
  for (std::size_t w = 0; w < tet_of.size(); ++w) {
    if (tet_of[w] == kInvalid) continue;
    if (kept != w) {
      std::copy_n(sample_xyz_.begin() + static_cast<std::ptrdiff_t>(3 * w), 3, sample_xyz_.begin() + static_cast<std::ptrdiff_t>(3 * kept));
      std::copy_n(sample_values_.begin() + static_cast<std::ptrdiff_t>(k * w), k, sample_values_.begin() + static_cast<std::ptrdiff_t>(k * kept));
    }
    tet_of[kept++] = tet_of[w];
  }
  tet_of.resize(kept);
  sample_xyz_.resize(3 * kept);
  sample_values_.resize(k * kept);
  out.range = std::move(range_);
  out.magnitude = std::move(magnitude_);
  out.positions = std::move(sample_xyz_);
  out.values = std::move(sample_values_);
  out.tet = std::move(tet_of);
  *this = FieldBounds();
}

void FieldBounds::set_everywhere(const MeshModel& mesh) {
  if (carried_) throw std::invalid_argument("field_bound_mode everywhere: not with samples carried from an earlier pass (out of core)");
  everywhere_ = true;
  // Every live tet is an original tet (its vertex ids are its samples' ids: the samples were taken
  // from this mesh) that overlaps itself alone.
  originals_.clear();
  overlaps_.assign(mesh.tets.size(), {});
  for (TetId t = 0; t < mesh.tets.size(); ++t) {
    if (mesh.flags[t] & tet_flag::kDead) continue;
    overlaps_[t].push_back(static_cast<std::uint32_t>(originals_.size()));
    originals_.push_back(mesh.tets[t]);
  }
}

void FieldBounds::set_limits(double max_abs, double max_rel) {
  const std::size_t k = static_cast<std::size_t>(k_);
  limit_.resize(k);
  slack_.resize(k);
  has_limit_ = false;
  for (std::size_t c = 0; c < k; ++c) {
    double limit = std::numeric_limits<double>::infinity();
    if (max_abs > 0.0) limit = std::min(limit, max_abs);
    if (max_rel > 0.0) limit = std::min(limit, max_rel * range_[c]);
    limit_[c] = limit;
    has_limit_ = has_limit_ || limit < std::numeric_limits<double>::infinity();
    // Interpolating at the same point in two tets, or with barycentric coordinates rounded
    // differently (the measurement's), differs by rounding: a few ulps of the largest value, and
    // up to kInsideTolerance of the range where a point on a shared face is taken in either tet.
    slack_[c] = 10.0 * kInsideTolerance * range_[c] + 8.0 * std::numeric_limits<double>::epsilon() * magnitude_[c];
  }
}

bool FieldBounds::evaluate(const MeshModel& mesh, std::span<const TetId> removed, VertId u, const glm::dvec3& p,
                           const double* fields_at_p, FieldBoundsScratch& s, bool stop_at_limit) const {
  if (k_ == 0) return true;
  const std::size_t n = s.star.size(), k = static_cast<std::size_t>(k_);
  const double* values_at_p = fields_at_p != nullptr ? fields_at_p : &mesh.field_values[u * k];
  s.corners.resize(n);
  s.values.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& tv = mesh.tets[s.star[i].tet];
    for (int j = 0; j < 4; ++j) {
      const bool moving = j == s.star[i].corner;
      s.corners[i][j] = moving ? p : mesh.positions[tv[j]];
      s.values[i][j] = moving ? values_at_p : &mesh.field_values[tv[j] * k];
    }
  }
  s.samples.clear();
  s.home.clear();
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t w = head_[s.star[i].tet]; w != kInvalid; w = next_[w]) {
      s.samples.push_back(w);
      s.home.push_back(i);
    }
  for (TetId t : removed)
    for (std::uint32_t w = head_[t]; w != kInvalid; w = next_[w]) {
      s.samples.push_back(w);
      s.home.push_back(kInvalid);
    }
  s.lands.resize(s.samples.size());
  s.bounds.assign(n * k, 0.0);
  Bary lambda{};
  for (std::size_t i = 0; i < s.samples.size(); ++i) {
    const std::uint32_t w = s.samples[i];
    bool outside = false;
    const std::uint32_t j = locate(s, sample_position(w), s.home[i], lambda, outside);
    // Under a limit no original vertex may leave the mesh: outside it the measurement takes the
    // globally closest tet, which this stencil cannot know (field_bounds.h).
    if (stop_at_limit && outside) return false;
    s.lands[i] = j;
    const auto& vals = s.values[j];
    for (std::size_t c = 0; c < k; ++c) {
      const double interpolated = lambda[0] * vals[0][c] + lambda[1] * vals[1][c] + lambda[2] * vals[2][c] + lambda[3] * vals[3][c];
      const double e = std::fabs(sample_values_[w * k + c] - interpolated) + slack_[c];
      double& b = s.bounds[j * k + c];
      if (e > b) {
        b = e;
        if (stop_at_limit && static_cast<double>(round_up(e)) > limit_[c]) return false;
      }
    }
  }
  return !everywhere_ || overlay_bounds(mesh, removed, p, s, stop_at_limit);
}

bool FieldBounds::overlay_bounds(const MeshModel& mesh, std::span<const TetId> removed, const glm::dvec3& p,
                                 FieldBoundsScratch& s, bool stop_at_limit) const {
  const std::size_t n = s.star.size(), k = static_cast<std::size_t>(k_);
  // The old stencil: the star's tets as they are, and the removed ones.
  s.old_tets.clear();
  VertId moving[2] = {kInvalid, kInvalid};
  const auto add_old = [&](TetId t) {
    AffineTet a;
    const auto& tv = mesh.tets[t];
    for (int j = 0; j < 4; ++j) {
      a.corner[j] = mesh.positions[tv[j]];
      a.values[j] = &mesh.field_values[tv[j] * k];
    }
    a.tet = t;
    make_affine(a);
    s.old_tets.push_back(a);
  };
  for (const BoundStarTet& st : s.star) {
    add_old(st.tet);
    const VertId m = mesh.tets[st.tet][st.corner];
    if (moving[0] == kInvalid || moving[0] == m)
      moving[0] = m;
    else
      moving[1] = m;
  }
  for (TetId t : removed) add_old(t);
  // The stencil's boundary must stay where it is: its faces through a moving vertex are the only
  // ones that move; they stay in place when their moving corners are at p already (and none has
  // two), or when they all lie in one plane with p (a flat boundary retriangulated within it).
  s.faces.clear();
  for (const AffineTet& a : s.old_tets) {
    const auto& tv = mesh.tets[a.tet];
    for (const auto& f : kTetFaces) {
      std::array<VertId, 3> face{tv[f[0]], tv[f[1]], tv[f[2]]};
      bool through = false;
      for (VertId x : face) through = through || x == moving[0] || x == moving[1];
      if (!through) continue;
      std::sort(face.begin(), face.end());
      s.faces.push_back(face);
    }
  }
  // A face of one tet is on the boundary: keep those (a face of two tets appears twice).
  std::sort(s.faces.begin(), s.faces.end());
  std::size_t boundary = 0;
  for (std::size_t i = 0; i < s.faces.size();) {
    std::size_t j = i + 1;
    while (j < s.faces.size() && s.faces[j] == s.faces[i]) ++j;
    if (j - i == 1) s.faces[boundary++] = s.faces[i];
    i = j;
  }
  s.faces.resize(boundary);
  bool in_place = true;
  glm::dvec3 lo(p), hi(p);
  for (const auto& face : s.faces) {
    int moving_corners = 0;
    for (VertId x : face) {
      lo = glm::min(lo, mesh.positions[x]);
      hi = glm::max(hi, mesh.positions[x]);
      if (x == moving[0] || x == moving[1]) {
        ++moving_corners;
        if (mesh.positions[x] != p) in_place = false;
      }
    }
    if (moving_corners > 1) in_place = false;
  }
  if (!in_place) {  // then all in one plane with p: the first face's
    const glm::dvec3 a = mesh.positions[s.faces[0][0]];
    const glm::dvec3 normal = glm::cross(mesh.positions[s.faces[0][1]] - a, mesh.positions[s.faces[0][2]] - a);
    const double length = glm::length(normal);
    if (!(length > 0.0)) return false;
    const double tol = 1e-12 * glm::length(hi - lo);
    const auto on_plane = [&](const glm::dvec3& x) { return std::fabs(glm::dot(normal / length, x - a)) <= tol; };
    if (!on_plane(p)) return false;
    for (const auto& face : s.faces)
      for (VertId x : face)
        if (!on_plane(mesh.positions[x])) return false;
  }
  // The original tets that overlap the old stencil (the lists of its tets), each once.
  s.candidates.clear();
  for (const AffineTet& a : s.old_tets) s.candidates.insert(s.candidates.end(), overlaps_[a.tet].begin(), overlaps_[a.tet].end());
  std::sort(s.candidates.begin(), s.candidates.end());
  s.candidates.erase(std::unique(s.candidates.begin(), s.candidates.end()), s.candidates.end());
  s.originals.resize(s.candidates.size());
  for (std::size_t i = 0; i < s.candidates.size(); ++i) {
    AffineTet& a = s.originals[i];
    const auto& tv = originals_[s.candidates[i]];
    for (int j = 0; j < 4; ++j) {
      a.corner[j] = sample_position(tv[j]);
      a.values[j] = &sample_values_[static_cast<std::size_t>(tv[j]) * k];
    }
    a.tet = s.candidates[i];
    make_affine(a);
  }
  // The new star: each tet's error is largest at a vertex of one of its cells with the original
  // tets, where both fields are affine.
  s.new_tets.resize(n);
  if (s.new_overlaps.size() < n) s.new_overlaps.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    AffineTet& t = s.new_tets[i];
    t.corner = s.corners[i];
    t.values = s.values[i];
    t.tet = s.star[i].tet;
    make_affine(t);
    double* out = &s.bounds[i * k];
    std::vector<std::uint32_t>& list = s.new_overlaps[i];
    list.clear();
    if (t.flat) {  // no tet the kernel accepts; a bound cannot be given
      for (std::size_t c = 0; c < k; ++c) out[c] = std::numeric_limits<double>::infinity();
      if (stop_at_limit) return false;
      continue;
    }
    // The cheap estimates (raise_by_cell's limit) for checks, and for commits unless exact.
    const double* estimate_within = has_limit_ && (stop_at_limit || !exact_commits_) ? limit_.data() : nullptr;
    for (const AffineTet& o : s.originals) {
      const bool boxes_meet = !(o.hi.x < t.lo.x || t.hi.x < o.lo.x || o.hi.y < t.lo.y || t.hi.y < o.lo.y ||
                                o.hi.z < t.lo.z || t.hi.z < o.lo.z);
      if (boxes_meet && !o.flat &&
          raise_by_cell(o, t, k, slack_.data(), estimate_within, stop_at_limit, skip_crossings_, out))
        list.push_back(o.tet);
      if (stop_at_limit && above_limit(out, limit_.data(), k)) return false;  // refused: no need to go on
    }
  }
  return true;
}

float FieldBounds::commit(std::span<const TetId> removed, FieldBoundsScratch& s) {
  if (k_ == 0) return 0.0f;
  const std::size_t n = s.star.size(), k = static_cast<std::size_t>(k_);
  for (const BoundStarTet& st : s.star) head_[st.tet] = kInvalid;
  for (TetId t : removed) head_[t] = kInvalid;
  for (std::size_t i = 0; i < s.samples.size(); ++i) {
    const std::uint32_t w = s.samples[i];
    const TetId t = s.star[s.lands[i]].tet;
    next_[w] = head_[t];
    head_[t] = w;
  }
  if (everywhere_) {
    for (TetId t : removed) std::vector<std::uint32_t>().swap(overlaps_[t]);
    for (std::size_t i = 0; i < n; ++i) overlaps_[s.star[i].tet].assign(s.new_overlaps[i].begin(), s.new_overlaps[i].end());
  }
  float worst_rel = 0.0f;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < k; ++c) {
      const float b = round_up(s.bounds[i * k + c]);
      bound_[static_cast<std::size_t>(s.star[i].tet) * k + c] = b;
      worst_rel = std::max(worst_rel, round_up(static_cast<double>(b) / range_[c]));
    }
  return worst_rel;
}

std::vector<float> FieldBounds::live_bounds(const MeshModel& mesh) const {
  const std::size_t k = static_cast<std::size_t>(k_);
  std::vector<float> out;
  out.reserve(mesh.live_tet_count() * k);
  for (TetId t = 0; t < mesh.tets.size(); ++t)
    if (!(mesh.flags[t] & tet_flag::kDead))
      out.insert(out.end(), bound_.begin() + static_cast<std::ptrdiff_t>(t * k), bound_.begin() + static_cast<std::ptrdiff_t>((t + 1) * k));
  return out;
}

std::vector<double> FieldBounds::max_bounds(const MeshModel& mesh) const {
  const std::size_t k = static_cast<std::size_t>(k_);
  std::vector<double> out(k, 0.0);
  for (TetId t = 0; t < mesh.tets.size(); ++t) {
    if (mesh.flags[t] & tet_flag::kDead) continue;
    for (std::size_t c = 0; c < k; ++c) out[c] = std::max(out[c], static_cast<double>(bound_[t * k + c]));
  }
  return out;
}

double FieldBounds::max_bound_rel(const MeshModel& mesh) const {
  const std::vector<double> b = max_bounds(mesh);
  double worst = 0.0;
  for (std::size_t c = 0; c < b.size(); ++c) worst = std::max(worst, b[c] / range_[c]);
  return worst;
}

std::size_t FieldBounds::memory_bytes() const {
  return range_.capacity() * 4 * sizeof(double) + bound_.capacity() * sizeof(float) +
         (head_.capacity() + next_.capacity()) * sizeof(std::uint32_t) + sample_xyz_.capacity() * sizeof(double) +
         sample_values_.capacity() * sizeof(double) + originals_.capacity() * sizeof(originals_[0]) + overlaps_bytes();
}

std::size_t FieldBounds::overlaps_bytes() const {
  std::size_t bytes = overlaps_.capacity() * sizeof(overlaps_[0]);
  for (const auto& list : overlaps_) bytes += list.capacity() * sizeof(std::uint32_t);
  return bytes;
}

}  // namespace topotet
