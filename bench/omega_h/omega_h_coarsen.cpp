// omega_h_coarsen: Sandia's Omega_h as a peer of `topotet simplify` (issue #50 item 3).
//
// Reads a MEDIT ASCII .mesh (what `topotet convert IN X.mesh` writes), builds the Omega_h mesh
// with the calls Omega_h's own Gmsh reader makes (build_from_elems_and_coords,
// classify_equal_order, then classification projected down), with class_id = the MEDIT ref:
//   tets: class_dim 3, id = material ref; listed triangles: dim 2, id = their ref; listed edges:
//   dim 1, id = their ref; Corners / RequiredVertices: dim 0. Faces between two materials or on
//   the boundary that the file does not list get dim 2 and an id per (material, material) pair;
//   surface edges whose faces turn by more than --feature-angle (as topotet's default, 45) become
//   model edges and the vertices where three model edges meet or a model edge turns sharply model
//   vertices (what Omega_h's classify_by_angles does for a boundary, extended to interfaces);
//   every closed loop of model edges gets three model vertices (Omega_h aborts otherwise).
// Then an isotropic metric, the implied one (current edge lengths) times 1/s^2, approached with
// approach_metric() + adapt() (AdaptOpts defaults: coarsen, refine, swap, sliver removal); s is
// searched (a few full runs from the input) so that the output reaches --vertices. Writes MEDIT:
// vertices, tets (ref = class_id), the triangles / edges / corners whose class ids came from the
// input (so `topotet check IN OUT` compares the same labels).
//
//   omega_h_coarsen IN.mesh OUT.mesh --vertices N [--feature-angle 45] [--max-tries 5]
//                   [--tolerance 0.03] [--scale S] [--json FILE] [--verbose]
// (--scale: the first metric scale tried instead of the guess (N_in / N)^(1/3).)
// Threads: OMP_NUM_THREADS.
#include <Omega_h_adapt.hpp>
#include <Omega_h_array_ops.hpp>
#include <Omega_h_build.hpp>
#include <Omega_h_class.hpp>
#include <Omega_h_config.h>
#include <Omega_h_library.hpp>
#include <Omega_h_mesh.hpp>
#include <Omega_h_metric.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>
#include <cstring>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {

#define OH_STR2(x) #x
#define OH_STR(x) OH_STR2(x)
constexpr char const* kVersion =
    OH_STR(OMEGA_H_VERSION_MAJOR) "." OH_STR(OMEGA_H_VERSION_MINOR) "." OH_STR(OMEGA_H_VERSION_PATCH);

using Omega_h::ClassId;
using Omega_h::I8;
using Omega_h::LO;

// Class ids above this are made here (untagged interfaces, feature edges), never written out.
constexpr ClassId kSynthetic = 1 << 28;
constexpr ClassId kCorner = 1, kRequired = 2;  // dim-0 ids: bit flags of the input pins

struct Medit {
  std::vector<std::array<double, 3>> xyz;
  std::vector<std::array<int, 4>> tets;  // 0-based
  std::vector<int> tet_ref;
  std::vector<std::array<int, 3>> tris;
  std::vector<int> tri_ref;
  std::vector<std::array<int, 2>> edges;
  std::vector<int> edge_ref;
  std::vector<int> corners, required;  // 0-based
  bool negative = false;                // input tets mostly negatively oriented
};

[[noreturn]] void fail(std::string const& what) { throw std::runtime_error(what); }

Medit read_medit(std::string const& path) {
  std::ifstream in(path);
  if (!in) fail("cannot open " + path);
  Medit m;
  // Items of the sections skipped: their number of values per line.
  const std::map<std::string, int> skip = {{"Ridges", 1}, {"RequiredEdges", 1}, {"RequiredTriangles", 1},
      {"Normals", 3}, {"NormalAtVertices", 2}, {"Tangents", 3}, {"TangentAtVertices", 2},
      {"NormalAtTriangleVertices", 3}, {"Quadrilaterals", 5}, {"Hexahedra", 9}, {"Prisms", 7},
      {"Pyramids", 6}, {"RequiredTetrahedra", 1}};
  std::string key;
  while (in >> key) {
    if (key[0] == '#') { std::getline(in, key); continue; }
    if (key == "MeshVersionFormatted" || key == "Dimension") {
      int v; in >> v;
      if (key == "Dimension" && v != 3) fail("only 3D meshes");
      continue;
    }
    if (key == "End") break;
    long n;
    if (!(in >> n)) fail("bad count after " + key);
    if (key == "Vertices") {
      m.xyz.resize(n);
      for (long i = 0; i < n; ++i) { int r; in >> m.xyz[i][0] >> m.xyz[i][1] >> m.xyz[i][2] >> r; }
    } else if (key == "Tetrahedra") {
      m.tets.resize(n); m.tet_ref.resize(n);
      for (long i = 0; i < n; ++i) {
        for (auto& v : m.tets[i]) { in >> v; --v; }
        in >> m.tet_ref[i];
      }
    } else if (key == "Triangles") {
      m.tris.resize(n); m.tri_ref.resize(n);
      for (long i = 0; i < n; ++i) {
        for (auto& v : m.tris[i]) { in >> v; --v; }
        in >> m.tri_ref[i];
      }
    } else if (key == "Edges") {
      m.edges.resize(n); m.edge_ref.resize(n);
      for (long i = 0; i < n; ++i) {
        for (auto& v : m.edges[i]) { in >> v; --v; }
        in >> m.edge_ref[i];
      }
    } else if (key == "Corners" || key == "RequiredVertices") {
      auto& dst = key == "Corners" ? m.corners : m.required;
      dst.resize(n);
      for (auto& v : dst) { in >> v; --v; }
    } else if (skip.count(key)) {
      double x;
      for (long i = 0; i < n * skip.at(key); ++i) in >> x;
    } else {
      fail("unsupported MEDIT section " + key + " (convert with topotet convert first)");
    }
    if (!in) fail("truncated section " + key);
  }
  if (m.tets.empty()) fail("no tetrahedra in " + path);
  return m;
}

double signed_volume(std::array<double, 3> const& a, std::array<double, 3> const& b,
    std::array<double, 3> const& c, std::array<double, 3> const& d) {
  double u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k) { u[k] = b[k] - a[k]; v[k] = c[k] - a[k]; w[k] = d[k] - a[k]; }
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

// The input with the vertices no tet uses left out and the tets positively oriented (Omega_h's
// convention); m.negative records the input's.
void compact_and_orient(Medit& m) {
  std::vector<int> newid(m.xyz.size(), -1);
  std::vector<std::array<double, 3>> xyz;
  for (auto& t : m.tets)
    for (auto& v : t) {
      if (newid[v] < 0) { newid[v] = int(xyz.size()); xyz.push_back(m.xyz[v]); }
      v = newid[v];
    }
  m.xyz = std::move(xyz);
  auto remap_list = [&](auto& items, auto& refs) {
    size_t k = 0;
    for (size_t i = 0; i < items.size(); ++i) {
      bool ok = true;
      for (auto& v : items[i]) ok = ok && newid[v] >= 0;
      if (!ok) continue;
      for (auto& v : items[i]) v = newid[v];
      items[k] = items[i]; refs[k] = refs[i]; ++k;
    }
    items.resize(k); refs.resize(k);
  };
  remap_list(m.tris, m.tri_ref);
  remap_list(m.edges, m.edge_ref);
  for (auto* list : {&m.corners, &m.required}) {
    std::vector<int> kept;
    for (int v : *list) if (newid[v] >= 0) kept.push_back(newid[v]);
    *list = kept;
  }
  size_t neg = 0;
  for (auto& t : m.tets) {
    if (signed_volume(m.xyz[t[0]], m.xyz[t[1]], m.xyz[t[2]], m.xyz[t[3]]) < 0) { std::swap(t[2], t[3]); ++neg; }
  }
  m.negative = 2 * neg > m.tets.size();
}

template <typename T>
Omega_h::Read<T> to_read(std::vector<T> const& v) {
  Omega_h::HostWrite<T> h(LO(v.size()));
  for (size_t i = 0; i < v.size(); ++i) h[LO(i)] = v[i];
  return Omega_h::Read<T>(h.write());
}

std::array<double, 3> sub(std::array<double, 3> a, std::array<double, 3> b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(std::array<double, 3> a, std::array<double, 3> b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Recompute the classification of dimension dim from that of dim + 1 (Omega_h's projection),
// starting from the given arrays.
void project(Omega_h::Mesh* mesh, int dim, std::vector<I8> cd, std::vector<ClassId> ci) {
  Omega_h::Write<I8> cdw = Omega_h::deep_copy(to_read(cd));
  Omega_h::Write<ClassId> ciw = Omega_h::deep_copy(to_read(ci));
  Omega_h::project_classification(mesh, dim, cdw, ciw);
  mesh->set_tag(dim, "class_dim", Omega_h::Read<I8>(cdw));
  mesh->set_tag(dim, "class_id", Omega_h::Read<ClassId>(ciw));
}

struct ClassStats {
  long untagged_faces = 0, feature_edges = 0, feature_vertices = 0, loop_vertices = 0;
};

// The Omega_h mesh of m, classified (see the head of the file).
ClassStats build(Omega_h::Library* lib, Omega_h::Mesh* mesh, Medit const& m, double feature_angle) {
  using namespace Omega_h;
  ClassStats st;
  const LO nv = LO(m.xyz.size());
  std::vector<LO> ev2v;
  ev2v.reserve(m.tets.size() * 4);
  for (auto& t : m.tets) for (int v : t) ev2v.push_back(v);
  std::vector<Real> coords(size_t(nv) * 3);
  for (LO i = 0; i < nv; ++i) for (int k = 0; k < 3; ++k) coords[size_t(i) * 3 + k] = m.xyz[i][k];
  build_from_elems_and_coords(mesh, OMEGA_H_SIMPLEX, 3, to_read(ev2v), to_read(coords));
  mesh->set_comm(lib->self());
  classify_equal_order(mesh, 3, to_read(ev2v), to_read<ClassId>(std::vector<ClassId>(m.tet_ref.begin(), m.tet_ref.end())));
  // Faces: the listed ones, then the untagged boundary and interface faces by material pair.
  {
    std::vector<LO> fv;
    for (auto& t : m.tris) for (int v : t) fv.push_back(v);
    classify_equal_order(mesh, 2, to_read(fv), to_read<ClassId>(std::vector<ClassId>(m.tri_ref.begin(), m.tri_ref.end())));
    HostRead<I8> cd0(mesh->get_array<I8>(2, "class_dim"));
    HostRead<ClassId> ci0(mesh->get_array<ClassId>(2, "class_id"));
    HostRead<ClassId> tet_id(mesh->get_array<ClassId>(3, "class_id"));
    auto f2t = mesh->ask_up(2, 3);
    HostRead<LO> a2ab(f2t.a2ab), ab2b(f2t.ab2b);
    const LO nf = mesh->nents(2);
    std::vector<I8> cd(nf);
    std::vector<ClassId> ci(nf);
    std::map<std::pair<ClassId, ClassId>, ClassId> pair_id;
    for (LO f = 0; f < nf; ++f) {
      cd[f] = cd0[f]; ci[f] = ci0[f];
      if (cd[f] == 2) continue;
      const LO b = a2ab[f], e = a2ab[f + 1];
      ClassId a = tet_id[ab2b[b]], c = (e - b == 2) ? tet_id[ab2b[b + 1]] : -1;
      if (e - b == 2 && a == c) { cd[f] = 3; ci[f] = a; continue; }
      auto key = std::make_pair(std::min(a, c), std::max(a, c));
      auto it = pair_id.emplace(key, kSynthetic + ClassId(pair_id.size())).first;
      cd[f] = 2; ci[f] = it->second; ++st.untagged_faces;
    }
    mesh->set_tag(2, "class_dim", to_read(cd));
    mesh->set_tag(2, "class_id", to_read(ci));
  }
  // Edges: the listed ones, the rest projected from the faces, then sharp surface edges.
  HostRead<Real> X(mesh->coords());
  auto P = [&](LO v) { return std::array<double, 3>{X[3 * v], X[3 * v + 1], X[3 * v + 2]}; };
  const double cos_limit = std::cos(feature_angle * M_PI / 180.0);
  {
    std::vector<LO> ev;
    for (auto& e : m.edges) for (int v : e) ev.push_back(v);
    classify_equal_order(mesh, 1, to_read(ev), to_read<ClassId>(std::vector<ClassId>(m.edge_ref.begin(), m.edge_ref.end())));
    HostRead<I8> cd0(mesh->get_array<I8>(1, "class_dim"));
    HostRead<ClassId> ci0(mesh->get_array<ClassId>(1, "class_id"));
    const LO ne = mesh->nents(1);
    std::vector<I8> cd(ne);
    std::vector<ClassId> ci(ne);
    for (LO e = 0; e < ne; ++e) { cd[e] = cd0[e]; ci[e] = ci0[e]; }
    project(mesh, 1, cd, ci);
    if (feature_angle < 180) {
      HostRead<I8> ecd(mesh->get_array<I8>(1, "class_dim"));
      HostRead<ClassId> eci(mesh->get_array<ClassId>(1, "class_id"));
      HostRead<I8> fcd(mesh->get_array<I8>(2, "class_dim"));
      HostRead<LO> e2v(mesh->ask_verts_of(1)), f2v(mesh->ask_verts_of(2));
      auto e2f = mesh->ask_up(1, 2);
      HostRead<LO> a2ab(e2f.a2ab), ab2b(e2f.ab2b);
      for (LO e = 0; e < ne; ++e) {
        cd[e] = ecd[e]; ci[e] = eci[e];
        if (ecd[e] != 2) continue;
        const LO a = e2v[2 * e], b = e2v[2 * e + 1];
        auto ab = sub(P(b), P(a));
        const double l2 = dot(ab, ab);
        std::vector<std::array<double, 3>> wing;  // per surface face: unit vector into it, normal to the edge
        for (LO k = a2ab[e]; k < a2ab[e + 1]; ++k) {
          const LO f = ab2b[k];
          if (fcd[f] != 2) continue;
          LO c = -1;
          for (int j = 0; j < 3; ++j) if (f2v[3 * f + j] != a && f2v[3 * f + j] != b) c = f2v[3 * f + j];
          auto ac = sub(P(c), P(a));
          const double t = dot(ac, ab) / l2;
          std::array<double, 3> w{ac[0] - t * ab[0], ac[1] - t * ab[1], ac[2] - t * ab[2]};
          const double n = std::sqrt(dot(w, w));
          wing.push_back({w[0] / n, w[1] / n, w[2] / n});
        }
        // Flat: the two wings opposite (cosine -1); the surface turns by acos(-cos).
        if (wing.size() == 2 && -dot(wing[0], wing[1]) < cos_limit) {
          cd[e] = 1; ci[e] = kSynthetic; ++st.feature_edges;
        }
      }
      mesh->set_tag(1, "class_dim", to_read(cd));
      mesh->set_tag(1, "class_id", to_read(ci));
    }
  }
  // Vertices: the pinned ones, the rest projected from the edges; a model edge turning sharply
  // at a vertex makes it a model vertex.
  {
    const LO n = mesh->nverts();
    std::vector<I8> cd(n, 3);
    std::vector<ClassId> ci(n, -1);
    for (int v : m.corners) { cd[v] = 0; ci[v] = (ci[v] < 0 ? 0 : ci[v]) | kCorner; }
    for (int v : m.required) { cd[v] = 0; ci[v] = (ci[v] < 0 ? 0 : ci[v]) | kRequired; }
    project(mesh, 0, cd, ci);
    if (feature_angle < 180) {
      HostRead<I8> vcd(mesh->get_array<I8>(0, "class_dim"));
      HostRead<ClassId> vci(mesh->get_array<ClassId>(0, "class_id"));
      HostRead<I8> ecd(mesh->get_array<I8>(1, "class_dim"));
      HostRead<LO> e2v(mesh->ask_verts_of(1));
      auto v2e = mesh->ask_up(0, 1);
      HostRead<LO> a2ab(v2e.a2ab), ab2b(v2e.ab2b);
      for (LO v = 0; v < n; ++v) {
        cd[v] = vcd[v]; ci[v] = vci[v];
        if (vcd[v] != 1) continue;
        std::vector<std::array<double, 3>> dirs;
        for (LO k = a2ab[v]; k < a2ab[v + 1]; ++k) {
          const LO e = ab2b[k];
          if (ecd[e] != 1) continue;
          const LO o = e2v[2 * e] == v ? e2v[2 * e + 1] : e2v[2 * e];
          auto d = sub(P(o), P(v));
          const double l = std::sqrt(dot(d, d));
          dirs.push_back({d[0] / l, d[1] / l, d[2] / l});
        }
        if (dirs.size() == 2 && -dot(dirs[0], dirs[1]) < cos_limit) {
          cd[v] = 0; ci[v] = kSynthetic; ++st.feature_vertices;
        }
      }
      mesh->set_tag(0, "class_dim", to_read(cd));
      mesh->set_tag(0, "class_id", to_read(ci));
    }
  }
  // Closed model-edge loops: Omega_h does not check the link condition, it relies on the
  // classification; a loop of model edges with fewer than three model vertices can be collapsed
  // to two edges on the same two vertices (it then aborts in find_matches). A CAD model has
  // vertices on its closed curves; here three are put on every loop: on each cycle without a
  // model vertex, on each chain from a model vertex back to itself, and in the middle of each of
  // several chains joining the same two model vertices.
  {
    const LO n = mesh->nverts();
    HostRead<I8> vcd0(mesh->get_array<I8>(0, "class_dim"));
    HostRead<ClassId> vci0(mesh->get_array<ClassId>(0, "class_id"));
    HostRead<I8> ecd(mesh->get_array<I8>(1, "class_dim"));
    HostRead<LO> e2v(mesh->ask_verts_of(1));
    auto v2e = mesh->ask_up(0, 1);
    HostRead<LO> a2ab(v2e.a2ab), ab2b(v2e.ab2b);
    std::vector<I8> cd(n);
    std::vector<ClassId> ci(n);
    for (LO v = 0; v < n; ++v) { cd[v] = vcd0[v]; ci[v] = vci0[v]; }
    std::vector<char> seen(mesh->nents(1), 0);
    auto other = [&](LO e, LO v) { return e2v[2 * e] == v ? e2v[2 * e + 1] : e2v[2 * e]; };
    auto next_edge = [&](LO v, LO e) {  // the other model edge at a vertex on a model edge
      for (LO k = a2ab[v]; k < a2ab[v + 1]; ++k)
        if (ab2b[k] != e && ecd[ab2b[k]] == 1) return ab2b[k];
      return LO(-1);
    };
    auto walk = [&](LO u, LO e, std::vector<LO>& inner) {  // from u along e to the next model vertex
      LO v = other(e, u);
      seen[e] = 1;
      while (vcd0[v] != 0 && v != u) {
        inner.push_back(v);
        LO f = next_edge(v, e);
        if (f < 0 || seen[f]) break;
        seen[f] = 1;
        e = f;
        v = other(e, v);
      }
      return v;
    };
    auto pin = [&](LO v) { if (cd[v] != 0) { cd[v] = 0; ci[v] = kSynthetic; ++st.loop_vertices; } };
    std::map<std::pair<LO, LO>, std::vector<std::vector<LO>>> chains;
    for (LO u = 0; u < n; ++u) {
      if (vcd0[u] != 0) continue;
      for (LO k = a2ab[u]; k < a2ab[u + 1]; ++k) {
        const LO e = ab2b[k];
        if (ecd[e] != 1 || seen[e]) continue;
        std::vector<LO> inner;
        const LO w = walk(u, e, inner);
        if (w == u) {  // a loop through one model vertex
          if (!inner.empty()) pin(inner[inner.size() / 3]);
          if (inner.size() >= 2) pin(inner[(2 * inner.size()) / 3]);
        } else {
          chains[{std::min(u, w), std::max(u, w)}].push_back(inner);
        }
      }
    }
    for (auto& kv : chains)
      if (kv.second.size() > 1)
        for (auto& inner : kv.second) if (!inner.empty()) pin(inner[inner.size() / 2]);
    for (LO e = 0; e < mesh->nents(1); ++e) {  // cycles without a model vertex
      if (ecd[e] != 1 || seen[e]) continue;
      const LO u = e2v[2 * e];
      std::vector<LO> inner{u};
      walk(u, e, inner);
      pin(inner[0]);
      if (inner.size() >= 3) { pin(inner[inner.size() / 3]); pin(inner[(2 * inner.size()) / 3]); }
    }
    mesh->set_tag(0, "class_dim", to_read(cd));
    mesh->set_tag(0, "class_id", to_read(ci));
  }
  return st;
}

void write_medit(std::string const& path, Omega_h::Mesh* mesh, bool negative, std::set<ClassId> const& tri_refs,
    std::set<ClassId> const& edge_refs) {
  using namespace Omega_h;
  std::ofstream out(path);
  if (!out) fail("cannot write " + path);
  out.precision(17);
  HostRead<Real> X(mesh->coords());
  const LO nv = mesh->nverts();
  out << "MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n" << nv << "\n";
  for (LO v = 0; v < nv; ++v) out << X[3 * v] << ' ' << X[3 * v + 1] << ' ' << X[3 * v + 2] << " 0\n";
  HostRead<LO> t2v(mesh->ask_elem_verts());
  HostRead<ClassId> tid(mesh->get_array<ClassId>(3, "class_id"));
  out << "\nTetrahedra\n" << mesh->nelems() << "\n";
  for (LO t = 0; t < mesh->nelems(); ++t) {
    LO v[4] = {t2v[4 * t], t2v[4 * t + 1], t2v[4 * t + 2], t2v[4 * t + 3]};
    if (negative) std::swap(v[2], v[3]);
    out << v[0] + 1 << ' ' << v[1] + 1 << ' ' << v[2] + 1 << ' ' << v[3] + 1 << ' ' << tid[t] << "\n";
  }
  auto listed = [&](int dim, std::set<ClassId> const& refs, char const* name) {
    HostRead<LO> e2v(mesh->ask_verts_of(dim));
    HostRead<I8> cd(mesh->get_array<I8>(dim, "class_dim"));
    HostRead<ClassId> ci(mesh->get_array<ClassId>(dim, "class_id"));
    std::vector<LO> keep;
    for (LO e = 0; e < mesh->nents(dim); ++e) if (cd[e] == dim && refs.count(ci[e])) keep.push_back(e);
    if (keep.empty()) return;
    out << "\n" << name << "\n" << keep.size() << "\n";
    for (LO e : keep) {
      for (int j = 0; j <= dim; ++j) out << e2v[(dim + 1) * e + j] + 1 << ' ';
      out << ci[e] << "\n";
    }
  };
  listed(2, tri_refs, "Triangles");
  listed(1, edge_refs, "Edges");
  HostRead<I8> vcd(mesh->get_array<I8>(0, "class_dim"));
  HostRead<ClassId> vci(mesh->get_array<ClassId>(0, "class_id"));
  for (auto [flag, name] : {std::pair<ClassId, char const*>{kCorner, "Corners"}, {kRequired, "RequiredVertices"}}) {
    std::vector<LO> keep;
    for (LO v = 0; v < nv; ++v) if (vcd[v] == 0 && vci[v] >= 0 && vci[v] < kSynthetic && (vci[v] & flag)) keep.push_back(v);
    if (keep.empty()) continue;
    out << "\n" << name << "\n" << keep.size() << "\n";
    for (LO v : keep) out << v + 1 << "\n";
  }
  out << "\nEnd\n";
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Try {
  double scale = 0, seconds = 0, min_quality_allowed = 0, max_length_allowed = 0;
  long vertices = 0, tets = 0;
  int adapt_calls = 0;
  int failed = 0;  // the try aborted: its signal (-1: another exit)
};

}  // namespace

int main(int argc, char** argv) {
  auto lib = Omega_h::Library(&argc, &argv);
  std::string in_path, out_path, json_path;
  long target = 0;
  double feature_angle = 45, tolerance = 0.03, first_scale = 0;
  int max_tries = 5;
  bool verbose = false;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) { std::cerr << a << " needs a value\n"; std::exit(2); }
      return argv[++i];
    };
    if (a == "--vertices") target = std::stol(next());
    else if (a == "--feature-angle") feature_angle = std::stod(next());
    else if (a == "--max-tries") max_tries = std::stoi(next());
    else if (a == "--scale") first_scale = std::stod(next());
    else if (a == "--tolerance") tolerance = std::stod(next());
    else if (a == "--json") json_path = next();
    else if (a == "--verbose" || a == "-v") verbose = true;
    else if (in_path.empty()) in_path = a;
    else if (out_path.empty()) out_path = a;
    else { std::cerr << "unexpected argument " << a << "\n"; return 2; }
  }
  if (in_path.empty() || out_path.empty() || target <= 0) {
    std::cerr << "usage: omega_h_coarsen IN.mesh OUT.mesh --vertices N [--feature-angle 45] [--max-tries 5]"
                 " [--tolerance 0.03] [--scale S] [--json FILE] [--verbose]\n";
    return 2;
  }
  try {
    auto t_read = std::chrono::steady_clock::now();
    Medit m = read_medit(in_path);
    compact_and_orient(m);
    const double read_seconds = seconds_since(t_read);
    std::set<ClassId> tri_refs(m.tri_ref.begin(), m.tri_ref.end()), edge_refs(m.edge_ref.begin(), m.edge_ref.end());
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    std::printf("omega_h_coarsen: Omega_h %s, %d thread(s)\n", kVersion, threads);
    std::printf("input   %zu vertices, %zu tets, %zu triangles, %zu edges, %zu pinned; target %ld vertices\n",
        m.xyz.size(), m.tets.size(), m.tris.size(), m.edges.size(), m.corners.size() + m.required.size(), target);
    std::vector<Try> tries;
    // First guess: N ~ s^-3 (or --scale, e.g. the one an earlier search chose, with --max-tries 1).
    double scale = first_scale > 0 ? first_scale : std::cbrt(double(m.xyz.size()) / double(target));
    long best = -1;
    ClassStats cst;
    double classify_seconds = 0;
    // Each try runs in a child process: Omega_h aborts on its internal assertions (built without
    // Omega_h_THROW), and a try it aborts is reported and the search goes on at a nearby scale.
    // The parent runs no OpenMP region, so fork() is safe.
    for (int k = 0; k < max_tries; ++k) {
      const std::string try_path = out_path + ".try" + std::to_string(k + 1) + ".mesh";
      struct Result { Try t; ClassStats cst; double classify_seconds; } r{};
      int fd[2];
      if (pipe(fd) != 0) fail("pipe failed");
      std::fflush(stdout);
      const pid_t pid = fork();
      if (pid < 0) fail("fork failed");
      if (pid == 0) {
        close(fd[0]);
        Omega_h::Mesh mesh(&lib);
        auto t_class = std::chrono::steady_clock::now();
        r.cst = build(&lib, &mesh, m, feature_angle);
        r.classify_seconds = seconds_since(t_class);
        auto t0 = std::chrono::steady_clock::now();
        auto opts = Omega_h::AdaptOpts(&mesh);
        opts.verbosity = verbose ? Omega_h::EACH_ADAPT : Omega_h::SILENT;
        Omega_h::add_implied_isos_tag(&mesh);
        // approach_metric() refuses a mesh worse than min_quality_allowed or with an edge longer
        // than max_length_allowed (in the metric): relax both to the input's, as Omega_h's
        // fix_for_given_metric() does.
        const double minq = mesh.min_quality(), maxl = mesh.max_length();
        if (minq < opts.min_quality_allowed) opts.min_quality_allowed = std::max(0.0, 0.99 * minq);
        if (maxl > opts.max_length_allowed) opts.max_length_allowed = 1.01 * maxl;
        auto target_metric = Omega_h::multiply_each_by(mesh.get_array<Omega_h::Real>(0, "metric"), 1.0 / (scale * scale));
        mesh.add_tag(0, "target_metric", 1, target_metric);
        r.t.scale = scale;
        r.t.min_quality_allowed = opts.min_quality_allowed;
        r.t.max_length_allowed = opts.max_length_allowed;
        while (Omega_h::approach_metric(&mesh, opts)) {
          Omega_h::adapt(&mesh, opts);
          ++r.t.adapt_calls;
        }
        r.t.seconds = seconds_since(t0);
        r.t.vertices = mesh.nverts();
        r.t.tets = mesh.nelems();
        write_medit(try_path, &mesh, m.negative, tri_refs, edge_refs);
        if (write(fd[1], &r, sizeof r) != ssize_t(sizeof r)) _exit(3);
        close(fd[1]);
        std::fflush(stdout);
        _exit(0);
      }
      close(fd[1]);
      const bool got = read(fd[0], &r, sizeof r) == ssize_t(sizeof r);
      close(fd[0]);
      int status = 0;
      waitpid(pid, &status, 0);
      Try t = r.t;
      t.scale = scale;
      if (!got || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        t.failed = WIFSIGNALED(status) ? WTERMSIG(status) : -1;
        tries.push_back(t);
        std::printf("try %d: scale %.4f -> Omega_h aborted (%s); next try at a scale 2%% larger\n", k + 1, scale,
            WIFSIGNALED(status) ? strsignal(WTERMSIG(status)) : "exit status");
        std::remove(try_path.c_str());
        scale *= 1.02;
        continue;
      }
      cst = r.cst;
      classify_seconds = r.classify_seconds;
      tries.push_back(t);
      std::printf("try %d: scale %.4f -> %ld vertices, %ld tets, adapt %.3f s (%d adapt calls)\n", k + 1, scale,
          t.vertices, t.tets, t.seconds, t.adapt_calls);
      const double err = std::fabs(double(t.vertices) / double(target) - 1);
      if (best < 0 || err < std::fabs(double(tries[best].vertices) / double(target) - 1)) {
        best = long(tries.size()) - 1;
        if (std::rename(try_path.c_str(), out_path.c_str()) != 0) fail("cannot write " + out_path);
      } else {
        std::remove(try_path.c_str());
      }
      if (err <= tolerance) break;
      // Next scale: N ~ s^-b, b from the last two tries that ran (clamped), 3 at first.
      double b = 3;
      std::vector<Try const*> ok;
      for (auto& x : tries) if (!x.failed) ok.push_back(&x);
      if (ok.size() >= 2) {
        auto& p = *ok[ok.size() - 2];
        auto& q = *ok.back();
        if (q.scale != p.scale && q.vertices != p.vertices)
          b = -std::log(double(q.vertices) / double(p.vertices)) / std::log(q.scale / p.scale);
        b = std::min(4.0, std::max(1.0, b));
      }
      scale *= std::pow(double(t.vertices) / double(target), 1.0 / b);
    }
    if (best < 0) fail("every try aborted inside Omega_h (see its messages above)");
    auto& c = tries[best];
    std::printf("output  %ld vertices, %ld tets (try %ld of %zu); adapt %.3f s with %d thread(s); all tries %.3f s\n",
        c.vertices, c.tets, best + 1, tries.size(), c.seconds, threads,
        [&] { double s = 0; for (auto& t : tries) s += t.seconds; return s; }());
    long aborted = 0;
    for (auto& t : tries) aborted += t.failed != 0;
    if (aborted) std::printf("%ld of %zu tries aborted inside Omega_h\n", aborted, tries.size());
    std::printf("classification: %ld untagged boundary/interface faces, %ld feature edges, %ld feature vertices, "
        "%ld vertices pinned on closed model-edge loops (%.3f s)\n",
        cst.untagged_faces, cst.feature_edges, cst.feature_vertices, cst.loop_vertices, classify_seconds);
    if (!json_path.empty()) {
      std::ofstream j(json_path);
      j.precision(17);
      j << "{\"omega_h\": \"" << kVersion << "\", \"threads\": " << threads
        << ", \"input_vertices\": " << m.xyz.size() << ", \"input_tets\": " << m.tets.size()
        << ", \"target_vertices\": " << target << ", \"read_seconds\": " << read_seconds
        << ", \"classify_seconds\": " << classify_seconds << ", \"untagged_faces\": " << cst.untagged_faces
        << ", \"feature_edges\": " << cst.feature_edges << ", \"feature_vertices\": " << cst.feature_vertices
        << ", \"loop_vertices\": " << cst.loop_vertices
        << ", \"feature_angle\": " << feature_angle << ", \"chosen\": " << best << ", \"tries\": [";
      for (size_t i = 0; i < tries.size(); ++i) {
        auto& t = tries[i];
        j << (i ? ", " : "") << "{\"scale\": " << t.scale << ", \"vertices\": " << t.vertices << ", \"tets\": " << t.tets
          << ", \"seconds\": " << t.seconds << ", \"adapt_calls\": " << t.adapt_calls
          << ", \"min_quality_allowed\": " << t.min_quality_allowed
          << ", \"max_length_allowed\": " << t.max_length_allowed << ", \"aborted\": " << (t.failed ? "true" : "false")
          << ", \"signal\": " << t.failed << "}";
      }
      j << "]}\n";
    }
  } catch (std::exception const& e) {
    std::fprintf(stderr, "omega_h_coarsen: %s\n", e.what());
    return 1;
  }
  return 0;
}
