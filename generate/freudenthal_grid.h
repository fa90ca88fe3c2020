// Shared machinery of the procedural families (generate.h): a jittered Freudenthal (Kuhn) grid.
//
// The box holds nx*ny*nz unit cubes in lattice coordinates (cell size 1; positions are scaled by
// h = 1 / max(nx, ny, nz) at the end, so the longest box side is 1). Every cube is split the same
// way into the 6 monotone lattice paths from its low corner to its high corner:
//   tet p of cube c = (c, c + e[a], c + e[a] + e[b], c + (1,1,1)),  (a, b, d) = kPerms[p].
// Splitting all cubes alike makes the mesh conforming, and the path structure gives every face
// neighbour in closed form (for_each_face), so no face map is ever built.
//
// Materials are decided on the unjittered lattice (by tet centroid), so the topology of every
// planted substructure depends only on the grid size, never on the seed; the jitter moves
// positions only.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "topotet/generate.h"
#include "topotet/mesh_data.h"

namespace topotet::gen {

// Family entry points (one per file). They check the target and throw InputError.
MeshData generate_cube_sphere(std::uint64_t target_tets, std::uint64_t seed);
MeshData generate_slab(std::uint64_t target_tets, std::uint64_t seed);
MeshData generate_linked_tori(std::uint64_t target_tets, std::uint64_t seed);
// cells = 0 picks the default count.
MeshData generate_polycrystal(std::uint64_t target_tets, std::uint64_t seed, std::uint32_t cells);
// The same mesh as generate_cube_sphere, handed to `sink` section by section (generate.h).
void stream_cube_sphere(std::uint64_t target_tets, std::uint64_t seed, GenerateSink& sink);

// splitmix64 (Steele, Lea, Flood 2014): a fixed, portable 64-bit mixer, so the generated meshes
// are the same on every platform and standard library (unlike std::uniform_real_distribution).
constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
// Uniform in [-1, 1) from the top 53 bits.
constexpr double to_symmetric_unit(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-52 - 1.0; }
// Uniform in [0, 1) from the top 53 bits.
constexpr double to_unit(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }

// Throws InputError("<family>: --tets must be at least <min>") (or at most, for targets whose
// indices would not fit 32 bits).
void check_target(std::string_view family, std::uint64_t target_tets, std::uint64_t min_tets);

using Cells = std::array<std::uint32_t, 3>;

// Cell counts with 6*nx*ny*nz close to target_tets (within a few percent once the grid has more
// than ~10 cells a side, always within 10% for the families' minimum targets) and a shape close
// to `aspect`. With fixed_nz > 0, nz is that and only nx, ny grow (aspect[2] is then ignored).
Cells choose_cells(std::uint64_t target_tets, std::array<double, 3> aspect, std::uint32_t fixed_nz = 0);

// The 6 axis orders of the Kuhn paths; odd permutations give negatively oriented paths, whose
// first two vertices are swapped in MeshData::tets.
inline constexpr std::array<std::array<int, 3>, 6> kPerms = {
    {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
inline constexpr std::array<bool, 6> kPermOdd = {false, true, true, false, false, true};
// Index into kPerms of the order starting (a, b); the third axis is implied.
constexpr int perm_index(int a, int b) {
  constexpr int kTable[9] = {-1, 0, 1, 2, -1, 3, 4, 5, -1};
  return kTable[a * 3 + b];
}
// Faces of a positively oriented tet, indexed by the opposite local vertex, with outward normals.
inline constexpr std::array<std::array<int, 3>, 4> kOutwardFace = {
    {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};

class FreudenthalGrid {
 public:
  explicit FreudenthalGrid(Cells cells);

  const Cells& cells() const { return cells_; }
  std::uint64_t vertex_count() const { return stride_[2] * (cells_[2] + 1ull); }
  std::uint64_t cube_count() const { return std::uint64_t{cells_[0]} * cells_[1] * cells_[2]; }
  std::uint64_t tet_count() const { return 6 * cube_count(); }
  // Lattice point -> vertex id; vertex ids run x fastest, then y, then z.
  VertId vertex(std::uint32_t i, std::uint32_t j, std::uint32_t k) const {
    return static_cast<VertId>(i + stride_[1] * j + stride_[2] * k);
  }
  VertId vertex(const std::array<std::uint32_t, 3>& p) const { return vertex(p[0], p[1], p[2]); }
  // Vertex id step along each axis.
  std::uint64_t stride(int axis) const { return stride_[axis]; }
  TetId tet(std::uint32_t i, std::uint32_t j, std::uint32_t k, int perm) const {
    return static_cast<TetId>(6 * (i + std::uint64_t{cells_[0]} * (j + std::uint64_t{cells_[1]} * k)) + perm);
  }
  // The longest box side is 1.
  double cell_size() const;

 private:
  Cells cells_;
  std::array<std::uint64_t, 3> stride_;
};

// The Kuhn tet `perm` of cube (i, j, k), positively oriented, and its lattice-coordinate centroid.
inline std::array<VertId, 4> kuhn_tet(const FreudenthalGrid& grid, std::uint32_t i, std::uint32_t j, std::uint32_t k,
                                      int perm) {
  const VertId v0 = grid.vertex(i, j, k);
  const VertId v3 = static_cast<VertId>(v0 + grid.stride(0) + grid.stride(1) + grid.stride(2));
  const auto [a, b, d] = kPerms[perm];
  const VertId v1 = static_cast<VertId>(v0 + grid.stride(a));
  const VertId v2 = static_cast<VertId>(v1 + grid.stride(b));
  return kPermOdd[perm] ? std::array<VertId, 4>{v1, v0, v2, v3} : std::array<VertId, 4>{v0, v1, v2, v3};
}
// Tet id -> its vertices (the inverse of FreudenthalGrid::tet).
inline std::array<VertId, 4> kuhn_tet(const FreudenthalGrid& grid, TetId t) {
  const std::uint64_t cube = t / 6;
  const Cells& n = grid.cells();
  return kuhn_tet(grid, static_cast<std::uint32_t>(cube % n[0]), static_cast<std::uint32_t>(cube / n[0] % n[1]),
                  static_cast<std::uint32_t>(cube / n[0] / n[1]), static_cast<int>(t % 6));
}
// Centroid = c + (3 e[a] + 2 e[b] + e[d]) / 4.
inline glm::dvec3 kuhn_centroid(std::uint32_t i, std::uint32_t j, std::uint32_t k, int perm) {
  const auto [a, b, d] = kPerms[perm];
  glm::dvec3 centroid(i, j, k);
  centroid[a] += 0.75;
  centroid[b] += 0.5;
  centroid[d] += 0.25;
  return centroid;
}

// Fills mesh.tets (positively oriented on the lattice) and mesh.tet_material, with
// material_of(centroid) deciding each tet from its lattice-coordinate centroid.
template <class MaterialOf>
void build_tets(const FreudenthalGrid& grid, MaterialOf&& material_of, MeshData& mesh) {
  const Cells& n = grid.cells();
  mesh.tets.resize(grid.tet_count());
  mesh.tet_material.resize(grid.tet_count());
  std::size_t t = 0;
  for (std::uint32_t k = 0; k < n[2]; ++k) {
    for (std::uint32_t j = 0; j < n[1]; ++j) {
      for (std::uint32_t i = 0; i < n[0]; ++i) {
        for (int p = 0; p < 6; ++p, ++t) {
          mesh.tets[t] = kuhn_tet(grid, i, j, k, p);
          mesh.tet_material[t] = material_of(kuhn_centroid(i, j, k, p));
        }
      }
    }
  }
}

// Calls f(tet, local_face, neighbour) once for every face of the grid mesh: local_face is the
// index in mesh.tets[tet] of the vertex opposite the face, neighbour the tet across it or
// kInvalid on the box boundary. The order is deterministic.
template <class F>
void for_each_face(const FreudenthalGrid& grid, F&& f) {
  const Cells& n = grid.cells();
  for (std::uint32_t k = 0; k < n[2]; ++k) {
    for (std::uint32_t j = 0; j < n[1]; ++j) {
      for (std::uint32_t i = 0; i < n[0]; ++i) {
        const std::uint32_t c[3] = {i, j, k};
        for (int p = 0; p < 6; ++p) {
          const auto [a, b, d] = kPerms[p];
          const TetId t = grid.tet(i, j, k, p);
          // Path vertex q sits at local index q, except that odd paths swap the first two.
          const auto local = [&](int q) { return kPermOdd[p] && q < 2 ? 1 - q : q; };
          // Faces opposite path vertices 1 and 2 are inside the cube: swapping two consecutive
          // axes of the path gives the neighbour; visit each pair once.
          if (a < b) f(t, local(1), grid.tet(i, j, k, perm_index(b, a)));
          if (b < d) f(t, local(2), grid.tet(i, j, k, perm_index(a, d)));
          // Face opposite path vertex 0 lies on the cube face x[a] = c[a] + 1; across it is the
          // path (b, d, a) of the next cube along a.
          if (c[a] + 1 < n[a]) {
            std::uint32_t nc[3] = {i, j, k};
            ++nc[a];
            f(t, local(0), grid.tet(nc[0], nc[1], nc[2], perm_index(b, d)));
          } else {
            f(t, local(0), kInvalid);
          }
          // Face opposite path vertex 3 lies on x[d] = c[d]; its neighbour (the path (d, a, b)
          // of the previous cube along d) visits it as its face opposite vertex 0.
          if (c[d] == 0) f(t, local(3), kInvalid);
        }
      }
    }
  }
}

// The face of mesh.tets[tet] opposite local vertex `local_face`, with its normal pointing out of
// the tet (or into it when `inward`).
Triangle tet_face(const MeshData& mesh, TetId tet, int local_face, bool inward, std::int32_t ref);

// Lists every face between tets of different materials, with ref ref_of(lower, higher) of the two
// materials, its normal pointing from the higher material into the lower one.
template <class RefOf>
void add_interface_triangles(const FreudenthalGrid& grid, RefOf&& ref_of, MeshData& mesh) {
  for_each_face(grid, [&](TetId t, int face, TetId nb) {
    if (nb == kInvalid) return;
    const std::int32_t mt = mesh.tet_material[t];
    const std::int32_t mn = mesh.tet_material[nb];
    if (mt == mn) return;
    mesh.triangles.push_back(tet_face(mesh, t, face, mt < mn, ref_of(std::min(mt, mn), std::max(mt, mn))));
  });
}

// The 24 tets around the interior lattice vertex (i, j, k) (0 < i < nx, ...).
std::array<TetId, 24> vertex_star(const FreudenthalGrid& grid, std::uint32_t i, std::uint32_t j, std::uint32_t k);

// Centroid classification of a curved surface occasionally pinches: two tets of a region meeting
// at only an edge or a vertex, so the interface is not a manifold there. This grows `material`
// over `background` at every interior vertex where the interface of `material` is not a disc,
// until there is none left; each repair adds at most the 24 tets around one vertex. Vertices on
// the box boundary are not looked at: planted shapes keep off it. Throws std::logic_error when a
// pinch has a third material around it (the planted shapes are too close).
void repair_pinches(const FreudenthalGrid& grid, std::int32_t material, std::int32_t background, MeshData& mesh);

// Lists every box boundary face, with outward normals.
void add_boundary_triangles(const FreudenthalGrid& grid, std::int32_t ref, MeshData& mesh);

// Lists the grid faces of the plane x[axis] = level inside the lattice rectangle lo..hi of the
// other two axes (in increasing axis order): each unit square is the two triangles split by its
// diagonal from the low to the high corner, which is how the Kuhn tets cut it.
void add_plane_patch(const FreudenthalGrid& grid, int axis, std::uint32_t level,
                     std::array<std::uint32_t, 2> lo, std::array<std::uint32_t, 2> hi, std::int32_t ref,
                     MeshData& mesh);

// Lists the chain of `count` grid edges from lattice point `start`, each step adding `step`.
// A step is a grid edge when its components are all in {0, 1} or all in {0, -1}.
void add_chain(const FreudenthalGrid& grid, std::array<std::uint32_t, 3> start, std::array<int, 3> step,
               std::uint32_t count, std::int32_t ref, MeshData& mesh);

// Sets mesh.positions: lattice points moved by a deterministic jitter (splitmix64 of seed and
// vertex id) of at most kJitter cells, tangential on the box faces so they stay flat, then scaled
// by the cell size. Vertices on the lattice planes z = flat_z[i] keep their z too.
inline constexpr double kJitter = 0.15;
void set_jittered_positions(const FreudenthalGrid& grid, std::uint64_t seed, MeshData& mesh,
                            const std::vector<std::uint32_t>& flat_z = {});
// The position set_jittered_positions gives lattice point (i, j, k), vertex id v; key =
// splitmix64(seed). The streaming writer calls it vertex by vertex.
std::array<double, 3> jittered_position(const FreudenthalGrid& grid, std::uint64_t key, std::uint32_t i, std::uint32_t j,
                                        std::uint32_t k, bool keep_z);
// The value add_feature_field gives a vertex at `position`.
double feature_value(const FreudenthalGrid& grid, const std::array<double, 3>& position);

// Appends the scalar field "f" at the vertices: a smooth sin/cos background plus a steep tanh front
// and a narrow Gaussian peak (both narrower than a cell at small sizes), in box-relative coordinates.
void add_feature_field(const FreudenthalGrid& grid, MeshData& mesh);

// Pins the 8 box corners.
void add_box_corners(const FreudenthalGrid& grid, MeshData& mesh);

}  // namespace topotet::gen
