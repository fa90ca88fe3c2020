// The collapse kernel (see collapse.h).
#include "collapse.h"

#include <algorithm>
#include <atomic>
#include <cassert>

#include "orient.h"

namespace topotet {

const char* to_string(CollapseReason reason) {
  switch (reason) {
    case CollapseReason::kOk: return "ok";
    case CollapseReason::kLinkK: return "link_K";
    case CollapseReason::kLinkKtilde: return "link_Ktilde";
    case CollapseReason::kPinned: return "pinned";
    case CollapseReason::kInversion: return "inversion";
    case CollapseReason::kQuality: return "quality";
    case CollapseReason::kTolerance: return "tolerance";
  }
  return "?";
}

namespace {

void star_of(const TetMesh& mesh, VertId x, std::vector<TetId>& out) {
  out.clear();
  mesh.for_each_tet_of(x, [&](TetId t) { out.push_back(t); });
  // Chains stay sorted (see collapse()), but sorting a sorted small vector is cheap insurance.
  if (!std::is_sorted(out.begin(), out.end())) std::sort(out.begin(), out.end());
}

std::array<VertId, 4> renamed(const std::array<VertId, 4>& v, VertId from, VertId to) {
  std::array<VertId, 4> r = v;
  for (VertId& x : r)
    if (x == from) x = to;
  return r;
}

// Writes `tets` (sorted) as the incidence list of x, packed along x's chain.
void write_incidence(TetMesh& mesh, VertId x, const std::vector<TetId>& tets) {
  std::size_t i = 0;
  for (std::uint32_t c = x; i < tets.size(); c = mesh.v2t_next[c]) {
    assert(c != kInvalid && "incidence chain capacity exceeded");
    const std::uint32_t begin = mesh.v2t_offsets[c], cap = mesh.v2t_offsets[c + 1] - begin;
    for (std::uint32_t k = 0; k < cap && i < tets.size(); ++k) mesh.v2t[begin + k] = tets[i++];
  }
  mesh.v2t_count[x] = static_cast<std::uint32_t>(tets.size());
}

// Removes dead tets from x's incidence list, in place and in order.
void drop_dead_tets(TetMesh& mesh, VertId x) {
  std::uint32_t remaining = mesh.v2t_count[x], kept = 0;
  std::uint32_t wc = x, wi = 0;  // write cursor: chunk, index within chunk
  for (std::uint32_t c = x; remaining != 0; c = mesh.v2t_next[c]) {
    const std::uint32_t begin = mesh.v2t_offsets[c];
    const std::uint32_t n = std::min(remaining, mesh.v2t_offsets[c + 1] - begin);
    for (std::uint32_t i = 0; i < n; ++i) {
      const TetId t = mesh.v2t[begin + i];
      if (mesh.is_dead_tet(t)) continue;
      while (wi == mesh.v2t_offsets[wc + 1] - mesh.v2t_offsets[wc]) {  // write chunk full: move on
        wc = mesh.v2t_next[wc];
        wi = 0;
      }
      mesh.v2t[mesh.v2t_offsets[wc] + wi++] = t;  // the write cursor never passes the read cursor
      ++kept;
    }
    remaining -= n;
  }
  mesh.v2t_count[x] = kept;
}

}  // namespace

bool gather_stars(const TetMesh& mesh, VertId u, VertId v, CollapseScratch& s) {
  star_of(mesh, u, s.star_u);
  star_of(mesh, v, s.star_v);
  s.star_uv.clear();
  std::set_intersection(s.star_u.begin(), s.star_u.end(), s.star_v.begin(), s.star_v.end(),
                        std::back_inserter(s.star_uv));
  s.new_star.clear();
  for (const VertId x : {u, v}) {
    const std::vector<TetId>& star = x == u ? s.star_u : s.star_v;
    for (TetId t : star) {
      if (std::binary_search(s.star_uv.begin(), s.star_uv.end(), t)) continue;
      const auto& tv = mesh.tets[t];
      const std::uint8_t corner = tv[0] == x ? 0 : tv[1] == x ? 1 : tv[2] == x ? 2 : 3;
      s.new_star.push_back({t, corner});
    }
  }
  return !s.star_uv.empty();
}

namespace {

// (mean ratio)^3 = 15552 V^2 / S^3 (signed like V): monotone in the mean ratio, and free of the
// cube root, which dominated the quality check.
double mean_ratio_cubed(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  const double vol = signed_volume6(a, b, c, d) / 6.0;
  const glm::dvec3 e[6] = {b - a, c - a, d - a, c - b, d - b, d - c};
  double s = 0.0;
  for (const glm::dvec3& x : e) s += x.x * x.x + x.y * x.y + x.z * x.z;
  if (!(s > 0.0)) return 0.0;
  const double q3 = 15552.0 * vol * vol / (s * s * s);
  return vol < 0.0 ? -q3 : q3;
}

// Worst (cubed) mean ratio of St(u) ∪ St(v) before the collapse.
double old_star_quality(const TetMesh& mesh, const CollapseScratch& s) {
  const auto& P = mesh.positions;
  double worst = 1.0;
  for (TetId t : s.star_u) {
    const auto& tv = mesh.tets[t];
    worst = std::min(worst, mean_ratio_cubed(P[tv[0]], P[tv[1]], P[tv[2]], P[tv[3]]));
  }
  for (TetId t : s.star_v) {
    if (std::binary_search(s.star_uv.begin(), s.star_uv.end(), t)) continue;  // counted in St(u)
    const auto& tv = mesh.tets[t];
    worst = std::min(worst, mean_ratio_cubed(P[tv[0]], P[tv[1]], P[tv[2]], P[tv[3]]));
  }
  return worst;
}

// Calls fn(q0, q1, q2, q3) with the corners of every tet of the new star (St(u) ∪ St(v) minus
// St(uv), with u and v at p) until fn returns false.
template <class Fn>
bool for_each_new_tet(const TetMesh& mesh, const glm::dvec3& p, const CollapseScratch& s, Fn&& fn) {
  const auto& P = mesh.positions;
  for (const auto& [t, corner] : s.new_star) {
    const auto& tv = mesh.tets[t];
    glm::dvec3 q[4] = {P[tv[0]], P[tv[1]], P[tv[2]], P[tv[3]]};
    q[corner] = p;
    if (!fn(q[0], q[1], q[2], q[3])) return false;
  }
  return true;
}

// Would a tet of the new star be inverted or flat (certified sign)?
bool inverts(const TetMesh& mesh, const glm::dvec3& p, const CollapseScratch& s) {
  return !for_each_new_tet(mesh, p, s, [](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                                                  const glm::dvec3& d) { return orient3d_sign(a, b, c, d) > 0; });
}

// Worst (cubed) mean ratio of the new star.
double new_star_quality(const TetMesh& mesh, const glm::dvec3& p, const CollapseScratch& s) {
  double worst = 1.0;
  for_each_new_tet(mesh, p, s, [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    worst = std::min(worst, mean_ratio_cubed(a, b, c, d));
    return true;
  });
  return worst;
}

// The tolerance check for one placement. Interior collapses (neither end on a surface or
// polyline of the original) return at once. An interior vertex may not absorb a surface vertex:
// that keeps SurfaceReference::on_surface an exact early out for the whole run (see
// surface_tolerance.h). The surface stencil is gathered once per edge, for either direction.
bool within_tolerance(const TetMesh& mesh, const Placement& pl, const CollapseOptions& options, CollapseScratch& s,
                      std::array<VertId, 2>& surface_edge) {
  const SurfaceReference& reference = *options.surfaces;
  const bool surface_u = reference.on_surface(pl.u), surface_v = reference.on_surface(pl.v);
  if (!surface_u && !surface_v) return true;
  if (!surface_u) return false;
  const std::array<VertId, 2> edge{std::min(pl.u, pl.v), std::max(pl.u, pl.v)};
  if (surface_edge != edge) {
    gather_surface_stencil(mesh, reference, pl.u, pl.v, s.star_u, s.star_v, s.star_uv, s.surface);
    surface_edge = edge;
  }
  return placement_within_tolerance(mesh, reference, options.tolerance, pl.u, pl.v, pl.p, s.surface);
}

}  // namespace

int first_acceptable(const TetMesh& mesh, const Placement* placements, int count, const CollapseOptions& options,
                     CollapseScratch& s, std::array<std::uint64_t, kCollapseReasonCount>* rejected,
                     bool check_topology) {
  auto reject = [&](CollapseReason r) {
    if (rejected != nullptr) ++(*rejected)[static_cast<int>(r)];
  };
  // Order hints are meant for this edge only: take them now so that none outlives this call.
  const std::array<VertId, 2> hints = s.link.known_interior;
  s.link.known_interior = {kInvalid, kInvalid};
  VertId gathered_u = kInvalid, gathered_v = kInvalid;
  bool link_done = false;
  double old_quality = -1.0;  // of this edge's stencil, computed once when first needed
  std::array<VertId, 2> surface_edge{kInvalid, kInvalid};  // edge whose surface stencil s.surface holds
  for (int i = 0; i < count; ++i) {
    const Placement& pl = placements[i];
    if (mesh.is_pinned(pl.v) || (mesh.is_pinned(pl.u) && pl.p != mesh.positions[pl.u])) {
      reject(CollapseReason::kPinned);
      continue;
    }
    if (pl.u != gathered_u || pl.v != gathered_v) {
      if (pl.u == gathered_v && pl.v == gathered_u) {
        std::swap(s.star_u, s.star_v);  // same edge, other direction
      } else if (!gather_stars(mesh, pl.u, pl.v, s)) {
        reject(CollapseReason::kLinkK);  // not an edge
        return -1;
      }
      gathered_u = pl.u;
      gathered_v = pl.v;
    }
    // Inversion first: it is the cheapest test and the most frequent rejection.
    if (inverts(mesh, pl.p, s)) {
      reject(CollapseReason::kInversion);
      continue;
    }
    if (check_topology && !link_done) {
      s.link.known_interior = hints;  // consumed (reset) by check_link_conditions
      const LinkResult link = check_link_conditions(mesh, pl.u, pl.v, s.star_uv, s.link);
      if (link != LinkResult::kOk) {
        reject(link == LinkResult::kLinkK ? CollapseReason::kLinkK : CollapseReason::kLinkKtilde);
        return -1;  // the same for every placement of this edge
      }
      link_done = true;
    }
    // Quality: the new star may not be worse than min(floor, worst of the old star). Above the
    // floor that holds whatever the old star was, so the old star is measured only below it.
    const double floor3 = options.quality_floor * options.quality_floor * options.quality_floor;
    const double new_quality = new_star_quality(mesh, pl.p, s);
    if (new_quality < floor3) {
      if (old_quality < 0.0) old_quality = old_star_quality(mesh, s);
      if (new_quality < std::min(floor3, old_quality)) {
        reject(CollapseReason::kQuality);
        continue;
      }
    }
    if (options.surfaces != nullptr && !within_tolerance(mesh, pl, options, s, surface_edge)) {
      reject(CollapseReason::kTolerance);
      continue;
    }
    return i;
  }
  return -1;
}

CollapseReason may_collapse(const TetMesh& mesh, VertId u, VertId v, const glm::dvec3& p,
                            const CollapseOptions& options, CollapseScratch& s) {
  std::array<std::uint64_t, kCollapseReasonCount> rejected{};
  const Placement placement{u, v, p};
  if (first_acceptable(mesh, &placement, 1, options, s, &rejected) == 0) return CollapseReason::kOk;
  for (int r = 1; r < kCollapseReasonCount; ++r)
    if (rejected[r] != 0) return static_cast<CollapseReason>(r);
  return CollapseReason::kLinkK;
}

void reserve_refs_headroom(TetMesh& mesh, std::uint32_t refs_used, std::size_t count) {
  if (mesh.refs_table.size() < refs_used + count)
    mesh.refs_table.resize(std::max<std::size_t>(refs_used + count, mesh.refs_table.size() * 3 / 2));
}

void collapse(TetMesh& mesh, VertId u, VertId v, const glm::dvec3& p, const double* fields_at_p,
              CollapseScratch& s, std::uint32_t& refs_used) {
  gather_stars(mesh, u, v, s);

  // 1. The flagged faces and edges of the old stencil, with v renamed to u. Faces and edges that
  //    contain both u and v degenerate and vanish with St(uv); merged ones appear twice and are
  //    united below (the listed ref wins over an implicit interface: refs sort descending).
  s.faces.clear();
  s.edges.clear();
  auto collect = [&](TetId t) {
    const TetFlags fl = mesh.flags[t];
    if (!(fl & (tet_flag::kSurfaceFaces | tet_flag::kPolylineEdges))) return;
    const SubstructureRefs& refs = mesh.refs_table[mesh.tet_refs_slot[t]];
    const auto r = renamed(mesh.tets[t], v, u);
    for (int f = 0; f < 4; ++f) {
      if (!is_surface_face(fl, f)) continue;
      std::array<VertId, 3> key{r[kTetFaces[f][0]], r[kTetFaces[f][1]], r[kTetFaces[f][2]]};
      std::sort(key.begin(), key.end());
      if (key[0] == key[1] || key[1] == key[2]) continue;
      s.faces.push_back({key, refs.face[f]});
    }
    for (int e = 0; e < 6; ++e) {
      if (!is_polyline_edge(fl, e)) continue;
      const VertId x = r[kTetEdges[e][0]], y = r[kTetEdges[e][1]];
      if (x == y) continue;
      s.edges.push_back({{std::min(x, y), std::max(x, y)}, refs.edge[e], ((refs.ridge_mask >> e) & 1u) != 0});
    }
  };
  for (TetId t : s.star_u) collect(t);
  for (TetId t : s.star_v)
    if (!std::binary_search(s.star_uv.begin(), s.star_uv.end(), t)) collect(t);
  std::sort(s.faces.begin(), s.faces.end());
  s.faces.erase(std::unique(s.faces.begin(), s.faces.end(), [](const auto& a, const auto& b) { return a.key == b.key; }),
                s.faces.end());
  std::sort(s.edges.begin(), s.edges.end());
  // A merged edge is a ridge if either part was: push ridge bits back to the first record of each
  // run of equal keys (walking backwards so runs longer than two are covered), which unique keeps.
  for (std::size_t i = s.edges.size(); i-- > 1;)
    if (s.edges[i].key == s.edges[i - 1].key && s.edges[i].ridge) s.edges[i - 1].ridge = true;
  s.edges.erase(std::unique(s.edges.begin(), s.edges.end(), [](const auto& a, const auto& b) { return a.key == b.key; }),
                s.edges.end());

  // 2. Remove St(uv), rename v to u in the rest of St(v).
  for (TetId t : s.star_uv) mesh.flags[t] = tet_flag::kDead;
  for (TetId t : s.star_v)
    if (!std::binary_search(s.star_uv.begin(), s.star_uv.end(), t)) mesh.tets[t] = renamed(mesh.tets[t], v, u);

  // 3. Incidence: u takes v's chunks; the other vertices of St(uv) lose the dead tets.
  s.merged.clear();
  std::set_union(s.star_u.begin(), s.star_u.end(), s.star_v.begin(), s.star_v.end(), std::back_inserter(s.merged));
  s.merged.erase(std::remove_if(s.merged.begin(), s.merged.end(), [&](TetId t) { return mesh.is_dead_tet(t); }),
                 s.merged.end());
  std::uint32_t last = u;
  while (mesh.v2t_next[last] != kInvalid) last = mesh.v2t_next[last];
  mesh.v2t_next[last] = v;
  write_incidence(mesh, u, s.merged);
  mesh.v2t_count[v] = 0;
  for (TetId t : s.star_uv)
    for (VertId x : mesh.tets[t])
      if (x != u && x != v) drop_dead_tets(mesh, x);

  // 4. Recompute flags and refs of the new star from the collected set (never patched by cases).
  std::atomic_ref<std::uint32_t> used(refs_used);
  for (TetId t : s.merged) {
    const auto& tv = mesh.tets[t];
    TetFlags fl = 0;
    SubstructureRefs refs;
    for (int f = 0; f < 4; ++f) {
      std::array<VertId, 3> key{tv[kTetFaces[f][0]], tv[kTetFaces[f][1]], tv[kTetFaces[f][2]]};
      std::sort(key.begin(), key.end());
      auto it = std::lower_bound(s.faces.begin(), s.faces.end(), CollapseScratch::FlaggedFace{key, INT32_MAX});
      if (it != s.faces.end() && it->key == key) {
        fl |= TetFlags(1u << (tet_flag::kSurfaceFaceShift + f));
        refs.face[f] = it->ref;
      }
    }
    for (int e = 0; e < 6; ++e) {
      const VertId x = tv[kTetEdges[e][0]], y = tv[kTetEdges[e][1]];
      const std::array<VertId, 2> key{std::min(x, y), std::max(x, y)};
      auto it = std::lower_bound(s.edges.begin(), s.edges.end(), CollapseScratch::FlaggedEdge{key, INT32_MAX, false});
      if (it != s.edges.end() && it->key == key) {
        fl |= TetFlags(1u << (tet_flag::kPolylineEdgeShift + e));
        refs.edge[e] = it->ref;
        if (it->ridge) refs.ridge_mask |= std::uint8_t(1u << e);
      }
    }
    mesh.flags[t] = fl;
    if (fl == 0) continue;
    if (mesh.tet_refs_slot[t] == kInvalid) {
      // Relaxed: slots only need to be distinct; the table is not read through the counter.
      mesh.tet_refs_slot[t] = used.fetch_add(1, std::memory_order_relaxed);
      assert(mesh.tet_refs_slot[t] < mesh.refs_table.size() && "reserve_refs_headroom was not called");
    }
    mesh.refs_table[mesh.tet_refs_slot[t]] = refs;
  }

  // 5. Geometry and fields.
  mesh.positions[u] = p;
  const int stride = mesh.field_stride();
  if (fields_at_p != nullptr && stride > 0)
    std::copy_n(fields_at_p, stride, mesh.field_values.begin() + static_cast<std::ptrdiff_t>(u) * stride);
  mesh.vertex_states[v] |= vertex_state::kDead;
}

}  // namespace topotet
