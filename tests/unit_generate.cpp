// Procedural meshes (topotet/generate.h): counts, orientation, shape, conformity of the listed
// substructures with the tets, topology of every planted surface and polyline, determinism; for
// polycrystal, every cell a ball and every listed interface a disc, checked independently.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numeric>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include <glm/geometric.hpp>

#include "generate/freudenthal_grid.h"
#include "generate/tet_neighbourhood.h"
#include "mesh/glm_convert.h"
#include "mesh/mesh_model.h"
#include "region_manifold.h"
#include "topotet/error.h"
#include "topotet/generate.h"
#include "topotet/metrics/topology.h"

namespace topotet {
namespace {

using Edge = std::array<VertId, 2>;
using Face = std::array<VertId, 3>;

std::uint64_t edge_key(VertId a, VertId b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t{a} << 32) | b;
}

Face sorted_face(Face f) {
  std::sort(f.begin(), f.end());
  return f;
}

// Test meshes stay below 2^21 vertices, so a sorted face packs into 63 bits.
std::uint64_t face_key(Face f) {
  f = sorted_face(f);
  return (std::uint64_t{f[0]} << 42) | (std::uint64_t{f[1]} << 21) | f[2];
}

struct TetFace {
  TetId tets[2] = {kInvalid, kInvalid};
  int count = 0;
};

std::unordered_map<std::uint64_t, TetFace> tet_faces(const MeshData& mesh) {
  EXPECT_LT(mesh.vertex_count(), 1u << 21);
  std::unordered_map<std::uint64_t, TetFace> faces;
  faces.reserve(mesh.tet_count() * 3);
  for (TetId t = 0; t < mesh.tet_count(); ++t) {
    const auto& v = mesh.tets[t];
    for (int q = 0; q < 4; ++q) {
      const auto& f = gen::kOutwardFace[q];
      TetFace& entry = faces[face_key({v[f[0]], v[f[1]], v[f[2]]})];
      if (entry.count < 2) entry.tets[entry.count] = t;
      ++entry.count;
    }
  }
  return faces;
}

// Which materials surround each of the given edges.
std::unordered_map<std::uint64_t, std::set<std::int32_t>> edge_materials(const MeshData& mesh,
                                                                         const std::vector<Segment>& edges) {
  std::unordered_map<std::uint64_t, std::set<std::int32_t>> out;
  for (const Segment& s : edges) out[edge_key(s.v[0], s.v[1])];
  for (TetId t = 0; t < mesh.tet_count(); ++t) {
    const auto& v = mesh.tets[t];
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        auto it = out.find(edge_key(v[i], v[j]));
        if (it != out.end()) it->second.insert(mesh.tet_material[t]);
      }
  }
  return out;
}

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

struct SurfaceStats {
  std::int64_t vertices = 0, edges = 0, faces = 0;
  int components = 0;
  std::int64_t boundary_edges = 0;     // in exactly one triangle
  std::int64_t nonmanifold_edges = 0;  // in three or more
  std::int64_t nonmanifold_vertices = 0;  // link is not one cycle or one path
  std::int64_t euler() const { return vertices - edges + faces; }
};

SurfaceStats surface_stats(const std::vector<Triangle>& tris) {
  SurfaceStats s;
  std::unordered_map<VertId, std::uint32_t> local;
  std::unordered_map<std::uint64_t, int> edge_count;
  for (const Triangle& t : tris)
    for (int i = 0; i < 3; ++i) {
      local.emplace(t.v[i], static_cast<std::uint32_t>(local.size()));
      ++edge_count[edge_key(t.v[i], t.v[(i + 1) % 3])];
    }
  s.vertices = static_cast<std::int64_t>(local.size());
  s.edges = static_cast<std::int64_t>(edge_count.size());
  s.faces = static_cast<std::int64_t>(tris.size());
  for (const auto& [key, count] : edge_count) {
    if (count == 1) ++s.boundary_edges;
    if (count > 2) ++s.nonmanifold_edges;
  }
  UnionFind uf(local.size());
  for (const Triangle& t : tris) {
    uf.unite(local[t.v[0]], local[t.v[1]]);
    uf.unite(local[t.v[0]], local[t.v[2]]);
  }
  for (std::uint32_t i = 0; i < local.size(); ++i) s.components += uf.find(i) == i;
  // Vertex links: the opposite edges of the triangles around a vertex must form one cycle (inside)
  // or one path (on the boundary); anything else is a pinch.
  std::unordered_map<VertId, std::vector<Edge>> link;
  for (const Triangle& t : tris)
    for (int i = 0; i < 3; ++i) link[t.v[i]].push_back({t.v[(i + 1) % 3], t.v[(i + 2) % 3]});
  for (const auto& [v, edges] : link) {
    std::map<VertId, int> degree;
    std::map<VertId, std::uint32_t> id;
    for (const Edge& e : edges)
      for (VertId w : e) {
        ++degree[w];
        id.emplace(w, static_cast<std::uint32_t>(id.size()));
      }
    UnionFind luf(id.size());
    for (const Edge& e : edges) luf.unite(id[e[0]], id[e[1]]);
    int roots = 0;
    for (std::uint32_t i = 0; i < id.size(); ++i) roots += luf.find(i) == i;
    const bool degrees_ok = std::all_of(degree.begin(), degree.end(), [](const auto& d) { return d.second <= 2; });
    if (roots != 1 || !degrees_ok) ++s.nonmanifold_vertices;
  }
  return s;
}

std::vector<Triangle> triangles_with_ref(const MeshData& mesh, std::int32_t ref) {
  std::vector<Triangle> out;
  for (const Triangle& t : mesh.triangles)
    if (t.ref == ref) out.push_back(t);
  return out;
}

std::vector<Segment> segments_with_ref(const MeshData& mesh, std::int32_t ref) {
  std::vector<Segment> out;
  for (const Segment& s : mesh.segments)
    if (s.ref == ref) out.push_back(s);
  return out;
}

std::set<VertId> vertices_of(const std::vector<Triangle>& tris) {
  std::set<VertId> out;
  for (const Triangle& t : tris) out.insert(t.v.begin(), t.v.end());
  return out;
}

// A polyline ref must be one simple path: degrees <= 2, connected, V - E = 1.
void expect_simple_path(const std::vector<Segment>& segs, std::int32_t ref) {
  std::unordered_map<VertId, int> degree;
  std::unordered_map<VertId, std::uint32_t> id;
  for (const Segment& s : segs)
    for (VertId v : s.v) {
      ++degree[v];
      id.emplace(v, static_cast<std::uint32_t>(id.size()));
    }
  UnionFind uf(id.size());
  for (const Segment& s : segs) uf.unite(id[s.v[0]], id[s.v[1]]);
  int roots = 0;
  for (std::uint32_t i = 0; i < id.size(); ++i) roots += uf.find(i) == i;
  EXPECT_EQ(roots, 1) << "polyline ref " << ref;
  EXPECT_EQ(static_cast<std::int64_t>(id.size()) - static_cast<std::int64_t>(segs.size()), 1) << "polyline ref " << ref;
  for (const auto& [v, d] : degree) EXPECT_LE(d, 2) << "polyline ref " << ref << " vertex " << v;
}

double tet_det(const MeshData& mesh, const std::array<VertId, 4>& t) {
  const glm::dvec3 p0 = to_glm(mesh.positions[t[0]]);
  return glm::dot(to_glm(mesh.positions[t[1]]) - p0,
                  glm::cross(to_glm(mesh.positions[t[2]]) - p0, to_glm(mesh.positions[t[3]]) - p0));
}

// Minimum and median over all tets of each tet's smallest dihedral angle, in degrees; and the
// largest dihedral angle anywhere.
struct Angles {
  double min = 0, median = 0, max = 0;
};
Angles dihedral_angles(const MeshData& mesh) {
  std::vector<double> smallest(mesh.tet_count());
  double largest = 0;
  for (std::size_t t = 0; t < mesh.tet_count(); ++t) {
    const auto& v = mesh.tets[t];
    double lo = 180;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        int k = 0;
        while (k == i || k == j) ++k;
        const int l = 6 - i - j - k;
        const glm::dvec3 p = to_glm(mesh.positions[v[i]]), e = to_glm(mesh.positions[v[j]]) - p;
        const glm::dvec3 n1 = glm::cross(e, to_glm(mesh.positions[v[k]]) - p);
        const glm::dvec3 n2 = glm::cross(e, to_glm(mesh.positions[v[l]]) - p);
        const double c = std::clamp(glm::dot(n1, n2) / (glm::length(n1) * glm::length(n2)), -1.0, 1.0);
        const double angle = std::acos(c) * 180.0 / 3.14159265358979323846;
        lo = std::min(lo, angle);
        largest = std::max(largest, angle);
      }
    smallest[t] = lo;
  }
  std::sort(smallest.begin(), smallest.end());
  return {smallest.front(), smallest[smallest.size() / 2], largest};
}

// What each family must list: the ref of a face between materials (lower, higher).
std::int32_t expected_interface_ref(const std::string& family, std::int32_t lower, std::int32_t higher) {
  if (family == "cube-sphere") return lower == 1 && higher == 2 ? 1 : -1;
  if (family == "slab") return higher == lower + 1 ? lower : -1;
  return lower == 1 ? higher - 1 : -1;  // linked-tori: 1-2 -> 1, 1-3 -> 2, tori never touch
}

// A polyline piercing a surface meets it only at isolated vertices, never along an edge: returns
// how many of its vertices lie on the surface, and fails on a chain edge that is a surface edge.
int chain_crossings(const MeshData& mesh, const std::vector<Segment>& chain, std::int32_t surface_ref) {
  const auto tris = triangles_with_ref(mesh, surface_ref);
  std::unordered_set<std::uint64_t> surface_edges;
  for (const Triangle& t : tris)
    for (int i = 0; i < 3; ++i) surface_edges.insert(edge_key(t.v[i], t.v[(i + 1) % 3]));
  for (const Segment& s : chain) {
    EXPECT_FALSE(surface_edges.count(edge_key(s.v[0], s.v[1]))) << "chain edge along surface " << surface_ref;
  }
  const auto on_surface = vertices_of(tris);
  std::set<VertId> chain_vertices;
  for (const Segment& s : chain) chain_vertices.insert(s.v.begin(), s.v.end());
  int count = 0;
  for (VertId v : chain_vertices) count += on_surface.count(v) > 0;
  return count;
}

// The materials a chain (listed in order) passes through, one entry per run of edges whose tets
// all have that material; -1 for an edge with several materials around it (on an interface).
std::vector<std::int32_t> chain_materials(const MeshData& mesh, const std::vector<Segment>& chain) {
  const auto around = edge_materials(mesh, chain);
  std::vector<std::int32_t> sequence;
  for (const Segment& s : chain) {
    const auto& m = around.at(edge_key(s.v[0], s.v[1]));
    const std::int32_t here = m.size() == 1 ? *m.begin() : -1;
    if (sequence.empty() || sequence.back() != here) sequence.push_back(here);
  }
  return sequence;
}

struct Case {
  std::string family;
  std::uint64_t target;
  std::uint64_t seed;
};

class GenerateCase : public ::testing::TestWithParam<Case> {};

TEST_P(GenerateCase, MeshIsValid) {
  const Case& c = GetParam();
  const MeshData mesh = generate_mesh({c.family, c.target, c.seed});
  const auto n_tets = static_cast<double>(mesh.tet_count());
  EXPECT_NEAR(n_tets / c.target, 1.0, 0.1) << mesh.tet_count() << " tets";
  ASSERT_EQ(mesh.tet_material.size(), mesh.tet_count());
  EXPECT_TRUE(mesh.vertex_refs.empty() || mesh.vertex_refs.size() == mesh.vertex_count());

  // Orientation and shape.
  for (const auto& t : mesh.tets) {
    for (VertId v : t) ASSERT_LT(v, mesh.vertex_count());
    ASSERT_GT(tet_det(mesh, t), 0.0);
  }
  const Angles angles = dihedral_angles(mesh);
  std::printf("[ %s %llu seed %llu ] %zu tets, %zu verts; dihedral min %.1f, median per-tet min %.1f, max %.1f\n",
              c.family.c_str(), static_cast<unsigned long long>(c.target), static_cast<unsigned long long>(c.seed),
              mesh.tet_count(), mesh.vertex_count(), angles.min, angles.median, angles.max);
  EXPECT_GT(angles.min, 25.0);
  EXPECT_LT(angles.max, 130.0);

  // Conformity: every face has one or two tets; every listed triangle is a face, every listed
  // segment an edge; no duplicates.
  const auto faces = tet_faces(mesh);
  std::unordered_set<std::uint64_t> edges;
  for (const auto& t : mesh.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) edges.insert(edge_key(t[i], t[j]));
  for (const auto& [key, f] : faces) ASSERT_LE(f.count, 2);
  std::unordered_set<std::uint64_t> listed_faces;
  for (const Triangle& t : mesh.triangles) {
    const auto it = faces.find(face_key(t.v));
    ASSERT_NE(it, faces.end()) << "triangle ref " << t.ref << " is not a tet face";
    EXPECT_TRUE(listed_faces.insert(face_key(t.v)).second) << "duplicate triangle";
    const TetFace& f = it->second;
    if (f.count == 2) {
      const std::int32_t m0 = mesh.tet_material[f.tets[0]], m1 = mesh.tet_material[f.tets[1]];
      if (m0 != m1) {
        EXPECT_EQ(t.ref, expected_interface_ref(c.family, std::min(m0, m1), std::max(m0, m1)));
      }
    }
  }
  std::unordered_set<std::uint64_t> listed_edges;
  for (const Segment& s : mesh.segments) {
    ASSERT_TRUE(edges.count(edge_key(s.v[0], s.v[1]))) << "segment ref " << s.ref << " is not a tet edge";
    EXPECT_TRUE(listed_edges.insert(edge_key(s.v[0], s.v[1])).second) << "duplicate segment";
  }
  // Every material interface is listed; box faces are flat (boundary jitter is tangential).
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : mesh.positions) {
    lo = glm::min(lo, to_glm(p));
    hi = glm::max(hi, to_glm(p));
  }
  std::size_t boundary_faces = 0;
  for (const auto& [key, f] : faces) {
    if (f.count == 2) {
      if (mesh.tet_material[f.tets[0]] != mesh.tet_material[f.tets[1]]) {
        EXPECT_TRUE(listed_faces.count(key)) << "unlisted interface face";
      }
      continue;
    }
    ++boundary_faces;
    const Face v = {static_cast<VertId>(key >> 42), static_cast<VertId>((key >> 21) & 0x1FFFFF),
                    static_cast<VertId>(key & 0x1FFFFF)};
    bool flat = false;
    for (int a = 0; a < 3; ++a) {
      for (double side : {lo[a], hi[a]}) {
        flat |= std::all_of(v.begin(), v.end(), [&](VertId w) { return mesh.positions[w][a] == side; });
      }
    }
    EXPECT_TRUE(flat) << "boundary face off the box faces";
  }

  // The field.
  ASSERT_EQ(mesh.fields.size(), 1u);
  EXPECT_EQ(mesh.fields[0].name, "f");
  EXPECT_EQ(mesh.fields[0].components, 1);
  ASSERT_EQ(mesh.fields[0].values.size(), mesh.vertex_count());
  for (double x : mesh.fields[0].values) ASSERT_TRUE(std::isfinite(x));

  // Topology of the planted substructures.
  const auto expect_surface = [&](std::int32_t ref, std::int64_t euler, bool closed) {
    const SurfaceStats s = surface_stats(triangles_with_ref(mesh, ref));
    std::printf("    triangles ref %d: V %lld E %lld F %lld, chi %lld, %d component(s)\n", ref,
                static_cast<long long>(s.vertices), static_cast<long long>(s.edges), static_cast<long long>(s.faces),
                static_cast<long long>(s.euler()), s.components);
    EXPECT_GT(s.faces, 0) << "ref " << ref;
    EXPECT_EQ(s.euler(), euler) << "ref " << ref;
    EXPECT_EQ(s.components, 1) << "ref " << ref;
    EXPECT_EQ(s.nonmanifold_edges, 0) << "ref " << ref;
    EXPECT_EQ(s.nonmanifold_vertices, 0) << "ref " << ref;
    if (closed) {
      EXPECT_EQ(s.boundary_edges, 0) << "ref " << ref;
    } else {
      EXPECT_GT(s.boundary_edges, 0) << "ref " << ref;
    }
  };
  std::set<std::int32_t> tri_refs, seg_refs, materials(mesh.tet_material.begin(), mesh.tet_material.end());
  for (const Triangle& t : mesh.triangles) tri_refs.insert(t.ref);
  for (const Segment& s : mesh.segments) seg_refs.insert(s.ref);
  for (std::int32_t ref : seg_refs) expect_simple_path(segments_with_ref(mesh, ref), ref);

  const auto crossings = [&](const std::vector<Segment>& chain, std::int32_t ref) {
    return chain_crossings(mesh, chain, ref);
  };

  if (c.family == "cube-sphere") {
    EXPECT_EQ(materials, (std::set<std::int32_t>{1, 2}));
    EXPECT_EQ(tri_refs, (std::set<std::int32_t>{1, 2, 10}));
    EXPECT_EQ(seg_refs, (std::set<std::int32_t>{1}));
    expect_surface(1, 2, true);   // sphere
    expect_surface(2, 1, false);  // disc
    expect_surface(10, 2, true);  // box boundary
    EXPECT_EQ(triangles_with_ref(mesh, 10).size(), boundary_faces);
    // The patch lies inside material 1 and touches neither the ball nor the boundary.
    const auto patch = vertices_of(triangles_with_ref(mesh, 2));
    for (std::int32_t other : {1, 10})
      for (VertId v : vertices_of(triangles_with_ref(mesh, other))) EXPECT_FALSE(patch.count(v));
    for (const Triangle& t : triangles_with_ref(mesh, 2)) {
      const TetFace& f = faces.at(face_key(t.v));
      ASSERT_EQ(f.count, 2);
      EXPECT_EQ(mesh.tet_material[f.tets[0]], 1);
      EXPECT_EQ(mesh.tet_material[f.tets[1]], 1);
    }
    // The polyline runs from material 1 into the ball, piercing its surface at one vertex.
    const auto chain = segments_with_ref(mesh, 1);
    EXPECT_EQ(crossings(chain, 1), 1);
    EXPECT_EQ(chain_materials(mesh, chain), (std::vector<std::int32_t>{1, 2}));
    // Corners: the 8 box corners.
    ASSERT_EQ(mesh.corners.size(), 8u);
    std::set<std::array<double, 3>> corner_points;
    for (VertId v : mesh.corners) {
      const glm::dvec3 p = to_glm(mesh.positions[v]);
      for (int a = 0; a < 3; ++a) EXPECT_TRUE(p[a] == lo[a] || p[a] == hi[a]);
      corner_points.insert({p.x, p.y, p.z});
    }
    EXPECT_EQ(corner_points.size(), 8u);
  } else if (c.family == "slab") {
    EXPECT_EQ(materials, (std::set<std::int32_t>{1, 2, 3, 4, 5}));
    EXPECT_EQ(tri_refs, (std::set<std::int32_t>{1, 2, 3, 4}));
    EXPECT_EQ(seg_refs, (std::set<std::int32_t>{1, 2, 3, 4}));
    for (std::int32_t ref = 1; ref <= 4; ++ref) {
      expect_surface(ref, 1, false);  // a disc bounded on the box
      // A plane: its vertices jitter within it only.
      const auto tris = triangles_with_ref(mesh, ref);
      const double z = mesh.positions[tris.front().v[0]][2];
      for (VertId v : vertices_of(tris)) EXPECT_EQ(mesh.positions[v][2], z) << "ref " << ref;
      // The polyline lies on its interface.
      std::unordered_set<std::uint64_t> surface_edges;
      for (const Triangle& t : triangles_with_ref(mesh, ref))
        for (int i = 0; i < 3; ++i) surface_edges.insert(edge_key(t.v[i], t.v[(i + 1) % 3]));
      for (const Segment& s : segments_with_ref(mesh, ref)) EXPECT_TRUE(surface_edges.count(edge_key(s.v[0], s.v[1])));
    }
    // Layer thicknesses 2, 3, 5, 4, 2 cells: tets per layer in that proportion.
    std::map<std::int32_t, std::size_t> per_layer;
    for (std::int32_t m : mesh.tet_material) ++per_layer[m];
    const std::size_t per_cell_layer = mesh.tet_count() / 16;
    EXPECT_EQ(per_layer[1], 2 * per_cell_layer);
    EXPECT_EQ(per_layer[3], 5 * per_cell_layer);
    EXPECT_EQ(per_layer[5], 2 * per_cell_layer);
  } else {
    EXPECT_EQ(materials, (std::set<std::int32_t>{1, 2, 3}));
    EXPECT_EQ(tri_refs, (std::set<std::int32_t>{1, 2}));
    EXPECT_EQ(seg_refs, (std::set<std::int32_t>{1}));
    expect_surface(1, 0, true);  // torus
    expect_surface(2, 0, true);
    // The tori are linked: a boundary-free surface each, disjoint.
    const auto va = vertices_of(triangles_with_ref(mesh, 1));
    for (VertId v : vertices_of(triangles_with_ref(mesh, 2))) EXPECT_FALSE(va.count(v));
    // The polyline pierces each tube twice: in and out, 4 vertices per torus.
    const auto chain = segments_with_ref(mesh, 1);
    EXPECT_EQ(crossings(chain, 1), 4);
    EXPECT_EQ(crossings(chain, 2), 4);
    // Along x: box, A, box, B (around A's centre), box, A (around B's centre), box, B, box.
    EXPECT_EQ(chain_materials(mesh, chain), (std::vector<std::int32_t>{1, 2, 1, 3, 1, 2, 1, 3, 1}));
  }
}

INSTANTIATE_TEST_SUITE_P(Families, GenerateCase,
                         ::testing::Values(Case{"cube-sphere", 5000, 1}, Case{"cube-sphere", 5000, 7},
                                           Case{"cube-sphere", 30000, 1}, Case{"cube-sphere", 30000, 7},
                                           Case{"slab", 5000, 1}, Case{"slab", 5000, 7}, Case{"slab", 30000, 1},
                                           Case{"slab", 30000, 7}, Case{"linked-tori", 36000, 1},
                                           Case{"linked-tori", 36000, 7}, Case{"linked-tori", 50000, 1},
                                           Case{"linked-tori", 50000, 7}),
                         [](const ::testing::TestParamInfo<Case>& param_info) {
                           const Case& p = param_info.param;
                           std::string name =
                               p.family + "_" + std::to_string(p.target) + "_seed" + std::to_string(p.seed);
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST(Generate, SameSeedSameMesh) {
  for (const std::string& family : generator_families()) {
    const MeshData a = generate_mesh({family, 40000, 3});
    const MeshData b = generate_mesh({family, 40000, 3});
    EXPECT_TRUE(a == b) << family;
  }
}

TEST(Generate, SeedMovesPositionsOnly) {
  for (const std::string& family : generator_families()) {
    const MeshData a = generate_mesh({family, 40000, 3});
    const MeshData b = generate_mesh({family, 40000, 4});
    EXPECT_NE(a.positions, b.positions) << family;
    // Materials and substructures are planted on the lattice, independent of the jitter.
    EXPECT_EQ(a.tets, b.tets) << family;
    EXPECT_EQ(a.tet_material, b.tet_material) << family;
    EXPECT_EQ(a.triangles, b.triangles) << family;
    EXPECT_EQ(a.segments, b.segments) << family;
  }
}

TEST(Generate, JitterIsBounded) {
  const MeshData mesh = generate_mesh({"cube-sphere", 6 * 20 * 20 * 20, 5});  // a 20^3 grid
  ASSERT_EQ(mesh.vertex_count(), 21u * 21 * 21);
  const double h = 1.0 / 20;
  double largest = 0;
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    const glm::dvec3 lattice(v % 21, (v / 21) % 21, v / 441);
    largest = std::max(largest, glm::length(to_glm(mesh.positions[v]) / h - lattice));
  }
  EXPECT_LE(largest, gen::kJitter + 1e-9);
  EXPECT_GT(largest, 0.8 * gen::kJitter);
}

TEST(Generate, Errors) {
  try {
    generate_mesh({"cube-sphere", 100, 1});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "cube-sphere: --tets must be at least 3000");
  }
  EXPECT_THROW(generate_mesh({"slab", 1999, 1}), InputError);
  EXPECT_THROW(generate_mesh({"polycrystal", 19999, 1}), InputError);
  try {
    generate_mesh({"polycrystal", 20000, 1, 41});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "polycrystal: --cells must be at most 40 for 20250 tets (500 tets per cell)");
  }
  try {
    generate_mesh({"slab", 5000, 1, 3});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "slab: --cells applies to polycrystal only");
  }
  EXPECT_THROW(generate_mesh({"linked-tori", 35999, 1}), InputError);
  EXPECT_NO_THROW(generate_mesh({"slab", 2000, 1}));
  EXPECT_NO_THROW(generate_mesh({"linked-tori", 36000, 1}));
  try {
    generate_mesh({"cube-ball", 5000, 1});
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const std::string& family : generator_families()) EXPECT_NE(what.find(family), std::string::npos) << what;
  }
}

// Tet counts stay within 10% of every target, from each family's minimum up.
TEST(Generate, CellCountsMeetTarget) {
  for (double target = 2000; target <= 2e9; target *= 1.07) {
    const auto t = static_cast<std::uint64_t>(target);
    for (const auto& [aspect, nz] : {std::pair{std::array<double, 3>{1, 1, 1}, 0u},
                                     std::pair{std::array<double, 3>{3.6, 2.6, 2.6}, 0u},
                                     std::pair{std::array<double, 3>{1, 1, 1}, 16u}}) {
      if (nz == 0 && t < 3000) continue;
      const gen::Cells n = gen::choose_cells(t, aspect, nz);
      const double tets = 6.0 * n[0] * n[1] * n[2];
      EXPECT_NEAR(tets / target, 1.0, 0.1) << t << " tets: " << n[0] << " x " << n[1] << " x " << n[2];
      if (nz) {
        EXPECT_EQ(n[2], nz);
      }
    }
  }
}

// The planted topology depends on the grid size only; sweep sizes so that no digitization
// accident (a pinched tube, a non-manifold vertex, a polyline along an interface) hides between
// the sizes tested above. linked-tori at ~124k tets needs repair_pinches. Set
// TOPOTET_GENERATE_SWEEP_MAX (tets) to sweep further than the default 400k.
TEST(Generate, SurfaceTopologyAcrossSizes) {
  const char* env = std::getenv("TOPOTET_GENERATE_SWEEP_MAX");
  const double sweep_max = env ? std::strtod(env, nullptr) : 400000;
  struct Expect {
    std::string family;
    std::uint64_t min;
    std::vector<std::pair<std::int32_t, std::int64_t>> euler;  // (ref, chi)
  };
  for (const Expect& e : {Expect{"cube-sphere", 3000, {{1, 2}, {2, 1}, {10, 2}}},
                          Expect{"slab", 2000, {{1, 1}, {2, 1}, {3, 1}, {4, 1}}},
                          Expect{"linked-tori", 36000, {{1, 0}, {2, 0}}}}) {
    std::vector<std::uint64_t> targets;
    for (double target = e.min; target < sweep_max; target *= 1.15) {
      targets.push_back(static_cast<std::uint64_t>(target));
    }
    if (e.family == "linked-tori") targets.push_back(124281);
    for (std::uint64_t target : targets) {
      const MeshData mesh = generate_mesh({e.family, target, 1});
      const std::string what = e.family + " " + std::to_string(mesh.tet_count()) + " tets";
      for (const auto& [ref, chi] : e.euler) {
        const SurfaceStats s = surface_stats(triangles_with_ref(mesh, ref));
        EXPECT_EQ(s.euler(), chi) << what << " ref " << ref;
        EXPECT_EQ(s.components, 1) << what << " ref " << ref;
        EXPECT_EQ(s.nonmanifold_edges + s.nonmanifold_vertices, 0) << what << " ref " << ref;
      }
      const auto chain = segments_with_ref(mesh, 1);
      if (e.family == "cube-sphere") {
        EXPECT_EQ(chain_crossings(mesh, chain, 1), 1) << what;
        EXPECT_EQ(chain_materials(mesh, chain), (std::vector<std::int32_t>{1, 2})) << what;
      } else if (e.family == "linked-tori") {
        EXPECT_EQ(chain_crossings(mesh, chain, 1), 4) << what;
        EXPECT_EQ(chain_crossings(mesh, chain, 2), 4) << what;
        EXPECT_EQ(chain_materials(mesh, chain), (std::vector<std::int32_t>{1, 2, 1, 3, 1, 2, 1, 3, 1})) << what;
      }
    }
  }
}

TEST(FreudenthalGrid, VertexStarIsTheTetsAroundTheVertex) {
  const gen::FreudenthalGrid grid({3, 4, 5});
  MeshData mesh;
  gen::build_tets(grid, [](const glm::dvec3&) { return 1; }, mesh);
  for (std::uint32_t k = 1; k < 5; ++k)
    for (std::uint32_t j = 1; j < 4; ++j)
      for (std::uint32_t i = 1; i < 3; ++i) {
        const VertId v = grid.vertex(i, j, k);
        std::set<TetId> expected;
        for (TetId t = 0; t < mesh.tet_count(); ++t)
          if (std::find(mesh.tets[t].begin(), mesh.tets[t].end(), v) != mesh.tets[t].end()) expected.insert(t);
        const auto star = gen::vertex_star(grid, i, j, k);
        EXPECT_EQ(std::set<TetId>(star.begin(), star.end()), expected) << i << " " << j << " " << k;
      }
}

// Two cubes of material 2 sharing only an edge: a pinched interface that repair_pinches must
// turn into one manifold sphere.
TEST(FreudenthalGrid, RepairPinchesJoinsAnEdgeContact) {
  const gen::FreudenthalGrid grid({6, 6, 6});
  MeshData mesh;
  gen::build_tets(
      grid,
      [](const glm::dvec3& c) {
        const auto in_cube = [&](int i, int j, int k) {
          return c.x > i && c.x < i + 1 && c.y > j && c.y < j + 1 && c.z > k && c.z < k + 1;
        };
        return in_cube(2, 2, 2) || in_cube(3, 3, 2) ? 2 : 1;
      },
      mesh);
  const auto interface_stats = [&] {
    MeshData copy = mesh;
    copy.triangles.clear();
    gen::add_interface_triangles(grid, [](std::int32_t, std::int32_t) { return 1; }, copy);
    return surface_stats(copy.triangles);
  };
  const SurfaceStats before = interface_stats();
  EXPECT_GT(before.nonmanifold_edges + before.nonmanifold_vertices, 0);
  gen::repair_pinches(grid, 2, 1, mesh);
  const SurfaceStats after = interface_stats();
  EXPECT_EQ(after.nonmanifold_edges + after.nonmanifold_vertices, 0);
  EXPECT_EQ(after.euler(), 2);
  EXPECT_EQ(after.components, 1);
  EXPECT_EQ(after.boundary_edges, 0);
}

// --- polycrystal ---

constexpr std::array<std::int64_t, 4> kBall = {1, 0, 0, 0};     // also a disc, a path, a point
constexpr std::array<std::int64_t, 4> kSphere = {1, 0, 1, 0};

// The documented default: one cell per ~4000 tets, at least 8.
std::uint32_t default_polycrystal_cells(std::size_t tets) {
  return static_cast<std::uint32_t>(std::max<std::size_t>(8, (tets + 2000) / 4000));
}

using MaterialPair = std::pair<std::int32_t, std::int32_t>;

struct PolycrystalCase {
  std::uint64_t target;
  std::uint32_t cells;  // 0 = the default
  std::uint64_t seed;
};

class Polycrystal : public ::testing::TestWithParam<PolycrystalCase> {};

TEST_P(Polycrystal, CellsAreBallsListedInterfacesDiscsAndCurvesTripleJunctions) {
  const PolycrystalCase& c = GetParam();
  const MeshData mesh = generate_mesh({"polycrystal", c.target, c.seed, c.cells});
  EXPECT_NEAR(static_cast<double>(mesh.tet_count()) / c.target, 1.0, 0.1);
  EXPECT_NO_THROW(build_mesh_model(mesh));  // orientation, conformity, listed elements are mesh faces/edges
  EXPECT_GT(dihedral_angles(mesh).min, 25.0);
  ASSERT_EQ(mesh.fields.size(), 1u);
  EXPECT_EQ(mesh.fields[0].name, "f");
  const topotet::TopologyReport topo = topotet::compute_topology(mesh);
  EXPECT_EQ(topo.mesh.betti, kBall);
  EXPECT_EQ(topo.boundary.betti, kSphere);

  // Materials 1..C, each a ball: Betti numbers of a point, and a manifold (region_manifold.h).
  const std::uint32_t cells = c.cells ? c.cells : default_polycrystal_cells(mesh.tet_count());
  const std::set<std::int32_t> materials(mesh.tet_material.begin(), mesh.tet_material.end());
  ASSERT_EQ(materials.size(), cells);
  EXPECT_EQ(*materials.begin(), 1);
  EXPECT_EQ(*materials.rbegin(), static_cast<std::int32_t>(cells));
  for (const auto& [m, complex] : topo.materials) EXPECT_EQ(complex.betti, kBall) << "material " << m;
  EXPECT_EQ(testing::count_nonmanifold_region_vertices(mesh), 0u);
  // A Voronoi cell has about 15 faces, each shared by two cells; fewer at the box.
  EXPECT_GE(topo.interfaces.size(), 2u * cells);
  EXPECT_LE(topo.interfaces.size(), 8u * cells);

  // Triangles: ref 1 is the box boundary; every other ref is one whole interface, a disc, with its
  // normal pointing from the higher material into the lower one.
  const auto faces = tet_faces(mesh);
  std::map<MaterialPair, std::size_t> interface_faces;
  std::size_t boundary_faces = 0;
  for (const auto& [key, f] : faces) {
    if (f.count == 1) ++boundary_faces;
    const std::int32_t m0 = mesh.tet_material[f.tets[0]], m1 = f.count == 2 ? mesh.tet_material[f.tets[1]] : m0;
    if (m0 != m1) ++interface_faces[{std::min(m0, m1), std::max(m0, m1)}];
  }
  std::map<std::int32_t, std::set<MaterialPair>> pairs_of_ref;
  std::map<MaterialPair, std::size_t> listed_faces;
  for (const Triangle& t : mesh.triangles) {
    const TetFace& f = faces.at(face_key(t.v));
    if (t.ref == 1) {
      EXPECT_EQ(f.count, 1) << "ref 1 triangle inside the box";
      continue;
    }
    ASSERT_EQ(f.count, 2) << "interface ref " << t.ref << " on the boundary";
    const std::int32_t m0 = mesh.tet_material[f.tets[0]], m1 = mesh.tet_material[f.tets[1]];
    ASSERT_NE(m0, m1) << "ref " << t.ref << " inside a cell";
    const MaterialPair pair = {std::min(m0, m1), std::max(m0, m1)};
    pairs_of_ref[t.ref].insert(pair);
    ++listed_faces[pair];
    const TetId higher = m0 > m1 ? f.tets[0] : f.tets[1];
    VertId apex = 0;
    for (VertId v : mesh.tets[higher])
      if (std::find(t.v.begin(), t.v.end(), v) == t.v.end()) apex = v;
    const glm::dvec3 a = to_glm(mesh.positions[t.v[0]]);
    const glm::dvec3 normal = glm::cross(to_glm(mesh.positions[t.v[1]]) - a, to_glm(mesh.positions[t.v[2]]) - a);
    EXPECT_LT(glm::dot(to_glm(mesh.positions[apex]) - a, normal), 0.0) << "ref " << t.ref << " points into the higher cell";
  }
  EXPECT_EQ(triangles_with_ref(mesh, 1).size(), boundary_faces);
  EXPECT_EQ(topo.surfaces.at(1).betti, kSphere);
  const std::size_t listed = pairs_of_ref.size();
  for (const auto& [ref, pairs] : pairs_of_ref) {
    EXPECT_EQ(ref, static_cast<std::int32_t>(2 + std::distance(pairs_of_ref.begin(), pairs_of_ref.find(ref))));
    ASSERT_EQ(pairs.size(), 1u) << "ref " << ref << " spans several interfaces";
    EXPECT_EQ(listed_faces[*pairs.begin()], interface_faces[*pairs.begin()]) << "ref " << ref << " is part of an interface";
    EXPECT_EQ(topo.surfaces.at(ref).betti, kBall) << "ref " << ref << " is not a disc";
  }
  // About three quarters of the interfaces are listed; the others are implicit.
  EXPECT_GE(listed, topo.interfaces.size() / 2);
  EXPECT_LT(listed, topo.interfaces.size());

  // Segments: refs 1..P, each a simple path of edges around which exactly three cells meet, always
  // the same three; both ends pinned.
  std::set<std::int32_t> seg_refs;
  for (const Segment& s : mesh.segments) seg_refs.insert(s.ref);
  ASSERT_FALSE(seg_refs.empty());
  EXPECT_EQ(*seg_refs.rbegin(), static_cast<std::int32_t>(seg_refs.size()));
  EXPECT_GE(seg_refs.size(), cells / 2);
  const std::set<VertId> corners(mesh.corners.begin(), mesh.corners.end());
  for (std::int32_t ref : seg_refs) {
    const auto chain = segments_with_ref(mesh, ref);
    expect_simple_path(chain, ref);
    EXPECT_EQ(topo.polylines.at(ref).betti, kBall) << "polyline ref " << ref;
    std::set<std::set<std::int32_t>> around;
    for (const auto& [edge, m] : edge_materials(mesh, chain)) around.insert(m);
    ASSERT_EQ(around.size(), 1u) << "polyline ref " << ref << " leaves its junction";
    EXPECT_EQ(around.begin()->size(), 3u) << "polyline ref " << ref << " is not a triple junction";
    std::map<VertId, int> degree;
    for (const Segment& s : chain)
      for (VertId v : s.v) ++degree[v];
    for (const auto& [v, d] : degree) {
      if (d == 1) {
        EXPECT_TRUE(corners.count(v)) << "end of polyline ref " << ref << " not pinned";
      }
    }
  }
  // Corners: the box corners and the curve ends.
  EXPECT_LE(corners.size(), 2 * seg_refs.size() + 8);
  std::size_t box_corners = 0;
  glm::dvec3 hi(0.0);
  for (const auto& p : mesh.positions) hi = glm::max(hi, to_glm(p));
  for (VertId v : corners) {
    const glm::dvec3 p = to_glm(mesh.positions[v]);
    box_corners += (p.x == 0 || p.x == hi.x) && (p.y == 0 || p.y == hi.y) && (p.z == 0 || p.z == hi.z);
  }
  EXPECT_EQ(box_corners, 8u);
  std::printf("[ polycrystal %llu, %u cells ] %zu tets: %zu interfaces (%zu listed), %zu polylines, %zu corners\n",
              static_cast<unsigned long long>(c.target), cells, mesh.tet_count(), topo.interfaces.size(), listed,
              seg_refs.size(), corners.size());
}

INSTANTIATE_TEST_SUITE_P(Sizes, Polycrystal,
                         ::testing::Values(PolycrystalCase{20000, 0, 1}, PolycrystalCase{30000, 20, 7},
                                           PolycrystalCase{60000, 100, 3}),
                         [](const ::testing::TestParamInfo<PolycrystalCase>& param_info) {
                           const PolycrystalCase& p = param_info.param;
                           return std::to_string(p.target) + "_cells" + std::to_string(p.cells) + "_seed" +
                                  std::to_string(p.seed);
                         });

// Ball-preserving growth can in principle get stuck (ball_growth.h); sweep sizes and cell counts
// (the structure depends on them only, not on the seed) so that no such case hides between the
// sizes tested above, and check every cell independently. TOPOTET_GENERATE_SWEEP_MAX (tets)
// sweeps further than the default 100k.
TEST(Polycrystal, EveryCellIsABallAcrossSizesAndCellCounts) {
  const char* env = std::getenv("TOPOTET_GENERATE_SWEEP_MAX");
  const double sweep_max = env ? std::strtod(env, nullptr) : 100000;
  for (double target = 20000; target < sweep_max; target *= 1.35) {
    const auto tets = static_cast<std::uint64_t>(target);
    for (const std::uint32_t cells : {0u, static_cast<std::uint32_t>(tets * 0.95 / 500)}) {
      const MeshData mesh = generate_mesh({"polycrystal", tets, 1, cells});
      const std::string what = std::to_string(mesh.tet_count()) + " tets, cells " + std::to_string(cells);
      const std::set<std::int32_t> materials(mesh.tet_material.begin(), mesh.tet_material.end());
      EXPECT_EQ(materials.size(), cells ? cells : default_polycrystal_cells(mesh.tet_count())) << what;
      EXPECT_EQ(testing::count_nonmanifold_region_vertices(mesh), 0u) << what;
      for (const auto& [m, complex] : topotet::compute_topology(mesh).materials) {
        EXPECT_EQ(complex.betti, kBall) << what << ", material " << m;
      }
    }
  }
}

TEST(TetNeighbourhood, NeighboursAreTheTetsSharingAVertexOrAFace) {
  const gen::FreudenthalGrid grid({4, 5, 3});
  MeshData mesh;
  gen::build_tets(grid, [](const glm::dvec3&) { return 1; }, mesh);
  const gen::TetNeighbourhood hood(grid);
  std::vector<std::set<TetId>> across(mesh.tet_count());
  gen::for_each_face(grid, [&](TetId t, int, TetId nb) {
    if (nb == kInvalid) return;
    across[t].insert(nb);
    across[nb].insert(t);
  });
  for (TetId t = 0; t < mesh.tet_count(); ++t) {
    std::set<TetId> sharing, faces, neighbours;
    for (TetId u = 0; u < mesh.tet_count(); ++u) {
      const auto& a = mesh.tets[t];
      const auto& b = mesh.tets[u];
      if (u != t && std::any_of(a.begin(), a.end(), [&](VertId v) { return std::count(b.begin(), b.end(), v); })) {
        sharing.insert(u);
      }
    }
    hood.for_each_face_neighbour(t, [&](TetId u) { faces.insert(u); });
    hood.for_each_neighbour(t, [&](TetId u) { neighbours.insert(u); });
    EXPECT_EQ(faces, across[t]) << "tet " << t;
    EXPECT_EQ(neighbours, sharing) << "tet " << t;
    const auto corners = gen::tet_vertices(grid, t);
    EXPECT_EQ(std::set<VertId>(corners.begin(), corners.end()),
              std::set<VertId>(mesh.tets[t].begin(), mesh.tets[t].end()));
  }
}

// The join and leave tests, at random on a small grid where most tets touch the box: regions
// change only by the steps they allow, and every region must stay a ball after each one.
TEST(TetNeighbourhood, JoinAndLeaveStepsKeepRegionsBalls) {
  const gen::FreudenthalGrid grid({4, 3, 3});
  MeshData mesh;
  gen::build_tets(grid, [](const glm::dvec3&) { return 0; }, mesh);
  gen::set_jittered_positions(grid, 1, mesh);
  const gen::TetNeighbourhood hood(grid);
  std::vector<std::int32_t> material(mesh.tet_count(), 0);
  material.front() = 1;
  material.back() = 2;
  material[material.size() / 2] = 3;
  int joins = 0, leaves = 0, refused = 0;
  for (std::uint64_t step = 0; step < 12000; ++step) {
    const std::uint64_t r = gen::splitmix64(step);
    const auto t = static_cast<TetId>(r % material.size());
    if (material[t] == 0) {
      const auto m = static_cast<std::int32_t>(1 + (r >> 32) % 3);
      if (!hood.joins_as_ball(t, m, material)) {
        ++refused;
        continue;
      }
      material[t] = m;
      ++joins;
    } else {
      if (!hood.leaves_as_ball(t, material)) {
        ++refused;
        continue;
      }
      material[t] = 0;
      ++leaves;
    }
    // The regions alone (free tets left out), checked independently.
    MeshData regions = mesh;
    regions.tets.clear();
    regions.tet_material.clear();
    for (TetId u = 0; u < mesh.tet_count(); ++u) {
      if (material[u] == 0) continue;
      regions.tets.push_back(mesh.tets[u]);
      regions.tet_material.push_back(material[u]);
    }
    ASSERT_EQ(testing::count_nonmanifold_region_vertices(regions), 0u) << "step " << step;
    for (const auto& [m, complex] : topotet::compute_topology(regions).materials) {
      ASSERT_EQ(complex.betti, kBall) << "step " << step << ", material " << m;
    }
  }
  std::printf("[ ball steps ] %d joins, %d leaves, %d refused\n", joins, leaves, refused);
  EXPECT_GT(joins, 500);
  EXPECT_GT(leaves, 500);
  EXPECT_GT(refused, 500);
}

// The independent check must see what Betti numbers miss: two cubes of a region sharing an edge.
TEST(Polycrystal, ManifoldCheckSeesAnEdgePinch) {
  const gen::FreudenthalGrid grid({6, 6, 6});
  MeshData mesh;
  gen::build_tets(
      grid,
      [](const glm::dvec3& c) {
        const auto in_cube = [&](int i, int j, int k) {
          return c.x > i && c.x < i + 1 && c.y > j && c.y < j + 1 && c.z > k && c.z < k + 1;
        };
        return in_cube(2, 2, 2) || in_cube(3, 3, 2) ? 2 : 1;
      },
      mesh);
  gen::set_jittered_positions(grid, 1, mesh);
  EXPECT_EQ(topotet::compute_topology(mesh).materials.at(2).betti, kBall);
  EXPECT_GT(testing::count_nonmanifold_region_vertices(mesh), 0u);
}

TEST(Generate, OneMillionTets) {
  for (const std::string& family : generator_families()) {
    const auto start = std::chrono::steady_clock::now();
    const MeshData mesh = generate_mesh({family, 1'000'000, 1});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("[ %s 1M ] %zu tets, %zu verts, %zu triangles, %zu segments in %.3f s\n", family.c_str(),
                mesh.tet_count(), mesh.vertex_count(), mesh.triangles.size(), mesh.segments.size(), seconds);
    EXPECT_NEAR(mesh.tet_count() / 1e6, 1.0, 0.1) << family;
    EXPECT_EQ(mesh.tet_material.size(), mesh.tet_count());
    EXPECT_EQ(mesh.positions.size(), mesh.fields.at(0).values.size());
    EXPECT_LT(seconds, 10.0) << family;
  }
}

// Collects what generate_streamed sends into a MeshData, checking the announced counts.
class CollectSink final : public GenerateSink {
 public:
  MeshData mesh;
  std::uint64_t announced[5] = {};
  void begin_vertices(std::uint64_t count) override {
    announced[0] = count;
    mesh.fields.push_back({"f", 1, {}});
  }
  void vertex(const std::array<double, 3>& p, double value) override {
    mesh.positions.push_back(p);
    mesh.fields[0].values.push_back(value);
  }
  void begin_tets(std::uint64_t count) override { announced[1] = count; }
  void tet(const std::array<VertId, 4>& v, std::int32_t material) override {
    mesh.tets.push_back(v);
    mesh.tet_material.push_back(material);
  }
  void begin_triangles(std::uint64_t count) override { announced[2] = count; }
  void triangle(const Triangle& t) override { mesh.triangles.push_back(t); }
  void begin_segments(std::uint64_t count) override { announced[3] = count; }
  void segment(const Segment& s) override { mesh.segments.push_back(s); }
  void begin_corners(std::uint64_t count) override { announced[4] = count; }
  void corner(VertId v) override { mesh.corners.push_back(v); }
};

// The streamed generator must send exactly the in-memory mesh: the CLI writes either one, and
// its output must not depend on which (tests/cli_test.sh compares the bytes).
TEST(GenerateStreamed, CubeSphereSendsTheInMemoryMesh) {
  for (const std::uint64_t tets : {3000ull, 10000ull, 50000ull, 200000ull}) {
    for (const std::uint64_t seed : {1ull, 7ull}) {
      const GenerateOptions options{"cube-sphere", tets, seed};
      ASSERT_TRUE(can_stream(options));
      const MeshData expected = generate_mesh(options);
      CollectSink sink;
      generate_streamed(options, sink);
      const MeshData& got = sink.mesh;
      SCOPED_TRACE(std::to_string(tets) + " tets, seed " + std::to_string(seed));
      EXPECT_EQ(sink.announced[0], got.positions.size());
      EXPECT_EQ(sink.announced[1], got.tets.size());
      EXPECT_EQ(sink.announced[2], got.triangles.size());
      EXPECT_EQ(sink.announced[3], got.segments.size());
      EXPECT_EQ(sink.announced[4], got.corners.size());
      EXPECT_TRUE(got.positions == expected.positions);  // bit for bit
      EXPECT_TRUE(got.tets == expected.tets);
      EXPECT_TRUE(got.tet_material == expected.tet_material);
      ASSERT_EQ(got.triangles.size(), expected.triangles.size());
      for (std::size_t i = 0; i < got.triangles.size(); ++i) {
        ASSERT_TRUE(got.triangles[i].v == expected.triangles[i].v && got.triangles[i].ref == expected.triangles[i].ref)
            << "triangle " << i;
      }
      ASSERT_EQ(got.segments.size(), expected.segments.size());
      for (std::size_t i = 0; i < got.segments.size(); ++i)
        EXPECT_TRUE(got.segments[i].v == expected.segments[i].v && got.segments[i].ref == expected.segments[i].ref);
      EXPECT_EQ(got.corners, expected.corners);
      ASSERT_EQ(expected.fields.size(), 1u);
      EXPECT_EQ(expected.fields[0].name, "f");
      EXPECT_TRUE(got.fields[0].values == expected.fields[0].values);
    }
  }
}

TEST(GenerateStreamed, OtherFamiliesStayInMemory) {
  for (const char* family : {"slab", "linked-tori", "polycrystal"}) {
    EXPECT_FALSE(can_stream({family, 100000, 1})) << family;
  }
}

}  // namespace
}  // namespace topotet
