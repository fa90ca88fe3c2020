// The collapse hierarchy's record (topotet/hierarchy.h): the engines' log (hierarchy_log.h), the
// running error, and the validation of a hierarchy (also used by the .tth reader). The driver that
// runs simplify() with the log is simplify_with_hierarchy.cpp, one floor up.
//
// Why a downward-closed set S of collapses, applied in recording order, replays each member i
// exactly as the engine verified it. The patch P_i of collapse i is St(u_i) ∪ St(v_i) at its time;
// the collapse changes exactly the tets of P_i (kills St(uv), renames v in the rest; u moves, and
// every tet holding u is in P_i). Parents of i: the collapses that last changed a tet of P_i.
// Induction over the members in order:
//  - every tet t of P_i: the collapses that changed t before i form a chain, each the parent of
//    the next (t was in the next one's patch), ending at a parent of i: all are in S, each is
//    replayed with its verified patch (induction), so each changes t the same way. t is the same.
//  - no other tet holds u_i in the replay. Say t' does: its applied changes are a prefix of its
//    changes (as above), and the first missing one, k < i, changed t' while t' held u_i. A legal
//    collapse keeps every link vertex: k left at least one tet holding u_i among the tets it
//    changed, and every later change of St(u_i) (which removes such a tet only by changing it)
//    again leaves one, so some tet of St(u_i) at time i, in P_i, descends from k: k is an
//    ancestor of i, in S. Contradiction. The same for v_i.
//  - positions: the last collapse j that moved w (u_j = w) changed every tet holding w then, and
//    every tet holding w afterwards descends from those; P_i holds one (w in P_i): j is in S.
// The kernel reads only the two stars, the positions and fields of their vertices, and immutable
// data (pinned flags, the original surfaces for the tolerance), so it gives the same verdict: the
// collapse is legal in the replayed mesh. tests/property_hierarchy.cpp replays random closed sets
// through the kernel (may_collapse must accept every collapse) to check exactly this.
#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <stdexcept>

#include "hierarchy/hierarchy_log.h"
#include "mesh/glm_convert.h"
#include "topotet/error.h"
#include "topotet/hierarchy.h"

namespace topotet {
namespace detail {

CollapseLog::CollapseLog(std::size_t tet_capacity, int field_stride, std::uint32_t first_id)
    : stride_(field_stride), first_id_(first_id), last_change_(tet_capacity, kInvalid) {}

void CollapseLog::seed_tets(std::vector<std::uint32_t> last_change) {
  if (last_change.size() != last_change_.size()) throw std::logic_error("CollapseLog::seed_tets: one seed per tet");
  last_change_ = std::move(last_change);
  seeded_ = true;
}

void CollapseLog::renumber_tets(const std::vector<TetId>& tet_old2new, std::size_t tet_capacity) {
  if (tet_old2new.size() != last_change_.size()) throw std::logic_error("CollapseLog::renumber_tets: one entry per tet");
  std::vector<std::uint32_t> renumbered(tet_capacity, kInvalid);
  for (std::size_t t = 0; t < tet_old2new.size(); ++t)
    if (tet_old2new[t] != kInvalid) renumbered[tet_old2new[t]] = last_change_[t];
  last_change_ = std::move(renumbered);
}

void CollapseLog::set_sink(std::function<void(const CollapseLog&)> sink, std::size_t every) {
  sink_ = std::move(sink);
  sink_every_ = every;
}

void CollapseLog::flush() {
  if (!sink_ || u.empty()) return;
  sink_(*this);
  handed_over_ += u.size();
  for (auto* ids : {&u, &v}) ids->clear();
  for (auto* points : {&u_before, &u_after, &v_position}) points->clear();
  for (auto* values : {&fields_before, &fields_after, &cost}) values->clear();
  error_bound.clear();
  parents.clear();
  parent_offsets.assign(1, 0);
}

std::vector<std::uint32_t> CollapseLog::keep_live_tets(const MeshModel& mesh) const {
  std::vector<std::uint32_t> live;
  live.reserve(mesh.live_tet_count());
  for (TetId t = 0; t < mesh.tet_capacity(); ++t)
    if (!mesh.is_dead_tet(t)) live.push_back(last_change_[t]);
  return live;
}

void CollapseLog::begin_batch(std::size_t slots) {
  batch_size_ = slots;
  if (slots_.size() < slots) slots_.resize(slots);
  slot_fields_.resize(slots * 2 * static_cast<std::size_t>(stride_));
}

void CollapseLog::record(std::size_t slot, const MeshModel& mesh, VertId cu, VertId cv, const glm::dvec3& p,
                         const double* fields_after_p, double collapse_cost) {
  Slot& s = slots_[slot];
  s.u = cu;
  s.v = cv;
  s.u_before = from_glm(mesh.positions[cu]);
  s.u_after = from_glm(p);
  s.v_position = from_glm(mesh.positions[cv]);
  s.cost = collapse_cost;
  s.bound = std::numeric_limits<float>::quiet_NaN();
  const std::size_t stride = static_cast<std::size_t>(stride_);
  double* f = slot_fields_.data() + slot * 2 * stride;
  const double* old_fields = mesh.field_values.data() + cu * stride;
  std::copy_n(old_fields, stride, f);
  std::copy_n(fields_after_p != nullptr ? fields_after_p : old_fields, stride, f + stride);
}

void CollapseLog::depend(std::size_t slot, const std::vector<TetId>& star_u, const std::vector<TetId>& star_v) {
  Slot& s = slots_[slot];
  // The collapses of earlier batches are committed (in the records or handed over), so
  // first_id_ + handed_over_ + u.size() is this batch's first id.
  const auto id = static_cast<std::uint32_t>(first_id_ + handed_over_ + u.size() + slot);
  s.parents.clear();
  for (const auto* star : {&star_u, &star_v})
    for (TetId t : *star) {
      std::uint32_t& last = last_change_[t];
      if (last != kInvalid && last != id) s.parents.push_back(last);
      last = id;  // killed tets too: no later collapse reads them
    }
  std::sort(s.parents.begin(), s.parents.end());
  s.parents.erase(std::unique(s.parents.begin(), s.parents.end()), s.parents.end());
}

void fill_running_error(Hierarchy& h) {
  h.error.resize(h.cost.size());
  // The bounds when every collapse has one (the run tracked them), else the costs.
  const bool bounded = !h.error_bound.empty() && h.error_bound.size() == h.cost.size() &&
                       std::none_of(h.error_bound.begin(), h.error_bound.end(), [](float b) { return std::isnan(b); });
  double running = 0.0;
  for (std::size_t i = 0; i < h.cost.size(); ++i) {
    running = std::max(running, bounded ? static_cast<double>(h.error_bound[i]) : h.cost[i]);
    h.error[i] = running;
  }
}

void CollapseLog::end_batch() {
  const std::size_t stride = static_cast<std::size_t>(stride_);
  for (std::size_t i = 0; i < batch_size_; ++i) {
    const Slot& s = slots_[i];
    u.push_back(s.u);
    v.push_back(s.v);
    u_before.push_back(s.u_before);
    u_after.push_back(s.u_after);
    v_position.push_back(s.v_position);
    cost.push_back(s.cost);
    error_bound.push_back(s.bound);
    const double* f = slot_fields_.data() + i * 2 * stride;
    fields_before.insert(fields_before.end(), f, f + stride);
    fields_after.insert(fields_after.end(), f + stride, f + 2 * stride);
    parents.insert(parents.end(), s.parents.begin(), s.parents.end());
    parent_offsets.push_back(static_cast<std::uint32_t>(parents.size()));
  }
  batch_size_ = 0;
  if (sink_ && u.size() >= sink_every_) flush();
}

}  // namespace detail

void validate_hierarchy(const Hierarchy& h, const std::string& label) {
  auto fail = [&](const std::string& what) { throw InputError(label + ": " + what); };
  const MeshData& m = h.original;
  const std::size_t nv = m.positions.size();
  auto check_vertex = [&](std::uint64_t x, const char* where, std::size_t index) {
    if (x >= nv)
      fail(std::string(where) + " " + std::to_string(index + 1) + ": vertex index " + std::to_string(x) +
           " out of range (the mesh has " + std::to_string(nv) + " vertices)");
  };
  // Every reader refuses non-finite coordinates and field values (a NaN would also make the
  // hierarchy differ from itself when compared); a hierarchy holds the same.
  // `what` names the record ("vertex", "collapse"), `detail` the value within it.
  auto check_finite = [&](const double* x, std::size_t count, std::size_t per_record, const std::string& what,
                          const std::string& detail) {
    for (std::size_t i = 0; i < count; ++i)
      if (!std::isfinite(x[i]))
        fail(what + " " + std::to_string(i / per_record + 1) + detail + ": non-finite value (nan or inf)");
  };
  auto doubles = [](const std::vector<std::array<double, 3>>& p) { return reinterpret_cast<const double*>(p.data()); };
  check_finite(doubles(m.positions), 3 * nv, 3, "vertex", "");
  if (!m.vertex_refs.empty() && m.vertex_refs.size() != nv) fail("vertex refs: count differs from the vertex count");
  if (m.tet_material.size() != m.tets.size()) fail("tet materials: count differs from the tet count");
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (VertId x : m.tets[t]) check_vertex(x, "tet", t);
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (VertId x : m.triangles[t].v) check_vertex(x, "triangle", t);
  for (std::size_t s = 0; s < m.segments.size(); ++s)
    for (VertId x : m.segments[s].v) check_vertex(x, "segment", s);
  for (std::size_t r = 0; r < m.ridges.size(); ++r)
    if (m.ridges[r] >= m.segments.size()) fail("ridge " + std::to_string(r + 1) + ": segment index out of range");
  for (std::size_t c = 0; c < m.corners.size(); ++c) check_vertex(m.corners[c], "corner", c);
  for (std::size_t c = 0; c < m.required_vertices.size(); ++c) check_vertex(m.required_vertices[c], "required vertex", c);
  int stride = 0;
  for (const VertexField& f : m.fields) {
    if (f.components < 1) fail("field '" + f.name + "': components must be >= 1");
    if (f.values.size() != nv * static_cast<std::size_t>(f.components))
      fail("field '" + f.name + "': value count differs from vertices x components");
    check_finite(f.values.data(), f.values.size(), static_cast<std::size_t>(f.components), "field '" + f.name + "': vertex",
                 "");
    stride += f.components;
  }
  if (stride != h.field_stride) fail("field stride " + std::to_string(h.field_stride) + " differs from the fields' components");
  const std::size_t n = h.u.size();
  const std::size_t sn = n * static_cast<std::size_t>(stride);
  if (h.v.size() != n || h.u_before.size() != n || h.u_after.size() != n || h.v_position.size() != n ||
      h.cost.size() != n || h.error.size() != n || h.error_bound.size() != n || h.fields_before.size() != sn ||
      h.fields_after.size() != sn || h.parent_offsets.size() != n + 1)
    fail("collapse arrays have different lengths");
  if (h.parent_offsets[0] != 0 || h.parent_offsets[n] != h.parents.size()) fail("parent offsets do not cover the parents");
  // Non-decreasing, so that every collapse's parents lie inside `parents` (an offset past the end
  // followed by a smaller one would pass the two ends above).
  for (std::size_t i = 0; i < n; ++i)
    if (h.parent_offsets[i + 1] < h.parent_offsets[i])
      fail("collapse " + std::to_string(i + 1) + ": parent offsets decrease");
  check_finite(doubles(h.u_before), 3 * n, 3, "collapse", " (u position before)");
  check_finite(doubles(h.u_after), 3 * n, 3, "collapse", " (u position after)");
  check_finite(doubles(h.v_position), 3 * n, 3, "collapse", " (v position)");
  if (stride > 0) {
    check_finite(h.fields_before.data(), sn, static_cast<std::size_t>(stride), "collapse", " (fields before)");
    check_finite(h.fields_after.data(), sn, static_cast<std::size_t>(stride), "collapse", " (fields after)");
  }
  std::vector<std::uint8_t> removed(nv, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::string where = "collapse " + std::to_string(i + 1);
    check_vertex(h.u[i], where.c_str(), 0);
    check_vertex(h.v[i], where.c_str(), 0);
    if (h.u[i] == h.v[i]) fail(where + ": u and v are the same vertex");
    if (removed[h.u[i]] || removed[h.v[i]]) fail(where + ": a vertex removed by an earlier collapse");
    removed[h.v[i]] = 1;
    std::uint64_t previous = 0;
    for (std::uint32_t k = h.parent_offsets[i]; k < h.parent_offsets[i + 1]; ++k) {
      const std::uint32_t p = h.parents[k];
      if (p >= i) fail(where + ": parent " + std::to_string(p + 1) + " does not come before it");
      if (k > h.parent_offsets[i] && p <= previous) fail(where + ": parents not sorted and distinct");
      previous = p;
    }
  }
}

}  // namespace topotet
