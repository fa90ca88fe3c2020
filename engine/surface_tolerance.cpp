// The original surfaces as an Embree scene, and the kernel's tolerance check (see surface_tolerance.h).
#include "surface_tolerance.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include "parallel/for_range.h"

namespace topotet {

// ---------------------------------------------------------------- exact distances

// Ericson, Real-Time Collision Detection, 5.1.5: the closest point by Voronoi regions.
double squared_distance_to_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                    const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  auto sq = [&](const glm::dvec3& q) { return glm::dot(p - q, p - q); };
  if (d1 <= 0.0 && d2 <= 0.0) return sq(a);
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return sq(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return sq(a + ab * (d1 / (d1 - d3)));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return sq(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return sq(a + ac * (d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return sq(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denom = va + vb + vc;
  if (!(denom > 0.0)) {  // degenerate triangle: the closest of its edges
    return std::min({squared_distance_to_segment(p, a, b), squared_distance_to_segment(p, b, c),
                     squared_distance_to_segment(p, a, c)});
  }
  return sq(a + ab * (vb / denom) + ac * (vc / denom));
}

double squared_distance_to_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  double t = len2 > 0.0 ? glm::dot(p - a, ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const glm::dvec3 d = p - (a + ab * t);
  return glm::dot(d, d);
}

// ---------------------------------------------------------------- Embree scene

namespace {

struct SegmentGeometry {  // user data of one polyline geometry
  const std::vector<float>* vertices;
  const std::vector<std::array<VertId, 2>>* segments;
  const std::vector<std::uint32_t>* primitives;
};

}  // namespace

struct SurfaceReference::Embree {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<float> vertices;                        // xyz per vertex, +1 float of padding
  std::vector<std::vector<std::uint32_t>> indices;    // [face label] triangle vertex triples
  std::vector<std::vector<std::uint32_t>> primitives; // [geometry] primID -> soup triangle/segment
  std::vector<SegmentGeometry> segment_data;          // [polyline label] user data
  ~Embree() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }
};

namespace {

void segment_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* g = static_cast<const SegmentGeometry*>(args->geometryUserPtr);
  const auto& s = (*g->segments)[(*g->primitives)[args->primID]];
  const float* a = &(*g->vertices)[3 * std::size_t{s[0]}];
  const float* b = &(*g->vertices)[3 * std::size_t{s[1]}];
  RTCBounds* o = args->bounds_o;
  o->lower_x = std::min(a[0], b[0]);
  o->lower_y = std::min(a[1], b[1]);
  o->lower_z = std::min(a[2], b[2]);
  o->upper_x = std::max(a[0], b[0]);
  o->upper_y = std::max(a[1], b[1]);
  o->upper_z = std::max(a[2], b[2]);
}

// State of one query, on the caller's stack (this is what makes queries thread-safe).
struct Query {
  const SurfaceSoup* soup;
  const std::vector<std::vector<std::uint32_t>>* primitives;
  unsigned geometry;
  bool is_segment;
  glm::dvec3 p;
  double best2;        // squared distance to beat (within: h^2, inclusive)
  double slack;
  bool stop_at_first;  // within(): any hit answers the question
  bool found = false;
};

float radius_for(double distance, double slack) {
  return std::nextafter(static_cast<float>(distance + slack), std::numeric_limits<float>::infinity());
}

bool on_primitive(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<Query*>(args->userPtr);
  if (args->geomID != q->geometry) return false;  // another label: filtered out
  const std::uint32_t k = (*q->primitives)[q->geometry][args->primID];
  const auto& P = q->soup->positions;
  double d2;
  if (q->is_segment) {
    const auto& s = q->soup->segments[k];
    d2 = squared_distance_to_segment(q->p, P[s[0]], P[s[1]]);
  } else {
    const auto& t = q->soup->triangles[k];
    d2 = squared_distance_to_triangle(q->p, P[t[0]], P[t[1]], P[t[2]]);
  }
  if (d2 > q->best2 || (q->found && d2 == q->best2)) return false;
  q->best2 = d2;
  q->found = true;
  args->query->radius = q->stop_at_first ? 0.0f : radius_for(std::sqrt(d2), q->slack);
  return true;
}

}  // namespace

SurfaceReference::SurfaceReference(SurfaceSoup soup) : soup_(std::move(soup)), embree_(std::make_unique<Embree>()) {
  if (face_labels_.size() < soup_.face_labels) face_labels_.resize(soup_.face_labels, SurfaceLabel{0, 0, 0});
  if (polyline_refs_.size() < soup_.polyline_labels) polyline_refs_.resize(soup_.polyline_labels, 0);
  double max_abs = 0.0;
  Embree& e = *embree_;
  e.vertices.resize(3 * soup_.positions.size() + 1, 0.0f);
  for (std::size_t i = 0; i < soup_.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      e.vertices[3 * i + k] = static_cast<float>(soup_.positions[i][k]);
      max_abs = std::max(max_abs, std::abs(soup_.positions[i][k]));
    }
  // Rounding of the vertices and of the query point to float, with a wide margin.
  slack_ = 8.0 * FLT_EPSILON * std::max(max_abs, 1e-30);

  const std::uint32_t geometries = soup_.face_labels + soup_.polyline_labels;
  e.indices.assign(soup_.face_labels, {});
  e.primitives.assign(geometries, {});
  for (std::uint32_t t = 0; t < soup_.triangles.size(); ++t) {
    const std::uint32_t g = soup_.triangle_label[t];
    e.primitives[g].push_back(t);
    for (VertId x : soup_.triangles[t]) e.indices[g].push_back(x);
  }
  for (std::uint32_t s = 0; s < soup_.segments.size(); ++s)
    e.primitives[soup_.face_labels + soup_.segment_label[s]].push_back(s);

  // One builder thread in the TSan build (parallel::kStdThreads): Embree's own TBB workers are
  // invisible to TSan there. Elsewhere Embree builds in the caller's task arena.
  e.device = rtcNewDevice(parallel::kStdThreads ? "threads=1" : nullptr);
  if (e.device == nullptr) throw std::runtime_error("Embree: cannot create a device");
  e.scene = rtcNewScene(e.device);
  e.segment_data.reserve(soup_.polyline_labels);  // no reallocation: Embree keeps pointers
  for (std::uint32_t g = 0; g < geometries; ++g) {
    RTCGeometry geom;
    if (g < soup_.face_labels) {
      geom = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_TRIANGLE);
      rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, e.vertices.data(), 0,
                                 3 * sizeof(float), soup_.positions.size());
      e.indices[g].push_back(0);  // padding: Embree may read 4 bytes past the last triple
      rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, e.indices[g].data(), 0,
                                 3 * sizeof(std::uint32_t), e.primitives[g].size());
    } else {
      geom = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_USER);
      SegmentGeometry& user = e.segment_data.emplace_back(SegmentGeometry{&e.vertices, &soup_.segments, &e.primitives[g]});
      rtcSetGeometryUserPrimitiveCount(geom, static_cast<unsigned>(e.primitives[g].size()));
      rtcSetGeometryUserData(geom, &user);
      rtcSetGeometryBoundsFunction(geom, segment_bounds, nullptr);
    }
    rtcCommitGeometry(geom);
    const unsigned id = rtcAttachGeometry(e.scene, geom);
    rtcReleaseGeometry(geom);
    if (id != g) throw std::runtime_error("Embree: unexpected geometry id");
  }
  rtcCommitScene(e.scene);
  if (rtcGetDeviceError(e.device) != RTC_ERROR_NONE) throw std::runtime_error("Embree: building the scene failed");
}

SurfaceReference::~SurfaceReference() = default;

int SurfaceReference::face_label_id(const SurfaceLabel& label) const {
  auto it = std::lower_bound(face_labels_.begin(), face_labels_.end(), label);
  return it != face_labels_.end() && *it == label ? static_cast<int>(it - face_labels_.begin()) : -1;
}

int SurfaceReference::polyline_label_id(std::int32_t ref) const {
  auto it = std::lower_bound(polyline_refs_.begin(), polyline_refs_.end(), ref);
  return it != polyline_refs_.end() && *it == ref
             ? static_cast<int>(face_labels_.size()) + static_cast<int>(it - polyline_refs_.begin())
             : -1;
}

namespace {

double run_query(const SurfaceSoup& soup, const std::vector<std::vector<std::uint32_t>>& primitives, RTCScene scene,
                 const glm::dvec3& p, int label, double radius, double slack, bool stop_at_first, bool* found) {
  Query q{&soup, &primitives, static_cast<unsigned>(label), label >= static_cast<int>(soup.face_labels), p,
          radius * radius, slack, stop_at_first};
  RTCPointQuery query;
  query.x = static_cast<float>(p.x);
  query.y = static_cast<float>(p.y);
  query.z = static_cast<float>(p.z);
  query.time = 0.0f;
  query.radius = radius_for(radius, slack);
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene, &query, &context, on_primitive, &q);
  *found = q.found;
  return q.best2;
}

}  // namespace

bool SurfaceReference::within(const glm::dvec3& p, int label, double h) const {
  if (label < 0 || static_cast<std::size_t>(label) >= embree_->primitives.size()) return false;
  bool found = false;
  run_query(soup_, embree_->primitives, embree_->scene, p, label, h, slack_, true, &found);
  return found;
}

double SurfaceReference::distance(const glm::dvec3& p, int label, double max_distance) const {
  if (label < 0 || static_cast<std::size_t>(label) >= embree_->primitives.size())
    return std::numeric_limits<double>::infinity();
  bool found = false;
  const double d2 = run_query(soup_, embree_->primitives, embree_->scene, p, label, max_distance, slack_, false, &found);
  return found ? std::sqrt(d2) : std::numeric_limits<double>::infinity();
}

// ---------------------------------------------------------------- from a MeshModel

namespace {

int local_of(const std::array<VertId, 4>& v, VertId a) {
  for (int k = 0; k < 4; ++k)
    if (v[k] == a) return k;
  return -1;
}

std::int32_t normalised_ref(std::int32_t ref) { return ref == kImplicitInterfaceRef ? kUnlistedRef : ref; }

// The tet other than t sharing face f of t, or kInvalid (boundary). Scans the star of the face's
// first vertex: no face adjacency is stored.
TetId across(const MeshModel& mesh, TetId t, int f) {
  const auto& tv = mesh.tets[t];
  const VertId a = tv[kTetFaces[f][0]], b = tv[kTetFaces[f][1]], c = tv[kTetFaces[f][2]];
  TetId other = kInvalid;
  mesh.for_each_tet_of(a, [&](TetId s) {
    if (s == t || other != kInvalid) return;
    const auto& sv = mesh.tets[s];
    if (local_of(sv, b) >= 0 && local_of(sv, c) >= 0) other = s;
  });
  return other;
}

struct LabelledFace {
  std::array<VertId, 3> v;
  SurfaceLabel label;
};
struct LabelledEdge {
  std::array<VertId, 2> v;
  std::int32_t ref;
  bool operator<(const LabelledEdge& o) const { return v != o.v ? v < o.v : ref < o.ref; }
  bool operator==(const LabelledEdge&) const = default;
};

}  // namespace

std::unique_ptr<SurfaceReference> SurfaceReference::from_mesh(const MeshModel& mesh) {
  // Blocks of tets in parallel; block results are concatenated in block order (deterministic).
  constexpr std::size_t kBlock = 8192;
  const std::size_t nt = mesh.tet_capacity();
  const std::size_t blocks = (nt + kBlock - 1) / kBlock;
  std::vector<std::vector<LabelledFace>> block_faces(blocks);
  std::vector<std::vector<LabelledEdge>> block_edges(blocks);
  parallel::for_range<std::size_t>(0, blocks, 1, "surface_reference", [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) {
      for (std::size_t ti = b * kBlock; ti < std::min(nt, (b + 1) * kBlock); ++ti) {
        const TetId t = static_cast<TetId>(ti);
        if (mesh.is_dead_tet(t)) continue;
        const TetFlags fl = mesh.flags[t];
        const auto& tv = mesh.tets[t];
        for (int f = 0; f < 4; ++f) {
          const TetId o = across(mesh, t, f);
          if (o != kInvalid && o < t) continue;  // an interior face is emitted by its smaller tet
          const bool flagged_here = is_surface_face(fl, f);
          bool flagged = flagged_here;
          std::int32_t ref = flagged_here ? normalised_ref(mesh.refs_table[mesh.tet_refs_slot[t]].face[f]) : kUnlistedRef;
          std::int32_t m_other = kOutsideMaterial;
          if (o != kInvalid) {
            m_other = mesh.material[o];
            // The face as seen from o: the local face opposite o's vertex that t does not have.
            int fo = -1;
            for (int k = 0; k < 4; ++k)
              if (local_of(tv, mesh.tets[o][k]) < 0) fo = k;
            if (is_surface_face(mesh.flags[o], fo)) {
              const std::int32_t r = normalised_ref(mesh.refs_table[mesh.tet_refs_slot[o]].face[fo]);
              ref = flagged ? std::max(ref, r) : r;
              flagged = true;
            }
          }
          if (o != kInvalid && !flagged) continue;  // not special
          const std::int32_t m = mesh.material[t];
          std::array<VertId, 3> key{tv[kTetFaces[f][0]], tv[kTetFaces[f][1]], tv[kTetFaces[f][2]]};
          block_faces[b].push_back({key, SurfaceLabel{ref, std::min(m, m_other), std::max(m, m_other)}});
        }
        if (!(fl & tet_flag::kPolylineEdges)) continue;
        const SubstructureRefs& refs = mesh.refs_table[mesh.tet_refs_slot[t]];
        for (int e = 0; e < 6; ++e) {
          if (!is_polyline_edge(fl, e)) continue;
          const VertId x = tv[kTetEdges[e][0]], y = tv[kTetEdges[e][1]];
          block_edges[b].push_back({{std::min(x, y), std::max(x, y)}, refs.edge[e]});
        }
      }
    }
  });

  SurfaceSoup soup;
  soup.positions = mesh.positions;
  std::vector<SurfaceLabel> labels;
  std::vector<std::int32_t> polyline_refs;
  std::vector<LabelledEdge> edges;
  for (const auto& bf : block_faces)
    for (const LabelledFace& f : bf) labels.push_back(f.label);
  for (const auto& be : block_edges) edges.insert(edges.end(), be.begin(), be.end());
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const LabelledEdge& e : edges) polyline_refs.push_back(e.ref);
  std::sort(polyline_refs.begin(), polyline_refs.end());
  polyline_refs.erase(std::unique(polyline_refs.begin(), polyline_refs.end()), polyline_refs.end());

  soup.face_labels = static_cast<std::uint32_t>(labels.size());
  // Polyline geometries, then one border geometry per face label.
  soup.polyline_labels = static_cast<std::uint32_t>(polyline_refs.size() + labels.size());
  std::vector<std::uint8_t> on_surface(mesh.vertex_capacity(), 0);
  for (const auto& bf : block_faces)
    for (const LabelledFace& f : bf) {
      soup.triangles.push_back(f.v);
      soup.triangle_label.push_back(static_cast<std::uint32_t>(
          std::lower_bound(labels.begin(), labels.end(), f.label) - labels.begin()));
      for (VertId x : f.v) on_surface[x] = 1;
    }
  for (const LabelledEdge& e : edges) {
    soup.segments.push_back(e.v);
    soup.segment_label.push_back(static_cast<std::uint32_t>(
        std::lower_bound(polyline_refs.begin(), polyline_refs.end(), e.ref) - polyline_refs.begin()));
    for (VertId x : e.v) on_surface[x] = 1;
  }
  // Border edges: the edges with exactly one face of their label.
  std::vector<std::pair<std::array<VertId, 2>, std::uint32_t>> face_edges;  // (edge, label id)
  for (std::size_t t = 0; t < soup.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const VertId x = soup.triangles[t][k], y = soup.triangles[t][(k + 1) % 3];
      face_edges.push_back({{std::min(x, y), std::max(x, y)}, soup.triangle_label[t]});
    }
  parallel::sort(face_edges.begin(), face_edges.end());
  for (std::size_t i = 0; i < face_edges.size();) {
    std::size_t j = i + 1;
    while (j < face_edges.size() && face_edges[j] == face_edges[i]) ++j;
    if (j - i == 1) {
      soup.segments.push_back(face_edges[i].first);
      soup.segment_label.push_back(static_cast<std::uint32_t>(polyline_refs.size()) + face_edges[i].second);
    }
    i = j;
  }
  block_faces = {};

  auto reference = std::make_unique<SurfaceReference>(std::move(soup));
  reference->face_labels_ = std::move(labels);
  reference->polyline_refs_ = std::move(polyline_refs);
  reference->on_surface_ = std::move(on_surface);
  return reference;
}

// ---------------------------------------------------------------- the kernel check

void gather_surface_stencil(const MeshModel& mesh, const SurfaceReference& reference, VertId u, VertId v,
                            const std::vector<TetId>& star_u, const std::vector<TetId>& star_v,
                            const std::vector<TetId>& star_uv, SurfaceStencil& out) {
  out.recs.clear();
  out.faces.clear();
  out.edges.clear();
  auto add = [&](TetId t) {
    const auto& tv = mesh.tets[t];
    const int iu = local_of(tv, u), iv = local_of(tv, v);
    for (int f = 0; f < 4; ++f) {
      if ((iu < 0 || iu == f) && (iv < 0 || iv == f)) continue;  // the face has neither u nor v
      std::array<VertId, 3> key{tv[kTetFaces[f][0]], tv[kTetFaces[f][1]], tv[kTetFaces[f][2]]};
      std::sort(key.begin(), key.end());
      out.recs.push_back({key, t, static_cast<std::uint8_t>(f)});
    }
    const TetFlags fl = mesh.flags[t];
    if (!(fl & tet_flag::kPolylineEdges)) return;
    const SubstructureRefs& refs = mesh.refs_table[mesh.tet_refs_slot[t]];
    for (int e = 0; e < 6; ++e) {
      if (!is_polyline_edge(fl, e)) continue;
      const int a = kTetEdges[e][0], b = kTetEdges[e][1];
      if (a != iu && b != iu && a != iv && b != iv) continue;
      const VertId x = tv[a], y = tv[b];
      out.edges.push_back({{std::min(x, y), std::max(x, y)}, reference.polyline_label_id(refs.edge[e])});
    }
  };
  for (TetId t : star_u) add(t);
  for (TetId t : star_v)
    if (!std::binary_search(star_uv.begin(), star_uv.end(), t)) add(t);

  std::sort(out.recs.begin(), out.recs.end());
  for (std::size_t i = 0; i < out.recs.size();) {
    std::size_t j = i + 1;
    while (j < out.recs.size() && out.recs[j].key == out.recs[i].key) ++j;
    bool flagged = false;
    std::int32_t ref = kUnlistedRef;
    for (std::size_t k = i; k < j; ++k) {
      const auto& r = out.recs[k];
      if (!is_surface_face(mesh.flags[r.tet], r.local_face)) continue;
      const std::int32_t fr = normalised_ref(mesh.refs_table[mesh.tet_refs_slot[r.tet]].face[r.local_face]);
      ref = flagged ? std::max(ref, fr) : fr;
      flagged = true;
    }
    const bool boundary = j - i == 1;
    if (boundary || flagged) {
      const std::int32_t m0 = mesh.material[out.recs[i].tet];
      const std::int32_t m1 = boundary ? kOutsideMaterial : mesh.material[out.recs[i + 1].tet];
      out.faces.push_back({out.recs[i].key, reference.face_label_id({ref, std::min(m0, m1), std::max(m0, m1)})});
    }
    i = j;
  }
  std::sort(out.edges.begin(), out.edges.end(), [](const auto& a, const auto& b) {
    return a.v != b.v ? a.v < b.v : a.label < b.label;
  });
  out.edges.erase(std::unique(out.edges.begin(), out.edges.end(),
                              [](const auto& a, const auto& b) { return a.v == b.v && a.label == b.label; }),
                  out.edges.end());
}

namespace {

bool contains(const std::array<VertId, 3>& f, VertId x) { return f[0] == x || f[1] == x || f[2] == x; }
bool contains(const std::array<VertId, 2>& e, VertId x) { return e[0] == x || e[1] == x; }

// Is `old` within h of the new triangles (segments) of label `label` around p? True when there
// are none (the label left this neighbourhood entirely; nothing local to compare with).
template <class Prims, class Dist>
bool old_point_covered(const glm::dvec3& old, int label, double h2, const Prims& prims, Dist&& dist2) {
  bool any = false;
  for (const auto& prim : prims) {
    if (prim.label != label) continue;
    any = true;
    if (dist2(old, prim) <= h2) return true;
  }
  return !any;
}

}  // namespace

bool placement_within_tolerance(const MeshModel& mesh, const SurfaceReference& reference, double h, VertId u,
                                VertId v, const glm::dvec3& p, SurfaceStencil& s) {
  const auto& P = mesh.positions;
  s.new_faces.clear();
  s.new_edges.clear();
  for (const SurfaceStencil::Face& f : s.faces) {
    const bool hu = contains(f.v, u), hv = contains(f.v, v);
    if (hu == hv) continue;  // vanishes with St(uv) (or does not move)
    if (f.label < 0) return false;
    SurfaceStencil::NewFace nf{{p, p, p}, {kInvalid, kInvalid}, f.label};
    int k = 0;
    for (VertId x : f.v)
      if (x != u && x != v) {
        nf.others[k] = x;
        nf.pts[1 + k++] = P[x];
      }
    s.new_faces.push_back(nf);
  }
  for (const SurfaceStencil::Edge& e : s.edges) {
    const bool hu = contains(e.v, u), hv = contains(e.v, v);
    if (hu == hv) continue;
    if (e.label < 0) return false;
    s.new_edges.push_back({{p, P[e.v[0] == u || e.v[0] == v ? e.v[1] : e.v[0]]}, e.label});
  }

  // Forward: the samples of the new surface near the original one. p first, once per label.
  int last_label = -1;
  for (const SurfaceStencil::NewFace& f : s.new_faces) {
    if (f.label != last_label && !reference.within(p, f.label, h)) return false;
    last_label = f.label;
  }
  for (const SurfaceStencil::NewEdge& e : s.new_edges)
    if (!reference.within(p, e.label, h)) return false;
  for (const SurfaceStencil::NewFace& f : s.new_faces) {
    const auto& q = f.pts;
    if (!reference.within((q[0] + q[1] + q[2]) / 3.0, f.label, h)) return false;
    // Barycentric grid of n subdivisions per edge, n = 2 (edge midpoints) for triangles up to 4h
    // long, up to 4 for larger ones: the unchecked gap between samples shrinks with them. Points
    // on the unmoved edge xy (checked when it was made) are skipped.
    const double longest = std::sqrt(std::max({glm::dot(q[1] - q[0], q[1] - q[0]), glm::dot(q[2] - q[0], q[2] - q[0]),
                                               glm::dot(q[2] - q[1], q[2] - q[1])}));
    const int n = longest <= 4.0 * h ? 2 : (longest <= 8.0 * h ? 3 : 4);
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {  // i + j == n is the edge xy
        if (i == 0 && j == 0) continue;  // p itself, checked above
        const glm::dvec3 x = q[0] + (q[1] - q[0]) * (double(i) / n) + (q[2] - q[0]) * (double(j) / n);
        if (!reference.within(x, f.label, h)) return false;
      }
  }
  for (const SurfaceStencil::NewEdge& e : s.new_edges)
    if (!reference.within(0.5 * (e.pts[0] + e.pts[1]), e.label, h)) return false;
  // Border edges p-x: every face containing the new edge contains p, so all are in new_faces.
  for (const SurfaceStencil::NewFace& f : s.new_faces)
    for (int k = 0; k < 2; ++k) {
      int count = 0;
      for (const SurfaceStencil::NewFace& g : s.new_faces)
        count += g.label == f.label && (g.others[0] == f.others[k] || g.others[1] == f.others[k]) ? 1 : 0;
      if (count != 1) continue;
      const int border = reference.border_label_id(f.label);
      if (!reference.within(p, border, h) || !reference.within(0.5 * (p + f.pts[1 + k]), border, h)) return false;
    }

  // Reverse: the points that leave the surface (u's and v's old positions) stay near the new one.
  const double h2 = h * h;
  const auto tri2 = [](const glm::dvec3& q, const SurfaceStencil::NewFace& f) {
    return squared_distance_to_triangle(q, f.pts[0], f.pts[1], f.pts[2]);
  };
  const auto seg2 = [](const glm::dvec3& q, const SurfaceStencil::NewEdge& e) {
    return squared_distance_to_segment(q, e.pts[0], e.pts[1]);
  };
  for (const VertId w : {u, v}) {
    if (P[w] == p) continue;
    int checked = -1;  // faces come sorted by vertices, so labels repeat in runs: skip repeats
    for (const SurfaceStencil::Face& f : s.faces) {
      if (!contains(f.v, w) || f.label == checked) continue;
      if (!old_point_covered(P[w], f.label, h2, s.new_faces, tri2)) return false;
      checked = f.label;
    }
    for (const SurfaceStencil::Edge& e : s.edges)
      if (contains(e.v, w) && !old_point_covered(P[w], e.label, h2, s.new_edges, seg2)) return false;
  }
  return true;
}

}  // namespace topotet
