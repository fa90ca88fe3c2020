// Simplex enumeration by radix sort of packed keys, and closure extraction. See simplex_index.h.
#include "simplex_index.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <glm/vec3.hpp>

#include "parallel/for_range.h"
#include "parallel/reduce.h"
#include "radix_sort.h"

namespace topotet::metrics::detail {
namespace {

// Local vertex pairs of the 6 edges of a tet with sorted vertices, and the edges of face i (the
// face opposite local vertex i) as indices into that list.
constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
constexpr int kTetFaceEdges[4][3] = {{3, 4, 5}, {1, 2, 5}, {0, 2, 4}, {0, 1, 3}};
// Edges of a triangle with sorted vertices.
constexpr int kTriangleEdges[3][2] = {{0, 1}, {0, 2}, {1, 2}};

// Sorted copies of the elements (in internal vertex ids), and whether each is valid (indices in
// range and distinct). Out-of-range ids are left as they are, so they stay invalid.
template <std::size_t N>
void sort_elements(const std::array<VertId, N>* elements, std::size_t count, const SimplexIndex& index,
                   std::vector<std::array<VertId, N>>& sorted, std::vector<std::uint8_t>& is_valid,
                   std::uint64_t& invalid_count) {
  const std::uint32_t n = index.vertex_count;
  sorted.resize(count);
  is_valid.resize(count);
  invalid_count += parallel::block_reduce(
      count, 16384, "sort_elements", std::uint64_t{0},
      [&](std::size_t begin, std::size_t end) {
        std::uint64_t invalid = 0;
        for (std::size_t i = begin; i < end; ++i) {
          auto s = elements[i];
          for (VertId& v : s) v = v < n ? index.vertex_of(v) : v;
          std::sort(s.begin(), s.end());
          bool ok = s[N - 1] < n;
          for (std::size_t k = 1; k < N; ++k) ok = ok && s[k - 1] < s[k];
          sorted[i] = s;
          is_valid[i] = ok;
          invalid += !ok;
        }
        return invalid;
      },
      [](std::uint64_t& total, std::uint64_t part) { total += part; });
}

// Below this many vertices everything fits in cache anyway, and the thousands of small checks of
// the property tests should not pay for a renumbering. Above it the renumbering pays already at
// 12k vertices (63k tets: the checker is 25% faster, the manifold certificates' random accesses
// to neighbouring tets stay in cache).
constexpr std::size_t kSpatialOrderVertexThreshold = 1u << 12;

// 21 bits of x spread to every third bit.
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// mesh vertex -> rank along the Morton curve of the bounding box (non-finite points go first).
std::vector<VertId> spatial_vertex_order(const std::vector<std::array<double, 3>>& positions) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const auto& p : positions)
    for (int k = 0; k < 3; ++k)
      if (std::isfinite(p[k])) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
  std::vector<KeyedSlot<std::uint64_t>> items(positions.size());
  parallel::for_range<std::size_t>(0, positions.size(), 16384, "morton_codes", [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      std::uint64_t code = 0;
      for (int k = 0; k < 3; ++k) {
        const double extent = hi[k] - lo[k];
        const double t = extent > 0 && std::isfinite(positions[v][k]) ? (positions[v][k] - lo[k]) / extent : 0.0;
        code |= spread_bits(static_cast<std::uint64_t>(t * 2097151.0)) << k;
      }
      items[v] = {code, static_cast<std::uint32_t>(v)};
    }
  });
  radix_sort(items, 63);
  std::vector<VertId> mesh2vertex(positions.size());
  for (std::size_t i = 0; i < items.size(); ++i) mesh2vertex[items[i].slot] = static_cast<VertId>(i);
  return mesh2vertex;
}

struct SortedElements {
  std::vector<std::array<VertId, 4>> tets;
  std::vector<std::uint8_t> tet_is_valid;
  std::vector<std::array<VertId, 3>> triangles;
  std::vector<std::uint8_t> triangle_is_valid;
  std::vector<std::array<VertId, 2>> segments;
  std::vector<std::uint8_t> segment_is_valid;
};

// Edge slots: 6t + j for edge j of tet t, 6T + 3i + j for edge j of triangle i, 6T + 3N + s for
// segment s. Returns slot -> edge id (kInvalid for slots of invalid elements).
std::vector<std::uint32_t> enumerate_edges(const SortedElements& el, std::uint64_t n, SimplexIndex& index) {
  const std::size_t tet_count = el.tets.size(), triangle_count = el.triangles.size();
  std::vector<KeyedSlot<std::uint64_t>> items;
  items.reserve(6 * tet_count + 3 * triangle_count + el.segments.size());
  auto key = [n](VertId a, VertId b) { return std::uint64_t{a} * n + b; };
  for (std::size_t t = 0; t < tet_count; ++t) {
    if (!el.tet_is_valid[t]) continue;
    const auto& s = el.tets[t];
    for (int j = 0; j < 6; ++j)
      items.push_back({key(s[kTetEdges[j][0]], s[kTetEdges[j][1]]), static_cast<std::uint32_t>(6 * t + j)});
  }
  const std::size_t triangle_base = 6 * tet_count;
  for (std::size_t i = 0; i < triangle_count; ++i) {
    if (!el.triangle_is_valid[i]) continue;
    const auto& s = el.triangles[i];
    for (int j = 0; j < 3; ++j)
      items.push_back({key(s[kTriangleEdges[j][0]], s[kTriangleEdges[j][1]]),
                       static_cast<std::uint32_t>(triangle_base + 3 * i + j)});
  }
  const std::size_t segment_base = triangle_base + 3 * triangle_count;
  for (std::size_t i = 0; i < el.segments.size(); ++i) {
    if (!el.segment_is_valid[i]) continue;
    items.push_back({key(el.segments[i][0], el.segments[i][1]), static_cast<std::uint32_t>(segment_base + i)});
  }
  bucket_sort(items, n, [n](std::uint64_t k) { return static_cast<std::size_t>(k / n); });

  std::vector<std::uint32_t> slot2edge(segment_base + el.segments.size(), kInvalid);
  index.edge2verts.clear();
  for (std::size_t begin = 0, end = 0; begin < items.size(); begin = end) {
    const std::uint64_t run_key = items[begin].key;
    const auto edge = static_cast<std::uint32_t>(index.edge2verts.size());
    index.edge2verts.push_back({static_cast<VertId>(run_key / n), static_cast<VertId>(run_key % n)});
    bool on_tet = false;
    std::uint64_t segment_count = 0;
    for (end = begin; end < items.size() && items[end].key == run_key; ++end) {
      slot2edge[items[end].slot] = edge;
      on_tet = on_tet || items[end].slot < triangle_base;
      segment_count += items[end].slot >= segment_base;
    }
    if (!on_tet) index.detached_segment_count += segment_count;
  }
  index.segment2edge.assign(slot2edge.begin() + static_cast<std::ptrdiff_t>(segment_base), slot2edge.end());
  return slot2edge;
}

// Face slots: 4t + i for face i of tet t (opposite its sorted vertex i), 4T + i for triangle i.
// Besides numbering faces, each run of equal keys tells which kept tets share the face: that is
// where duplicate tets, boundary faces, interfaces and non-manifold faces are found.
template <class Key>
void enumerate_faces(const MeshData& mesh, const SortedElements& el, std::uint64_t n,
                     const std::vector<std::uint32_t>& slot2edge, SimplexIndex& index) {
  const std::size_t tet_count = el.tets.size(), triangle_count = el.triangles.size();
  auto key = [n](VertId a, VertId b, VertId c) { return (Key{a} * n + b) * n + c; };
  std::vector<KeyedSlot<Key>> items;
  items.reserve(4 * tet_count + triangle_count);
  for (std::size_t t = 0; t < tet_count; ++t) {
    if (!el.tet_is_valid[t]) continue;
    const auto& s = el.tets[t];
    items.push_back({key(s[1], s[2], s[3]), static_cast<std::uint32_t>(4 * t + 0)});
    items.push_back({key(s[0], s[2], s[3]), static_cast<std::uint32_t>(4 * t + 1)});
    items.push_back({key(s[0], s[1], s[3]), static_cast<std::uint32_t>(4 * t + 2)});
    items.push_back({key(s[0], s[1], s[2]), static_cast<std::uint32_t>(4 * t + 3)});
  }
  const std::size_t triangle_base = 4 * tet_count;
  for (std::size_t i = 0; i < triangle_count; ++i) {
    if (!el.triangle_is_valid[i]) continue;
    const auto& s = el.triangles[i];
    items.push_back({key(s[0], s[1], s[2]), static_cast<std::uint32_t>(triangle_base + i)});
  }
  bucket_sort(items, n, [n2 = Key{n} * n](Key k) { return static_cast<std::size_t>(k / n2); });

  index.tet2faces.assign(tet_count, {kInvalid, kInvalid, kInvalid, kInvalid});
  index.triangle2face.assign(triangle_count, kInvalid);
  index.face2edges.clear();
  std::vector<std::uint8_t> is_duplicate(tet_count, 0);
  struct RunTet {
    TetId tet;
    VertId opposite;
  };
  std::vector<RunTet> run_tets;
  for (std::size_t begin = 0, end = 0; begin < items.size(); begin = end) {
    end = begin + 1;
    while (end < items.size() && items[end].key == items[begin].key) ++end;
    const auto face = static_cast<std::uint32_t>(index.face2edges.size());
    const std::uint32_t first = items[begin].slot;
    if (first < triangle_base) {
      const std::size_t t = first / 4, i = first % 4;
      index.face2edges.push_back({slot2edge[6 * t + kTetFaceEdges[i][0]], slot2edge[6 * t + kTetFaceEdges[i][1]],
                                  slot2edge[6 * t + kTetFaceEdges[i][2]]});
    } else {
      const std::size_t e = 6 * tet_count + 3 * (first - triangle_base);
      index.face2edges.push_back({slot2edge[e], slot2edge[e + 1], slot2edge[e + 2]});
    }
    run_tets.clear();
    std::uint64_t triangle_count_in_run = 0;
    for (std::size_t k = begin; k < end; ++k) {
      const std::uint32_t slot = items[k].slot;
      if (slot >= triangle_base) {
        index.triangle2face[slot - triangle_base] = face;
        ++triangle_count_in_run;
        continue;
      }
      const TetId t = slot / 4;
      const int i = static_cast<int>(slot % 4);
      index.tet2faces[t][i] = face;
      // Two tets sharing this face are the same tet iff their opposite vertices agree. The run is
      // in increasing internal tet order, and copies of a tet are in mesh order (see
      // build_simplex_index), so the lowest-numbered copy is the one kept, in every face run.
      const VertId opposite = el.tets[t][i];
      const bool seen = std::any_of(run_tets.begin(), run_tets.end(),
                                    [&](const RunTet& r) { return r.opposite == opposite; });
      if (seen) {
        is_duplicate[t] = 1;
      } else {
        run_tets.push_back({t, opposite});
      }
    }
    if (run_tets.empty()) {
      index.detached_triangle_count += triangle_count_in_run;
    } else if (run_tets.size() == 1) {
      index.boundary_faces.push_back(face);
    } else if (run_tets.size() == 2) {
      const std::int32_t a = material_of(mesh, index.mesh_tet(run_tets[0].tet));
      const std::int32_t b = material_of(mesh, index.mesh_tet(run_tets[1].tet));
      if (a != b) index.interface_faces.push_back({face, std::min(a, b), std::max(a, b)});
    } else if (run_tets.size() > 2) {
      ++index.nonmanifold_face_count;
    }
  }
  for (std::size_t t = 0; t < tet_count; ++t) {
    if (!el.tet_is_valid[t]) continue;
    if (is_duplicate[t]) {
      ++index.duplicate_tet_count;
    } else {
      index.kept_tets.push_back(static_cast<TetId>(t));
    }
  }
}

}  // namespace

SimplexIndex build_simplex_index(const MeshData& mesh) {
  SimplexIndex index;
  const std::uint64_t n = mesh.positions.size();
  const std::uint64_t slot_count = 6 * std::uint64_t{mesh.tets.size()} + 3 * std::uint64_t{mesh.triangles.size()} +
                                   mesh.segments.size();
  if (n >= kInvalid || slot_count >= kInvalid)
    throw std::length_error("compute_topology: mesh too large for 32-bit simplex ids");
  index.vertex_count = static_cast<std::uint32_t>(n);

  const bool is_spatially_ordered = n >= kSpatialOrderVertexThreshold;
  if (is_spatially_ordered) index.mesh2vertex = spatial_vertex_order(mesh.positions);

  SortedElements el;
  sort_elements(mesh.tets.data(), mesh.tets.size(), index, el.tets, el.tet_is_valid, index.invalid_tet_count);
  if (is_spatially_ordered) {
    // Internal tet order: by smallest vertex. Stable, so copies of a tet (which share that
    // vertex) keep their mesh order and the lowest mesh id stays the one kept.
    std::vector<KeyedSlot<std::uint64_t>> items(el.tets.size());
    for (std::size_t t = 0; t < items.size(); ++t)
      items[t] = {el.tet_is_valid[t] ? el.tets[t][0] : n, static_cast<std::uint32_t>(t)};
    radix_sort(items, bit_width_of(n));
    index.tet2mesh.resize(items.size());
    SortedElements reordered;
    reordered.tets.resize(items.size());
    reordered.tet_is_valid.resize(items.size());
    for (std::size_t t = 0; t < items.size(); ++t) {
      index.tet2mesh[t] = items[t].slot;
      reordered.tets[t] = el.tets[items[t].slot];
      reordered.tet_is_valid[t] = el.tet_is_valid[items[t].slot];
    }
    el.tets.swap(reordered.tets);
    el.tet_is_valid.swap(reordered.tet_is_valid);
  }
  std::vector<std::array<VertId, 3>> triangles(mesh.triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) triangles[i] = mesh.triangles[i].v;
  sort_elements(triangles.data(), triangles.size(), index, el.triangles, el.triangle_is_valid,
                index.invalid_triangle_count);
  std::vector<std::array<VertId, 2>> segments(mesh.segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) segments[i] = mesh.segments[i].v;
  sort_elements(segments.data(), segments.size(), index, el.segments, el.segment_is_valid,
                index.invalid_segment_count);

  std::vector<std::uint8_t> is_referenced(n, 0);
  for (std::size_t t = 0; t < el.tets.size(); ++t)
    if (el.tet_is_valid[t])
      for (VertId v : el.tets[t]) is_referenced[v] = 1;
  index.unreferenced_vertex_count =
      static_cast<std::uint64_t>(std::count(is_referenced.begin(), is_referenced.end(), std::uint8_t{0}));

  const std::vector<std::uint32_t> slot2edge = enumerate_edges(el, n, index);
  // n^3 < 2^64 keeps face keys in one machine word (n up to 2,642,245 vertices).
  if (U128{n} * n * n <= ~std::uint64_t{0}) {
    enumerate_faces<std::uint64_t>(mesh, el, n, slot2edge, index);
  } else {
    enumerate_faces<U128>(mesh, el, n, slot2edge, index);
  }
  return index;
}

void extract_closure(const SimplexIndex& index, const TopSimplices& tops, ClosureScratch& scratch,
                     LocalComplex& out) {
  out.clear();
  if (scratch.vertex_slots.size() != index.vertex_count || scratch.edge_slots.size() != index.edge2verts.size() ||
      scratch.face_slots.size() != index.face2edges.size() || ++scratch.stamp == 0) {
    // A new index (or a wrapped stamp): start with clean maps.
    scratch.vertex_slots.assign(index.vertex_count, {});
    scratch.edge_slots.assign(index.edge2verts.size(), {});
    scratch.face_slots.assign(index.face2edges.size(), {});
    scratch.stamp = 1;
  }
  const std::uint32_t stamp = scratch.stamp;
  auto& face_globals = scratch.face_globals;
  auto& edge_globals = scratch.edge_globals;
  face_globals.clear();
  edge_globals.clear();
  auto local_face = [&](std::uint32_t f) {
    auto& slot = scratch.face_slots[f];
    if (slot.stamp != stamp) {
      slot = {stamp, static_cast<std::uint32_t>(face_globals.size())};
      face_globals.push_back(f);
    }
    return slot.local;
  };
  auto local_edge = [&](std::uint32_t e) {
    auto& slot = scratch.edge_slots[e];
    if (slot.stamp != stamp) {
      slot = {stamp, static_cast<std::uint32_t>(edge_globals.size())};
      edge_globals.push_back(e);
    }
    return slot.local;
  };
  auto local_vertex = [&](VertId v) {
    auto& slot = scratch.vertex_slots[v];
    if (slot.stamp != stamp) slot = {stamp, out.vertex_count++};
    return slot.local;
  };

  out.tets.reserve(tops.tets.size());
  for (TetId t : tops.tets) {
    const auto& f = index.tet2faces[t];
    out.tets.push_back({local_face(f[0]), local_face(f[1]), local_face(f[2]), local_face(f[3])});
  }
  for (std::uint32_t f : tops.faces) local_face(f);
  out.faces.resize(face_globals.size());
  for (std::size_t lf = 0; lf < face_globals.size(); ++lf) {
    const auto& e = index.face2edges[face_globals[lf]];
    out.faces[lf] = {local_edge(e[0]), local_edge(e[1]), local_edge(e[2])};
  }
  for (std::uint32_t e : tops.edges) local_edge(e);
  out.edges.resize(edge_globals.size());
  for (std::size_t le = 0; le < edge_globals.size(); ++le) {
    const auto& v = index.edge2verts[edge_globals[le]];
    out.edges[le] = {local_vertex(v[0]), local_vertex(v[1])};
  }
  for (VertId v : tops.vertices) local_vertex(v);
}

}  // namespace topotet::metrics::detail
