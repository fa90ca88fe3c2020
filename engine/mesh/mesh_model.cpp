// MeshModel bookkeeping: counts, memory, incidence rebuild, compaction, export to MeshData.
#include <algorithm>
#include <limits>
#include <numeric>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "mesh/glm_convert.h"
#include "mesh/mesh_model.h"
#include "parallel/for_range.h"
#include "mesh/prefetch.h"
#include "mesh/probe_set.h"

namespace topotet {

std::size_t MeshModel::live_vertex_count() const {
  std::size_t n = 0;
  for (std::uint8_t s : vertex_states) n += (s & vertex_state::kDead) ? 0 : 1;
  return n;
}

std::size_t MeshModel::live_tet_count() const {
  std::size_t n = 0;
  for (TetFlags f : flags) n += (f & tet_flag::kDead) ? 0 : 1;
  return n;
}

int MeshModel::field_stride() const {
  int s = 0;
  for (const FieldInfo& f : fields) s += f.components;
  return s;
}

// The vertices x of v's live tets with keep(x), each once, in the order the star meets them.
// Every neighbour appears in several tets of the star (about 5 times in the interior): a probe
// set drops the repeats. This runs for every candidate edge.
template <class Keep>
void MeshModel::gather_neighbours(VertId v, std::vector<VertId>& out, Keep&& keep) const {
  out.clear();
  const std::size_t slots = probe_slots_for(3 * static_cast<std::size_t>(v2t_count[v]));
  std::array<VertId, 512> on_stack;  // stars of up to 85 tets
  std::vector<VertId> on_heap;
  if (slots > on_stack.size()) on_heap.resize(slots);
  ProbeSet<VertId> seen(slots > on_stack.size() ? std::span<VertId>(on_heap) : std::span<VertId>(on_stack.data(), slots));
  prefetch_star(*this, v);
  for_each_tet_of(v, [&](TetId t) {
    for (VertId x : tets[t])
      if (keep(x) && seen.insert(x).second) out.push_back(x);
  });
}

void MeshModel::neighbours(VertId v, std::vector<VertId>& out) const {
  gather_neighbours(v, out, [v](VertId x) { return x != v; });
  std::sort(out.begin(), out.end());  // only the distinct ones are sorted
}

void MeshModel::neighbours_above(VertId v, std::vector<VertId>& out) const {
  gather_neighbours(v, out, [v](VertId x) { return x > v; });
}

std::size_t MeshModel::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(positions) + bytes(field_values) + bytes(vertex_refs) + bytes(vertex_states) + bytes(tets) +
         bytes(material) + bytes(flags) + bytes(tet_refs_slot) + bytes(refs_table) + bytes(v2t_offsets) +
         bytes(v2t_next) + bytes(v2t_count) + bytes(v2t);
}

void rebuild_incidence(MeshModel& m) {
  const std::size_t nv = m.positions.size(), nt = m.tets.size();
  m.v2t_count.assign(nv, 0);
  for (std::size_t t = 0; t < nt; ++t)
    if (!(m.flags.empty() ? false : m.is_dead_tet(static_cast<TetId>(t))))
      for (VertId v : m.tets[t]) ++m.v2t_count[v];
  m.v2t_offsets.assign(nv + 1, 0);
  for (std::size_t v = 0; v < nv; ++v) m.v2t_offsets[v + 1] = m.v2t_offsets[v] + m.v2t_count[v];
  m.v2t.assign(m.v2t_offsets[nv], kInvalid);
  m.v2t_next.assign(nv, kInvalid);
  std::vector<std::uint32_t> fill(m.v2t_offsets.begin(), m.v2t_offsets.end() - 1);
  // Filling in tet order keeps every star sorted by tet id: deterministic traversal orders.
  for (std::size_t t = 0; t < nt; ++t)
    if (!(m.flags.empty() ? false : m.is_dead_tet(static_cast<TetId>(t))))
      for (VertId v : m.tets[t]) m.v2t[fill[v]++] = static_cast<TetId>(t);
}

void compact(MeshModel& m) {
  const std::size_t nv = m.positions.size(), nt = m.tets.size();
  std::vector<VertId> vmap(nv, kInvalid);
  VertId nv_new = 0;
  for (std::size_t v = 0; v < nv; ++v)
    if (!m.is_dead_vertex(static_cast<VertId>(v))) vmap[v] = nv_new++;
  const int stride = m.field_stride();
  for (std::size_t v = 0; v < nv; ++v) {
    const VertId w = vmap[v];
    if (w == kInvalid || w == v) continue;  // w <= v always: moving down in place is safe
    m.positions[w] = m.positions[v];
    m.vertex_refs[w] = m.vertex_refs[v];
    m.vertex_states[w] = m.vertex_states[v];
    std::copy_n(m.field_values.begin() + static_cast<std::ptrdiff_t>(v * stride), stride,
                m.field_values.begin() + static_cast<std::ptrdiff_t>(w * stride));
  }
  m.positions.resize(nv_new);
  m.vertex_refs.resize(nv_new);
  m.vertex_states.resize(nv_new);
  m.field_values.resize(static_cast<std::size_t>(nv_new) * stride);

  std::vector<SubstructureRefs> refs;
  TetId nt_new = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    if (m.is_dead_tet(static_cast<TetId>(t))) continue;
    std::array<VertId, 4> v = m.tets[t];
    for (VertId& x : v) x = vmap[x];
    m.tets[nt_new] = v;
    m.material[nt_new] = m.material[t];
    m.flags[nt_new] = m.flags[t];
    std::uint32_t slot = kInvalid;
    if (m.flags[t] & (tet_flag::kSurfaceFaces | tet_flag::kPolylineEdges)) {
      slot = static_cast<std::uint32_t>(refs.size());
      refs.push_back(m.refs_table[m.tet_refs_slot[t]]);
    }
    m.tet_refs_slot[nt_new] = slot;
    ++nt_new;
  }
  m.tets.resize(nt_new);
  m.material.resize(nt_new);
  m.flags.resize(nt_new);
  m.tet_refs_slot.resize(nt_new);
  m.refs_table = std::move(refs);
  rebuild_incidence(m);
}

void compact_tets(MeshModel& m) {
  TetId nt_new = 0;
  for (TetId t = 0; t < m.tets.size(); ++t) {
    if (m.is_dead_tet(t)) continue;
    m.tets[nt_new] = m.tets[t];
    m.material[nt_new] = m.material[t];
    m.flags[nt_new] = m.flags[t];
    m.tet_refs_slot[nt_new] = m.tet_refs_slot[t];
    ++nt_new;
  }
  m.tets.resize(nt_new);
  m.material.resize(nt_new);
  m.flags.resize(nt_new);
  m.tet_refs_slot.resize(nt_new);
  rebuild_incidence(m);
}

namespace {

template <std::size_t N>
struct KeyedItem {
  std::array<VertId, N> key;       // sorted new vertex ids
  std::array<VertId, N> oriented;  // as seen from the first tet that has it
  std::int32_t ref;
  bool ridge;
  bool operator<(const KeyedItem& o) const { return key < o.key; }
};

}  // namespace

MeshData MeshModel::to_mesh_data(const MeshExportOptions& options) const {
  MeshData d;
  const std::size_t nv = positions.size(), nt = tets.size();
  std::vector<VertId> vmap(nv, kInvalid);
  for (std::size_t v = 0; v < nv; ++v) {
    if (is_dead_vertex(static_cast<VertId>(v))) continue;
    vmap[v] = static_cast<VertId>(d.positions.size());
    d.positions.push_back(from_glm(positions[v]));
    d.vertex_refs.push_back(vertex_refs[v]);
    if ((vertex_states[v] & vertex_state::kCorner) ||
        (options.feature_edges && (vertex_states[v] & vertex_state::kFeatureCorner)))
      d.corners.push_back(vmap[v]);
    if (vertex_states[v] & vertex_state::kRequired) d.required_vertices.push_back(vmap[v]);
  }
  if (std::all_of(d.vertex_refs.begin(), d.vertex_refs.end(), [](std::int32_t r) { return r == 0; }))
    d.vertex_refs.clear();

  std::vector<KeyedItem<3>> faces;
  std::vector<KeyedItem<2>> edges;
  for (std::size_t t = 0; t < nt; ++t) {
    if (is_dead_tet(static_cast<TetId>(t))) continue;
    std::array<VertId, 4> v = tets[t];
    for (VertId& x : v) x = vmap[x];
    d.tets.push_back(v);
    d.tet_material.push_back(material[t]);
    const TetFlags f = flags[t];
    if (!(f & (tet_flag::kSurfaceFaces | tet_flag::kPolylineEdges))) continue;
    const SubstructureRefs& r = refs_table[tet_refs_slot[t]];
    for (int k = 0; k < 4; ++k) {
      if (!is_surface_face(f, k) || r.face[k] == kImplicitInterfaceRef) continue;
      KeyedItem<3> item{{}, {v[kTetFaces[k][0]], v[kTetFaces[k][1]], v[kTetFaces[k][2]]}, r.face[k], false};
      item.key = item.oriented;
      std::sort(item.key.begin(), item.key.end());
      faces.push_back(item);
    }
    for (int e = 0; e < 6; ++e) {
      if (!is_polyline_edge(f, e)) continue;
      const bool feature = r.edge[e] == kFeatureCurveRef;
      if (feature && !options.feature_edges) continue;
      KeyedItem<2> item{{}, {v[kTetEdges[e][0]], v[kTetEdges[e][1]]}, feature ? options.feature_ref : r.edge[e],
                        feature || ((r.ridge_mask >> e) & 1u) != 0};
      item.key = {std::min(item.oriented[0], item.oriented[1]), std::max(item.oriented[0], item.oriented[1])};
      edges.push_back(item);
    }
  }
  // stable_sort keeps the first tet's orientation first among equal keys: deterministic output.
  std::stable_sort(faces.begin(), faces.end());
  std::stable_sort(edges.begin(), edges.end());
  // A stand-in ref is written back as one element per ref of its set.
  auto for_each_ref = [](const std::vector<SharedRefs>& shared, std::int32_t ref, auto&& f) {
    const auto it = std::lower_bound(shared.begin(), shared.end(), ref,
                                     [](const SharedRefs& s, std::int32_t r) { return s.stand_in < r; });
    if (it == shared.end() || it->stand_in != ref) return f(ref);
    for (std::int32_t r : it->refs) f(r);
  };
  for (std::size_t i = 0; i < faces.size(); ++i)
    if (i == 0 || faces[i].key != faces[i - 1].key)
      for_each_ref(shared_face_refs, faces[i].ref, [&](std::int32_t r) { d.triangles.push_back({faces[i].oriented, r}); });
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (i != 0 && edges[i].key == edges[i - 1].key) continue;
    for_each_ref(shared_edge_refs, edges[i].ref, [&](std::int32_t r) {
      if (edges[i].ridge) d.ridges.push_back(static_cast<std::uint32_t>(d.segments.size()));
      d.segments.push_back({edges[i].oriented, r});
    });
  }

  d.group_names = group_names;
  const int stride = field_stride();
  int offset = 0;
  for (const FieldInfo& fi : fields) {
    VertexField out{fi.name, fi.components, {}};
    out.values.reserve(d.positions.size() * fi.components);
    for (std::size_t v = 0; v < nv; ++v) {
      if (vmap[v] == kInvalid) continue;
      for (int c = 0; c < fi.components; ++c) out.values.push_back(field_values[v * stride + offset + c]);
    }
    d.fields.push_back(std::move(out));
    offset += fi.components;
  }
  return d;
}

double bounding_box_diagonal(const MeshModel& mesh) {
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (VertId v = 0; v < mesh.vertex_capacity(); ++v) {
    if (mesh.is_dead_vertex(v)) continue;
    lo = glm::min(lo, mesh.positions[v]);
    hi = glm::max(hi, mesh.positions[v]);
  }
  return lo.x <= hi.x ? glm::length(hi - lo) : 0.0;
}

}  // namespace topotet
