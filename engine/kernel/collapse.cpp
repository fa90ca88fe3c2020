// The collapse kernel (see collapse.h).
#include "kernel/collapse.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>

#include "mesh/moved_corner.h"
#include "mesh/orient.h"
#include "mesh/prefetch.h"

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
    case CollapseReason::kFieldError: return "field_error";
  }
  return "?";
}

namespace {

void star_of(const MeshModel& mesh, VertId x, std::vector<TetId>& out) {
  out.clear();
  mesh.for_each_tet_of(x, [&](TetId t) { out.push_back(t); });
  // Chains are kept sorted by tet id (rebuild_incidence fills them in tet order, collapse() writes
  // a sorted union, drop_dead_tets keeps the order): the set logic below relies on it.
  assert(std::is_sorted(out.begin(), out.end()));
}

std::uint64_t pack_pair(VertId x, VertId y) {
  return x < y ? (std::uint64_t{x} << 32) | y : (std::uint64_t{y} << 32) | x;
}

std::array<VertId, 4> renamed(const std::array<VertId, 4>& v, VertId from, VertId to) {
  std::array<VertId, 4> r = v;
  for (VertId& x : r)
    if (x == from) x = to;
  return r;
}

// Writes `tets` (sorted) as the incidence list of x, packed along x's chain.
void write_incidence(MeshModel& mesh, VertId x, const std::vector<TetId>& tets) {
  std::size_t i = 0;
  for (std::uint32_t c = x; i < tets.size(); c = mesh.v2t_next[c]) {
    assert(c != kInvalid && "incidence chain capacity exceeded");
    const std::uint32_t begin = mesh.v2t_offsets[c], cap = mesh.v2t_offsets[c + 1] - begin;
    for (std::uint32_t k = 0; k < cap && i < tets.size(); ++k) mesh.v2t[begin + k] = tets[i++];
  }
  mesh.v2t_count[x] = static_cast<std::uint32_t>(tets.size());
}

// Removes the tets of `removed` (sorted; the tets a collapse just killed) from x's incidence
// list, in place and in order. Chains hold only live tets, so those are the only dead ones there;
// looking them up in the short list spares a flag load (a cache miss) per tet of St(x).
void drop_dead_tets(MeshModel& mesh, VertId x, const std::vector<TetId>& removed) {
  std::uint32_t remaining = mesh.v2t_count[x], kept = 0;
  std::uint32_t wc = x, wi = 0;  // write cursor: chunk, index within chunk
  for (std::uint32_t c = x; remaining != 0; c = mesh.v2t_next[c]) {
    const std::uint32_t begin = mesh.v2t_offsets[c];
    const std::uint32_t n = std::min(remaining, mesh.v2t_offsets[c + 1] - begin);
    for (std::uint32_t i = 0; i < n; ++i) {
      const TetId t = mesh.v2t[begin + i];
      if (std::find(removed.begin(), removed.end(), t) != removed.end()) continue;
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

namespace {

// Starts a new edge: nothing gathered yet.
void reset_stars(CollapseScratch& s) {
  s.star_u.clear();
  s.star_v.clear();
  s.star_uv.clear();
  s.new_star.clear();
  s.prepared.clear();
  s.have_u = s.have_v = false;
}

// Gathers St(x) (x = u or v of the edge, `other` the other end) into `star`: a tet with `other`
// is in St(uv) (listed from the first star gathered: the chains are sorted, so St(uv) is too),
// any other one survives the collapse with x's corner moving.
void gather_star(const MeshModel& mesh, VertId x, VertId other, std::vector<TetId>& star, CollapseScratch& s) {
  const bool first = !s.have_u && !s.have_v;
  star_of(mesh, x, star);
  for (TetId t : star) prefetch(&mesh.tets[t]);
  for (TetId t : star) {
    const auto& tv = mesh.tets[t];
    std::uint8_t corner = 0;
    bool has_other = false;
    for (std::uint8_t k = 0; k < 4; ++k) {
      corner = tv[k] == x ? k : corner;
      has_other |= tv[k] == other;
    }
    if (!has_other)
      s.new_star.push_back({t, corner, x});
    else if (first)
      s.star_uv.push_back(t);
  }
}

// Makes sure the stars asked for are gathered (u, v: the edge in the scratch's current
// orientation). False when uv is not an edge.
bool need_stars(const MeshModel& mesh, VertId u, VertId v, bool need_u, bool need_v, CollapseScratch& s) {
  if (need_v && !s.have_v) {
    gather_star(mesh, v, u, s.star_v, s);
    s.have_v = true;
  }
  if (need_u && !s.have_u) {
    gather_star(mesh, u, v, s.star_u, s);
    s.have_u = true;
  }
  return !s.star_uv.empty();
}

}  // namespace

bool gather_stars(const MeshModel& mesh, VertId u, VertId v, CollapseScratch& s) {
  reset_stars(s);
  return need_stars(mesh, u, v, true, true, s);
}

namespace {

// Worst (cubed) mean ratio of St(u) ∪ St(v) before the collapse.
double old_star_quality(const MeshModel& mesh, const CollapseScratch& s) {
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

// Smallest sin^2 of a dihedral angle in St(u) ∪ St(v) before the collapse, over the tets the
// floor's screen does not clear (the others are above the floor: they cannot lower min(floor, it)).
double old_star_dihedral(const MeshModel& mesh, const CollapseScratch& s, const DihedralFloor& floor) {
  const auto& P = mesh.positions;
  double worst = 1.0;
  auto visit = [&](TetId t) {
    const auto& tv = mesh.tets[t];
    if (std::fabs(mean_ratio_cubed(P[tv[0]], P[tv[1]], P[tv[2]], P[tv[3]])) >= floor.screen_q3) return;
    worst = std::min(worst, min_dihedral_sine_sq(P[tv[0]], P[tv[1]], P[tv[2]], P[tv[3]]));
  };
  for (TetId t : s.star_u) visit(t);
  for (TetId t : s.star_v)
    if (!std::binary_search(s.star_uv.begin(), s.star_uv.end(), t)) visit(t);
  return worst;
}

// The geometric test of one placement reads, for every tet of the new star, only the three corners
// that stay and p (mesh/moved_corner.h).
void prepare_moved_tet(const MeshModel& mesh, CollapseScratch& s, std::size_t i) {
  const auto& P = mesh.positions;
  const auto& [t, corner, at] = s.new_star[i];
  const auto& tv = mesh.tets[t];
  s.moved[i] = prepare_moved_corner(P[tv[kTetFaces[corner][0]]], P[tv[kTetFaces[corner][1]]], P[tv[kTetFaces[corner][2]]]);
}

// Places the moving corner of every new tet at p. Returns false when a tet would be inverted or
// flat (sign not certainly positive); otherwise `worst_q3` is the worst (mean ratio)^3 of the new star.
// Most placements fail on one of the first tets, so the per-tet data is prepared lazily: tet i
// is prepared the first time a placement of this edge gets that far.
// With a dihedral floor, `worst_sine_sq` is the smallest sin^2 of a dihedral angle among the new
// tets its screen does not clear (1 if none). `worst_at` receives the tets where the two minima
// are reached (kInvalid: none below 1), the witnesses of a quality refusal.
bool new_star_geometry(const MeshModel& mesh, CollapseScratch& s, const glm::dvec3& p, VertId staying,
                       const DihedralFloor& floor, double& worst_q3, double& worst_sine_sq,
                       std::array<TetId, 2>& worst_at) {
  double worst = 1.0, worst_sine = 1.0;
  worst_at = {kInvalid, kInvalid};
  if (s.moved.size() < s.new_star.size()) s.moved.resize(s.new_star.size());
  if (s.prepared.size() < s.new_star.size()) s.prepared.resize(s.new_star.size(), 0);
  for (std::size_t i = 0; i < s.new_star.size(); ++i) {
    // A tet whose moving corner is the vertex that stays where it is keeps its shape: it can
    // neither invert nor fall below the quality it had (which the floor rule compares against).
    if (s.new_star[i].at == staying) continue;
    if (!s.prepared[i]) {
      prepare_moved_tet(mesh, s, i);
      s.prepared[i] = 1;
    }
    double q3 = 0.0;
    if (!moved_corner_quality(s.moved[i], p, q3)) {
      // The next placement is likely to fail on the same tet: test it first (move to front).
      if (i != 0) {
        std::swap(s.new_star[i], s.new_star[0]);
        std::swap(s.moved[i], s.moved[0]);
        std::swap(s.prepared[i], s.prepared[0]);
      }
      return false;
    }
    if (q3 < worst) {
      worst = q3;
      worst_at[0] = s.new_star[i].tet;
    }
    if (q3 < floor.screen_q3) {
      const MovedCorner& m = s.moved[i];
      const double sine = min_dihedral_sine_sq(m.a, p, m.c, m.d);
      if (sine < worst_sine) {
        worst_sine = sine;
        worst_at[1] = s.new_star[i].tet;
      }
    }
  }
  worst_q3 = worst;
  worst_sine_sq = worst_sine;
  return true;
}

// The tolerance check for one placement. Interior collapses (neither end on a surface or
// polyline of the original) return at once. An interior vertex may not absorb a surface vertex:
// that keeps SurfaceReference::on_surface an exact early out for the whole run (see
// surface_tolerance.h). The surface stencil is gathered once per edge, for either direction.
// The original triangles held near a stencil that the tolerance check tries before a search
// (SurfaceStencil::near_triangles): up to this many. Polycrystal 30k at 10% (many small interface
// labels, whose Embree scene is shared): 12, 16, 24 ran -5.2%, -8.1%, -7.0% instructions; sphere3
// (long lists of cut pieces, few searches): -0.2%, 0.0%, +1.7%.
constexpr std::size_t kMaxNearTriangles = 16;

bool within_tolerance(const MeshModel& mesh, const Placement& pl, const CollapseOptions& options, CollapseScratch& s,
                      std::array<VertId, 2>& surface_edge) {
  const SurfaceReference& reference = *options.surfaces;
  const bool surface_u = reference.on_surface(pl.u), surface_v = reference.on_surface(pl.v);
  if (!surface_u && !surface_v) return true;
  if (!surface_u) return false;
  if (!options.prove_tolerance) return true;
  const std::array<VertId, 2> edge{std::min(pl.u, pl.v), std::max(pl.u, pl.v)};
  if (surface_edge != edge) {
    gather_surface_stencil(mesh, reference, pl.u, pl.v, s.star_u, s.star_v, s.star_uv, s.surface);
    // A few original triangles are cheaper to try than a search; many are not: then none.
    s.surface.near_triangles.clear();
    s.surface.found_triangles.clear();
    if (options.coverage != nullptr)
      options.coverage->held_triangles(s.star_u, s.star_v, s.star_uv, kMaxNearTriangles, s.surface.near_triangles);
    surface_edge = edge;
  }
  if (!placement_within_tolerance(mesh, reference, options.tolerance, pl.u, pl.v, pl.p, s.surface,
                                  options.screen_tolerance || options.screen_only, !options.screen_only))
    return false;
  if (options.screen_only) return true;  // not proved: the caller proves it later
  if (options.coverage == nullptr) return true;
  s.coverage_for.u = kInvalid;
  if (!options.coverage->place(mesh, pl.u, pl.v, s.star_u, s.star_v, s.star_uv, s.surface, s.coverage)) return false;
  s.coverage_for = {pl.u, pl.v, pl.p};
  return true;
}

// The new star as the field bounds see it (the tets that survive, with their moving corner).
void bound_star(const CollapseScratch& s, FieldBoundsScratch& b) {
  b.star.clear();
  for (const CollapseScratch::NewStarTet& t : s.new_star) b.star.push_back({t.tet, t.corner});
}

// The field error check of one placement (both stars gathered).
bool within_field_bounds(const MeshModel& mesh, const Placement& pl, const FieldBounds& bounds, CollapseScratch& s) {
  bound_star(s, s.bounds);
  return bounds.evaluate(mesh, s.star_uv, pl.u, pl.p, pl.fields, s.bounds, true);
}

}  // namespace

int first_acceptable(const MeshModel& mesh, const Placement* placements, int count, const CollapseOptions& options,
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
  double old_dihedral = -1.0;  // likewise
  bool quality_refused = false;  // the quality fallbacks are tried only then
  std::array<VertId, 2> surface_edge{kInvalid, kInvalid};  // edge whose surface stencil s.surface holds
  s.refusal = CollapseScratch::Refusal{true, 0, {kInvalid, kInvalid}};
  const auto uncertain = [&] { s.refusal.certified = false; };
  // A tet that refuses a placement alone (it inverts, or falls below a floor the old star was
  // above): a witness of the refusal.
  const auto witness = [&](TetId t) {
    CollapseScratch::Refusal& r = s.refusal;
    if (t == kInvalid) r.certified = false;
    if (!r.certified || (r.count > 0 && r.witness[0] == t) || (r.count > 1 && r.witness[1] == t)) return;
    if (r.count == r.witness.size()) {
      r.certified = false;
    } else {
      r.witness[r.count++] = t;
    }
  };
  for (int i = 0; i < count; ++i) {
    const Placement& pl = placements[i];
    if (pl.quality_fallback && !quality_refused) continue;
    if (mesh.is_frozen(pl.u) || mesh.is_frozen(pl.v) || mesh.is_pinned(pl.v) ||
        (mesh.is_pinned(pl.u) && pl.p != mesh.positions[pl.u])) {
      reject(CollapseReason::kPinned);
      continue;
    }
    if (pl.u != gathered_u || pl.v != gathered_v) {
      if (pl.u == gathered_v && pl.v == gathered_u) {
        // Same edge, other direction: the new star is the same.
        std::swap(s.star_u, s.star_v);
        std::swap(s.have_u, s.have_v);
      } else {
        reset_stars(s);
      }
      gathered_u = pl.u;
      gathered_v = pl.v;
    }
    // Geometry first (inversion, then quality): it is cheap once the edge is prepared and by far
    // the most frequent rejection; the link conditions (placement-independent) come after it.
    // At an endpoint, the tets around that endpoint do not move, and its star is not needed yet.
    const VertId staying = pl.p == mesh.positions[pl.u] ? pl.u : (pl.p == mesh.positions[pl.v] ? pl.v : kInvalid);
    if (!need_stars(mesh, pl.u, pl.v, staying != pl.u, staying != pl.v, s)) {
      reject(CollapseReason::kLinkK);  // not an edge
      uncertain();
      return -1;
    }
    double new_quality = 0.0, new_dihedral = 1.0;
    std::array<TetId, 2> worst_at{};
    if (!new_star_geometry(mesh, s, pl.p, staying, options.dihedral_floor, new_quality, new_dihedral, worst_at)) {
      reject(CollapseReason::kInversion);
      witness(s.new_star.front().tet);  // moved to the front by new_star_geometry
      continue;
    }
    need_stars(mesh, pl.u, pl.v, true, true, s);  // the rest needs the whole stencil
    // Quality: the new star may not be worse than min(floor, worst of the old star). Above the
    // floor that holds whatever the old star was, so the old star is measured only below it.
    // A refusal by the floor itself (the old star above it) is witnessed by the new tet below
    // it; one by the old star's worst is not (the old star changes with every nearby collapse).
    // (The floor's witness holds while the stars keep no tet worse than that new one: collapses
    // keep every new star above min(floor, its old worst), so a tet below the floor reaches a
    // star only from a worse one nearby, which is rare. A ban is never a safety matter.)
    const double floor3 = options.quality_floor * options.quality_floor * options.quality_floor;
    if (new_quality < floor3) {
      if (old_quality < 0.0) old_quality = old_star_quality(mesh, s);
      if (new_quality < std::min(floor3, old_quality)) {
        reject(CollapseReason::kQuality);
        quality_refused = true;
        if (old_quality >= floor3) witness(worst_at[0]); else uncertain();
        continue;
      }
    }
    // The dihedral floor, by the same rule: min(floor, smallest angle of the old star).
    if (new_dihedral < options.dihedral_floor.sine_sq) {
      if (old_dihedral < 0.0) old_dihedral = old_star_dihedral(mesh, s, options.dihedral_floor);
      if (new_dihedral < std::min(options.dihedral_floor.sine_sq, old_dihedral)) {
        reject(CollapseReason::kQuality);
        quality_refused = true;
        if (old_dihedral >= options.dihedral_floor.sine_sq) witness(worst_at[1]); else uncertain();
        continue;
      }
    }
    uncertain();  // whatever refuses this placement from here on may change with the stencil
    if (check_topology && !link_done) {
      s.link.known_interior = hints;  // consumed (reset) by check_link_conditions
      const LinkResult link = check_link_conditions(mesh, pl.u, pl.v, s.star_uv, s.link);
      if (link != LinkResult::kOk) {
        reject(link == LinkResult::kLinkK ? CollapseReason::kLinkK : CollapseReason::kLinkKtilde);
        return -1;  // the same for every placement of this edge
      }
      link_done = true;
    }
    if (options.surfaces != nullptr && !within_tolerance(mesh, pl, options, s, surface_edge)) {
      reject(CollapseReason::kTolerance);
      continue;
    }
    if (options.field_bounds != nullptr && options.field_bounds->has_limit() && !within_field_bounds(mesh, pl, *options.field_bounds, s)) {
      reject(CollapseReason::kFieldError);
      continue;
    }
    return i;
  }
  return -1;
}

CollapseReason may_collapse(const MeshModel& mesh, VertId u, VertId v, const glm::dvec3& p,
                            const CollapseOptions& options, CollapseScratch& s) {
  std::array<std::uint64_t, kCollapseReasonCount> rejected{};
  const Placement placement{u, v, p};
  if (first_acceptable(mesh, &placement, 1, options, s, &rejected) == 0) return CollapseReason::kOk;
  for (int r = 1; r < kCollapseReasonCount; ++r)
    if (rejected[r] != 0) return static_cast<CollapseReason>(r);
  return CollapseReason::kLinkK;
}

void reserve_refs_headroom(MeshModel& mesh, std::uint32_t refs_used, std::size_t count) {
  if (mesh.refs_table.size() < refs_used + count)
    mesh.refs_table.resize(std::max<std::size_t>(refs_used + count, mesh.refs_table.size() * 3 / 2));
}

float collapse(MeshModel& mesh, VertId u, VertId v, const glm::dvec3& p, const double* fields_at_p,
               CollapseScratch& s, std::uint32_t& refs_used, FieldBounds* bounds, SurfaceCoverage* coverage) {
  gather_stars(mesh, u, v, s);
  // The original surface items of the faces that move, placed on the new faces and stored now:
  // they are keyed by tet ids and local faces, which the collapse keeps.
  if (coverage != nullptr && coverage->reference().on_surface(u)) {
    const bool checked = s.coverage_for.u == u && s.coverage_for.v == v && s.coverage_for.p == p;
    if (!checked) {
      gather_surface_stencil(mesh, coverage->reference(), u, v, s.star_u, s.star_v, s.star_uv, s.surface);
      if (!new_surface_around(mesh, u, v, p, s.surface) ||
          !coverage->place(mesh, u, v, s.star_u, s.star_v, s.star_uv, s.surface, s.coverage))
        throw std::logic_error("collapse: a placement the check accepted leaves the original surface uncovered");
    }
    coverage->commit(mesh, u, v, s.star_u, s.star_v, s.star_uv, s.coverage);
    s.coverage_for.u = kInvalid;
  } else if (coverage != nullptr) {
    coverage->keep_segments_of_removed_tets(mesh, s.star_u, s.star_v, s.star_uv);
  }
  // 0. The field bounds of the new star, from the mesh as it is (nothing written yet); stored at once:
  //    they are keyed by tet ids, which the collapse keeps.
  float star_bound = 0.0f;
  if (bounds != nullptr) {
    bound_star(s, s.bounds);
    bounds->evaluate(mesh, s.star_uv, u, p, fields_at_p, s.bounds, false);
    star_bound = bounds->commit(s.star_uv, s.bounds);
  }

  // 1. The flagged faces and edges through u or v in the old stencil, with v renamed to u: only
  //    those can change (a face or edge away from u and v keeps its vertices, its tets and its
  //    flags). Faces and edges that contain both u and v degenerate and vanish with St(uv); merged
  //    ones (uxy and vxy of a removed tet uvxy, ux and vx of a removed face uvx) appear twice and
  //    are united below (the listed ref wins over an implicit interface: refs sort descending).
  s.faces.clear();
  s.edges.clear();
  auto collect = [&](TetId t) {
    const TetFlags fl = mesh.flags[t];
    if (!(fl & (tet_flag::kSurfaceFaces | tet_flag::kPolylineEdges))) return;
    const SubstructureRefs& refs = mesh.refs_table[mesh.tet_refs_slot[t]];
    const auto r = renamed(mesh.tets[t], v, u);
    for (int f = 0; f < 4; ++f) {
      if (!is_surface_face(fl, f)) continue;
      VertId others[3];
      int n = 0, at_u = 0;
      for (int k = 0; k < 4; ++k) {
        if (k == f) continue;
        if (r[k] == u)
          ++at_u;
        else
          others[n++] = r[k];
      }
      if (at_u == 1) s.faces.push_back({pack_pair(others[0], others[1]), refs.face[f]});
    }
    for (int e = 0; e < 6; ++e) {
      if (!is_polyline_edge(fl, e)) continue;
      const VertId x = r[kTetEdges[e][0]], y = r[kTetEdges[e][1]];
      if ((x == u) != (y == u)) s.edges.push_back({x == u ? y : x, refs.edge[e], ((refs.ridge_mask >> e) & 1u) != 0});
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
  s.merged.erase(std::remove_if(s.merged.begin(), s.merged.end(),
                                [&](TetId t) { return std::find(s.star_uv.begin(), s.star_uv.end(), t) != s.star_uv.end(); }),
                 s.merged.end());
  std::uint32_t last = u;
  while (mesh.v2t_next[last] != kInvalid) last = mesh.v2t_next[last];
  mesh.v2t_next[last] = v;
  write_incidence(mesh, u, s.merged);
  mesh.v2t_count[v] = 0;
  // The link of uv is a cycle (or a path): each of its vertices lies in two removed tets; drop the
  // dead tets from its list once.
  s.link_vertices.clear();
  for (TetId t : s.star_uv)
    for (VertId x : mesh.tets[t])
      if (x != u && x != v && std::find(s.link_vertices.begin(), s.link_vertices.end(), x) == s.link_vertices.end())
        s.link_vertices.push_back(x);
  for (VertId x : s.link_vertices) drop_dead_tets(mesh, x, s.star_uv);

  // 4. Recompute the flags and refs of the faces and edges through u in the new star from the
  //    collected set (never patched by cases); the face and edges opposite u keep theirs. Nothing
  //    collected means no flag changes: the usual interior collapse.
  std::atomic_ref<std::uint32_t> used(refs_used);
  const bool nothing_through_u = s.faces.empty() && s.edges.empty();  // every flag stays as it is
  for (TetId t : nothing_through_u ? std::span<const TetId>() : std::span<const TetId>(s.merged)) {
    const TetFlags old_flags = mesh.flags[t];
    const auto& tv = mesh.tets[t];
    const int cu = tv[0] == u ? 0 : tv[1] == u ? 1 : tv[2] == u ? 2 : 3;
    // Kept: face cu and the edges of that face.
    TetFlags fl = old_flags & TetFlags(1u << (tet_flag::kSurfaceFaceShift + cu));
    for (int e = 0; e < 6; ++e)
      if (kTetEdges[e][0] != cu && kTetEdges[e][1] != cu) fl |= old_flags & TetFlags(1u << (tet_flag::kPolylineEdgeShift + e));
    SubstructureRefs refs;
    if (old_flags != 0) refs = mesh.refs_table[mesh.tet_refs_slot[t]];
    refs.ridge_mask &= static_cast<std::uint8_t>(fl >> tet_flag::kPolylineEdgeShift);
    for (int f = 0; f < 4; ++f) {
      if (f == cu) continue;
      int o[2], n = 0;
      for (int k = 0; k < 4; ++k)
        if (k != f && k != cu) o[n++] = k;
      const std::uint64_t key = pack_pair(tv[o[0]], tv[o[1]]);
      const auto it = std::lower_bound(s.faces.begin(), s.faces.end(), CollapseScratch::FlaggedFace{key, INT32_MAX});
      if (it != s.faces.end() && it->key == key) {
        fl |= TetFlags(1u << (tet_flag::kSurfaceFaceShift + f));
        refs.face[f] = it->ref;
      }
    }
    for (int e = 0; e < 6; ++e) {
      if (kTetEdges[e][0] != cu && kTetEdges[e][1] != cu) continue;
      const VertId other = tv[kTetEdges[e][0] == cu ? kTetEdges[e][1] : kTetEdges[e][0]];
      const auto it = std::lower_bound(s.edges.begin(), s.edges.end(), CollapseScratch::FlaggedEdge{other, INT32_MAX, false});
      if (it != s.edges.end() && it->key == other) {
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
  mesh.vertex_states[u] |= vertex_state::kReshaped;  // every tet of u's new star is new or moved
  // v is in this collapse's stencil, so no other collapse of the round writes its entry.
  if (!mesh.merged_into.empty()) mesh.merged_into[v] = u;
  return star_bound;
}

}  // namespace topotet
