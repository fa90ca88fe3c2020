// Morton renumbering of vertices and tets (see reorder.h).
#include "mesh/reorder.h"

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include <glm/common.hpp>

#include "mesh/morton.h"
#include "parallel/filter.h"
#include "parallel/for_range.h"

namespace topotet {
namespace {

// Points of the bounding box quantised to 21 bits per axis, interleaved.
class MortonFrame {
 public:
  explicit MortonFrame(const MeshModel& m) {
    glm::dvec3 hi(-std::numeric_limits<double>::infinity());
    lo_ = glm::dvec3(std::numeric_limits<double>::infinity());
    for (VertId v = 0; v < m.vertex_capacity(); ++v) {
      if (m.is_dead_vertex(v)) continue;
      lo_ = glm::min(lo_, m.positions[v]);
      hi = glm::max(hi, m.positions[v]);
    }
    const double extent = std::max({hi.x - lo_.x, hi.y - lo_.y, hi.z - lo_.z});
    scale_ = extent > 0.0 ? static_cast<double>((1u << 21) - 1) / extent : 0.0;
  }
  std::uint64_t key(const glm::dvec3& p) const {
    const glm::dvec3 q = (p - lo_) * scale_;
    const auto cell = [](double x) { return static_cast<std::uint32_t>(std::clamp(x, 0.0, double((1u << 21) - 1))); };
    return morton_code(cell(q.x), cell(q.y), cell(q.z));
  }

 private:
  glm::dvec3 lo_;
  double scale_ = 0.0;
};

template <class T>
void permute(std::vector<T>& values, const std::vector<std::pair<std::uint64_t, std::uint32_t>>& order, std::size_t stride) {
  std::vector<T> out(order.size() * stride);
  parallel::for_range<std::size_t>(0, order.size(), 8192, "permute", [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(order[i].second * stride), stride,
                  out.begin() + static_cast<std::ptrdiff_t>(i * stride));
  });
  values = std::move(out);
}

}  // namespace

void reorder_for_locality(MeshModel& m, std::vector<VertId>* new2old, std::vector<TetId>* tet_old2new) {
  const MortonFrame frame(m);
  using Keyed = std::pair<std::uint64_t, std::uint32_t>;  // (Morton key, old id): a total order

  std::vector<Keyed> vertex_order;
  parallel::filter_map(
      m.vertex_capacity(), vertex_order, [&](std::size_t v) { return !m.is_dead_vertex(static_cast<VertId>(v)); },
      [&](std::size_t v) { return Keyed{frame.key(m.positions[v]), static_cast<std::uint32_t>(v)}; });
  parallel::sort(vertex_order.begin(), vertex_order.end());
  std::vector<VertId> new_id(m.vertex_capacity(), kInvalid);
  parallel::for_range<std::size_t>(0, vertex_order.size(), 8192, "vertex_ids", [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) new_id[vertex_order[i].second] = static_cast<VertId>(i);
  });
  if (new2old != nullptr) {
    new2old->resize(vertex_order.size());
    for (std::size_t i = 0; i < vertex_order.size(); ++i) (*new2old)[i] = vertex_order[i].second;
  }

  std::vector<Keyed> tet_order;
  parallel::filter_map(
      m.tet_capacity(), tet_order, [&](std::size_t t) { return !m.is_dead_tet(static_cast<TetId>(t)); },
      [&](std::size_t t) {
        const auto& v = m.tets[t];
        const glm::dvec3 centroid = 0.25 * (m.positions[v[0]] + m.positions[v[1]] + m.positions[v[2]] + m.positions[v[3]]);
        return Keyed{frame.key(centroid), static_cast<std::uint32_t>(t)};
      });
  parallel::sort(tet_order.begin(), tet_order.end());
  if (tet_old2new != nullptr) {
    tet_old2new->assign(m.tet_capacity(), kInvalid);
    for (std::size_t i = 0; i < tet_order.size(); ++i) (*tet_old2new)[tet_order[i].second] = static_cast<TetId>(i);
  }

  const std::size_t stride = static_cast<std::size_t>(m.field_stride());
  permute(m.positions, vertex_order, 1);
  if (stride > 0) permute(m.field_values, vertex_order, stride);
  permute(m.vertex_refs, vertex_order, 1);
  permute(m.vertex_states, vertex_order, 1);

  permute(m.tets, tet_order, 1);
  parallel::for_range<std::size_t>(0, m.tets.size(), 8192, "tet_vertex_ids", [&](std::size_t b, std::size_t e) {
    for (std::size_t t = b; t < e; ++t)
      for (VertId& x : m.tets[t]) x = new_id[x];
  });
  permute(m.material, tet_order, 1);
  permute(m.flags, tet_order, 1);
  permute(m.tet_refs_slot, tet_order, 1);
  rebuild_incidence(m);
}

}  // namespace topotet
