// embed_isosurfaces (topotet/isosurface.h): one level at a time,
//
//   side[v]       <- sign(f(v) - level)                     parallel over vertices
//   snap          vertices within `snap` of a crossing take the level (decided on the input values)
//   crossed edges <- edges with sides -1 and +1, sorted by (min id, max id), unique
//   new vertices  <- one per crossed edge, in that order (ids from the input's vertex count up)
//   crossed tets  <- split_tet (parallel); each piece checked with orient3d_sign
//   tets          <- a crossed tet's first piece in its slot, the others appended in tet order
//   triangles     <- listed ones cut by the level replaced by their pieces (same ref), then the
//                    level's: caps in tet order, then the faces lying in the level (sorted)
//   segments      <- cut ones replaced by their halves (ridges follow)
//
// Work is split in fixed blocks of tets whose results are joined in block order, so the output
// does not depend on the thread count.
#include "topotet/isosurface.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>

#include <glm/vec3.hpp>

#include "isosurface/split_tet.h"
#include "mesh/glm_convert.h"
#include "mesh/orient.h"
#include "parallel/for_range.h"
#include "topotet/error.h"

namespace topotet {
namespace {

using iso::Side;
constexpr std::size_t kBlock = 1 << 14;  // tets per block of the parallel passes

std::uint64_t edge_key(VertId a, VertId b) {
  return a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
}

constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
constexpr int kFaces[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};  // iso::detail::kFaces

// Runs body(block, begin, end) over fixed blocks of [0, n).
template <class Body>
void for_blocks(std::size_t n, Body&& body) {
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  parallel::for_range<std::size_t>(0, blocks, 1, "iso_blocks", [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) body(b, b * kBlock, std::min(n, (b + 1) * kBlock));
  });
}

template <class T>
std::vector<T> join(std::vector<std::vector<T>>& parts) {
  std::size_t total = 0;
  for (const auto& p : parts) total += p.size();
  std::vector<T> out;
  out.reserve(total);
  for (auto& p : parts) out.insert(out.end(), p.begin(), p.end()), std::vector<T>().swap(p);
  return out;
}

std::string shortest(double value) {
  char buf[64];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, value);
    if (std::strtod(buf, nullptr) == value) break;
  }
  return buf;
}

struct Level {
  const IsoLevel* spec;
  std::size_t field = 0;   // index into MeshData::fields
  int components = 1;
  std::vector<double> protected_values;  // other levels of the same component: never snapped away
};

class LevelEmbedding {
 public:
  LevelEmbedding(MeshData& data, const Level& level, double snap, IsoLevelStats& stats)
      : d_(data), level_(level), value_(level.spec->value), snap_(snap), stats_(stats),
        field_(data.fields[level.field]), c_(level.spec->component), stride_(field_.components),
        nv_(data.positions.size()) {}

  void run() {
    classify();
    if (snap_ > 0.0) snap_vertices();
    collect_crossed_edges();
    add_vertices();
    split_tets();
    split_listed_triangles();
    split_segments();
    add_level_faces();
  }

 private:
  double f(VertId v) const { return field_.values[static_cast<std::size_t>(v) * stride_ + c_]; }
  static Side sign_of(double x) { return x < 0.0 ? Side{-1} : x > 0.0 ? Side{1} : Side{0}; }

  void classify() {
    side_.resize(nv_);
    parallel::for_range<std::size_t>(0, nv_, 8192, "iso_classify", [&](std::size_t b, std::size_t e) {
      for (std::size_t v = b; v < e; ++v) side_[v] = sign_of(f(static_cast<VertId>(v)) - value_);
    });
  }

  // A crossing closer than snap (in edge parameter) to an end moves onto that end: the end's
  // value becomes the level. Decided from the values before any snap, and with every edge read
  // from its smaller id, so the set of snapped vertices depends on nothing but the input.
  void snap_vertices() {
    auto mark = std::make_unique<std::atomic<std::uint8_t>[]>(nv_);
    parallel::for_range<std::size_t>(0, nv_, 1 << 16, "iso_snap_clear", [&](std::size_t b, std::size_t e) {
      for (std::size_t v = b; v < e; ++v) mark[v].store(0, std::memory_order_relaxed);
    });
    // Relaxed stores of the same value 1; the loop's join orders them before the reads below.
    for_blocks(d_.tets.size(), [&](std::size_t, std::size_t b, std::size_t e) {
      for (std::size_t t = b; t < e; ++t) {
        const auto& tv = d_.tets[t];
        for (const auto& ed : kEdges) {
          const VertId a = std::min(tv[ed[0]], tv[ed[1]]), z = std::max(tv[ed[0]], tv[ed[1]]);
          if (side_[a] * side_[z] >= 0) continue;
          const double t01 = (value_ - f(a)) / (f(z) - f(a));
          if (t01 < snap_) mark[a].store(1, std::memory_order_relaxed);
          else if (t01 > 1.0 - snap_) mark[z].store(1, std::memory_order_relaxed);
        }
      }
    });
    std::atomic<std::uint64_t> snapped{0};
    parallel::for_range<std::size_t>(0, nv_, 1 << 16, "iso_snap", [&](std::size_t b, std::size_t e) {
      std::uint64_t count = 0;
      for (std::size_t v = b; v < e; ++v) {
        if (!mark[v].load(std::memory_order_relaxed)) continue;
        const double old = f(static_cast<VertId>(v));
        // A vertex exactly on another level of this component stays there: that level's surface
        // goes through it and its value is pinned (the two levels are then closer than the snap).
        if (std::binary_search(level_.protected_values.begin(), level_.protected_values.end(), old)) continue;
        field_.values[v * stride_ + c_] = value_;
        side_[v] = 0;
        ++count;
      }
      snapped.fetch_add(count, std::memory_order_relaxed);  // a sum: the same for any order
    });
    stats_.vertices_snapped = snapped.load();
  }

  void collect_crossed_edges() {
    const std::size_t blocks = (d_.tets.size() + kBlock - 1) / kBlock;
    std::vector<std::vector<std::uint64_t>> edges(blocks);
    std::vector<std::vector<TetId>> tets(blocks);
    for_blocks(d_.tets.size(), [&](std::size_t block, std::size_t b, std::size_t e) {
      for (std::size_t t = b; t < e; ++t) {
        const auto& tv = d_.tets[t];
        const Side s0 = side_[tv[0]], s1 = side_[tv[1]], s2 = side_[tv[2]], s3 = side_[tv[3]];
        const bool below = s0 < 0 || s1 < 0 || s2 < 0 || s3 < 0, above = s0 > 0 || s1 > 0 || s2 > 0 || s3 > 0;
        if (!(below && above)) continue;
        tets[block].push_back(static_cast<TetId>(t));
        for (const auto& ed : kEdges)
          if (side_[tv[ed[0]]] * side_[tv[ed[1]]] < 0) edges[block].push_back(edge_key(tv[ed[0]], tv[ed[1]]));
      }
    });
    crossed_edges_ = join(edges);
    crossed_tets_ = join(tets);
    parallel::sort(crossed_edges_.begin(), crossed_edges_.end());
    crossed_edges_.erase(std::unique(crossed_edges_.begin(), crossed_edges_.end()), crossed_edges_.end());
  }

  VertId crossing(VertId a, VertId b) const {
    const std::uint64_t key = edge_key(a, b);
    const auto it = std::lower_bound(crossed_edges_.begin(), crossed_edges_.end(), key);
    return static_cast<VertId>(nv_ + static_cast<std::size_t>(it - crossed_edges_.begin()));
  }

  // The same for an edge of a listed triangle or segment, which need not be a tet's (build_tet_mesh
  // rejects or drops such elements; here they must not index past the new vertices).
  VertId listed_crossing(VertId a, VertId b) const {
    const std::uint64_t key = edge_key(a, b);
    const auto it = std::lower_bound(crossed_edges_.begin(), crossed_edges_.end(), key);
    if (it == crossed_edges_.end() || *it != key)
      throw InputError("isosurface: a listed triangle or segment crossed by the level is not part of any tet (edge " +
                       std::to_string(a + 1) + " " + std::to_string(b + 1) + ")");
    return static_cast<VertId>(nv_ + static_cast<std::size_t>(it - crossed_edges_.begin()));
  }

  // Positions and fields linear along the edge; the level's component exactly the level (the
  // interpolation would round). Other fields keep exact values where both ends agree (a + t * 0),
  // so a crossing on another level's triangle keeps that level exactly.
  void add_vertices() {
    const std::size_t n = crossed_edges_.size();
    if (nv_ + n > std::size_t{kInvalid}) throw InputError("isosurface: more than 2^32 - 1 vertices");
    d_.positions.resize(nv_ + n);
    if (!d_.vertex_refs.empty()) d_.vertex_refs.resize(nv_ + n, 0);
    for (auto& fd : d_.fields) fd.values.resize((nv_ + n) * static_cast<std::size_t>(fd.components));
    parallel::for_range<std::size_t>(0, n, 4096, "iso_vertices", [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        const VertId a = static_cast<VertId>(crossed_edges_[i] >> 32), z = static_cast<VertId>(crossed_edges_[i]);
        const double t = (value_ - f(a)) / (f(z) - f(a));
        for (int k = 0; k < 3; ++k) d_.positions[nv_ + i][k] = d_.positions[a][k] + t * (d_.positions[z][k] - d_.positions[a][k]);
        for (auto& fd : d_.fields) {
          const std::size_t s = static_cast<std::size_t>(fd.components);
          for (std::size_t k = 0; k < s; ++k) {
            const double fa = fd.values[a * s + k], fz = fd.values[z * s + k];
            fd.values[(nv_ + i) * s + k] = fa + t * (fz - fa);
          }
        }
        field_.values[(nv_ + i) * stride_ + c_] = value_;
      }
    });
    stats_.vertices_added = n;
  }

  glm::dvec3 pos(VertId v) const {
    const auto& p = d_.positions[v];
    return {p[0], p[1], p[2]};
  }

  void split_tets() {
    const std::size_t n = crossed_tets_.size();
    std::vector<iso::TetPieces> pieces(n);
    std::atomic<std::size_t> first_bad{n};
    parallel::for_range<std::size_t>(0, n, 1024, "iso_split", [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        // The pieces take the parent's orientation: a mesh whose tets are all negatively oriented
        // (build_tet_mesh flips such input as a whole) is split as its mirror and flipped back.
        std::array<VertId, 4> tv = d_.tets[crossed_tets_[i]];
        const int parent = orient3d_sign(pos(tv[0]), pos(tv[1]), pos(tv[2]), pos(tv[3]));
        if (parent < 0) std::swap(tv[0], tv[1]);
        const std::array<Side, 4> s = {side_[tv[0]], side_[tv[1]], side_[tv[2]], side_[tv[3]]};
        pieces[i] = iso::split_tet(tv, s, [&](VertId a, VertId z) { return crossing(a, z); });
        if (parent < 0)
          for (int k = 0; k < pieces[i].tet_count; ++k) std::swap(pieces[i].tets[k][0], pieces[i].tets[k][1]);
        for (int k = 0; k < pieces[i].tet_count; ++k) {
          const auto& p = pieces[i].tets[k];
          if (parent == 0 || orient3d_sign(pos(p[0]), pos(p[1]), pos(p[2]), pos(p[3])) != parent) {
            std::size_t cur = first_bad.load(std::memory_order_relaxed);
            while (i < cur && !first_bad.compare_exchange_weak(cur, i, std::memory_order_relaxed)) {
            }
            break;
          }
        }
      }
    });
    if (first_bad.load() < n) {  // the smallest failing tet, whatever the thread count
      const std::size_t i = first_bad.load();
      const auto& tv = d_.tets[crossed_tets_[i]];
      throw InputError("isosurface " + isosurface_group_name(*level_.spec, stride_) + ": splitting tet " +
                       std::to_string(crossed_tets_[i] + 1) + " (vertices " + std::to_string(tv[0] + 1) + " " +
                       std::to_string(tv[1] + 1) + " " + std::to_string(tv[2] + 1) + " " + std::to_string(tv[3] + 1) +
                       ") would make a flat or inverted tet (a crossing too close to a vertex: raise the snap; or "
                       "the tet itself is flat)");
    }
    std::vector<std::size_t> offset(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) offset[i + 1] = offset[i] + static_cast<std::size_t>(pieces[i].tet_count - 1);
    const std::size_t nt = d_.tets.size();
    d_.tets.resize(nt + offset[n]);
    const bool materials = !d_.tet_material.empty();
    if (materials) d_.tet_material.resize(nt + offset[n]);
    // Cell arrays stay aligned with the tets (mesh_data.h): each piece takes its tet's values, an
    // extensive array's amount shared out by the pieces' volumes (their sum is the tet's).
    for (CellField& f : d_.cell_fields)
      if (f.values.size() == nt * static_cast<std::size_t>(f.components))
        f.values.resize((nt + offset[n]) * static_cast<std::size_t>(f.components));
    const auto volume = [&](const std::array<VertId, 4>& tv) {
      const auto p = [&](int k) { return to_glm(d_.positions[tv[static_cast<std::size_t>(k)]]); };
      return std::fabs(signed_volume6(p(0), p(1), p(2), p(3)));
    };
    parallel::for_range<std::size_t>(0, n, 1024, "iso_write", [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        const TetId t = crossed_tets_[i];
        const double whole = d_.cell_fields.empty() ? 0.0 : volume(d_.tets[t]);
        for (CellField& f : d_.cell_fields) {
          const std::size_t c = static_cast<std::size_t>(f.components);
          if (f.values.size() != (nt + offset[n]) * c) continue;  // misaligned already: build_tet_mesh says so
          for (int k = pieces[i].tet_count - 1; k >= 0; --k) {  // the tet's own slot (piece 0) last
            const std::size_t slot = k == 0 ? t : nt + offset[i] + static_cast<std::size_t>(k) - 1;
            const double share = f.kind == CellFieldKind::kExtensive && whole > 0.0
                                     ? volume(pieces[i].tets[static_cast<std::size_t>(k)]) / whole
                                     : 1.0;
            for (std::size_t j = 0; j < c; ++j) f.values[slot * c + j] = f.values[t * c + j] * share;
          }
        }
        d_.tets[t] = pieces[i].tets[0];
        for (int k = 1; k < pieces[i].tet_count; ++k) {
          d_.tets[nt + offset[i] + k - 1] = pieces[i].tets[k];
          if (materials) d_.tet_material[nt + offset[i] + k - 1] = d_.tet_material[t];
        }
      }
    });
    for (const auto& p : pieces)
      for (int k = 0; k < p.cap_count; ++k) caps_.push_back(p.cap[k]);
    stats_.tets_split = n;
    stats_.tets_added = offset[n];
  }

  std::array<Side, 3> sides(const std::array<VertId, 3>& tri) const {
    return {side_at(tri[0]), side_at(tri[1]), side_at(tri[2])};
  }
  // New vertices (ids >= nv_) lie on the level; ids out of range (which build_tet_mesh rejects)
  // are left alone the same way.
  Side side_at(VertId v) const { return v < nv_ ? side_[v] : Side{0}; }

  void split_listed_triangles() {
    std::vector<Triangle> out;
    bool any = false;
    for (const Triangle& tri : d_.triangles) {
      const auto s = sides(tri.v);
      if (std::min({s[0], s[1], s[2]}) < 0 && std::max({s[0], s[1], s[2]}) > 0) any = true;
    }
    if (!any) return;
    out.reserve(d_.triangles.size());
    for (const Triangle& tri : d_.triangles) {
      const auto s = sides(tri.v);
      if (!(std::min({s[0], s[1], s[2]}) < 0 && std::max({s[0], s[1], s[2]}) > 0)) {
        out.push_back(tri);
        continue;
      }
      const iso::TrianglePieces p = iso::split_triangle(tri.v, s, [&](VertId a, VertId z) { return listed_crossing(a, z); });
      for (int k = 0; k < p.count; ++k) out.push_back({p.tris[k], tri.ref});
      ++stats_.triangles_split;
    }
    d_.triangles = std::move(out);
  }

  void split_segments() {
    std::vector<Segment> out;
    std::vector<std::uint32_t> new_index(d_.segments.size());
    bool any = false;
    for (const Segment& seg : d_.segments) any = any || side_at(seg.v[0]) * side_at(seg.v[1]) < 0;
    if (!any) return;
    for (std::size_t i = 0; i < d_.segments.size(); ++i) {
      const Segment& seg = d_.segments[i];
      new_index[i] = static_cast<std::uint32_t>(out.size());
      if (side_at(seg.v[0]) * side_at(seg.v[1]) < 0) {
        const VertId x = listed_crossing(seg.v[0], seg.v[1]);
        out.push_back({{seg.v[0], x}, seg.ref});
        out.push_back({{x, seg.v[1]}, seg.ref});
        ++stats_.segments_split;
      } else {
        out.push_back(seg);
      }
    }
    std::vector<std::uint32_t> ridges;
    for (std::uint32_t r : d_.ridges) {
      if (r >= d_.segments.size()) continue;  // out of range: the builder would not use it either
      ridges.push_back(new_index[r]);
      const Segment& seg = d_.segments[r];
      if (side_at(seg.v[0]) * side_at(seg.v[1]) < 0) ridges.push_back(new_index[r] + 1);
    }
    d_.segments = std::move(out);
    d_.ridges = std::move(ridges);
  }

  // Caps, then the tet faces lying in the level that bound {f < level}: a face with three
  // vertices on the level belongs to the level set when exactly one of its tets has its fourth
  // vertex below (isosurface.h). Such tets are not crossed (a crossed tet has no such face), so
  // their faces are read from the input tets, which keep their slots.
  void add_level_faces() {
    struct LevelFace {
      std::array<VertId, 3> key;  // sorted
      std::array<VertId, 3> face; // oriented as a face of its tet
      bool below;
    };
    const std::size_t blocks = (d_.tets.size() + kBlock - 1) / kBlock;
    std::vector<std::vector<LevelFace>> parts(blocks);
    const std::size_t nt = d_.tets.size() - stats_.tets_added;  // the input's tets (crossed ones skipped below)
    for_blocks(nt, [&](std::size_t block, std::size_t b, std::size_t e) {
      for (std::size_t t = b; t < e; ++t) {
        const auto& tv = d_.tets[t];
        // A crossed tet's slot now holds a piece, whose vertices may be new (side 0): skip by
        // the old sides, which a piece cannot fool (a piece has a new vertex, id >= nv_).
        if (tv[0] >= nv_ || tv[1] >= nv_ || tv[2] >= nv_ || tv[3] >= nv_) continue;
        int zeros = 0, other = -1;
        for (int k = 0; k < 4; ++k) (side_[tv[k]] == 0 ? ++zeros : other = k);
        if (zeros != 3) continue;
        const auto& fl = kFaces[other];
        LevelFace lf{{tv[fl[0]], tv[fl[1]], tv[fl[2]]}, {tv[fl[0]], tv[fl[1]], tv[fl[2]]}, side_[tv[other]] < 0};
        std::sort(lf.key.begin(), lf.key.end());
        parts[block].push_back(lf);
      }
    });
    std::vector<LevelFace> faces = join(parts);
    std::sort(faces.begin(), faces.end(), [](const LevelFace& a, const LevelFace& b) {
      return a.key != b.key ? a.key < b.key : a.below > b.below;  // the tet below first
    });
    std::int32_t ref = level_.spec->ref;
    std::size_t added = 0;
    for (const auto& cap : caps_) d_.triangles.push_back({cap, ref}), ++added;
    for (std::size_t i = 0; i < faces.size();) {
      std::size_t j = i;
      int below = 0;
      while (j < faces.size() && faces[j].key == faces[i].key) below += faces[j++].below;
      if (below == 1) d_.triangles.push_back({faces[i].face, ref}), ++added;
      i = j;
    }
    stats_.triangles = added;
  }

  MeshData& d_;
  const Level& level_;
  double value_, snap_;
  IsoLevelStats& stats_;
  VertexField& field_;
  int c_;
  int stride_;
  std::size_t nv_;
  std::vector<Side> side_;
  std::vector<std::uint64_t> crossed_edges_;
  std::vector<TetId> crossed_tets_;
  std::vector<std::array<VertId, 3>> caps_;
};

// Checks the levels against the mesh; finds each one's field.
std::vector<Level> resolve(const MeshData& data, const std::vector<IsoLevel>& levels) {
  std::vector<Level> out;
  for (const IsoLevel& l : levels) {
    Level r;
    r.spec = &l;
    const auto it = std::find_if(data.fields.begin(), data.fields.end(), [&](const VertexField& f) { return f.name == l.field; });
    if (it == data.fields.end()) throw InputError("isosurface: no vertex field named '" + l.field + "'");
    r.field = static_cast<std::size_t>(it - data.fields.begin());
    r.components = it->components;
    if (l.component < 0 || l.component >= it->components)
      throw InputError("isosurface: field '" + l.field + "' has " + std::to_string(it->components) +
                       " component(s); component " + std::to_string(l.component) + " does not exist");
    if (!std::isfinite(l.value)) throw InputError("isosurface: level of '" + l.field + "' is not finite");
    if (it->values.size() != data.positions.size() * static_cast<std::size_t>(it->components))
      throw InputError("isosurface: field '" + l.field + "' does not have one value per vertex");
    for (const Level& earlier : out)
      if (earlier.spec->field == l.field && earlier.spec->component == l.component && earlier.spec->value == l.value)
        throw InputError("isosurface: level " + isosurface_group_name(l, it->components) + " given twice");
    out.push_back(r);
  }
  for (Level& r : out) {
    for (const Level& o : out)
      if (&o != &r && o.field == r.field && o.spec->component == r.spec->component) r.protected_values.push_back(o.spec->value);
    std::sort(r.protected_values.begin(), r.protected_values.end());
  }
  return out;
}

}  // namespace

std::string isosurface_group_name(const IsoLevel& level, int field_components) {
  std::string name = "iso:";
  name.append(level.field);
  if (field_components > 1) name.append(":").append(std::to_string(level.component));
  return name.append("=").append(shortest(level.value));
}

IsoEmbedReport embed_isosurfaces(MeshData& data, const std::vector<IsoLevel>& levels, const IsoEmbedOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  IsoEmbedReport report;
  report.levels = levels;
  std::vector<Level> resolved = resolve(data, report.levels);
  // Refs that no listed triangle or triangle group name uses: above the largest of them.
  std::int32_t next_ref = 0;
  for (const Triangle& t : data.triangles) next_ref = std::max(next_ref, t.ref);
  for (const GroupName& g : data.group_names)
    if (g.dim == 2) next_ref = std::max(next_ref, g.ref);
  for (std::size_t i = 0; i < resolved.size(); ++i) {
    IsoLevel& level = report.levels[i];
    if (next_ref == std::numeric_limits<std::int32_t>::max()) throw InputError("isosurface: no triangle ref left above the input's");
    level.ref = ++next_ref;
    const auto level_start = std::chrono::steady_clock::now();
    IsoLevelStats stats;
    LevelEmbedding(data, resolved[i], options.snap, stats).run();
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - level_start).count();
    report.stats.push_back(stats);
    data.group_names.push_back({2, level.ref, isosurface_group_name(level, resolved[i].components)});
  }
  std::sort(data.group_names.begin(), data.group_names.end());
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

std::string parse_isosurface_spec(const std::string& spec, std::vector<IsoLevel>& out) {
  const std::size_t eq = spec.rfind('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
    return "expected FIELD=VALUE[,VALUE...] (FIELD may be name:component), got '" + spec + "'";
  std::string field = spec.substr(0, eq);
  int component = 0;
  const std::size_t colon = field.rfind(':');
  if (colon != std::string::npos) {
    const std::string c = field.substr(colon + 1);
    char* end = nullptr;
    const long value = std::strtol(c.c_str(), &end, 10);
    if (c.empty() || *end != '\0' || value < 0 || value > 1000) return "bad component '" + c + "' in '" + spec + "'";
    component = static_cast<int>(value);
    field.resize(colon);
  }
  std::vector<IsoLevel> levels;
  for (std::size_t begin = eq + 1; begin <= spec.size();) {
    std::size_t comma = spec.find(',', begin);
    if (comma == std::string::npos) comma = spec.size();
    const std::string text = spec.substr(begin, comma - begin);
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(value)) return "bad level '" + text + "' in '" + spec + "'";
    levels.push_back({field, component, value, 0});
    begin = comma + 1;
  }
  out.insert(out.end(), levels.begin(), levels.end());
  return {};
}

}  // namespace topotet
