// Face and edge swaps (see swap.h).
#include "optimize/swap.h"

#include <algorithm>
#include <array>
#include <tuple>
#include <vector>

#include "mesh/moved_corner.h"
#include "mesh/orient.h"

namespace topotet {

namespace {

using FaceKey = std::array<VertId, 3>;
using EdgeKey = std::array<VertId, 2>;

FaceKey face_key(VertId a, VertId b, VertId c) {
  FaceKey k{a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}
EdgeKey edge_key(VertId a, VertId b) { return a < b ? EdgeKey{a, b} : EdgeKey{b, a}; }

// The flagged faces and edges of the tets a flip replaces, with their refs: every one of them is a
// face or an edge of the new tets (swap.h), which take them back by their vertices.
struct RegionFlags {
  std::vector<std::pair<FaceKey, std::int32_t>> faces;
  std::vector<std::tuple<EdgeKey, std::int32_t, bool>> edges;  // key, ref, MEDIT ridge

  void clear() {
    faces.clear();
    edges.clear();
  }
  void add(const MeshModel& m, TetId t) {
    const TetFlags fl = m.flags[t];
    if (!(fl & (tet_flag::kSurfaceFaces | tet_flag::kPolylineEdges))) return;
    const SubstructureRefs& r = m.refs_table[m.tet_refs_slot[t]];
    const auto& tv = m.tets[t];
    for (int f = 0; f < 4; ++f)
      if (is_surface_face(fl, f))
        faces.emplace_back(face_key(tv[kTetFaces[f][0]], tv[kTetFaces[f][1]], tv[kTetFaces[f][2]]), r.face[f]);
    for (int e = 0; e < 6; ++e)
      if (is_polyline_edge(fl, e))
        edges.emplace_back(edge_key(tv[kTetEdges[e][0]], tv[kTetEdges[e][1]]), r.edge[e], (r.ridge_mask >> e) & 1u);
  }
};

// Writes tet v (positively oriented) into `slot` (an old tet's, or one past the end: appended),
// with the flags and refs its faces and edges had in the region.
void write_tet(MeshModel& m, TetId slot, const std::array<VertId, 4>& v, std::int32_t material, const RegionFlags& region) {
  TetFlags fl = 0;
  SubstructureRefs refs{};
  for (int f = 0; f < 4; ++f) {
    const FaceKey k = face_key(v[kTetFaces[f][0]], v[kTetFaces[f][1]], v[kTetFaces[f][2]]);
    for (const auto& [key, ref] : region.faces)
      if (key == k) {
        fl |= static_cast<TetFlags>(1u << (tet_flag::kSurfaceFaceShift + f));
        refs.face[static_cast<std::size_t>(f)] = ref;
        break;
      }
  }
  for (int e = 0; e < 6; ++e) {
    const EdgeKey k = edge_key(v[kTetEdges[e][0]], v[kTetEdges[e][1]]);
    for (const auto& [key, ref, ridge] : region.edges)
      if (key == k) {
        fl |= static_cast<TetFlags>(1u << (tet_flag::kPolylineEdgeShift + e));
        refs.edge[static_cast<std::size_t>(e)] = ref;
        if (ridge) refs.ridge_mask |= static_cast<std::uint8_t>(1u << e);
        break;
      }
  }
  if (slot == m.tets.size()) {
    m.tets.push_back(v);
    m.material.push_back(material);
    m.flags.push_back(fl);
    m.tet_refs_slot.push_back(kInvalid);
  } else {
    m.tets[slot] = v;
    m.material[slot] = material;
    m.flags[slot] = fl;
  }
  std::uint32_t& refs_slot = m.tet_refs_slot[slot];
  if (fl == 0) {
    refs_slot = kInvalid;  // an old slot stays unused until compact() packs the table
  } else if (refs_slot != kInvalid) {
    m.refs_table[refs_slot] = refs;  // the old tet's own record: it is gone
  } else {
    refs_slot = static_cast<std::uint32_t>(m.refs_table.size());
    m.refs_table.push_back(refs);
  }
}

bool positive(const MeshModel& m, const std::array<VertId, 4>& v) {
  const auto& P = m.positions;
  return orient3d_sign(P[v[0]], P[v[1]], P[v[2]], P[v[3]]) > 0;
}

double quality(const MeshModel& m, const std::array<VertId, 4>& v) {
  const auto& P = m.positions;
  return mean_ratio_cubed(P[v[0]], P[v[1]], P[v[2]], P[v[3]]);
}

bool contains(const std::array<VertId, 4>& tv, VertId x) {
  return tv[0] == x || tv[1] == x || tv[2] == x || tv[3] == x;
}

// One flip: the tets it replaces and the tets it makes (3 -> 2 or 2 -> 3).
struct Flip {
  std::array<TetId, 3> old{kInvalid, kInvalid, kInvalid};
  int old_count = 0;
  std::array<std::array<VertId, 4>, 3> made{};
  int made_count = 0;
  double quality = 0.0;  // the worst (mean ratio)^3 of the tets it makes
};

class Swapper {
 public:
  explicit Swapper(MeshModel& m) : m_(m), touched_(m.vertex_capacity(), 0) {}

  void reset() { std::fill(touched_.begin(), touched_.end(), 0); }

  // The best flip that removes tet t (worst quality q), if one beats q.
  bool best_flip(TetId t, double q, Flip& best) {
    best.quality = q;
    bool found = false;
    const auto& tv = m_.tets[t];
    for (VertId x : tv)
      if (touched_[x] || m_.is_frozen(x)) return false;
    Flip f;
    for (int e = 0; e < 6; ++e)
      if (edge_flip(t, tv[kTetEdges[e][0]], tv[kTetEdges[e][1]], f) && f.quality > best.quality) {
        best = f;
        found = true;
      }
    for (int k = 0; k < 4; ++k)
      if (face_flip(t, k, f) && f.quality > best.quality) {
        best = f;
        found = true;
      }
    return found;
  }

  void apply(const Flip& f) {
    region_.clear();
    const std::int32_t material = m_.material[f.old[0]];
    for (int i = 0; i < f.old_count; ++i) {
      region_.add(m_, f.old[static_cast<std::size_t>(i)]);
      for (VertId x : m_.tets[f.old[static_cast<std::size_t>(i)]]) touched_[x] = 1;
    }
    for (int i = 0; i < f.made_count; ++i) {
      const TetId slot = i < f.old_count ? f.old[static_cast<std::size_t>(i)] : static_cast<TetId>(m_.tets.size());
      write_tet(m_, slot, f.made[static_cast<std::size_t>(i)], material, region_);
    }
    for (int i = f.made_count; i < f.old_count; ++i) {
      const TetId t = f.old[static_cast<std::size_t>(i)];
      m_.flags[t] = tet_flag::kDead;
      m_.tet_refs_slot[t] = kInvalid;
    }
  }

 private:
  // 3 -> 2 around edge ab of tet t: ab has exactly three tets, one material, a closed ring pqr, and
  // neither ab nor a face through it is flagged.
  bool edge_flip(TetId t, VertId a, VertId b, Flip& f) {
    ring_.clear();
    bool ok = true;
    m_.for_each_tet_of(a, [&](TetId s) {
      if (ok && contains(m_.tets[s], b)) {
        if (ring_.size() == 3) ok = false;
        else ring_.push_back(s);
      }
    });
    if (!ok || ring_.size() != 3) return false;
    std::array<VertId, 6> others{};
    std::size_t n = 0;
    for (TetId s : ring_) {
      if (m_.material[s] != m_.material[t]) return false;
      const auto& sv = m_.tets[s];
      const TetFlags fl = m_.flags[s];
      int la = -1, lb = -1;
      for (int k = 0; k < 4; ++k) {
        if (sv[k] == a) la = k;
        if (sv[k] == b) lb = k;
      }
      if (is_polyline_edge(fl, local_edge_index(la, lb))) return false;
      for (int k = 0; k < 4; ++k) {
        if (k == la || k == lb) continue;
        // Face k (opposite corner k) holds a and b: it disappears.
        if (is_surface_face(fl, k)) return false;
        others[n++] = sv[k];
      }
    }
    std::sort(others.begin(), others.end());
    // A closed ring: three vertices, each in two of the tets (an open fan of three has four).
    if (!(others[0] == others[1] && others[2] == others[3] && others[4] == others[5] && others[1] != others[2] &&
          others[3] != others[4]))
      return false;
    VertId p = others[0], q = others[2], r = others[4];
    for (VertId x : {p, q, r})
      if (touched_[x] || m_.is_frozen(x)) return false;
    const auto& P = m_.positions;
    const int side = orient3d_sign(P[p], P[q], P[r], P[a]);
    if (side == 0) return false;
    if (side < 0) std::swap(q, r);
    f.old = {ring_[0], ring_[1], ring_[2]};
    f.old_count = 3;
    f.made[0] = {p, q, r, a};
    f.made[1] = {q, p, r, b};
    f.made_count = 2;
    if (!positive(m_, f.made[0]) || !positive(m_, f.made[1])) return false;
    f.quality = std::min(quality(m_, f.made[0]), quality(m_, f.made[1]));
    return true;
  }

  // 2 -> 3 through face k of tet t (opposite its corner k): an unflagged face between two tets of
  // one material, whose apexes a and b are not yet joined by an edge.
  bool face_flip(TetId t, int k, Flip& f) {
    const auto& tv = m_.tets[t];
    if (is_surface_face(m_.flags[t], k)) return false;
    VertId x = tv[kTetFaces[k][0]], y = tv[kTetFaces[k][1]], z = tv[kTetFaces[k][2]];
    const VertId a = tv[k];
    TetId nb = kInvalid;
    m_.for_each_tet_of(x, [&](TetId s) {
      if (s != t && contains(m_.tets[s], y) && contains(m_.tets[s], z)) nb = s;
    });
    if (nb == kInvalid || m_.material[nb] != m_.material[t]) return false;
    VertId b = kInvalid;
    for (VertId w : m_.tets[nb])
      if (w != x && w != y && w != z) b = w;
    if (touched_[b] || m_.is_frozen(b)) return false;
    bool joined = false;
    m_.for_each_tet_of(a, [&](TetId s) { joined = joined || contains(m_.tets[s], b); });
    if (joined) return false;
    const auto& P = m_.positions;
    const int side = orient3d_sign(P[x], P[y], P[z], P[a]);
    if (side == 0) return false;
    if (side < 0) std::swap(y, z);
    // Each new tet is (x, y, z, a) with one face vertex replaced by b: positive iff ab crosses the face.
    f.old = {t, nb, kInvalid};
    f.old_count = 2;
    f.made[0] = {b, y, z, a};
    f.made[1] = {x, b, z, a};
    f.made[2] = {x, y, b, a};
    f.made_count = 3;
    f.quality = 1.0;
    for (int i = 0; i < 3; ++i) {
      if (!positive(m_, f.made[static_cast<std::size_t>(i)])) return false;
      f.quality = std::min(f.quality, quality(m_, f.made[static_cast<std::size_t>(i)]));
    }
    return true;
  }

  MeshModel& m_;
  std::vector<std::uint8_t> touched_;  // [vertex] its star changed in this pass
  std::vector<TetId> ring_;
  RegionFlags region_;
};

}  // namespace

SwapStats swap_bad_tets(MeshModel& mesh, const SwapOptions& options) {
  SwapStats stats;
  const double target3 = options.target_quality * options.target_quality * options.target_quality;
  Swapper swapper(mesh);
  std::vector<std::pair<double, TetId>> bad;
  for (int pass = 0; pass < options.max_passes; ++pass) {
    bad.clear();
    for (TetId t = 0; t < mesh.tets.size(); ++t) {
      if (mesh.is_dead_tet(t)) continue;
      const double q = quality(mesh, mesh.tets[t]);
      if (q < target3) bad.emplace_back(q, t);
    }
    std::sort(bad.begin(), bad.end());
    swapper.reset();
    std::uint64_t flips = 0;
    Flip flip;
    for (const auto& [q, t] : bad) {
      // A tet an earlier flip of this pass replaced has a touched vertex: best_flip refuses it.
      if (!swapper.best_flip(t, q, flip)) continue;
      swapper.apply(flip);
      ++(flip.old_count == 3 ? stats.flips_32 : stats.flips_23);
      ++flips;
    }
    if (flips == 0) break;
    stats.passes = pass + 1;
    rebuild_incidence(mesh);
  }
  return stats;
}

}  // namespace topotet
