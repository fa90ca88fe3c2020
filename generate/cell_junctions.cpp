#include "generate/cell_junctions.h"

#include <algorithm>
#include <tuple>

namespace topotet::gen {
namespace {


std::uint64_t pair_key(std::int32_t lower, std::int32_t higher) {
  return (std::uint64_t{static_cast<std::uint32_t>(lower)} << 32) | static_cast<std::uint32_t>(higher);
}

std::uint64_t edge_key(VertId a, VertId b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t{a} << 32) | b;
}

TriangleCorners face_vertices(const MeshData& mesh, const InterfaceFace& f) {
  const auto& v = mesh.tets[f.tet];
  const auto& o = kOutwardFace[f.face];
  return {v[o[0]], v[o[1]], v[o[2]]};
}

// The vertices of the edges in order, when they form one simple open path; empty otherwise.
std::vector<VertId> simple_path(const std::vector<std::uint64_t>& edges) {
  std::vector<std::pair<VertId, VertId>> adjacent;  // both directions, sorted
  for (std::uint64_t e : edges) {
    const auto a = static_cast<VertId>(e >> 32), b = static_cast<VertId>(e & 0xFFFFFFFFu);
    adjacent.emplace_back(a, b);
    adjacent.emplace_back(b, a);
  }
  std::sort(adjacent.begin(), adjacent.end());
  VertId start = kInvalid;
  std::size_t vertex_count = 0;
  for (std::size_t a = 0, b = 0; a < adjacent.size(); a = b) {
    while (b < adjacent.size() && adjacent[b].first == adjacent[a].first) ++b;
    if (b - a > 2) return {};
    if (b - a == 1 && start == kInvalid) start = adjacent[a].first;
    ++vertex_count;
  }
  if (start == kInvalid) return {};  // a cycle
  // Walk from the lowest end; with degrees <= 2, reaching every vertex means one path.
  std::vector<VertId> path = {start};
  VertId previous = kInvalid;
  for (VertId current = start;;) {
    auto it = std::lower_bound(adjacent.begin(), adjacent.end(), std::pair<VertId, VertId>{current, 0});
    VertId next = kInvalid;
    for (; it != adjacent.end() && it->first == current; ++it)
      if (it->second != previous) next = it->second;
    if (next == kInvalid) break;
    previous = current;
    current = next;
    path.push_back(current);
  }
  if (path.size() != vertex_count) return {};
  return path;
}

std::vector<JunctionCurve> junction_curves(const MeshData& mesh, const CellJunctions& junctions) {
  // Each interface face names the two materials on either side of its three edges.
  struct EdgeSide {
    std::uint64_t edge;
    std::int32_t lower, higher;
  };
  std::vector<EdgeSide> sides;
  sides.reserve(3 * junctions.faces.size());
  for (const Interface& f : junctions.interfaces)
    for (std::uint32_t i = f.first_face; i < f.first_face + f.face_count; ++i) {
      const TriangleCorners v = face_vertices(mesh, junctions.faces[i]);
      for (int e = 0; e < 3; ++e) sides.push_back({edge_key(v[e], v[(e + 1) % 3]), f.lower, f.higher});
    }
  std::sort(sides.begin(), sides.end(), [](const EdgeSide& x, const EdgeSide& y) {
    return std::tie(x.edge, x.lower, x.higher) < std::tie(y.edge, y.lower, y.higher);
  });
  struct TripleEdge {
    std::array<std::int32_t, 3> materials;
    std::uint64_t edge;
  };
  std::vector<TripleEdge> triple;
  for (std::size_t a = 0, b = 0; a < sides.size(); a = b) {
    std::array<std::int32_t, 4> materials{};  // the first four distinct ones: four means "more than three"
    int count = 0;
    for (b = a; b < sides.size() && sides[b].edge == sides[a].edge; ++b)
      for (std::int32_t m : {sides[b].lower, sides[b].higher})
        if (count < 4 && std::find(materials.begin(), materials.begin() + count, m) == materials.begin() + count) {
          materials[count++] = m;
        }
    if (count != 3) continue;
    std::sort(materials.begin(), materials.begin() + 3);
    triple.push_back({{materials[0], materials[1], materials[2]}, sides[a].edge});
  }
  std::sort(triple.begin(), triple.end(), [](const TripleEdge& x, const TripleEdge& y) {
    return std::tie(x.materials, x.edge) < std::tie(y.materials, y.edge);
  });
  std::vector<JunctionCurve> curves;
  std::vector<std::uint64_t> edges;
  for (std::size_t a = 0, b = 0; a < triple.size(); a = b) {
    edges.clear();
    for (b = a; b < triple.size() && triple[b].materials == triple[a].materials; ++b) edges.push_back(triple[b].edge);
    curves.push_back({triple[a].materials, simple_path(edges)});
  }
  return curves;
}

}  // namespace

CellJunctions find_cell_junctions(const FreudenthalGrid& grid, const MeshData& mesh) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;  // (material pair, discovery index)
  std::vector<InterfaceFace> found;
  for_each_face(grid, [&](TetId t, int face, TetId nb) {
    if (nb == kInvalid) return;
    const std::int32_t mt = mesh.tet_material[t], mn = mesh.tet_material[nb];
    if (mt == mn) return;
    keyed.emplace_back(pair_key(std::min(mt, mn), std::max(mt, mn)), static_cast<std::uint32_t>(found.size()));
    found.push_back({t, static_cast<std::uint8_t>(face), mt < mn});
  });
  std::sort(keyed.begin(), keyed.end());

  CellJunctions out;
  out.faces.reserve(found.size());
  for (const auto& [key, i] : keyed) out.faces.push_back(found[i]);
  DiscTest is_disc;
  std::vector<TriangleCorners> tris;
  for (std::size_t a = 0, b = 0; a < keyed.size(); a = b) {
    tris.clear();
    for (b = a; b < keyed.size() && keyed[b].first == keyed[a].first; ++b) tris.push_back(face_vertices(mesh, out.faces[b]));
    out.interfaces.push_back({static_cast<std::int32_t>(keyed[a].first >> 32),
                              static_cast<std::int32_t>(keyed[a].first & 0xFFFFFFFFu), static_cast<std::uint32_t>(a),
                              static_cast<std::uint32_t>(b - a), is_disc(tris)});
  }
  out.curves = junction_curves(mesh, out);
  return out;
}

}  // namespace topotet::gen
