// Whole meshes in and out of the distributed form: from_whole, distribute (METIS) and gather.
#include <algorithm>
#include <array>
#include <numeric>
#include <unordered_map>

#include "directory.h"
#include "exchange.h"
#include "migrate.h"
#include "partition.h"
#include "topotet/mpi.h"

namespace topotet::mpi {

using detail::Packer;
using detail::Unpacker;

DistributedMesh from_whole(const MeshData& whole) {
  DistributedMesh m;
  m.local = whole;
  m.global_ids.resize(whole.vertex_count());
  std::iota(m.global_ids.begin(), m.global_ids.end(), GlobalId{0});
  m.owner.assign(whole.vertex_count(), 0);
  return m;
}

void distribute(MPI_Comm comm, DistributedMesh& mesh, std::int32_t metis_seed) {
  detail::check_part(comm, mesh);
  detail::agree_layout(comm, mesh);
  std::vector<std::uint8_t> pending;
  const std::vector<int> dest = detail::partition(comm, mesh, pending, metis_seed, nullptr);
  detail::migrate(comm, mesh, pending, dest, nullptr);
  detail::agree_layout(comm, mesh);
  mesh.owner = detail::find_sharing(comm, mesh.global_ids, nullptr).owner;
}

void distribute_to(MPI_Comm comm, DistributedMesh& mesh, const std::vector<int>& dest) {
  detail::check_part(comm, mesh);
  const int ranks = detail::size_of(comm);
  const bool ok = dest.size() == mesh.local.tet_count() &&
                  std::all_of(dest.begin(), dest.end(), [&](int r) { return r >= 0 && r < ranks; });
  detail::agree_or_throw(comm, ok, "distribute_to: one destination rank in [0, ranks) per local tet");
  detail::agree_layout(comm, mesh);
  std::vector<std::uint8_t> pending(mesh.local.vertex_count(), 0);
  detail::migrate(comm, mesh, pending, dest, nullptr);
  detail::agree_layout(comm, mesh);
  mesh.owner = detail::find_sharing(comm, mesh.global_ids, nullptr).owner;
}

MeshData gather(MPI_Comm comm, const DistributedMesh& mesh, int root, std::vector<GlobalId>* global_ids) {
  const int ranks = detail::size_of(comm), me = detail::rank_of(comm);
  const MeshData& d = mesh.local;
  // The owners anew: the caller's part may come straight from its own code, without them.
  const std::vector<int> owner = detail::find_sharing(comm, mesh.global_ids, nullptr).owner;
  // Each rank sends the vertices it owns, its tets, listed triangles and segments (in global ids).
  Packer p;
  std::vector<std::uint8_t> mark(d.vertex_count(), 0);
  for (VertId v : d.corners) mark[v] |= 1;
  for (VertId v : d.required_vertices) mark[v] |= 2;
  std::vector<std::uint8_t> ridge(d.segments.size(), 0);
  for (std::uint32_t s : d.ridges) ridge[s] = 1;
  const std::uint64_t owned = std::count(owner.begin(), owner.end(), me);
  p.put(owned);
  p.put<std::uint64_t>(d.tet_count());
  p.put<std::uint64_t>(d.triangles.size());
  p.put<std::uint64_t>(d.segments.size());
  for (VertId v = 0; v < d.vertex_count(); ++v) {
    if (owner[v] != me) continue;
    p.put(mesh.global_ids[v]);
    p.put(d.positions[v]);
    p.put<std::int32_t>(d.vertex_refs.empty() ? 0 : d.vertex_refs[v]);
    p.put(mark[v]);
    for (const VertexField& f : d.fields) p.put_array(f.values.data() + static_cast<std::size_t>(v) * f.components, f.components);
  }
  for (std::size_t t = 0; t < d.tet_count(); ++t) {
    for (VertId v : d.tets[t]) p.put(mesh.global_ids[v]);
    p.put(d.tet_material[t]);
  }
  for (const Triangle& t : d.triangles) {
    for (VertId v : t.v) p.put(mesh.global_ids[v]);
    p.put(t.ref);
  }
  for (std::size_t s = 0; s < d.segments.size(); ++s) {
    for (VertId v : d.segments[s].v) p.put(mesh.global_ids[v]);
    p.put(d.segments[s].ref);
    p.put(ridge[s]);
  }
  std::vector<std::vector<char>> out(ranks);
  out[root] = std::move(p.bytes());
  const auto in = detail::exchange(comm, out, nullptr);
  MeshData whole;
  if (me != root) return whole;

  struct Vertex {
    GlobalId id;
    std::array<double, 3> x;
    std::int32_t ref;
    std::uint8_t mark;
    std::vector<double> values;
  };
  int stride = 0;
  for (const VertexField& f : d.fields) stride += f.components;
  std::vector<Vertex> vertices;
  std::vector<std::pair<std::array<GlobalId, 4>, std::int32_t>> tets;
  std::vector<std::pair<std::array<GlobalId, 3>, std::int32_t>> triangles;
  std::vector<std::tuple<std::array<GlobalId, 2>, std::int32_t, std::uint8_t>> segments;
  for (int r = 0; r < ranks; ++r) {
    Unpacker u(in[r].data(), in[r].size());
    if (u.done()) continue;
    const auto nv = u.get<std::uint64_t>(), nt = u.get<std::uint64_t>();
    const auto ntri = u.get<std::uint64_t>(), nseg = u.get<std::uint64_t>();
    for (std::uint64_t i = 0; i < nv; ++i) {
      Vertex v;
      v.id = u.get<GlobalId>();
      v.x = u.get<std::array<double, 3>>();
      v.ref = u.get<std::int32_t>();
      v.mark = u.get<std::uint8_t>();
      v.values.resize(stride);
      u.get_array(v.values.data(), stride);
      vertices.push_back(std::move(v));
    }
    for (std::uint64_t i = 0; i < nt; ++i) {
      std::array<GlobalId, 4> t;
      u.get_array(t.data(), 4);
      tets.emplace_back(t, u.get<std::int32_t>());
    }
    for (std::uint64_t i = 0; i < ntri; ++i) {
      std::array<GlobalId, 3> t;
      u.get_array(t.data(), 3);
      triangles.emplace_back(t, u.get<std::int32_t>());
    }
    for (std::uint64_t i = 0; i < nseg; ++i) {
      std::array<GlobalId, 2> s;
      u.get_array(s.data(), 2);
      const auto ref = u.get<std::int32_t>();
      segments.emplace_back(s, ref, u.get<std::uint8_t>());
    }
  }
  std::sort(vertices.begin(), vertices.end(), [](const Vertex& a, const Vertex& b) { return a.id < b.id; });
  std::unordered_map<GlobalId, VertId> index;
  index.reserve(vertices.size());
  whole.fields = d.fields;
  for (VertexField& f : whole.fields) f.values.clear();
  whole.group_names = d.group_names;
  bool any_ref = false;
  for (const Vertex& v : vertices) {
    const VertId i = static_cast<VertId>(whole.positions.size());
    index.emplace(v.id, i);
    whole.positions.push_back(v.x);
    whole.vertex_refs.push_back(v.ref);
    any_ref = any_ref || v.ref != 0;
    if (v.mark & 1) whole.corners.push_back(i);
    if (v.mark & 2) whole.required_vertices.push_back(i);
    int k = 0;
    for (VertexField& f : whole.fields)
      for (int c = 0; c < f.components; ++c) f.values.push_back(v.values[k++]);
    if (global_ids != nullptr) global_ids->push_back(v.id);
  }
  if (!any_ref) whole.vertex_refs.clear();
  for (const auto& [t, material] : tets) {
    whole.tets.push_back({index.at(t[0]), index.at(t[1]), index.at(t[2]), index.at(t[3])});
    whole.tet_material.push_back(material);
  }
  // A face or edge listed on both sides of a partition border is written once.
  std::vector<std::pair<std::array<GlobalId, 3>, std::int32_t>> seen_triangles;
  for (const auto& [t, ref] : triangles) {
    auto key = t;
    std::sort(key.begin(), key.end());
    seen_triangles.emplace_back(key, ref);
  }
  std::vector<std::size_t> order(triangles.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return seen_triangles[a] < seen_triangles[b]; });
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (k > 0 && seen_triangles[order[k]] == seen_triangles[order[k - 1]]) continue;
    const auto& [t, ref] = triangles[order[k]];
    whole.triangles.push_back({{index.at(t[0]), index.at(t[1]), index.at(t[2])}, ref});
  }
  std::vector<std::pair<std::array<GlobalId, 2>, std::int32_t>> seg_keys;
  for (const auto& [s, ref, ridge_mark] : segments) seg_keys.push_back({{std::min(s[0], s[1]), std::max(s[0], s[1])}, ref});
  order.resize(segments.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return seg_keys[a] < seg_keys[b]; });
  for (std::size_t k = 0; k < order.size(); ++k) {
    const bool repeat = k > 0 && seg_keys[order[k]] == seg_keys[order[k - 1]];
    const auto& [s, ref, ridge_mark] = segments[order[k]];
    if (!repeat) whole.segments.push_back({{index.at(s[0]), index.at(s[1])}, ref});
    if (ridge_mark && (whole.ridges.empty() || whole.ridges.back() != whole.segments.size() - 1))
      whole.ridges.push_back(static_cast<std::uint32_t>(whole.segments.size() - 1));
  }
  return whole;
}

}  // namespace topotet::mpi
