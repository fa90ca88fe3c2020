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
  const std::size_t n = mesh.vertex_capacity();
  value_lo_.assign(k, std::numeric_limits<double>::infinity());
  std::vector<double> hi_value(k, -std::numeric_limits<double>::infinity());
  box_lo_ = glm::dvec3(std::numeric_limits<double>::infinity());
  std::size_t live = 0;
  for (VertId v = 0; v < n; ++v) {
    if (mesh.is_dead_vertex(v)) continue;
    ++live;
    box_lo_ = glm::min(box_lo_, mesh.positions[v]);
    for (std::size_t c = 0; c < k; ++c) {
      value_lo_[c] = std::min(value_lo_[c], mesh.field_values[v * k + c]);
      hi_value[c] = std::max(hi_value[c], mesh.field_values[v * k + c]);
    }
  }
  if (live == 0) return;
  for (std::size_t c = 0; c < k; ++c) {
    const double range = hi_value[c] - value_lo_[c];
    inv_range_.push_back(range > 0.0 ? 1.0 / range : 0.0);
  }
  positions_.resize(n);
  values_.resize(n * k);
  for (VertId v = 0; v < n; ++v) {
    // A vertex of no tet is no sample (the field error is measured at the tets' vertices): NaN.
    positions_[v] = mesh.is_dead_vertex(v) ? glm::vec3(std::numeric_limits<float>::quiet_NaN())
                                           : glm::vec3(mesh.positions[v] - box_lo_);
    for (std::size_t c = 0; c < k; ++c) values_[v * k + c] = static_cast<float>(mesh.field_values[v * k + c] - value_lo_[c]);
  }
}

glm::dvec3 InputSamples::input_position(const MeshModel& mesh, VertId s) const {
  return mesh.is_reshaped(s) ? box_lo_ + glm::dvec3(positions_[s]) : mesh.positions[s];
}

double InputSamples::input_value(const MeshModel& mesh, VertId s, std::size_t m) const {
  const auto k = static_cast<std::size_t>(stride_);
  return mesh.is_reshaped(s) ? value_lo_[m] + static_cast<double>(values_[s * k + m]) : mesh.field_values[s * k + m];
}

void InputSamples::index(const MeshModel& mesh) {
  ids_.clear();
  start_.clear();
  if (empty()) return;
  // Every vertex live at the recording (a NaN position: it had no tet).
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  std::size_t count = 0;
  for (VertId v = 0; v < positions_.size(); ++v) {
    if (std::isnan(positions_[v].x)) continue;
    const glm::dvec3 p = input_position(mesh, v);
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
    ++count;
  }
  if (count == 0) return;
  // Cells of equal sides, about two vertices each: the regions asked about are a few output tets,
  // each of which covers ~1 / ratio input vertices. At most 1024 cells a side.
  const glm::dvec3 extent = glm::max(hi - lo, glm::dvec3(1e-300));
  const double side = std::max({std::cbrt(extent.x * extent.y * extent.z * 2.0 / static_cast<double>(count)),
                                extent.x / 1024.0, extent.y / 1024.0, extent.z / 1024.0});
  dims_ = glm::ivec3(glm::max(glm::dvec3(1.0), glm::ceil(extent / side)));
  origin_ = lo;
  inv_cell_ = glm::dvec3(dims_) / extent;
  // Counting sort by cell, vertices in increasing order: each cell's ids stay increasing.
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  start_.assign(static_cast<std::size_t>(dims_.x) * static_cast<std::size_t>(dims_.y) * static_cast<std::size_t>(dims_.z) + 1, 0);
  std::vector<std::uint32_t> cell(positions_.size(), kNone);
  for (VertId v = 0; v < positions_.size(); ++v) {
    if (std::isnan(positions_[v].x)) continue;
    const glm::ivec3 c = cell_of(input_position(mesh, v));
    cell[v] = static_cast<std::uint32_t>(index(c.x, c.y, c.z));
    ++start_[cell[v] + 1];
  }
  for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
  ids_.resize(count);
  std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
  for (VertId v = 0; v < positions_.size(); ++v)
    if (cell[v] != kNone) ids_[next[cell[v]]++] = v;
}

void InputSamples::inside(const MeshModel& mesh, std::span<const FieldTet> before, VertId moving, Inside& out) const {
  out.vertices.clear();
  out.places.clear();
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
          if (s != moving && !mesh.is_dead_vertex(s) && !mesh.is_reshaped(s)) continue;
          const glm::dvec3 q = input_position(mesh, s);
          if (q.x < lo.x || q.y < lo.y || q.z < lo.z || q.x > hi.x || q.y > hi.y || q.z > hi.z) continue;
          std::size_t i = 0;
          std::array<double, 4> l{};
          if (locator.locate_if_inside(q, i, l) < -kInsideSlack) continue;
          out.vertices.push_back(s);
          out.places.push_back(q);
          out.error += squared_error(mesh, before[i], l, s);
        }
      }
}

double InputSamples::errors_after(const MeshModel& mesh, std::span<const FieldTet> after, const Inside& in) const {
  if (in.vertices.empty()) return 0.0;
  thread_local RegionLocator locator;
  locator.reset(after);
  double error = 0.0;
  for (std::size_t n = 0; n < in.vertices.size(); ++n) {
    std::size_t i = 0;
    std::array<double, 4> l{};
    locator.locate(in.places[n], i, l);
    error += squared_error(mesh, after[i], l, in.vertices[n]);
  }
  return error;
}

double InputSamples::squared_error(const MeshModel& mesh, const FieldTet& t, const std::array<double, 4>& l, VertId s) const {
  const auto k = static_cast<std::size_t>(stride_);
  double sum = 0.0;
  for (std::size_t m = 0; m < k; ++m) {
    const double e = (interpolate(t, l, static_cast<int>(m)) - input_value(mesh, s, m)) * inv_range_[m];
    sum += e * e;
  }
  return sum;
}

std::size_t InputSamples::memory_bytes() const {
  return positions_.capacity() * sizeof(glm::vec3) + values_.capacity() * sizeof(float) +
         start_.capacity() * sizeof(std::uint32_t) + ids_.capacity() * sizeof(VertId);
}

glm::ivec3 InputSamples::cell_of(const glm::dvec3& p) const {
  const glm::dvec3 c = glm::floor((p - origin_) * inv_cell_);
  return glm::clamp(glm::ivec3(glm::clamp(c, glm::dvec3(-1.0), glm::dvec3(dims_))), glm::ivec3(0), dims_ - 1);
}

}  // namespace topotet
