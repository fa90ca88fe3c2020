// Levels of a collapse hierarchy (topotet/hierarchy.h): selections of collapses, and the mesh a
// selection gives.
//
// A level is computed without any mesh connectivity: each vertex's representative comes from one
// backward pass over the applied collapses (when collapse i is reached, every later collapse
// that removed u_i has been seen, so rep[u_i] is final and rep[v_i] = rep[u_i]); each original
// tet survives iff its four representatives are distinct (a collapse u <- v kills exactly the
// tets holding both u and v, which become degenerate under v -> u, and nothing else); the
// positions and fields are those the last applied collapse that moved a vertex gave it.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "mesh/glm_convert.h"
#include "topotet/error.h"
#include "topotet/hierarchy.h"

namespace topotet {
namespace {

void require_downward_closed(const Hierarchy& h, const std::vector<std::uint8_t>& applied) {
  if (applied.size() != h.collapse_count())
    throw InputError("hierarchy selection: " + std::to_string(applied.size()) + " entries for " +
                     std::to_string(h.collapse_count()) + " collapses");
  for (std::size_t i = 0; i < applied.size(); ++i) {
    if (!applied[i]) continue;
    for (std::uint32_t k = h.parent_offsets[i]; k < h.parent_offsets[i + 1]; ++k)
      if (!applied[h.parents[k]])
        throw InputError("hierarchy selection: collapse " + std::to_string(i + 1) + " is applied without its parent " +
                         std::to_string(h.parents[k] + 1));
  }
}

bool touches(const Hierarchy& h, std::size_t i, const Voi& voi) {
  return voi.contains(h.u_before[i]) || voi.contains(h.v_position[i]) || voi.contains(h.u_after[i]);
}

// Keeps the first of each group of elements with the same key, in their order. Keys are the
// sorted vertex ids and the ref: a face (edge) that two collapses merged is listed once per ref,
// as MeshModel::to_mesh_data lists it.
template <class Element, std::size_t N>
std::vector<std::uint8_t> first_occurrences(const std::vector<Element>& elements) {
  using Key = std::pair<std::array<VertId, N>, std::int32_t>;
  std::vector<std::pair<Key, std::uint32_t>> keyed(elements.size());
  for (std::uint32_t i = 0; i < elements.size(); ++i) {
    std::array<VertId, N> v = elements[i].v;
    std::sort(v.begin(), v.end());
    keyed[i] = {{v, elements[i].ref}, i};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint8_t> keep(elements.size(), 1);
  for (std::size_t i = 1; i < keyed.size(); ++i)
    if (keyed[i].first == keyed[i - 1].first) keep[keyed[i].second] = 0;
  return keep;
}

template <std::size_t N>
bool distinct(const std::array<VertId, N>& v) {
  for (std::size_t a = 0; a < N; ++a)
    for (std::size_t b = a + 1; b < N; ++b)
      if (v[a] == v[b]) return false;
  return true;
}

}  // namespace

// ---- selections ----

std::vector<std::uint8_t> select_prefix(const Hierarchy& h, std::size_t count) {
  std::vector<std::uint8_t> applied(h.collapse_count(), 0);
  std::fill_n(applied.begin(), std::min(count, applied.size()), 1);
  return applied;
}

std::size_t prefix_for_vertices(const Hierarchy& h, std::size_t vertices) {
  // Every collapse removes one vertex.
  const std::size_t start = h.original.positions.size();
  return std::min(h.collapse_count(), start > vertices ? start - vertices : 0);
}

std::size_t prefix_for_error(const Hierarchy& h, double max_error) {
  return static_cast<std::size_t>(std::upper_bound(h.error.begin(), h.error.end(), max_error) - h.error.begin());
}

double collapse_error(const Hierarchy& h, std::size_t i) {
  // Hierarchy::error is the running maximum of the per-collapse values: where it equals the
  // collapse's own bound, that bound is the value; a bounded hierarchy has no NaN.
  return !h.error_bound.empty() && !std::isnan(h.error_bound[i]) ? static_cast<double>(h.error_bound[i]) : h.cost[i];
}

std::vector<std::uint8_t> select_error(const Hierarchy& h, double max_error) {
  std::vector<std::uint8_t> applied(h.collapse_count(), 0);
  for (std::size_t i = 0; i < applied.size(); ++i) {
    if (collapse_error(h, i) > max_error) continue;
    bool parents_applied = true;
    for (std::uint32_t k = h.parent_offsets[i]; k < h.parent_offsets[i + 1] && parents_applied; ++k)
      parents_applied = applied[h.parents[k]] != 0;
    applied[i] = parents_applied;
  }
  return applied;
}

std::vector<std::uint8_t> select_voi(const Hierarchy& h, const Voi& voi, double inside_error, double outside_error,
                                     VoiClosure closure) {
  std::vector<std::uint8_t> applied(h.collapse_count(), 0);
  auto wanted = [&](std::size_t i) { return collapse_error(h, i) <= (touches(h, i, voi) ? inside_error : outside_error); };
  if (closure == VoiClosure::kReachCoarse) {
    // Parents come before their children: one backward pass adds every ancestor.
    for (std::size_t i = applied.size(); i-- > 0;) {
      if (!applied[i] && !wanted(i)) continue;
      applied[i] = 1;
      for (std::uint32_t k = h.parent_offsets[i]; k < h.parent_offsets[i + 1]; ++k) applied[h.parents[k]] = 1;
    }
    return applied;
  }
  for (std::size_t i = 0; i < applied.size(); ++i) {
    if (!wanted(i)) continue;
    bool parents_applied = true;
    for (std::uint32_t k = h.parent_offsets[i]; k < h.parent_offsets[i + 1] && parents_applied; ++k)
      parents_applied = applied[h.parents[k]] != 0;
    applied[i] = parents_applied;
  }
  return applied;
}

// ---- volumes of interest ----

bool Voi::contains(const std::array<double, 3>& p) const {
  if (kind == Kind::kBox)
    return p[0] >= lo[0] && p[0] <= hi[0] && p[1] >= lo[1] && p[1] <= hi[1] && p[2] >= lo[2] && p[2] <= hi[2];
  const glm::dvec3 d = to_glm(p) - to_glm(centre);
  return d.x * d.x + d.y * d.y + d.z * d.z <= radius * radius;
}

Voi Voi::moved(const std::array<double, 3>& by) const {
  Voi m = *this;
  m.lo = from_glm(to_glm(lo) + to_glm(by));
  m.hi = from_glm(to_glm(hi) + to_glm(by));
  m.centre = from_glm(to_glm(centre) + to_glm(by));
  return m;
}

double Voi::size() const {
  if (kind == Kind::kSphere) return 2.0 * radius;
  const glm::dvec3 d = to_glm(hi) - to_glm(lo);
  return std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
}

Voi parse_voi(const std::string& text) {
  auto fail = [&](const std::string& why) {
    throw InputError("--voi '" + text + "': " + why + " (expected box:x0,y0,z0,x1,y1,z1 or sphere:x,y,z,r)");
  };
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) fail("no ':'");
  const std::string kind = text.substr(0, colon);
  std::vector<double> values;
  std::stringstream in(text.substr(colon + 1));
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      fail("'" + item + "' is not a number");
    }
    if (used != item.size() || !std::isfinite(x)) fail("'" + item + "' is not a finite number");
    values.push_back(x);
  }
  Voi voi;
  if (kind == "box") {
    if (values.size() != 6) fail("a box takes 6 numbers");
    voi.kind = Voi::Kind::kBox;
    voi.lo = {values[0], values[1], values[2]};
    voi.hi = {values[3], values[4], values[5]};
    if (voi.lo[0] > voi.hi[0] || voi.lo[1] > voi.hi[1] || voi.lo[2] > voi.hi[2]) fail("the low corner is above the high one");
  } else if (kind == "sphere") {
    if (values.size() != 4) fail("a sphere takes 4 numbers");
    voi.kind = Voi::Kind::kSphere;
    voi.centre = {values[0], values[1], values[2]};
    voi.radius = values[3];
    if (!(voi.radius >= 0.0)) fail("the radius must be >= 0");
  } else {
    fail("unknown shape '" + kind + "'");
  }
  return voi;
}

// ---- the mesh of a level ----

HierarchyCursor::HierarchyCursor(const Hierarchy& hierarchy)
    : h_(hierarchy), applied_(hierarchy.collapse_count(), 0), positions_(hierarchy.original.positions) {
  const MeshData& m = h_.original;
  const std::size_t stride = static_cast<std::size_t>(h_.field_stride);
  fields_.resize(m.positions.size() * stride);
  std::size_t offset = 0;
  for (const VertexField& f : m.fields) {
    const std::size_t c = static_cast<std::size_t>(f.components);
    for (std::size_t x = 0; x < m.positions.size(); ++x)
      std::copy_n(f.values.data() + x * c, c, fields_.data() + x * stride + offset);
    offset += c;
  }
}

std::size_t HierarchyCursor::move_to(const std::vector<std::uint8_t>& applied) {
  require_downward_closed(h_, applied);
  const std::size_t stride = static_cast<std::size_t>(h_.field_stride);
  std::size_t changed = 0;
  // Undo, latest first: a collapse that later moved the same u depends on this one (u is in both
  // stencils), so it is not in the new set either and has already been undone.
  for (std::size_t i = applied_.size(); i-- > 0;) {
    if (!applied_[i] || applied[i]) continue;
    positions_[h_.u[i]] = h_.u_before[i];
    std::copy_n(h_.fields_before.data() + i * stride, stride, fields_.data() + h_.u[i] * stride);
    applied_[i] = 0;
    ++changed;
  }
  for (std::size_t i = 0; i < applied_.size(); ++i) {
    if (applied_[i] || !applied[i]) continue;
    positions_[h_.u[i]] = h_.u_after[i];
    std::copy_n(h_.fields_after.data() + i * stride, stride, fields_.data() + h_.u[i] * stride);
    applied_[i] = 1;
    ++changed;
  }
  return changed;
}

MeshData HierarchyCursor::mesh() const {
  const MeshData& m = h_.original;
  const std::size_t nv = m.positions.size();
  std::vector<VertId> rep(nv);
  std::iota(rep.begin(), rep.end(), VertId{0});
  for (std::size_t i = applied_.size(); i-- > 0;)
    if (applied_[i]) rep[h_.v[i]] = rep[h_.u[i]];
  std::vector<VertId> new_id(nv, kInvalid);
  MeshData out;
  std::size_t live = 0;
  for (VertId x = 0; x < nv; ++x)
    if (rep[x] == x) new_id[x] = static_cast<VertId>(live++);
  // Composed once so that the hot loops below do one lookup per corner.
  std::vector<VertId> to_out(nv);
  for (VertId x = 0; x < nv; ++x) to_out[x] = new_id[rep[x]];

  out.positions.resize(live);
  if (!m.vertex_refs.empty()) out.vertex_refs.resize(live);
  for (VertId x = 0; x < nv; ++x) {
    if (new_id[x] == kInvalid) continue;
    out.positions[new_id[x]] = positions_[x];
    if (!m.vertex_refs.empty()) out.vertex_refs[new_id[x]] = m.vertex_refs[x];
  }
  out.tets.reserve(m.tets.size());
  out.tet_material.reserve(m.tets.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const std::array<VertId, 4>& s = m.tets[t];
    const std::array<VertId, 4> v = {to_out[s[0]], to_out[s[1]], to_out[s[2]], to_out[s[3]]};
    if (!distinct(v)) continue;
    out.tets.push_back(v);
    out.tet_material.push_back(m.tet_material[t]);
  }
  for (const Triangle& tri : m.triangles) {
    Triangle r{{to_out[tri.v[0]], to_out[tri.v[1]], to_out[tri.v[2]]}, tri.ref};
    if (distinct(r.v)) out.triangles.push_back(r);
  }
  const std::vector<std::uint8_t> keep_triangles = first_occurrences<Triangle, 3>(out.triangles);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < out.triangles.size(); ++i)
    if (keep_triangles[i]) out.triangles[kept++] = out.triangles[i];
  out.triangles.resize(kept);

  // Segments, with the ridge marks following them.
  std::vector<std::uint8_t> is_ridge(m.segments.size(), 0);
  for (std::uint32_t r : m.ridges) is_ridge[r] = 1;
  std::vector<std::uint8_t> ridge_of;
  for (std::size_t s = 0; s < m.segments.size(); ++s) {
    Segment r{{to_out[m.segments[s].v[0]], to_out[m.segments[s].v[1]]}, m.segments[s].ref};
    if (!distinct(r.v)) continue;
    out.segments.push_back(r);
    ridge_of.push_back(is_ridge[s]);
  }
  const std::vector<std::uint8_t> keep_segments = first_occurrences<Segment, 2>(out.segments);
  kept = 0;
  for (std::size_t i = 0; i < out.segments.size(); ++i) {
    if (!keep_segments[i]) continue;
    if (ridge_of[i]) out.ridges.push_back(static_cast<std::uint32_t>(kept));
    out.segments[kept++] = out.segments[i];
  }
  out.segments.resize(kept);

  // Pinned vertices are never removed; a hierarchy that removed one anyway (a hand-edited file)
  // loses the pin with the vertex.
  for (VertId x : m.corners)
    if (new_id[x] != kInvalid) out.corners.push_back(new_id[x]);
  for (VertId x : m.required_vertices)
    if (new_id[x] != kInvalid) out.required_vertices.push_back(new_id[x]);

  const std::size_t stride = static_cast<std::size_t>(h_.field_stride);
  std::size_t offset = 0;
  for (const VertexField& f : m.fields) {
    VertexField g{f.name, f.components, {}};
    const std::size_t c = static_cast<std::size_t>(f.components);
    g.values.resize(live * c);
    for (VertId x = 0; x < nv; ++x)
      if (new_id[x] != kInvalid) std::copy_n(fields_.data() + x * stride + offset, c, g.values.data() + new_id[x] * c);
    offset += c;
    out.fields.push_back(std::move(g));
  }
  out.group_names = m.group_names;
  return out;
}

MeshData extract(const Hierarchy& hierarchy, const std::vector<std::uint8_t>& applied) {
  HierarchyCursor cursor(hierarchy);
  cursor.move_to(applied);
  return cursor.mesh();
}

}  // namespace topotet
