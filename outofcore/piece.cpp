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
