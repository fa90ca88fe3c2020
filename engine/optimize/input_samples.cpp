// The input's vertices, recorded before the collapses, in a grid (see input_samples.h).
#include "optimize/input_samples.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/matrix.hpp>

namespace topotet {

void RegionLocator::reset(std::span<const FieldTet> tets) {
  maps_.resize(tets.size());
  for (std::size_t i = 0; i < tets.size(); ++i) {
    const auto& p = tets[i].p;
    Map& m = maps_[i];
    const glm::dmat3 edges(p[1] - p[0], p[2] - p[0], p[3] - p[0]);
    const double det = glm::determinant(edges);
    m.valid = det > 0.0 && std::isfinite(det);
    m.origin = p[0];
    if (m.valid) m.inverse = glm::inverse(edges);
    m.lo = glm::min(glm::min(p[0], p[1]), glm::min(p[2], p[3]));
    m.hi = glm::max(glm::max(p[0], p[1]), glm::max(p[2], p[3]));
    const glm::dvec3 hair = 1e-8 * (m.hi - m.lo) + glm::dvec3(1e-300);
    m.lo -= hair;
    m.hi += hair;
  }
}

double RegionLocator::search(const glm::dvec3& x, bool boxes, std::size_t& tet, std::array<double, 4>& l) const {
  double best = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < maps_.size(); ++i) {
    const Map& m = maps_[i];
    if (!m.valid) continue;
    if (boxes && (x.x < m.lo.x || x.y < m.lo.y || x.z < m.lo.z || x.x > m.hi.x || x.y > m.hi.y || x.z > m.hi.z)) continue;
    const glm::dvec3 b = m.inverse * (x - m.origin);
    const double b0 = 1.0 - b.x - b.y - b.z;
    const double lo = std::min(std::min(b0, b.x), std::min(b.y, b.z));
    if (lo <= best) continue;
    best = lo;
    tet = i;
    l = {b0, b.x, b.y, b.z};
    if (lo >= 0.0) break;  // inside: no other tet holds x but on a shared face, with the same field
  }
  return best;
}

double RegionLocator::locate(const glm::dvec3& x, std::size_t& tet, std::array<double, 4>& l) const {
  tet = 0;
  const double best = search(x, true, tet, l);
  // No box holds x: it is outside the region; the tet nearest in barycentric terms, as promised.
  return best > -std::numeric_limits<double>::infinity() ? best : search(x, false, tet, l);
}

InputSamples::InputSamples(const MeshModel& mesh) : stride_(mesh.field_stride()) {
  if (stride_ == 0) return;  // nothing to measure
  const auto k = static_cast<std::size_t>(stride_);
  std::vector<double> lo_value(k, std::numeric_limits<double>::infinity()), hi_value(k, -std::numeric_limits<double>::infinity());
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  positions_.resize(mesh.vertex_capacity());
  values_.resize(mesh.vertex_capacity() * k);
  for (VertId v = 0; v < mesh.vertex_capacity(); ++v) {
    positions_[v] = mesh.positions[v];
    for (std::size_t c = 0; c < k; ++c) values_[v * k + c] = mesh.field_values[v * k + c];
    if (mesh.is_dead_vertex(v)) continue;
    ids_.push_back(v);
    lo = glm::min(lo, mesh.positions[v]);
    hi = glm::max(hi, mesh.positions[v]);
    for (std::size_t c = 0; c < k; ++c) {
      lo_value[c] = std::min(lo_value[c], values_[v * k + c]);
      hi_value[c] = std::max(hi_value[c], values_[v * k + c]);
    }
  }
  for (std::size_t c = 0; c < k; ++c) {
    const double range = hi_value[c] - lo_value[c];
    inv_range_.push_back(range > 0.0 ? 1.0 / range : 0.0);
  }
  if (ids_.empty()) return;
  // Cells of equal sides, about two vertices each: the regions asked about are a few output tets,
  // each of which covers ~1 / ratio input vertices. At most 1024 cells a side.
  const glm::dvec3 extent = glm::max(hi - lo, glm::dvec3(1e-300));
  const double side = std::max({std::cbrt(extent.x * extent.y * extent.z * 2.0 / static_cast<double>(ids_.size())),
                                extent.x / 1024.0, extent.y / 1024.0, extent.z / 1024.0});
  dims_ = glm::ivec3(glm::max(glm::dvec3(1.0), glm::ceil(extent / side)));
  origin_ = lo;
  inv_cell_ = glm::dvec3(dims_) / extent;
  // Counting sort by cell; ids_ is increasing, so each cell's ids stay increasing.
  start_.assign(static_cast<std::size_t>(dims_.x) * static_cast<std::size_t>(dims_.y) * static_cast<std::size_t>(dims_.z) + 1, 0);
  std::vector<std::uint32_t> cell(ids_.size());
  for (std::size_t i = 0; i < ids_.size(); ++i) {
    const glm::ivec3 c = cell_of(positions_[ids_[i]]);
    cell[i] = static_cast<std::uint32_t>(index(c.x, c.y, c.z));
    ++start_[cell[i] + 1];
  }
  for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
  std::vector<VertId> sorted(ids_.size());
  std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < ids_.size(); ++i) sorted[next[cell[i]]++] = ids_[i];
  ids_ = std::move(sorted);
}

void InputSamples::inside(const MeshModel& mesh, std::span<const FieldTet> before, VertId moving, Inside& out) const {
  out.vertices.clear();
  out.error = 0.0;
  if (ids_.empty()) return;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const FieldTet& t : before)
    for (const glm::dvec3& p : t.p) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  // A sample on a face of the region up to rounding is in it (barycentric, so scale-free).
  constexpr double kInsideSlack = 1e-9;
  thread_local RegionLocator locator;
  locator.reset(before);
  const glm::ivec3 a = cell_of(lo), b = cell_of(hi);
  for (int z = a.z; z <= b.z; ++z)
    for (int y = a.y; y <= b.y; ++y)
      for (int x = a.x; x <= b.x; ++x) {
        const std::size_t c = index(x, y, z);
        for (std::uint32_t n = start_[c]; n < start_[c + 1]; ++n) {
          const VertId s = ids_[n];
          const glm::dvec3& q = positions_[s];
          if (q.x < lo.x || q.y < lo.y || q.z < lo.z || q.x > hi.x || q.y > hi.y || q.z > hi.z) continue;
          if (s != moving && !mesh.is_dead_vertex(s) && !mesh.is_reshaped(s)) continue;
          std::size_t i = 0;
          std::array<double, 4> l{};
          if (locator.locate(q, i, l) < -kInsideSlack) continue;
          out.vertices.push_back(s);
          out.error += squared_error(before[i], l, s);
        }
      }
}

double InputSamples::errors_after(std::span<const FieldTet> after, const Inside& in) const {
  if (in.vertices.empty()) return 0.0;
  thread_local RegionLocator locator;
  locator.reset(after);
  double error = 0.0;
  for (VertId s : in.vertices) {
    std::size_t i = 0;
    std::array<double, 4> l{};
    locator.locate(positions_[s], i, l);
    error += squared_error(after[i], l, s);
  }
  return error;
}

double InputSamples::squared_error(const FieldTet& t, const std::array<double, 4>& l, VertId s) const {
  const auto k = static_cast<std::size_t>(stride_);
  double sum = 0.0;
  for (std::size_t m = 0; m < k; ++m) {
    const double e = (interpolate(t, l, static_cast<int>(m)) - values_[s * k + m]) * inv_range_[m];
    sum += e * e;
  }
  return sum;
}

std::size_t InputSamples::memory_bytes() const {
  return positions_.capacity() * sizeof(glm::dvec3) + values_.capacity() * sizeof(double) +
         start_.capacity() * sizeof(std::uint32_t) + ids_.capacity() * sizeof(VertId);
}

glm::ivec3 InputSamples::cell_of(const glm::dvec3& p) const {
  const glm::dvec3 c = glm::floor((p - origin_) * inv_cell_);
  return glm::clamp(glm::ivec3(glm::clamp(c, glm::dvec3(-1.0), glm::dvec3(dims_))), glm::ivec3(0), dims_ - 1);
}

}  // namespace topotet
