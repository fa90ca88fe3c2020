#include "piece.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <utility>

#include "scratch.h"
#include "topotet/error.h"

namespace topotet::ooc {

namespace {

constexpr std::uint64_t kMagic = 0x34656365'6970746fULL;  // "otpiece4"

void put_string(ScratchWriter& out, const std::string& s) {
  out.put<std::uint64_t>(s.size());
  out.write(s.data(), s.size());
}

std::string get_string(ScratchReader& in) {
  std::string s(in.get<std::uint64_t>(), '\0');
  in.read(s.data(), s.size());
  return s;
}

}  // namespace

void save_piece(const std::string& path, const Piece& piece) {
  const MeshData& m = piece.mesh;
  ScratchWriter out(path);
  out.put(kMagic);
  out.put_counted(piece.global_ids);
  out.put_counted(m.positions);
  out.put_counted(m.vertex_refs);
  out.put_counted(m.tets);
  out.put_counted(m.tet_material);
  out.put_counted(m.triangles);
  out.put_counted(m.segments);
  out.put_counted(m.ridges);
  out.put_counted(m.corners);
  out.put_counted(m.required_vertices);
  out.put<std::uint64_t>(m.fields.size());
  for (const VertexField& f : m.fields) {
    put_string(out, f.name);
    out.put<std::int32_t>(f.components);
    out.put_counted(f.values);
  }
  out.put<std::uint64_t>(m.cell_fields.size());
  for (const CellField& f : m.cell_fields) {
    put_string(out, f.name);
    out.put<std::int32_t>(f.components);
    out.put<std::uint8_t>(static_cast<std::uint8_t>(f.kind));
    out.put_counted(f.values);
  }
  out.put<std::uint32_t>(piece.quadric_doubles);
  out.put_counted(piece.quadrics);
  const FieldBoundSamples& f = piece.samples;
  out.put<std::int32_t>(f.components);
  out.put_counted(f.range);
  out.put_counted(f.magnitude);
  out.put_counted(f.positions);
  out.put_counted(f.values);
  out.put_counted(f.tet);
  out.put_counted(f.bounds);
  out.put_counted(piece.last_collapse);
  out.close();
}

Piece load_piece(const std::string& path) {
  Piece piece;
  MeshData& m = piece.mesh;
  ScratchReader in(path);
  if (in.get<std::uint64_t>() != kMagic) throw InputError("scratch file " + path + ": not a piece of this run");
  in.get_counted(piece.global_ids);
  in.get_counted(m.positions);
  in.get_counted(m.vertex_refs);
  in.get_counted(m.tets);
  in.get_counted(m.tet_material);
  in.get_counted(m.triangles);
  in.get_counted(m.segments);
  in.get_counted(m.ridges);
  in.get_counted(m.corners);
  in.get_counted(m.required_vertices);
  m.fields.resize(in.get<std::uint64_t>());
  for (VertexField& f : m.fields) {
    f.name = get_string(in);
    f.components = in.get<std::int32_t>();
    in.get_counted(f.values);
  }
  m.cell_fields.resize(in.get<std::uint64_t>());
  for (CellField& f : m.cell_fields) {
    f.name = get_string(in);
    f.components = in.get<std::int32_t>();
    f.kind = static_cast<CellFieldKind>(in.get<std::uint8_t>());
    in.get_counted(f.values);
  }
  piece.quadric_doubles = in.get<std::uint32_t>();
  in.get_counted(piece.quadrics);
  FieldBoundSamples& f = piece.samples;
  f.components = in.get<std::int32_t>();
  in.get_counted(f.range);
  in.get_counted(f.magnitude);
  in.get_counted(f.positions);
  in.get_counted(f.values);
  in.get_counted(f.tet);
  in.get_counted(f.bounds);
  in.get_counted(piece.last_collapse);
  return piece;
}

namespace {

// Sorted-vertex keys, so that the same triangle (edge) listed by both pieces is found whatever
// its orientation; the ref is part of the key (two listings with different refs are two entries).
std::array<GlobalId, 4> triangle_key(const Triangle& t, const std::vector<GlobalId>& ids) {
  std::array<GlobalId, 3> v = {ids[t.v[0]], ids[t.v[1]], ids[t.v[2]]};
  std::sort(v.begin(), v.end());
  return {v[0], v[1], v[2], static_cast<GlobalId>(t.ref)};
}

std::array<GlobalId, 3> segment_key(const Segment& s, const std::vector<GlobalId>& ids) {
  return {std::min(ids[s.v[0]], ids[s.v[1]]), std::max(ids[s.v[0]], ids[s.v[1]]), static_cast<GlobalId>(s.ref)};
}

// mine += theirs, one array at a time, each freed as soon as it is copied: the samples are the
// largest arrays of a late merge (every input vertex at the last), and growing `mine` in place
// would hold its old and new buffers and `theirs` at once (memory_budget.h counts this way).
template <class T>
void append_releasing(std::vector<T>& mine, std::vector<T>& theirs) {
  std::vector<T> joined;
  joined.reserve(mine.size() + theirs.size());
  joined.insert(joined.end(), mine.begin(), mine.end());
  std::vector<T>().swap(mine);
  joined.insert(joined.end(), theirs.begin(), theirs.end());
  std::vector<T>().swap(theirs);
  mine = std::move(joined);
}

}  // namespace

Piece merge_pieces(Piece a, Piece b) {
  MeshData& m = a.mesh;
  const MeshData& n = b.mesh;
  if (m.fields.size() != n.fields.size() || m.cell_fields.size() != n.cell_fields.size())
    throw std::logic_error("merge_pieces: the pieces' field layouts differ");
  const std::size_t qs = a.quadric_doubles;
  const bool quadrics = !a.quadrics.empty() && !b.quadrics.empty() && qs == b.quadric_doubles;
  if (!quadrics) {  // one piece was never run (nothing to remove): the merged piece builds its own
    a.quadrics.clear();
    a.quadric_doubles = 0;
  }
  // b's vertex -> merged vertex: a's own when a has it (binary search in a's sorted ids).
  std::vector<std::pair<GlobalId, VertId>> a_ids(a.global_ids.size());
  for (VertId v = 0; v < a.global_ids.size(); ++v) a_ids[v] = {a.global_ids[v], v};
  std::sort(a_ids.begin(), a_ids.end());
  const std::size_t a_vertices = m.positions.size();
  std::vector<VertId> map(n.positions.size());
  std::vector<VertId> added;  // b's vertices that a lacks, in b's order
  for (VertId v = 0; v < n.positions.size(); ++v) {
    const auto it = std::lower_bound(a_ids.begin(), a_ids.end(), std::pair<GlobalId, VertId>{b.global_ids[v], 0});
    if (it != a_ids.end() && it->first == b.global_ids[v]) {
      map[v] = it->second;
      if (quadrics)
        for (std::size_t k = 0; k < qs; ++k) a.quadrics[it->second * qs + k] += b.quadrics[v * qs + k];
    } else {
      map[v] = static_cast<VertId>(a_vertices + added.size());
      added.push_back(v);
    }
  }
  a_ids = {};
  const bool refs = !m.vertex_refs.empty() || !n.vertex_refs.empty();
  if (refs) m.vertex_refs.resize(a_vertices, 0);
  for (VertId v : added) {
    m.positions.push_back(n.positions[v]);
    a.global_ids.push_back(b.global_ids[v]);
    if (refs) m.vertex_refs.push_back(n.vertex_refs.empty() ? 0 : n.vertex_refs[v]);
    if (quadrics) a.quadrics.insert(a.quadrics.end(), b.quadrics.begin() + v * qs, b.quadrics.begin() + (v + 1) * qs);
  }
  for (std::size_t f = 0; f < m.fields.size(); ++f) {
    const int c = m.fields[f].components;
    for (VertId v : added)
      for (int k = 0; k < c; ++k) m.fields[f].values.push_back(n.fields[f].values[std::size_t{v} * c + k]);
  }
  // b's samples follow b's tets, which follow a's.
  if (a.samples.components != b.samples.components)
    throw std::logic_error("merge_pieces: one piece has field samples, the other not");
  if (a.samples.components != 0) {
    const auto a_tets = static_cast<std::uint32_t>(m.tets.size());
    for (std::uint32_t& t : b.samples.tet) t += a_tets;
    append_releasing(a.samples.positions, b.samples.positions);
    append_releasing(a.samples.values, b.samples.values);
    append_releasing(a.samples.tet, b.samples.tet);
    append_releasing(a.samples.bounds, b.samples.bounds);
  }
  // b's tets follow a's, and so do their last collapses.
  if (a.last_collapse.size() != m.tets.size() || b.last_collapse.size() != n.tets.size()) {
    if (!a.last_collapse.empty() || !b.last_collapse.empty())
      throw std::logic_error("merge_pieces: one piece has its tets' last collapses, the other not");
  } else {
    append_releasing(a.last_collapse, b.last_collapse);
  }
  for (const auto& t : n.tets) m.tets.push_back({map[t[0]], map[t[1]], map[t[2]], map[t[3]]});
  m.tet_material.insert(m.tet_material.end(), n.tet_material.begin(), n.tet_material.end());
  for (std::size_t f = 0; f < m.cell_fields.size(); ++f)
    m.cell_fields[f].values.insert(m.cell_fields[f].values.end(), n.cell_fields[f].values.begin(),
                                   n.cell_fields[f].values.end());

  // Listed triangles and edges on the common border are in both pieces: once.
  {
    std::vector<std::array<GlobalId, 4>> keys;
    keys.reserve(m.triangles.size());
    for (const Triangle& t : m.triangles) keys.push_back(triangle_key(t, a.global_ids));
    std::sort(keys.begin(), keys.end());
    for (const Triangle& t : n.triangles)
      if (!std::binary_search(keys.begin(), keys.end(), triangle_key(t, b.global_ids)))
        m.triangles.push_back({{map[t.v[0]], map[t.v[1]], map[t.v[2]]}, t.ref});
  }
  {
    std::vector<std::pair<std::array<GlobalId, 3>, std::uint32_t>> keys;  // key, a's segment
    for (std::uint32_t s = 0; s < m.segments.size(); ++s) keys.push_back({segment_key(m.segments[s], a.global_ids), s});
    std::sort(keys.begin(), keys.end());
    std::vector<std::uint32_t> segment_map(n.segments.size());  // b's edge -> merged edge (ridges)
    for (std::uint32_t s = 0; s < n.segments.size(); ++s) {
      const auto key = segment_key(n.segments[s], b.global_ids);
      const auto it = std::lower_bound(keys.begin(), keys.end(), std::pair<std::array<GlobalId, 3>, std::uint32_t>{key, 0});
      if (it != keys.end() && it->first == key) {
        segment_map[s] = it->second;
      } else {
        segment_map[s] = static_cast<std::uint32_t>(m.segments.size());
        m.segments.push_back({{map[n.segments[s].v[0]], map[n.segments[s].v[1]]}, n.segments[s].ref});
      }
    }
    std::vector<std::uint32_t> ridges = m.ridges;
    for (std::uint32_t r : n.ridges) ridges.push_back(segment_map[r]);
    std::sort(ridges.begin(), ridges.end());
    ridges.erase(std::unique(ridges.begin(), ridges.end()), ridges.end());
    m.ridges = std::move(ridges);
  }
  const auto unite = [&](std::vector<VertId>& mine, const std::vector<VertId>& theirs) {
    for (VertId v : theirs) mine.push_back(map[v]);
    std::sort(mine.begin(), mine.end());
    mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
  };
  unite(m.corners, n.corners);
  unite(m.required_vertices, n.required_vertices);
  return a;
}

}  // namespace topotet::ooc

namespace topotet::ooc {

VertexTets::VertexTets(const MeshData& mesh) : first(mesh.positions.size() + 1, 0), incident(mesh.tets.size() * 4) {
  for (const auto& t : mesh.tets)
    for (VertId v : t) ++first[v + 1];
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) first[v + 1] += first[v];
  std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
  for (std::uint32_t t = 0; t < mesh.tets.size(); ++t)
    for (VertId v : mesh.tets[t]) incident[fill[v]++] = t;
}

namespace {
bool in_tet(const std::array<VertId, 4>& tv, VertId v) { return tv[0] == v || tv[1] == v || tv[2] == v || tv[3] == v; }
}  // namespace

std::uint64_t interior_vertices(const Piece& piece, const std::vector<std::uint8_t>& holders) {
  std::uint64_t n = 0;
  for (GlobalId g : piece.global_ids) n += holders[g] == 1;
  return n;
}

bool VertexTets::has_face(const MeshData& mesh, VertId a, VertId b, VertId c) const {
  for (std::uint32_t k = first[a]; k < first[a + 1]; ++k)
    if (in_tet(mesh.tets[incident[k]], b) && in_tet(mesh.tets[incident[k]], c)) return true;
  return false;
}

bool VertexTets::has_edge(const MeshData& mesh, VertId a, VertId b) const {
  for (std::uint32_t k = first[a]; k < first[a + 1]; ++k)
    if (in_tet(mesh.tets[incident[k]], b)) return true;
  return false;
}

Piece sub_piece(const Piece& piece, const std::vector<std::uint32_t>& tets) {
  const MeshData& m = piece.mesh;
  Piece out;
  MeshData& s = out.mesh;
  // Vertices in the piece's order (their relative order, and so the runs, do not depend on how
  // the tets were chosen).
  std::vector<VertId> local(m.positions.size(), kInvalid);
  for (std::uint32_t t : tets)
    for (VertId v : m.tets[t]) local[v] = 0;
  std::vector<VertId> kept;
  for (VertId v = 0; v < local.size(); ++v)
    if (local[v] == 0) {
      local[v] = static_cast<VertId>(kept.size());
      kept.push_back(v);
    }
  const std::size_t qs = piece.quadrics.empty() ? 0 : piece.quadric_doubles;
  out.quadric_doubles = qs != 0 ? piece.quadric_doubles : 0;
  for (VertId v : kept) {
    s.positions.push_back(m.positions[v]);
    if (!m.vertex_refs.empty()) s.vertex_refs.push_back(m.vertex_refs[v]);
    out.global_ids.push_back(piece.global_ids[v]);
    out.quadrics.insert(out.quadrics.end(), piece.quadrics.begin() + v * qs, piece.quadrics.begin() + (v + 1) * qs);
  }
  for (const VertexField& f : m.fields) {
    VertexField g = f;
    g.values.clear();
    for (VertId v : kept)
      g.values.insert(g.values.end(), f.values.begin() + std::size_t{v} * f.components,
                      f.values.begin() + (std::size_t{v} + 1) * f.components);
    s.fields.push_back(std::move(g));
  }
  std::vector<std::uint32_t> new_tet(m.tets.size(), kInvalid);
  for (std::uint32_t t : tets) {
    new_tet[t] = static_cast<std::uint32_t>(s.tets.size());
    const auto& tv = m.tets[t];
    s.tets.push_back({local[tv[0]], local[tv[1]], local[tv[2]], local[tv[3]]});
    s.tet_material.push_back(m.tet_material[t]);
    if (!piece.last_collapse.empty()) out.last_collapse.push_back(piece.last_collapse[t]);
  }
  for (const CellField& f : m.cell_fields) {
    CellField g = f;
    g.values.clear();
    for (std::uint32_t t : tets)
      g.values.insert(g.values.end(), f.values.begin() + std::size_t{t} * f.components,
                      f.values.begin() + (std::size_t{t} + 1) * f.components);
    s.cell_fields.push_back(std::move(g));
  }
  // A sample stays with its tet; the tets' bounds follow them.
  const FieldBoundSamples& in = piece.samples;
  FieldBoundSamples& samples = out.samples;
  samples.components = in.components;
  samples.range = in.range;
  samples.magnitude = in.magnitude;
  const auto k = static_cast<std::size_t>(in.components);
  if (k != 0) {
    for (std::size_t i = 0; i < in.tet.size(); ++i) {
      if (new_tet[in.tet[i]] == kInvalid) continue;
      samples.positions.insert(samples.positions.end(), in.positions.begin() + 3 * i, in.positions.begin() + 3 * i + 3);
      samples.values.insert(samples.values.end(), in.values.begin() + k * i, in.values.begin() + k * (i + 1));
      samples.tet.push_back(new_tet[in.tet[i]]);
    }
    if (!in.bounds.empty())  // (none before the piece's first run)
      for (std::uint32_t t : tets)
        samples.bounds.insert(samples.bounds.end(), in.bounds.begin() + k * t, in.bounds.begin() + k * (t + 1));
  }
  // Listed triangles and edges that are faces (edges) of the kept tets, as the cut takes them.
  const VertexTets at(s);
  for (const Triangle& tri : m.triangles) {
    const VertId a = local[tri.v[0]], b = local[tri.v[1]], c = local[tri.v[2]];
    if (a != kInvalid && b != kInvalid && c != kInvalid && at.has_face(s, a, b, c)) s.triangles.push_back({{a, b, c}, tri.ref});
  }
  std::vector<std::uint32_t> segment_local(m.segments.size(), kInvalid);
  for (std::size_t i = 0; i < m.segments.size(); ++i) {
    const VertId a = local[m.segments[i].v[0]], b = local[m.segments[i].v[1]];
    if (a == kInvalid || b == kInvalid || !at.has_edge(s, a, b)) continue;
    segment_local[i] = static_cast<std::uint32_t>(s.segments.size());
    s.segments.push_back({{a, b}, m.segments[i].ref});
  }
  for (std::uint32_t r : m.ridges)
    if (segment_local[r] != kInvalid) s.ridges.push_back(segment_local[r]);
  std::sort(s.ridges.begin(), s.ridges.end());
  for (VertId v : m.corners)
    if (local[v] != kInvalid) s.corners.push_back(local[v]);
  for (VertId v : m.required_vertices)
    if (local[v] != kInvalid) s.required_vertices.push_back(local[v]);
  return out;
}

std::vector<std::uint32_t> band_tets(const Piece& piece, const std::vector<GlobalId>& seeds, std::uint64_t max_tets,
                                     int max_rings) {
  const MeshData& m = piece.mesh;
  const VertexTets at(m);
  std::vector<bool> taken_vertex(m.positions.size(), false), taken_tet(m.tets.size(), false);
  std::vector<VertId> ring;
  for (VertId v = 0; v < piece.global_ids.size(); ++v)
    if (std::binary_search(seeds.begin(), seeds.end(), piece.global_ids[v])) {
      ring.push_back(v);
      taken_vertex[v] = true;
    }
  std::uint64_t count = 0;
  // Ring after ring: the tets at the ring's vertices; a ring that would pass max_tets is not taken
  // (the first is taken whole all the same: without it the seeds would stay on the band's border).
  for (int rings = 0; !ring.empty() && rings < max_rings; ++rings) {
    const bool first_ring = rings == 0;
    std::vector<std::uint32_t> added;
    for (VertId v : ring)
      for (std::uint32_t i = at.first[v]; i < at.first[v + 1]; ++i)
        if (!taken_tet[at.incident[i]]) {
          taken_tet[at.incident[i]] = true;
          added.push_back(at.incident[i]);
        }
    if (!first_ring && count + added.size() > max_tets) {
      for (std::uint32_t t : added) taken_tet[t] = false;
      break;
    }
    count += added.size();
    std::vector<VertId> next;
    for (std::uint32_t t : added)
      for (VertId v : m.tets[t])
        if (!taken_vertex[v]) {
          taken_vertex[v] = true;
          next.push_back(v);
        }
    ring = std::move(next);
  }
  std::vector<std::uint32_t> tets;
  tets.reserve(count);
  for (std::uint32_t t = 0; t < m.tets.size(); ++t)
    if (taken_tet[t]) tets.push_back(t);
  return tets;
}

}  // namespace topotet::ooc
