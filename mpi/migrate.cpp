#include "migrate.h"

#include <algorithm>
#include <array>
#include <string>
#include <unordered_map>

#include "exchange.h"

namespace topotet::mpi::detail {

namespace {

constexpr std::uint8_t kCornerBit = 1, kRequiredBit = 2;

int field_stride(const MeshData& d) {
  int s = 0;
  for (const VertexField& f : d.fields) s += f.components;
  return s;
}

// Local vertex -> its tets, as CSR.
struct Incidence {
  std::vector<std::uint32_t> offsets, tets;
  explicit Incidence(const MeshData& d) : offsets(d.vertex_count() + 1, 0) {
    for (const auto& t : d.tets)
      for (VertId v : t) ++offsets[v + 1];
    for (std::size_t v = 0; v < d.vertex_count(); ++v) offsets[v + 1] += offsets[v];
    tets.resize(offsets.back());
    std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
    for (std::uint32_t t = 0; t < d.tets.size(); ++t)
      for (VertId v : d.tets[t]) tets[fill[v]++] = t;
  }
  // Calls f(tet) for every tet of a that also has all of `others`.
  template <class F, std::size_t N>
  void for_each_tet_with(VertId a, const std::array<VertId, N>& others, const MeshData& d, F&& f) const {
    for (std::uint32_t i = offsets[a]; i < offsets[a + 1]; ++i) {
      const auto& t = d.tets[tets[i]];
      if (std::all_of(others.begin(), others.end(), [&](VertId o) { return std::find(t.begin(), t.end(), o) != t.end(); }))
        f(tets[i]);
    }
  }
};

template <std::size_t N>
struct Key {
  std::array<GlobalId, N> v;
  std::int32_t ref;
  bool operator==(const Key& o) const { return v == o.v && ref == o.ref; }
};
template <std::size_t N>
struct KeyHash {
  std::size_t operator()(const Key<N>& k) const {
    std::uint64_t h = static_cast<std::uint32_t>(k.ref) * 0x9E3779B97F4A7C15ull;
    for (GlobalId g : k.v) h = (h ^ g) * 0xff51afd7ed558ccdull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
template <std::size_t N>
Key<N> sorted_key(std::array<GlobalId, N> v, std::int32_t ref) {
  std::sort(v.begin(), v.end());
  return {v, ref};
}

}  // namespace

void check_part(MPI_Comm comm, const DistributedMesh& mesh) {
  const MeshData& d = mesh.local;
  const std::size_t nv = d.vertex_count();
  std::string error;
  auto bad_vertex = [&](VertId v) { return v >= nv; };
  if (mesh.global_ids.size() != nv)
    error = "global_ids has " + std::to_string(mesh.global_ids.size()) + " entries for " + std::to_string(nv) + " vertices";
  else if (d.tet_material.size() != d.tet_count())
    error = "tet_material has " + std::to_string(d.tet_material.size()) + " entries for " + std::to_string(d.tet_count()) + " tets";
  else if (!d.vertex_refs.empty() && d.vertex_refs.size() != nv)
    error = "vertex_refs has the wrong size";
  for (std::size_t t = 0; error.empty() && t < d.tet_count(); ++t)
    if (std::any_of(d.tets[t].begin(), d.tets[t].end(), bad_vertex)) error = "tet " + std::to_string(t + 1) + ": vertex index out of range";
  for (std::size_t i = 0; error.empty() && i < d.triangles.size(); ++i)
    if (std::any_of(d.triangles[i].v.begin(), d.triangles[i].v.end(), bad_vertex)) error = "triangle " + std::to_string(i + 1) + ": vertex index out of range";
  for (std::size_t i = 0; error.empty() && i < d.segments.size(); ++i)
    if (std::any_of(d.segments[i].v.begin(), d.segments[i].v.end(), bad_vertex)) error = "segment " + std::to_string(i + 1) + ": vertex index out of range";
  for (std::size_t i = 0; error.empty() && i < d.ridges.size(); ++i)
    if (d.ridges[i] >= d.segments.size()) error = "ridge " + std::to_string(i + 1) + ": segment index out of range";
  for (VertId v : d.corners)
    if (error.empty() && bad_vertex(v)) error = "corner vertex index out of range";
  for (VertId v : d.required_vertices)
    if (error.empty() && bad_vertex(v)) error = "required vertex index out of range";
  for (const VertexField& f : d.fields)
    if (error.empty() && (f.components < 1 || f.values.size() != nv * static_cast<std::size_t>(f.components)))
      error = "field '" + f.name + "' has the wrong number of values";
  if (error.empty()) {
    std::vector<GlobalId> ids = mesh.global_ids;
    std::sort(ids.begin(), ids.end());
    if (std::adjacent_find(ids.begin(), ids.end()) != ids.end()) error = "a global id is repeated within the part";
  }
  agree_or_throw(comm, error.empty(), "DistributedMesh: " + error);
}

void agree_layout(MPI_Comm comm, DistributedMesh& mesh) {
  const int ranks = size_of(comm), me = rank_of(comm);
  int mine = mesh.local.tet_count() > 0 ? me : ranks, source = ranks;
  MPI_Allreduce(&mine, &source, 1, MPI_INT, MPI_MIN, comm);
  if (source == ranks) return;  // no tets anywhere
  Packer p;
  if (me == source) {
    p.put<std::uint64_t>(mesh.local.fields.size());
    for (const VertexField& f : mesh.local.fields) {
      p.put_string(f.name);
      p.put<std::int32_t>(f.components);
    }
    p.put<std::uint64_t>(mesh.local.group_names.size());
    for (const GroupName& g : mesh.local.group_names) {
      p.put<std::int32_t>(g.dim);
      p.put<std::int32_t>(g.ref);
      p.put_string(g.name);
    }
  }
  std::uint64_t size = p.bytes().size();
  MPI_Bcast(&size, 1, MPI_UINT64_T, source, comm);
  p.bytes().resize(size);
  MPI_Bcast(p.bytes().data(), static_cast<int>(size), MPI_BYTE, source, comm);
  Unpacker u(p.bytes().data(), size);
  std::vector<VertexField> fields(u.get<std::uint64_t>());
  for (VertexField& f : fields) {
    f.name = u.get_string();
    f.components = u.get<std::int32_t>();
  }
  std::vector<GroupName> names(u.get<std::uint64_t>());
  for (GroupName& g : names) {
    g.dim = u.get<std::int32_t>();
    g.ref = u.get<std::int32_t>();
    g.name = u.get_string();
  }
  bool same = true;
  if (mesh.local.tet_count() > 0) {
    same = fields.size() == mesh.local.fields.size();
    for (std::size_t i = 0; same && i < fields.size(); ++i)
      same = fields[i].name == mesh.local.fields[i].name && fields[i].components == mesh.local.fields[i].components;
  } else {
    for (VertexField& f : fields) f.values.assign(mesh.local.vertex_count() * f.components, 0.0);
    mesh.local.fields = std::move(fields);
  }
  if (mesh.local.group_names.empty()) mesh.local.group_names = std::move(names);
  agree_or_throw(comm, same, "DistributedMesh: the ranks' field layouts (names, components) differ");
}

std::uint64_t migrate(MPI_Comm comm, DistributedMesh& mesh, std::vector<std::uint8_t>& pending,
                      const std::vector<int>& dest, std::uint64_t* bytes_sent) {
  const int ranks = size_of(comm), me = rank_of(comm);
  const MeshData& d = mesh.local;
  const std::size_t nv = d.vertex_count();
  const int stride = field_stride(d);
  std::vector<std::uint8_t> marks(nv, 0);
  for (VertId v : d.corners) marks[v] |= kCornerBit;
  for (VertId v : d.required_vertices) marks[v] |= kRequiredBit;
  std::vector<std::uint8_t> is_ridge(d.segments.size(), 0);
  for (std::uint32_t s : d.ridges) is_ridge[s] = 1;

  // What goes where: tets by destination, and each listed face / edge to every destination of a
  // tet that has it.
  std::vector<std::vector<std::uint32_t>> tets_to(ranks), triangles_to(ranks), segments_to(ranks);
  std::uint64_t leaving = 0;
  for (std::uint32_t t = 0; t < d.tet_count(); ++t) {
    tets_to[dest[t]].push_back(t);
    if (dest[t] != me) ++leaving;
  }
  {
    const Incidence inc(d);
    std::vector<int> seen;
    auto add_to_dests = [&](std::vector<std::vector<std::uint32_t>>& lists, std::uint32_t item, auto&& each_tet) {
      seen.clear();
      each_tet([&](std::uint32_t t) {
        if (std::find(seen.begin(), seen.end(), dest[t]) == seen.end()) seen.push_back(dest[t]);
      });
      std::sort(seen.begin(), seen.end());
      for (int r : seen) lists[r].push_back(item);
    };
    for (std::uint32_t i = 0; i < d.triangles.size(); ++i) {
      const auto& v = d.triangles[i].v;
      add_to_dests(triangles_to, i, [&](auto&& f) { inc.for_each_tet_with(v[0], std::array<VertId, 2>{v[1], v[2]}, d, f); });
    }
    for (std::uint32_t i = 0; i < d.segments.size(); ++i) {
      const auto& v = d.segments[i].v;
      add_to_dests(segments_to, i, [&](auto&& f) { inc.for_each_tet_with(v[0], std::array<VertId, 1>{v[1]}, d, f); });
    }
  }

  std::vector<std::vector<char>> out(ranks);
  std::vector<std::uint32_t> slot(nv, kInvalid);
  std::vector<VertId> listed;
  std::vector<double> values(stride);
  for (int r = 0; r < ranks; ++r) {
    listed.clear();
    for (std::uint32_t t : tets_to[r])
      for (VertId v : d.tets[t])
        if (slot[v] == kInvalid) {
          slot[v] = static_cast<std::uint32_t>(listed.size());
          listed.push_back(v);
        }
    Packer p;
    p.put<std::uint64_t>(listed.size());
    p.put<std::uint64_t>(tets_to[r].size());
    p.put<std::uint64_t>(triangles_to[r].size());
    p.put<std::uint64_t>(segments_to[r].size());
    for (VertId v : listed) {
      p.put(mesh.global_ids[v]);
      p.put(d.positions[v]);
      p.put<std::int32_t>(d.vertex_refs.empty() ? 0 : d.vertex_refs[v]);
      p.put<std::uint8_t>(marks[v]);
      p.put<std::uint8_t>(pending.empty() ? 0 : pending[v]);
      int k = 0;
      for (const VertexField& f : d.fields)
        for (int c = 0; c < f.components; ++c) values[k++] = f.values[static_cast<std::size_t>(v) * f.components + c];
      p.put_array(values.data(), values.size());
    }
    for (std::uint32_t t : tets_to[r]) {
      for (VertId v : d.tets[t]) p.put<std::uint32_t>(slot[v]);
      p.put<std::int32_t>(d.tet_material[t]);
    }
    for (std::uint32_t i : triangles_to[r]) {
      for (VertId v : d.triangles[i].v) p.put<std::uint32_t>(slot[v]);
      p.put<std::int32_t>(d.triangles[i].ref);
    }
    for (std::uint32_t i : segments_to[r]) {
      for (VertId v : d.segments[i].v) p.put<std::uint32_t>(slot[v]);
      p.put<std::int32_t>(d.segments[i].ref);
      p.put<std::uint8_t>(is_ridge[i]);
    }
    for (VertId v : listed) slot[v] = kInvalid;
    out[r] = std::move(p.bytes());
  }

  const auto incoming = exchange(comm, out, bytes_sent);
  DistributedMesh next;
  MeshData& n = next.local;
  n.fields = d.fields;
  for (VertexField& f : n.fields) f.values.clear();
  n.group_names = d.group_names;
  std::vector<std::uint8_t> next_marks, next_pending;
  std::vector<std::int32_t> refs;
  std::unordered_map<GlobalId, VertId> local_of;
  std::unordered_map<Key<3>, std::uint32_t, KeyHash<3>> triangle_index;
  std::unordered_map<Key<2>, std::uint32_t, KeyHash<2>> segment_index;
  std::vector<std::uint8_t> next_ridge;
  std::vector<VertId> here;
  for (int r = 0; r < ranks; ++r) {
    Unpacker u(incoming[r].data(), incoming[r].size());
    if (u.done()) continue;
    const auto vertex_count = u.get<std::uint64_t>(), tet_count = u.get<std::uint64_t>();
    const auto triangle_count = u.get<std::uint64_t>(), segment_count = u.get<std::uint64_t>();
    here.assign(vertex_count, kInvalid);
    for (std::uint64_t i = 0; i < vertex_count; ++i) {
      const auto g = u.get<GlobalId>();
      const auto x = u.get<std::array<double, 3>>();
      const auto ref = u.get<std::int32_t>();
      const auto mark = u.get<std::uint8_t>();
      const auto pend = u.get<std::uint8_t>();
      u.get_array(values.data(), values.size());
      auto [it, inserted] = local_of.emplace(g, static_cast<VertId>(n.positions.size()));
      here[i] = it->second;
      if (!inserted) {
        next_pending[it->second] |= pend;
        continue;
      }
      next.global_ids.push_back(g);
      n.positions.push_back(x);
      refs.push_back(ref);
      next_marks.push_back(mark);
      next_pending.push_back(pend);
      int k = 0;
      for (VertexField& f : n.fields)
        for (int c = 0; c < f.components; ++c) f.values.push_back(values[k++]);
    }
    for (std::uint64_t i = 0; i < tet_count; ++i) {
      std::array<VertId, 4> t;
      for (VertId& v : t) v = here[u.get<std::uint32_t>()];
      n.tets.push_back(t);
      n.tet_material.push_back(u.get<std::int32_t>());
    }
    for (std::uint64_t i = 0; i < triangle_count; ++i) {
      Triangle tri;
      for (VertId& v : tri.v) v = here[u.get<std::uint32_t>()];
      tri.ref = u.get<std::int32_t>();
      const Key<3> key = sorted_key<3>({next.global_ids[tri.v[0]], next.global_ids[tri.v[1]], next.global_ids[tri.v[2]]}, tri.ref);
      if (triangle_index.emplace(key, static_cast<std::uint32_t>(n.triangles.size())).second) n.triangles.push_back(tri);
    }
    for (std::uint64_t i = 0; i < segment_count; ++i) {
      Segment seg;
      for (VertId& v : seg.v) v = here[u.get<std::uint32_t>()];
      seg.ref = u.get<std::int32_t>();
      const std::uint8_t ridge = u.get<std::uint8_t>();
      const Key<2> key = sorted_key<2>({next.global_ids[seg.v[0]], next.global_ids[seg.v[1]]}, seg.ref);
      auto [it, inserted] = segment_index.emplace(key, static_cast<std::uint32_t>(n.segments.size()));
      if (inserted) {
        n.segments.push_back(seg);
        next_ridge.push_back(ridge);
      } else {
        next_ridge[it->second] |= ridge;
      }
    }
  }
  for (VertId v = 0; v < n.vertex_count(); ++v) {
    if (next_marks[v] & kCornerBit) n.corners.push_back(v);
    if (next_marks[v] & kRequiredBit) n.required_vertices.push_back(v);
  }
  for (std::uint32_t s = 0; s < next_ridge.size(); ++s)
    if (next_ridge[s]) n.ridges.push_back(s);
  if (std::any_of(refs.begin(), refs.end(), [](std::int32_t r) { return r != 0; })) n.vertex_refs = std::move(refs);
  next.owner.assign(n.vertex_count(), me);  // provisional: find_sharing gives the real owners
  mesh = std::move(next);
  pending = std::move(next_pending);
  return leaving;
}

}  // namespace topotet::mpi::detail
