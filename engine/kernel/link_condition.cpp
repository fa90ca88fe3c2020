// Link conditions (see link_condition.h for the orders and the tests (A)-(I)).
#include "kernel/link_condition.h"

#include <algorithm>
#include <span>

#include "mesh/prefetch.h"
#include "mesh/probe_set.h"

namespace topotet {
namespace {

constexpr std::int32_t kNoRef = INT32_MIN + 1;        // special face that is not flagged (plain boundary)
constexpr std::int32_t kBoundarySide = INT32_MIN;     // "material" on the outer side of a boundary face
constexpr int kFiltrationK = 0, kFiltrationKtilde = 1;

std::uint64_t pack(VertId x, VertId y) {
  return x < y ? (std::uint64_t{x} << 32) | y : (std::uint64_t{y} << 32) | x;
}

// The local vertices of face f other than la (both != f): kFaceOthers[la][f].
constexpr std::array<std::array<std::array<std::uint8_t, 2>, 4>, 4> kFaceOthers = [] {
  std::array<std::array<std::array<std::uint8_t, 2>, 4>, 4> t{};
  for (int la = 0; la < 4; ++la)
    for (int f = 0; f < 4; ++f) {
      int m = 0;
      for (int k = 0; k < 4 && m < 2; ++k)
        if (k != f && k != la) t[la][f][m++] = static_cast<std::uint8_t>(k);
    }
  return t;
}();

int local_of(const std::array<VertId, 4>& v, VertId a) {
  for (int k = 0; k < 4; ++k)
    if (v[k] == a) return k;
  return -1;
}

using Neighbour = LinkScratch::Neighbour;
using VertexData = LinkScratch::VertexData;

Neighbour* find_neighbour(VertexData& d, VertId x) {
  auto it = std::lower_bound(d.neighbours.begin(), d.neighbours.end(), x,
                             [](const Neighbour& n, VertId key) { return n.x < key; });
  return (it != d.neighbours.end() && it->x == x) ? &*it : nullptr;
}
const Neighbour* find_neighbour(const VertexData& d, VertId x) {
  return find_neighbour(const_cast<VertexData&>(d), x);
}

bool is_special_in(const LinkScratch::SpecialFace& s, int filtration) {
  return filtration == kFiltrationKtilde || s.boundary;
}

// The two link neighbours of x in the graph of special faces (filtration f); x must have count 2.
bool other_two(const VertexData& d, int f, VertId x, VertId out[2]) {
  int n = 0;
  for (const auto& s : d.special) {
    if (!is_special_in(s, f)) continue;
    if (s.x == x || s.y == x) {
      if (n == 2) return false;
      out[n++] = s.x == x ? s.y : s.x;
    }
  }
  return n == 2;
}

std::size_t node_count(const VertexData& d, int f) {
  std::size_t n = 0;
  for (const Neighbour& nb : d.neighbours) n += nb.order[f] >= 1 ? 1 : 0;
  return n;
}

// Order 1 shape: the special faces around a form exactly one cycle through all order>=1 neighbours.
bool is_single_cycle(const VertexData& d, int f) {
  const std::size_t nodes = node_count(d, f);
  VertId start = kInvalid;
  for (const Neighbour& nb : d.neighbours) {
    if (nb.order[f] == 0) continue;
    if (nb.count[f] != 2) return false;
    if (start == kInvalid) start = nb.x;
  }
  if (start == kInvalid) return false;
  VertId adj[2];
  if (!other_two(d, f, start, adj)) return false;
  VertId prev = start, cur = adj[0];
  std::size_t steps = 1;
  while (cur != start) {
    if (!other_two(d, f, cur, adj)) return false;
    const VertId next = adj[0] == prev ? adj[1] : adj[0];
    prev = cur;
    cur = next;
    if (++steps > nodes) return false;
  }
  return steps == nodes;
}

// Order 2 shape: the special faces around a form k arcs from x1 to x2 covering every other
// order>=1 neighbour exactly once (k half-disks glued along the curve x1-a-x2).
bool is_curve_point(const VertexData& d, int f, VertId x1, VertId x2) {
  const std::size_t nodes = node_count(d, f);
  std::size_t visited = 0;
  for (const auto& s : d.special) {
    if (!is_special_in(s, f) || (s.x != x1 && s.y != x1)) continue;
    VertId prev = x1, cur = s.x == x1 ? s.y : s.x;
    while (cur != x2) {
      if (cur == x1) return false;
      const Neighbour* nb = find_neighbour(d, cur);
      if (nb == nullptr || nb->count[f] != 2) return false;
      VertId adj[2];
      if (!other_two(d, f, cur, adj)) return false;
      const VertId next = adj[0] == prev ? adj[1] : adj[0];
      prev = cur;
      cur = next;
      if (++visited > nodes) return false;
    }
  }
  return visited + 2 == nodes;
}

void face_labels_at(const VertexData& d, VertId x, std::vector<LinkScratch::Label>& out) {
  out.clear();
  for (const auto& s : d.special)
    if (s.x == x || s.y == x) out.push_back(s.label);
  std::sort(out.begin(), out.end());
}

std::uint8_t vertex_order(const MeshModel& mesh, VertId a, const VertexData& d, int f, LinkScratch& scratch) {
  if (d.non_manifold) return 3;
  if (f == kFiltrationKtilde && mesh.is_pinned(a)) return 3;
  const Neighbour* c2[2] = {nullptr, nullptr};
  int c2_count = 0;
  bool has_special = false;
  for (const Neighbour& nb : d.neighbours) {
    if (nb.order[f] == 2) {
      if (c2_count == 2) return 3;  // three or more curve edges: a junction
      c2[c2_count++] = &nb;
    }
    has_special |= nb.count[f] > 0;
  }
  if (c2_count == 1) return 3;  // a curve ends here
  if (c2_count == 2) {
    if (c2[0]->count[f] != c2[1]->count[f]) return 3;
    if (f == kFiltrationKtilde) {
      if (c2[0]->polyline != c2[1]->polyline || (c2[0]->polyline && c2[0]->polyline_ref != c2[1]->polyline_ref))
        return 3;
      face_labels_at(d, c2[0]->x, scratch.labels_x1);
      face_labels_at(d, c2[1]->x, scratch.labels_x2);
      if (scratch.labels_x1 != scratch.labels_x2) return 3;  // the curve changes kind here
    }
    return is_curve_point(d, f, c2[0]->x, c2[1]->x) ? 2 : 3;
  }
  if (has_special) return is_single_cycle(d, f) ? 1 : 3;
  return 0;
}

// Sorted intersection of two sorted ranges, projected by key(); calls f(key) for common keys.
template <class It1, class It2, class Key1, class Key2, class F>
bool all_common(It1 b1, It1 e1, It2 b2, It2 e2, Key1 k1, Key2 k2, F&& ok) {
  while (b1 != e1 && b2 != e2) {
    const auto x = k1(*b1), y = k2(*b2);
    if (x < y) {
      ++b1;
    } else if (y < x) {
      ++b2;
    } else {
      if (!ok(x)) return false;
      ++b1;
      ++b2;
    }
  }
  return true;
}

// For a vertex known to be of order 0: only the neighbour list (for test (A)) is needed.
void interior_neighbours(const MeshModel& mesh, VertId a, VertexData& d, LinkScratch& scratch) {
  d.vertex = kInvalid;  // not a classification
  d.recs.clear();
  d.special.clear();
  d.neighbours.clear();
  d.non_manifold = false;
  d.orders = {0, 0};
  auto& nbv = scratch.tmp_vertices;
  mesh.neighbours(a, nbv);
  for (VertId x : nbv) d.neighbours.push_back(Neighbour{x, {0, 0}, {0, 0}, false, false, 0, {}});
}

// (A)-(C) for an edge whose ends are both interior (order 0 in both filtrations, so (D)-(I) hold
// trivially). Returns the failed test, 0 when all hold, or '?' when the star is too unusual for
// this path (the caller then runs the general one). C = the vertices of St(ab) other than a, b
// (the link of ab); every common neighbour of a and b that spans a triangle with ab is in C.
//   (A) a common neighbour outside C;
//   (B) a pair of C joined by an edge of Lk(a) and of Lk(b) (some tet of each star holds both)
//       that is not a pair of a tet of St(ab);
//   (C) a triple of C that is a face of Lk(a) and of Lk(b).
// With (A) passed the common neighbours are exactly C, which is the domain the general tests
// range over, so the answers agree.
char interior_link_test(const MeshModel& mesh, VertId a, VertId b, const std::vector<TetId>& stab, LinkScratch& s) {
  auto& c = s.common;
  c.clear();
  for (TetId t : stab)
    for (VertId x : mesh.tets[t])
      if (x != a && x != b && std::find(c.begin(), c.end(), x) == c.end()) c.push_back(x);
  if (c.size() > 32) return '?';
  // a's neighbours in a probe set, each tagged with its index in C (-1: not in C).
  const std::size_t slots = probe_slots_for(3 * static_cast<std::size_t>(mesh.v2t_count[a]));
  std::array<VertId, 512> keys;
  std::array<std::int8_t, 512> tag;
  if (slots > keys.size()) return '?';
  ProbeSet<VertId> around_a(std::span<VertId>(keys.data(), slots));
  // Bit j of adjacency[i]: the pair (c_i, c_j) lies in a tet of the star (an edge of its link).
  std::array<std::uint32_t, 32> adj_a{}, adj_b{}, adj_ab{};
  auto& triples_a = s.pairs_a;
  auto& triples_b = s.pairs_b;
  triples_a.clear();
  triples_b.clear();
  const auto record = [](const int* idx, int n, std::array<std::uint32_t, 32>& adj, std::vector<std::uint64_t>& triples) {
    for (int p = 0; p < n; ++p)
      for (int q = p + 1; q < n; ++q) {
        adj[idx[p]] |= 1u << idx[q];
        adj[idx[q]] |= 1u << idx[p];
      }
    if (n == 3) {
      int sorted[3] = {idx[0], idx[1], idx[2]};
      std::sort(sorted, sorted + 3);
      triples.push_back((std::uint64_t(sorted[0]) << 16) | (std::uint64_t(sorted[1]) << 8) | std::uint64_t(sorted[2]));
    }
  };
  mesh.for_each_tet_of(a, [&](TetId t) {
    int idx[3], n = 0;
    for (VertId x : mesh.tets[t]) {
      if (x == a) continue;
      const auto [slot, fresh] = around_a.insert(x);
      if (fresh) {
        const auto it = std::find(c.begin(), c.end(), x);
        tag[slot] = it == c.end() ? std::int8_t{-1} : static_cast<std::int8_t>(it - c.begin());
      }
      if (tag[slot] >= 0) idx[n++] = tag[slot];
    }
    record(idx, n, adj_a, triples_a);
  });
  // (A) and St(b)'s side of (B), (C) in one pass.
  bool failed_a = false;
  mesh.for_each_tet_of(b, [&](TetId t) {
    int idx[3], n = 0;
    for (VertId x : mesh.tets[t]) {
      if (x == a || x == b) continue;
      const std::uint32_t slot = around_a.find(x);
      if (slot == ProbeSet<VertId>::kNotFound) continue;  // not a common neighbour
      if (tag[slot] < 0) failed_a = true;                 // a common neighbour outside Lk(ab)
      else idx[n++] = tag[slot];
    }
    record(idx, n, adj_b, triples_b);
  });
  if (failed_a) return 'A';
  for (TetId t : stab) {
    int idx[2], n = 0;
    for (VertId x : mesh.tets[t])
      if (x != a && x != b) idx[n++] = tag[around_a.find(x)];
    adj_ab[idx[0]] |= 1u << idx[1];
    adj_ab[idx[1]] |= 1u << idx[0];
  }
  for (std::size_t i = 0; i < c.size(); ++i)
    if ((adj_a[i] & adj_b[i] & ~adj_ab[i]) != 0) return 'B';
  for (std::uint64_t x : triples_a)
    if (std::find(triples_b.begin(), triples_b.end(), x) != triples_b.end()) return 'C';
  return 0;
}

}  // namespace

VertexOrders classify_vertex(const MeshModel& mesh, VertId a, VertexData& d, LinkScratch& scratch) {
  d.vertex = a;  // every path below fills d from St(a) alone
  d.recs.clear();
  d.special.clear();
  d.neighbours.clear();
  d.non_manifold = false;

  // One walk over St(a) (in chain order: ascending tet ids) collects a's neighbours, the faces
  // through a (grouped below by their two other vertices) and the polyline edges at a.
  auto& nbv = scratch.tmp_vertices;
  nbv.clear();
  scratch.vertex_slots.resize(probe_slots_for(3 * static_cast<std::size_t>(mesh.v2t_count[a])));
  ProbeSet<VertId> seen(scratch.vertex_slots);
  auto& polylines = scratch.polyline_ends;  // (other end, ref), in chain order
  polylines.clear();
  prefetch_star(mesh, a);
  mesh.for_each_tet_of(a, [&](TetId t) {
    const auto& v = mesh.tets[t];
    const int la = local_of(v, a);
    for (int k = 0; k < 4; ++k)
      if (k != la && seen.insert(v[k]).second) nbv.push_back(v[k]);
    for (int f = 0; f < 4; ++f) {
      if (f == la) continue;
      const auto& o = kFaceOthers[la][f];
      d.recs.push_back({pack(v[o[0]], v[o[1]]), t, static_cast<std::uint8_t>(f)});
    }
    const TetFlags fl = mesh.flags[t];
    if (!(fl & tet_flag::kPolylineEdges)) return;
    for (int e = 0; e < 6; ++e) {
      if (!is_polyline_edge(fl, e) || (kTetEdges[e][0] != la && kTetEdges[e][1] != la)) continue;
      polylines.push_back({v[kTetEdges[e][0] == la ? kTetEdges[e][1] : kTetEdges[e][0]],
                           mesh.refs_table[mesh.tet_refs_slot[t]].edge[e]});
    }
  });
  std::sort(nbv.begin(), nbv.end());
  for (VertId x : nbv) d.neighbours.push_back(Neighbour{x, {0, 0}, {0, 0}, false, false, 0, {}});

  scratch.face_slots.resize(probe_slots_for(d.recs.size()));
  scratch.slot_group.resize(scratch.face_slots.size());
  ProbeSet<std::uint64_t> faces(scratch.face_slots);
  auto& groups = scratch.face_groups;  // in order of first appearance: deterministic
  groups.clear();
  for (std::uint32_t i = 0; i < d.recs.size(); ++i) {
    const LinkScratch::FaceRec& r = d.recs[i];
    const bool flagged = is_surface_face(mesh.flags[r.tet], r.local_face);
    const auto [slot, fresh] = faces.insert(r.key);
    if (fresh) {
      scratch.slot_group[slot] = static_cast<std::uint32_t>(groups.size());
      groups.push_back({1, i, kInvalid, flagged ? i : kInvalid});
      continue;
    }
    LinkScratch::FaceGroup& g = groups[scratch.slot_group[slot]];
    if (++g.count == 2) g.second = i;
    if (flagged) g.last_flagged = i;  // the flagged tet of highest id gives the ref
  }

  for (const LinkScratch::FaceGroup& g : groups) {
    if (g.count > 2) d.non_manifold = true;
    const bool boundary = g.count == 1;
    const LinkScratch::FaceRec& first = d.recs[g.first];
    if (boundary || g.last_flagged != kInvalid) {
      LinkScratch::Label label{kNoRef, 0, 0};
      if (g.last_flagged != kInvalid) {
        const LinkScratch::FaceRec& flagged = d.recs[g.last_flagged];
        label.ref = mesh.refs_table[mesh.tet_refs_slot[flagged.tet]].face[flagged.local_face];
      }
      const std::int32_t m0 = mesh.material[first.tet];
      const std::int32_t m1 = boundary ? kBoundarySide : mesh.material[d.recs[g.second].tet];
      label.m0 = std::min(m0, m1);
      label.m1 = std::max(m0, m1);
      d.special.push_back({first.x(), first.y(), label, boundary});
      for (VertId x : {first.x(), first.y()}) {
        Neighbour* nb = find_neighbour(d, x);
        nb->count[kFiltrationK] += boundary ? 1 : 0;
        if (nb->count[kFiltrationKtilde]++ == 0)
          nb->first_label = label;
        else if (!(nb->first_label == label))
          nb->mixed_labels = true;
      }
    }
  }

  for (const auto& [x, ref] : polylines) {  // the last tet in chain order gives the ref
    Neighbour* nb = find_neighbour(d, x);
    nb->polyline = true;
    nb->polyline_ref = ref;
  }

  for (Neighbour& nb : d.neighbours) {
    const std::uint8_t ck = nb.count[kFiltrationK], ckt = nb.count[kFiltrationKtilde];
    nb.order[kFiltrationK] = ck == 0 ? 0 : (ck != 2 ? 2 : 1);
    nb.order[kFiltrationKtilde] = nb.polyline ? 2 : (ckt == 0 ? 0 : ((ckt != 2 || nb.mixed_labels) ? 2 : 1));
  }
  d.orders.k = vertex_order(mesh, a, d, kFiltrationK, scratch);
  d.orders.ktilde = vertex_order(mesh, a, d, kFiltrationKtilde, scratch);
  return d.orders;
}

bool is_interior_vertex(const MeshModel& mesh, VertId a) {
  if (mesh.is_pinned(a)) return false;
  // Faces through a, keyed by their two other vertices, counted in a probe set on the stack (3
  // faces per tet; stars of more than 170 tets take the classification instead).
  const std::size_t items = 3 * static_cast<std::size_t>(mesh.v2t_count[a]);
  const std::size_t slots = probe_slots_for(items);
  std::array<std::uint64_t, 512> keys;
  std::array<std::uint8_t, 512> counts;
  if (slots > keys.size()) return false;
  ProbeSet<std::uint64_t> faces(std::span<std::uint64_t>(keys.data(), slots));
  prefetch_star(mesh, a);
  bool special = false;  // a flagged face or edge through a, or a face in three or more tets
  std::size_t distinct = 0;
  mesh.for_each_tet_of(a, [&](TetId t) {
    const auto& v = mesh.tets[t];
    const int la = local_of(v, a);
    const TetFlags fl = mesh.flags[t];
    for (int f = 0; f < 4; ++f) {
      if (f == la) continue;
      special |= is_surface_face(fl, f);  // face f contains a (it is opposite another corner)
      const auto& o = kFaceOthers[la][f];
      const auto [slot, fresh] = faces.insert(pack(v[o[0]], v[o[1]]));
      if (fresh) {
        counts[slot] = 1;
        ++distinct;
      } else {
        special |= ++counts[slot] > 2;
      }
    }
    for (int e = 0; e < 6; ++e)
      if (is_polyline_edge(fl, e) && (kTetEdges[e][0] == la || kTetEdges[e][1] == la)) special = true;
  });
  // No count above 2 and 3|St(a)| = 2 * distinct: every face through a is in exactly two tets
  // (none on the boundary).
  return !special && 2 * distinct == items;
}

VertexOrders vertex_orders(const MeshModel& mesh, VertId a, LinkScratch& scratch) {
  return classify_vertex(mesh, a, scratch.a, scratch);
}

LinkResult check_link_conditions(const MeshModel& mesh, VertId a, VertId b, const std::vector<TetId>& stab,
                                 LinkScratch& scratch) {
  // Reusing classifications (ReuseClassifications): a slot holding b's, or the other slot holding
  // a's, trades places, so that each end finds its own.
  const bool reuse = scratch.reuse_classified;
  if (reuse && (scratch.a.vertex == b || scratch.b.vertex == a)) std::swap(scratch.a, scratch.b);
  VertexData& da = scratch.a;
  VertexData& db = scratch.b;
  scratch.failed_test = 0;
  auto failed = [&](char test, int filtration) {
    scratch.failed_test = test;
    scratch.failed_filtration = filtration;
    return filtration == kFiltrationK ? LinkResult::kLinkK : LinkResult::kLinkKtilde;
  };
  const auto hinted = [&](VertId x) { return scratch.known_interior[0] == x || scratch.known_interior[1] == x; };
  const bool interior_a = hinted(a), interior_b = hinted(b);
  scratch.known_interior = {kInvalid, kInvalid};
  if (interior_a && interior_b) {
    const char test = interior_link_test(mesh, a, b, stab, scratch);
    if (test == 0) return LinkResult::kOk;
    if (test != '?') return failed(test, kFiltrationK);
  }
  if (interior_a)
    interior_neighbours(mesh, a, da, scratch);
  else if (!reuse || da.vertex != a)
    classify_vertex(mesh, a, da, scratch);
  if (interior_b)
    interior_neighbours(mesh, b, db, scratch);
  else if (!reuse || db.vertex != b)
    classify_vertex(mesh, b, db, scratch);

  // (A) every common neighbour x spans a triangle abx: x is a vertex of a tet of St(ab).
  auto& common = scratch.common;
  common.clear();
  const auto nx = [](const Neighbour& n) { return n.x; };
  all_common(da.neighbours.begin(), da.neighbours.end(), db.neighbours.begin(), db.neighbours.end(), nx, nx,
             [&](VertId x) {
               if (x != a && x != b) common.push_back(x);
               return true;
             });
  auto& lk_ab = scratch.tmp_vertices;
  lk_ab.clear();
  auto& pairs_ab = scratch.pairs_ab;
  pairs_ab.clear();
  for (TetId t : stab) {
    VertId o[2];
    int n = 0;
    for (VertId x : mesh.tets[t])
      if (x != a && x != b) o[n++] = x;
    lk_ab.push_back(o[0]);
    lk_ab.push_back(o[1]);
    pairs_ab.push_back(pack(o[0], o[1]));
  }
  std::sort(lk_ab.begin(), lk_ab.end());
  for (VertId x : common)
    if (!std::binary_search(lk_ab.begin(), lk_ab.end(), x)) return failed('A', kFiltrationK);

  // (B) and (C) concern link edges and triangles whose vertices are all common neighbours, so
  // only the faces opposite a (resp. b) inside `common` matter: a handful, not the whole link.
  const auto in_common = [&](VertId x) { return std::binary_search(common.begin(), common.end(), x); };
  auto collect = [&](VertId c, std::vector<std::uint64_t>& pairs, std::vector<std::array<VertId, 3>>& faces) {
    pairs.clear();
    faces.clear();
    mesh.for_each_tet_of(c, [&](TetId t) {
      VertId o[3];
      int n = 0;
      for (VertId x : mesh.tets[t])
        if (x != c && in_common(x)) o[n++] = x;
      if (n >= 2) {
        pairs.push_back(pack(o[0], o[1]));
        if (n == 3) {
          pairs.push_back(pack(o[0], o[2]));
          pairs.push_back(pack(o[1], o[2]));
          std::array<VertId, 3> f{o[0], o[1], o[2]};
          std::sort(f.begin(), f.end());
          faces.push_back(f);
        }
      }
    });
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    std::sort(faces.begin(), faces.end());
  };
  collect(a, scratch.pairs_a, scratch.faces_a);
  collect(b, scratch.pairs_b, scratch.faces_b);
  std::sort(pairs_ab.begin(), pairs_ab.end());
  const auto id = [](std::uint64_t e) { return e; };
  if (!all_common(scratch.pairs_a.begin(), scratch.pairs_a.end(), scratch.pairs_b.begin(), scratch.pairs_b.end(), id, id,
                  [&](std::uint64_t e) { return std::binary_search(pairs_ab.begin(), pairs_ab.end(), e); }))
    return failed('B', kFiltrationK);
  const auto fid = [](const std::array<VertId, 3>& f) { return f; };
  if (!all_common(scratch.faces_a.begin(), scratch.faces_a.end(), scratch.faces_b.begin(), scratch.faces_b.end(), fid, fid,
                  [](const std::array<VertId, 3>&) { return false; }))
    return failed('C', kFiltrationK);

  const Neighbour* ab = find_neighbour(da, b);
  for (int f : {kFiltrationK, kFiltrationKtilde}) {
    const std::uint8_t oa = f == kFiltrationK ? da.orders.k : da.orders.ktilde;
    const std::uint8_t ob = f == kFiltrationK ? db.orders.k : db.orders.ktilde;
    const std::uint8_t oab = ab->order[f];
    if (oa >= 1 && ob >= 1 && oab < 1) return failed('D', f);
    if (oa >= 2 && ob >= 2 && oab < 2) return failed('G', f);
    if (oa == 3 && ob == 3) return failed('I', f);
    if (oa == 0 || ob == 0) continue;                // (E), (F), (H) need special simplices at both ends

    auto abx_special = [&](VertId x) {
      const std::uint64_t key = pack(b, x);
      for (const auto& s : da.special)
        if (pack(s.x, s.y) == key) return is_special_in(s, f);
      return false;
    };
    // (E) and (H): walk the common neighbours once.
    std::size_t i = 0, j = 0;
    while (i < da.neighbours.size() && j < db.neighbours.size()) {
      const Neighbour& p = da.neighbours[i];
      const Neighbour& q = db.neighbours[j];
      if (p.x < q.x) {
        ++i;
      } else if (q.x < p.x) {
        ++j;
      } else {
        if (p.x != a && p.x != b) {
          if (p.order[f] == 2 && q.order[f] == 2) return failed('H', f);
          if (p.order[f] >= 1 && q.order[f] >= 1 && !abx_special(p.x)) return failed('E', f);
        }
        ++i;
        ++j;
      }
    }
    // (F) no link edge xy with both axy and bxy special. Faces at a through b, or at b through a,
    // are faces abx: they are never equal to a face at the other end.
    for (const auto& s : da.special) {
      if (!is_special_in(s, f) || s.x == b || s.y == b) continue;
      for (const auto& r : db.special)
        if (r.x == s.x && r.y == s.y && is_special_in(r, f)) return failed('F', f);
    }
  }
  return LinkResult::kOk;
}

}  // namespace topotet
