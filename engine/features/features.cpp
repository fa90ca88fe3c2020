// detect_features (topotet/features.h): find sharp surface edges from the vertex classification
// of the link conditions, flag them as polyline edges, pin the corners they make.
#include "features/features.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "kernel/link_condition.h"
#include "parallel/for_range.h"

namespace topotet {
namespace {

constexpr int kKtilde = 1;  // index of the substructure filtration in Neighbour::count / order

// The angle between the normals of triangles a x y1 and a x y2 is π minus their dihedral angle at
// edge ax, measured between the components of (y - a) orthogonal to ax. A sharp edge has a small
// dihedral angle φ: φ < π - θ, i.e. cos φ > -cos θ. Degenerate triangles decide nothing.
bool is_sharp(const glm::dvec3& a, const glm::dvec3& x, const glm::dvec3& y1, const glm::dvec3& y2,
              double minus_cos_theta) {
  const glm::dvec3 axis = x - a;
  const double len2 = glm::dot(axis, axis);
  if (!(len2 > 0.0)) return false;
  const auto across = [&](const glm::dvec3& y) {
    const glm::dvec3 d = y - a;
    return d - axis * (glm::dot(d, axis) / len2);
  };
  const glm::dvec3 u1 = across(y1), u2 = across(y2);
  const double n1 = glm::length(u1), n2 = glm::length(u2);
  if (!(n1 > 0.0 && n2 > 0.0)) return false;
  return glm::dot(u1, u2) / (n1 * n2) > minus_cos_theta;
}

// The edges (a, x), a < x, of St(a) that are sharp inner edges of one surface.
void sharp_edges_at(const MeshModel& mesh, VertId a, double minus_cos_theta, LinkScratch& scratch,
                    std::vector<std::pair<VertId, VertId>>& out) {
  LinkScratch::VertexData& d = scratch.a;
  classify_vertex(mesh, a, d, scratch);
  for (const LinkScratch::Neighbour& nb : d.neighbours) {
    if (nb.x < a || nb.polyline || nb.mixed_labels || nb.count[kKtilde] != 2) continue;
    VertId y[2];
    int n = 0;
    for (const auto& s : d.special) {
      if (s.x == nb.x) y[n++] = s.y;
      else if (s.y == nb.x) y[n++] = s.x;
      if (n == 2) break;
    }
    if (n == 2 && is_sharp(mesh.positions[a], mesh.positions[nb.x], mesh.positions[y[0]], mesh.positions[y[1]],
                           minus_cos_theta))
      out.push_back({a, nb.x});
  }
}

// Flags edge ab as a feature curve in every tet that has it (a side table slot is added to tets
// that had none).
void flag_edge(MeshModel& mesh, VertId a, VertId b) {
  mesh.for_each_tet_of(a, [&](TetId t) {
    const auto& v = mesh.tets[t];
    int la = -1, lb = -1;
    for (int k = 0; k < 4; ++k) {
      if (v[k] == a) la = k;
      if (v[k] == b) lb = k;
    }
    if (lb < 0) return;
    const int e = local_edge_index(la, lb);
    if (mesh.tet_refs_slot[t] == kInvalid) {
      mesh.tet_refs_slot[t] = static_cast<std::uint32_t>(mesh.refs_table.size());
      SubstructureRefs r;
      r.face.fill(kImplicitInterfaceRef);
      mesh.refs_table.push_back(r);
    }
    mesh.flags[t] |= TetFlags(1u << (tet_flag::kPolylineEdgeShift + e));
    mesh.refs_table[mesh.tet_refs_slot[t]].edge[e] = kFeatureCurveRef;
  });
}

}  // namespace

FeatureStats detect_features(MeshModel& mesh, double angle_degrees) {
  FeatureStats stats;
  if (!(angle_degrees < 180.0)) return stats;
  const double minus_cos_theta = -std::cos(std::max(angle_degrees, 0.0) * std::numbers::pi / 180.0);
  const std::size_t nv = mesh.vertex_capacity();

  // Found in parallel (reading only), sorted afterwards: the result does not depend on the split.
  std::vector<std::pair<VertId, VertId>> sharp;
  std::mutex merge;
  parallel::for_range<std::size_t>(0, nv, 1024, "detect_features", [&](std::size_t begin, std::size_t end) {
    LinkScratch scratch;
    std::vector<std::pair<VertId, VertId>> local;
    for (std::size_t i = begin; i < end; ++i) {
      const VertId a = static_cast<VertId>(i);
      if (mesh.is_dead_vertex(a) || is_interior_vertex(mesh, a)) continue;
      sharp_edges_at(mesh, a, minus_cos_theta, scratch, local);
    }
    const std::lock_guard<std::mutex> lock(merge);
    sharp.insert(sharp.end(), local.begin(), local.end());
  });
  std::sort(sharp.begin(), sharp.end());
  for (const auto& [a, b] : sharp) flag_edge(mesh, a, b);
  stats.edges = sharp.size();

  // Corners: the vertices of the new curves that the classification cannot take as an inner
  // curve point (order 3). They would not move anyway (the end of higher order stays); pinning
  // makes it a promise that no later change of their neighbourhood can undo.
  std::vector<VertId> ends;
  ends.reserve(2 * sharp.size());
  for (const auto& [a, b] : sharp) {
    ends.push_back(a);
    ends.push_back(b);
  }
  std::sort(ends.begin(), ends.end());
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
  std::vector<char> corner(ends.size(), 0);
  parallel::for_range<std::size_t>(0, ends.size(), 256, "feature_corners", [&](std::size_t begin, std::size_t end) {
    LinkScratch scratch;
    for (std::size_t i = begin; i < end; ++i)
      corner[i] = !mesh.is_pinned(ends[i]) && vertex_orders(mesh, ends[i], scratch).ktilde == 3;
  });
  for (std::size_t i = 0; i < ends.size(); ++i) {
    if (!corner[i]) continue;
    mesh.vertex_states[ends[i]] |= vertex_state::kPinned | vertex_state::kFeatureCorner;
    ++stats.corners;
  }
  return stats;
}

}  // namespace topotet
