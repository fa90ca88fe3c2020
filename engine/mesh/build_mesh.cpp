// build_tet_mesh: validate raw input, then build the model (incidence, flags, side table).
//
// The input's large arrays (positions, tets, materials, vertex refs, fields) are first loaded into
// the model's own arrays, from a MeshData here or straight from a caller's strided arrays
// (build_from_view.cpp); every check then runs on the model, so both sources share one validation
// code path and the same messages, and neither keeps a second copy of the mesh.
//
// Every check runs in parallel and reports the FIRST offending element in index order, so the
// message is the same for every thread count. Faces are matched per vertex: the faces whose
// smallest vertex is a are found in St(a), sorted and paired there, so each face is seen by exactly
// one task and no global face table (16 bytes x 4 per tet) is ever built.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "mesh/glm_convert.h"
#include "mesh/mesh_model.h"
#include "mesh/mesh_view.h"
#include "mesh/orient.h"
#include "parallel/for_range.h"
#include "topotet/error.h"

namespace topotet {
namespace {

constexpr std::uint64_t kNone = ~std::uint64_t{0};

// Smallest index i in [0, n) with bad(i), or kNone. Deterministic for any thread count.
template <class Pred>
std::uint64_t first_where(std::uint64_t n, Pred bad) {
  std::atomic<std::uint64_t> first{kNone};
  parallel::for_range<std::uint64_t>(0, n, 1u << 14, "first_where", [&](std::uint64_t b, std::uint64_t e) {
    for (std::uint64_t i = b; i < e && i < first.load(std::memory_order_relaxed); ++i) {
      if (bad(i)) {
        std::uint64_t cur = first.load(std::memory_order_relaxed);
        // relaxed is enough: we only need the minimum once the loop has joined.
        while (i < cur && !first.compare_exchange_weak(cur, i, std::memory_order_relaxed)) {
        }
        return;
      }
    }
  });
  return first.load();
}

[[noreturn]] void fail(const std::string& message) { throw InputError(message); }

// Element and vertex numbers in messages are 1-based, as in every file format the readers take
// (the readers' own messages count the same way), whatever the 0-based arrays say.
std::string one_based(std::uint64_t i) { return std::to_string(i + 1); }

std::string verts_str(const VertId* v, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) {
    if (i) s.push_back(' ');
    s.append(one_based(v[i]));
  }
  return s;
}

void check_sizes(const MeshData& d) {
  if (d.positions.size() >= kInvalid) fail("too many vertices for 32-bit ids: " + std::to_string(d.positions.size()));
  if (d.tets.size() >= kInvalid / 4) fail("too many tets for 32-bit ids: " + std::to_string(d.tets.size()));
  if (d.tets.empty()) fail("the mesh has no tetrahedra");
  if (d.tet_material.size() != d.tets.size())
    fail("tet_material has " + std::to_string(d.tet_material.size()) + " entries for " +
         std::to_string(d.tets.size()) + " tets");
  if (!d.vertex_refs.empty() && d.vertex_refs.size() != d.positions.size())
    fail("vertex_refs has " + std::to_string(d.vertex_refs.size()) + " entries for " +
         std::to_string(d.positions.size()) + " vertices");
  for (const VertexField& f : d.fields) {
    if (f.components < 1) fail("field '" + f.name + "': " + std::to_string(f.components) + " components");
    if (f.values.size() != d.positions.size() * static_cast<std::size_t>(f.components))
      fail("field '" + f.name + "' has " + std::to_string(f.values.size()) + " values for " +
           std::to_string(d.positions.size()) + " vertices x " + std::to_string(f.components) + " components");
  }
}

void check_vertices_and_tets(const MeshModel& m) {
  const std::uint64_t nv = m.positions.size();
  std::uint64_t i = first_where(nv, [&](std::uint64_t v) {
    const glm::dvec3& p = m.positions[v];
    return !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  });
  if (i != kNone) fail("vertex " + one_based(i) + ": coordinate is not finite (NaN or infinity)");
  const std::uint64_t stride = static_cast<std::uint64_t>(m.field_stride());
  std::uint64_t offset = 0;
  for (const FieldInfo& f : m.fields) {
    const std::uint64_t n = static_cast<std::uint64_t>(f.components);
    i = first_where(nv * n, [&](std::uint64_t k) { return !std::isfinite(m.field_values[k / n * stride + offset + k % n]); });
    if (i != kNone)
      fail("field '" + f.name + "', vertex " + one_based(i / n) + ": value is not finite");
    offset += n;
  }
  i = first_where(m.tets.size(), [&](std::uint64_t t) {
    const auto& v = m.tets[t];
    for (int k = 0; k < 4; ++k) {
      if (v[k] >= nv) return true;
      for (int l = 0; l < k; ++l)
        if (v[k] == v[l]) return true;
    }
    return false;
  });
  if (i != kNone) {
    const auto& v = m.tets[i];
    for (int k = 0; k < 4; ++k)
      if (v[k] >= nv)
        fail("tet " + one_based(i) + ": vertex index " + one_based(v[k]) + " out of range [1, " + std::to_string(nv) + "]");
    fail("tet " + one_based(i) + ": repeated vertex (" + verts_str(v.data(), 4) + ")");
  }
}

// Checks the orientation of m.tets, flipping all of them if all are inverted and the option allows it.
void orient_tets(const BuildOptions& options, MeshModel& m) {
  const std::size_t nt = m.tets.size();
  std::vector<std::int8_t> sign(nt);
  parallel::for_range<std::size_t>(0, nt, 1u << 12, "orient", [&](std::size_t b, std::size_t e) {
    for (std::size_t t = b; t < e; ++t) {
      const auto& v = m.tets[t];
      sign[t] = static_cast<std::int8_t>(
          orient3d_sign(m.positions[v[0]], m.positions[v[1]], m.positions[v[2]], m.positions[v[3]]));
    }
  });
  std::uint64_t i = first_where(nt, [&](std::uint64_t t) { return sign[t] == 0; });
  if (i != kNone)
    fail("tet " + one_based(i) + ": zero or near-zero volume (vertices " + verts_str(m.tets[i].data(), 4) +
         " are coplanar)");
  const bool flip = sign[0] < 0 && options.reorient_inverted &&
                    first_where(nt, [&](std::uint64_t t) { return sign[t] > 0; }) == kNone;
  if (!flip) {
    i = first_where(nt, [&](std::uint64_t t) { return sign[t] < 0; });
    if (i != kNone)
      fail("tet " + one_based(i) + ": inverted (negative volume; vertices " + verts_str(m.tets[i].data(), 4) +
           ")" + (sign[0] < 0 ? ", and not all tets are inverted, so the mesh cannot be reoriented" : ""));
  }
  if (flip)
    for (auto& v : m.tets) std::swap(v[2], v[3]);
}

// Finds the local index (0..3) of vertex x in tet t, or -1.
int local_index(const std::array<VertId, 4>& v, VertId x) {
  for (int k = 0; k < 4; ++k)
    if (v[k] == x) return k;
  return -1;
}

enum FaceKind : std::uint8_t { kBoundary = 0, kInterior = 1, kInterface = 2 };

// Classifies every tet face; fails on faces with more than two tets and on duplicate tets.
std::vector<std::uint8_t> classify_faces(const MeshModel& m) {
  const std::size_t nv = m.positions.size();
  std::vector<std::uint8_t> kind(4 * m.tets.size(), kBoundary);
  struct FaceRec {
    VertId b, c;
    std::uint32_t half_face;  // 4 * tet + local face
    bool operator<(const FaceRec& o) const {
      return b != o.b ? b < o.b : (c != o.c ? c < o.c : half_face < o.half_face);
    }
  };
  std::atomic<std::uint64_t> first_bad{kNone};  // half-face of the first bad face found by its min vertex
  parallel::for_range<std::size_t>(0, nv, 256, "classify_faces", [&](std::size_t vb, std::size_t ve) {
    std::vector<FaceRec> recs;
    for (std::size_t a = vb; a < ve; ++a) {
      recs.clear();
      m.for_each_tet_of(static_cast<VertId>(a), [&](TetId t) {
        const auto& v = m.tets[t];
        const int la = local_index(v, static_cast<VertId>(a));
        for (int f = 0; f < 4; ++f) {
          if (f == la) continue;  // the face opposite a does not contain a
          VertId o[2];
          int n = 0;
          for (int k = 0; k < 4; ++k)
            if (k != f && k != la) o[n++] = v[k];
          if (o[0] < a || o[1] < a) continue;  // a is not the smallest vertex of this face
          recs.push_back({std::min(o[0], o[1]), std::max(o[0], o[1]), 4 * t + static_cast<std::uint32_t>(f)});
        }
      });
      std::sort(recs.begin(), recs.end());
      for (std::size_t i = 0; i < recs.size();) {
        std::size_t j = i + 1;
        while (j < recs.size() && recs[j].b == recs[i].b && recs[j].c == recs[i].c) ++j;
        bool bad = j - i > 2;
        if (j - i == 2) {
          const TetId t0 = recs[i].half_face / 4, t1 = recs[i + 1].half_face / 4;
          // Same face and same opposite vertex: the two tets are the same tet listed twice.
          bad = m.tets[t0][recs[i].half_face % 4] == m.tets[t1][recs[i + 1].half_face % 4];
          if (!bad) {
            const std::uint8_t k = m.material[t0] == m.material[t1] ? kInterior : kInterface;
            kind[recs[i].half_face] = k;  // each half-face is written by exactly one task
            kind[recs[i + 1].half_face] = k;
          }
        }
        if (bad) {
          std::uint64_t hf = recs[i].half_face, cur = first_bad.load(std::memory_order_relaxed);
          while (hf < cur && !first_bad.compare_exchange_weak(cur, hf, std::memory_order_relaxed)) {
          }
        }
        i = j;
      }
    }
  });
  if (first_bad.load() != kNone) {
    // Re-derive the message deterministically from the smallest offending half-face.
    const TetId t = static_cast<TetId>(first_bad.load() / 4);
    const int f = static_cast<int>(first_bad.load() % 4);
    VertId fv[3];
    int n = 0;
    for (int k = 0; k < 4; ++k)
      if (k != f) fv[n++] = m.tets[t][k];
    std::vector<TetId> sharing;
    m.for_each_tet_of(fv[0], [&](TetId s) {
      if (local_index(m.tets[s], fv[1]) >= 0 && local_index(m.tets[s], fv[2]) >= 0) sharing.push_back(s);
    });
    std::sort(sharing.begin(), sharing.end());
    if (sharing.size() == 2)
      fail("tet " + one_based(sharing[1]) + " duplicates tet " + one_based(sharing[0]) + " (vertices " +
           verts_str(m.tets[sharing[0]].data(), 4) + ")");
    std::string list;
    for (TetId s : sharing) {
      if (!list.empty()) list.append(", ");
      list.append(one_based(s));
    }
    fail("non-manifold input: face (" + verts_str(fv, 3) + ") is shared by " + std::to_string(sharing.size()) +
         " tets (" + list + "); at most two tets may share a face");
  }
  return kind;
}

struct PlacedRef {
  TetId tet;
  std::uint8_t local;  // face (0..3) or edge (0..5)
  std::int32_t ref;
  bool ridge;
};

// Finds every tet having all `n` vertices; calls f(tet, local indices).
template <class F>
void for_each_tet_with(const MeshModel& m, const VertId* v, int n, F&& f) {
  m.for_each_tet_of(v[0], [&](TetId t) {
    int loc[3] = {-1, -1, -1};
    for (int k = 0; k < n; ++k)
      if ((loc[k] = local_index(m.tets[t], v[k])) < 0) return;
    f(t, loc);
  });
}

// One listed triangle (N = 3) or segment (N = 2): sorted vertices, ref, index in its list.
template <std::size_t N>
struct ListedKey {
  std::array<VertId, N> v;
  std::int32_t ref;
  std::uint32_t index;
  auto operator<=>(const ListedKey&) const = default;  // vertices, then ref, then index
};

// The listed elements on one face (edge) of the mesh: their refs, merged.
struct ListedGroup {
  std::uint32_t begin, end;    // range of the sorted keys
  std::uint32_t lowest_index;  // the element named in messages
  std::int32_t ref;            // the ref, or a stand-in once assign_stand_ins has run
  std::int32_t shared = -1;    // index into the shared sets when the group has several refs
  bool ridge = false;
};

// Sorts the keys and groups them by vertex set. Repeats (same vertices, same ref) are noted and
// count once; a group with several refs gets an entry in `shared_sets` (deduplicated).
template <std::size_t N>
std::vector<ListedGroup> group_listed(std::vector<ListedKey<N>>& keys, std::vector<std::uint32_t>* repeated,
                                      std::map<std::vector<std::int32_t>, std::int32_t>& shared_sets) {
  std::sort(keys.begin(), keys.end());
  std::vector<ListedGroup> groups;
  std::vector<std::int32_t> refs;
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j].v == keys[i].v) ++j;
    ListedGroup g{static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), keys[i].index, keys[i].ref};
    refs.clear();
    for (std::size_t k = i; k < j; ++k) {
      g.lowest_index = std::min(g.lowest_index, keys[k].index);
      if (k > i && keys[k].ref == keys[k - 1].ref) {
        if (repeated) repeated->push_back(keys[k].index);
      } else {
        refs.push_back(keys[k].ref);
      }
    }
    if (refs.size() > 1)
      g.shared = shared_sets.emplace(refs, static_cast<std::int32_t>(shared_sets.size())).first->second;
    groups.push_back(g);
    i = j;
  }
  if (repeated) std::sort(repeated->begin(), repeated->end());
  return groups;
}

// Gives every shared set its stand-in ref: the smallest values from kFirstStandInRef up that no
// listed element uses, in the sets' sorted order (so the same input always gets the same ones).
template <std::size_t N>
std::vector<SharedRefs> assign_stand_ins(const std::vector<ListedKey<N>>& keys,
                                         const std::map<std::vector<std::int32_t>, std::int32_t>& shared_sets,
                                         std::vector<ListedGroup>& groups) {
  if (shared_sets.empty()) return {};
  std::vector<std::int32_t> used;
  used.reserve(keys.size());
  for (const auto& k : keys) used.push_back(k.ref);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<SharedRefs> out;
  std::vector<std::int32_t> stand_in_of(shared_sets.size());
  std::int32_t next = kFirstStandInRef;
  auto u = used.begin();
  for (const auto& [refs, id] : shared_sets) {
    while (u != used.end() && *u < next) ++u;
    while (u != used.end() && *u == next) ++next, ++u;
    stand_in_of[id] = next;
    out.push_back({next, refs});
    ++next;
  }
  for (ListedGroup& g : groups)
    if (g.shared >= 0) g.ref = stand_in_of[g.shared];
  return out;
}

// Fails on, or notes, the detached groups (their lowest index named), in index order.
void handle_detached(std::vector<std::uint32_t>& detached, bool skip, std::vector<std::uint32_t>* noted,
                     const std::function<std::string(std::uint32_t)>& describe) {
  if (detached.empty()) return;
  std::sort(detached.begin(), detached.end());
  if (!skip) fail(describe(detached.front()));
  if (noted) *noted = std::move(detached);
}

std::vector<PlacedRef> place_triangles(const detail::ListedSubstructures& d, const MeshModel& m, const BuildOptions& options,
                                       BuildNotes* notes, std::vector<SharedRefs>& shared) {
  const std::size_t nv = m.positions.size();
  std::vector<ListedKey<3>> keys(d.triangles.size());
  for (std::size_t i = 0; i < d.triangles.size(); ++i) {
    const Triangle& tri = d.triangles[i];
    for (VertId x : tri.v)
      if (x >= nv)
        fail("triangle " + one_based(i) + ": vertex index " + one_based(x) + " out of range [1, " + std::to_string(nv) + "]");
    if (tri.v[0] == tri.v[1] || tri.v[1] == tri.v[2] || tri.v[0] == tri.v[2])
      fail("triangle " + one_based(i) + ": repeated vertex (" + verts_str(tri.v.data(), 3) + ")");
    keys[i] = {tri.v, tri.ref, static_cast<std::uint32_t>(i)};
    std::sort(keys[i].v.begin(), keys[i].v.end());
  }
  std::map<std::vector<std::int32_t>, std::int32_t> shared_sets;
  std::vector<ListedGroup> groups = group_listed(keys, notes ? &notes->repeated_triangles : nullptr, shared_sets);
  shared = assign_stand_ins(keys, shared_sets, groups);
  std::vector<PlacedRef> placed;
  std::vector<std::uint32_t> detached;
  for (const ListedGroup& g : groups) {
    bool found = false;
    for_each_tet_with(m, keys[g.begin].v.data(), 3, [&](TetId t, const int* loc) {
      placed.push_back({t, static_cast<std::uint8_t>(6 - loc[0] - loc[1] - loc[2]), g.ref, false});
      found = true;
    });
    if (!found)
      for (std::uint32_t k = g.begin; k < g.end; ++k) detached.push_back(keys[k].index);
  }
  handle_detached(detached, options.skip_detached_substructures, notes ? &notes->detached_triangles : nullptr,
                  [&](std::uint32_t i) {
                    const Triangle& tri = d.triangles[i];
                    return "triangle " + one_based(i) + " (vertices " + verts_str(tri.v.data(), 3) + ", ref " +
                           std::to_string(tri.ref) + ") is not a face of any tet";
                  });
  return placed;
}

std::vector<PlacedRef> place_segments(const detail::ListedSubstructures& d, const MeshModel& m, const BuildOptions& options,
                                      BuildNotes* notes, std::vector<SharedRefs>& shared) {
  const std::size_t nv = m.positions.size();
  std::vector<char> is_ridge(d.segments.size(), 0);
  for (std::size_t i = 0; i < d.ridges.size(); ++i) {
    if (d.ridges[i] >= d.segments.size())
      fail("ridge " + one_based(i) + ": edge index " + one_based(d.ridges[i]) + " out of range [1, " +
           std::to_string(d.segments.size()) + "]");
    is_ridge[d.ridges[i]] = 1;
  }
  std::vector<ListedKey<2>> keys(d.segments.size());
  for (std::size_t i = 0; i < d.segments.size(); ++i) {
    const Segment& s = d.segments[i];
    for (VertId x : s.v)
      if (x >= nv)
        fail("edge " + one_based(i) + ": vertex index " + one_based(x) + " out of range [1, " + std::to_string(nv) + "]");
    if (s.v[0] == s.v[1]) fail("edge " + one_based(i) + ": repeated vertex " + one_based(s.v[0]));
    keys[i] = {{std::min(s.v[0], s.v[1]), std::max(s.v[0], s.v[1])}, s.ref, static_cast<std::uint32_t>(i)};
  }
  std::map<std::vector<std::int32_t>, std::int32_t> shared_sets;
  std::vector<ListedGroup> groups = group_listed(keys, notes ? &notes->repeated_segments : nullptr, shared_sets);
  shared = assign_stand_ins(keys, shared_sets, groups);
  std::vector<PlacedRef> placed;
  std::vector<std::uint32_t> detached;
  for (ListedGroup& g : groups) {
    // A ridge is a property of the edge: one listing as a ridge makes it one.
    for (std::uint32_t k = g.begin; k < g.end; ++k) g.ridge = g.ridge || is_ridge[keys[k].index];
    bool found = false;
    for_each_tet_with(m, keys[g.begin].v.data(), 2, [&](TetId t, const int* loc) {
      placed.push_back({t, static_cast<std::uint8_t>(local_edge_index(loc[0], loc[1])), g.ref, g.ridge});
      found = true;
    });
    if (!found)
      for (std::uint32_t k = g.begin; k < g.end; ++k) detached.push_back(keys[k].index);
  }
  handle_detached(detached, options.skip_detached_substructures, notes ? &notes->detached_segments : nullptr,
                  [&](std::uint32_t i) {
                    const Segment& s = d.segments[i];
                    return "edge " + one_based(i) + " (vertices " + verts_str(s.v.data(), 2) + ", ref " +
                           std::to_string(s.ref) + ") is not an edge of any tet";
                  });
  return placed;
}

void copy_fields(const MeshData& d, MeshModel& m) {
  int stride = 0;
  for (const VertexField& f : d.fields) {
    m.fields.push_back({f.name, f.components});
    stride += f.components;
  }
  const std::size_t nv = d.positions.size();
  m.field_values.assign(nv * stride, 0.0);
  int offset = 0;
  for (const VertexField& f : d.fields) {
    for (std::size_t v = 0; v < nv; ++v)
      for (int c = 0; c < f.components; ++c)
        m.field_values[v * stride + offset + c] = f.values[v * f.components + c];
    offset += f.components;
  }
}

void mark_pinned(const detail::ListedSubstructures& d, MeshModel& m) {
  const std::size_t nv = m.positions.size();
  auto mark = [&](const std::vector<VertId>& list, const char* what, std::uint8_t bit) {
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (list[i] >= nv)
        fail(std::string(what) + " " + one_based(i) + ": vertex index " + one_based(list[i]) +
             " out of range [1, " + std::to_string(nv) + "]");
      m.vertex_states[list[i]] |= bit | vertex_state::kPinned;
    }
  };
  mark(d.corners, "corner", vertex_state::kCorner);
  mark(d.required_vertices, "required vertex", vertex_state::kRequired);
}

}  // namespace

MeshModel build_mesh_model(const MeshData& d, const BuildOptions& options, BuildNotes* notes) {
  check_sizes(d);
  MeshModel m;
  m.positions.resize(d.positions.size());
  std::transform(d.positions.begin(), d.positions.end(), m.positions.begin(), to_glm);
  m.tets = d.tets;
  m.material = d.tet_material;
  m.vertex_refs = d.vertex_refs.empty() ? std::vector<std::int32_t>(d.positions.size(), 0) : d.vertex_refs;
  copy_fields(d, m);
  m.group_names = d.group_names;
  return detail::build_loaded_model(std::move(m), {d.triangles, d.segments, d.ridges, d.corners, d.required_vertices},
                                    options, notes);
}

MeshModel detail::build_loaded_model(MeshModel m, const ListedSubstructures& d, const BuildOptions& options,
                                     BuildNotes* notes) {
  if (notes) *notes = {};
  check_vertices_and_tets(m);
  m.vertex_states.assign(m.positions.size(), 0);
  orient_tets(options, m);
  m.flags.assign(m.tets.size(), 0);
  m.tet_refs_slot.assign(m.tets.size(), kInvalid);
  rebuild_incidence(m);
  mark_pinned(d, m);
  for (std::size_t v = 0; v < m.positions.size(); ++v)
    if (m.v2t_count[v] == 0) m.vertex_states[v] |= vertex_state::kDead;  // referenced by no tet

  const std::vector<std::uint8_t> face_kind = classify_faces(m);
  const std::vector<PlacedRef> faces = place_triangles(d, m, options, notes, m.shared_face_refs);
  const std::vector<PlacedRef> edges = place_segments(d, m, options, notes, m.shared_edge_refs);

  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (int f = 0; f < 4; ++f)
      if (face_kind[4 * t + f] == kInterface) m.flags[t] |= TetFlags(1u << (tet_flag::kSurfaceFaceShift + f));
  for (const PlacedRef& p : faces) m.flags[p.tet] |= TetFlags(1u << (tet_flag::kSurfaceFaceShift + p.local));
  for (const PlacedRef& p : edges) m.flags[p.tet] |= TetFlags(1u << (tet_flag::kPolylineEdgeShift + p.local));

  // Side table slots in tet order (deterministic); implicit interfaces first, listed refs override.
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    if (m.flags[t] == 0) continue;
    m.tet_refs_slot[t] = static_cast<std::uint32_t>(m.refs_table.size());
    SubstructureRefs r;
    r.face.fill(kImplicitInterfaceRef);
    m.refs_table.push_back(r);
  }
  for (const PlacedRef& p : faces) m.refs_table[m.tet_refs_slot[p.tet]].face[p.local] = p.ref;
  for (const PlacedRef& p : edges) {
    SubstructureRefs& r = m.refs_table[m.tet_refs_slot[p.tet]];
    r.edge[p.local] = p.ref;
    if (p.ridge) r.ridge_mask |= std::uint8_t(1u << p.local);
  }
  for (VertId v = 0; v < m.positions.size(); ++v)
    if (m.is_dead_vertex(v)) m.vertex_states[v] &= ~(vertex_state::kCorner | vertex_state::kRequired | vertex_state::kPinned);
  return m;
}

}  // namespace topotet

namespace topotet {

void drop_noted_substructures(MeshData& d, const BuildNotes& notes) {
  auto drop = [](auto& list, const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
    std::vector<char> gone(list.size(), 0);
    for (std::uint32_t i : a) gone[i] = 1;
    for (std::uint32_t i : b) gone[i] = 1;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (gone[i]) continue;
      list[kept++] = list[i];
    }
    list.resize(kept);
  };
  drop(d.triangles, notes.repeated_triangles, notes.detached_triangles);
  // Pinned vertices on no tet are not pinned in the model (they are not in it at all).
  if (!notes.detached_triangles.empty() || !notes.detached_segments.empty()) {
    std::vector<char> on_tet(d.positions.size(), 0);
    for (const auto& t : d.tets)
      for (VertId v : t)
        if (v < on_tet.size()) on_tet[v] = 1;
    for (auto* list : {&d.corners, &d.required_vertices})
      list->erase(std::remove_if(list->begin(), list->end(), [&](VertId v) { return v >= on_tet.size() || !on_tet[v]; }),
                  list->end());
  }
  if (notes.repeated_segments.empty() && notes.detached_segments.empty()) return;
  // The builder makes an edge a ridge when any of its listings is one, and the model writes every
  // listing of a ridge edge as a ridge: the ridges are re-derived by edge the same way.
  std::vector<std::array<VertId, 2>> ridge_edges;
  for (std::uint32_t r : d.ridges)
    if (r < d.segments.size())
      ridge_edges.push_back({std::min(d.segments[r].v[0], d.segments[r].v[1]), std::max(d.segments[r].v[0], d.segments[r].v[1])});
  drop(d.segments, notes.repeated_segments, notes.detached_segments);
  std::sort(ridge_edges.begin(), ridge_edges.end());
  d.ridges.clear();
  for (std::size_t i = 0; i < d.segments.size(); ++i) {
    const std::array<VertId, 2> e{std::min(d.segments[i].v[0], d.segments[i].v[1]),
                                  std::max(d.segments[i].v[0], d.segments[i].v[1])};
    if (std::binary_search(ridge_edges.begin(), ridge_edges.end(), e)) d.ridges.push_back(static_cast<std::uint32_t>(i));
  }
}

}  // namespace topotet
