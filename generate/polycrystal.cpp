// polycrystal: a box cut into C grains (materials 1..C): hundreds of cells meeting along triple
// junction curves and at quadruple points, like the multi-material meshes users bring (8 to 600
// materials, thousands of surfaces).
//
// Cells: C sites at least 0.6 of the mean site spacing apart (voronoi_sites.h), from a fixed
// random stream: the sites depend on the grid and C only, so the family keeps the rule of every
// family that the seed moves positions only (another microstructure comes from another C or size).
// Each tet prefers the site nearest its centroid on the unjittered lattice (its Voronoi cell); in
// the cubes along the box edges all 6 tets prefer the site nearest the cube's centre (see
// `preferred_site`). The cells then grow from the tets holding their sites by ball-preserving
// steps only (ball_growth.h), so every material is a 3-ball whatever the digitization does near
// thin parts of a Voronoi cell; the few tets the growth cannot give their own cell go to a
// neighbouring one.
// Substructures:
//  - ref 1 triangles: the box boundary (a sphere);
//  - ref 2, 3, ... triangles: one ref per listed interface, in increasing (lower, higher) order.
//    Listed: the interfaces that are discs (cell_junctions.h), except a quarter of them chosen by
//    hashing the material pair, which stay implicit (derived from the materials), as do the rare
//    interfaces that are not discs (two cells meeting in two patches);
//  - ref 1, 2, ... segments: half of the triple junction curves (chosen by hashing the three
//    materials) that are one simple path of grid edges;
//  - corners: the 8 box corners and both ends of every listed junction curve (quadruple points,
//    or where a curve meets the box).
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>

#include "generate/ball_growth.h"
#include "generate/cell_junctions.h"
#include "generate/freudenthal_grid.h"
#include "generate/voronoi_sites.h"
#include "topotet/error.h"

namespace topotet::gen {
namespace {

constexpr std::uint64_t kMinTets = 20000;
constexpr std::uint64_t kTetsPerDefaultCell = 4000;
constexpr std::uint32_t kMinDefaultCells = 8;
// --cells may ask for cells down to this size: sites then stay more than 2 cells apart, so each
// lies in its own tet, and a cell is still several tets across.
constexpr std::uint64_t kMinTetsPerCell = 500;
constexpr double kSeparation = 0.6;  // of the mean site spacing
// A Kuhn tet's centroid is within sqrt(2) / 4 of its cube's centre.
constexpr double kCentroidReach = 0.3536;

constexpr std::uint64_t kSiteStream = 0x5349544553ull;   // the sites' fixed random stream
constexpr std::uint64_t kListingStream = 0x4C495354ull;  // which interfaces and curves are listed
constexpr std::int32_t kBoundaryRef = 1;

std::uint32_t cell_count(std::uint64_t tets, std::uint32_t requested) {
  const std::uint64_t most = tets / kMinTetsPerCell;
  if (requested > most) {
    throw InputError("polycrystal: --cells must be at most " + std::to_string(most) + " for " + std::to_string(tets) +
                     " tets (" + std::to_string(kMinTetsPerCell) + " tets per cell)");
  }
  if (requested > 0) return requested;
  return static_cast<std::uint32_t>(
      std::max<std::uint64_t>(kMinDefaultCells, (tets + kTetsPerDefaultCell / 2) / kTetsPerDefaultCell));
}

// The preferred site (0-based) of each tet, from its lattice-coordinate centroid; build_tets calls
// it tet by tet, the 6 tets of a cube in a row.
class PreferredSite {
 public:
  PreferredSite(const FreudenthalGrid& grid, const std::vector<glm::dvec3>& sites, double spacing)
      : cells_(grid.cells()), sites_(sites), buckets_(grid.cells(), spacing) {
    for (const glm::dvec3& s : sites) buckets_.add(s);
  }

  std::uint32_t operator()(const glm::dvec3& centroid) {
    const std::array<double, 3> cube = {std::floor(centroid.x), std::floor(centroid.y), std::floor(centroid.z)};
    if (cube != cube_) visit_cube(cube);
    if (is_edge_cube_) return cube_site_;
    std::uint32_t best = candidates_.front();
    double best_distance = 1e300;
    for (std::uint32_t s : candidates_) {  // increasing: ties go to the lowest site
      const glm::dvec3 d = sites_[s] - centroid;
      const double distance = d.x * d.x + d.y * d.y + d.z * d.z;
      if (distance < best_distance) {
        best_distance = distance;
        best = s;
      }
    }
    return best;
  }

 private:
  // The site nearest any centroid in the cube is within 2 * kCentroidReach of the distance from
  // the cube's centre to its nearest site, so one radius query per cube gives the candidates.
  void visit_cube(const std::array<double, 3>& cube) {
    cube_ = cube;
    const glm::dvec3 centre(cube[0] + 0.5, cube[1] + 0.5, cube[2] + 0.5);
    cube_site_ = buckets_.nearest(centre);
    const glm::dvec3 d = sites_[cube_site_] - centre;
    buckets_.within(centre, std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z) + 2 * kCentroidReach, candidates_);
    // Along a box edge, each grid segment of the edge lies in one tet, which has two faces on the
    // box. A cell interface crossing such a cube diagonally can wedge that tet between two cells
    // that each touch it along a box edge, and neither can take it as a ball (ball_growth.h):
    // whole cubes there make the interfaces cross the box edges between cubes.
    int extremes = 0;
    for (int a = 0; a < 3; ++a) extremes += cube[a] == 0 || cube[a] + 1 == cells_[a];
    is_edge_cube_ = extremes >= 2;
  }

  Cells cells_;
  const std::vector<glm::dvec3>& sites_;
  SiteBuckets buckets_;
  std::array<double, 3> cube_ = {-1, -1, -1};
  std::uint32_t cube_site_ = 0;
  bool is_edge_cube_ = false;
  std::vector<std::uint32_t> candidates_;
};

// The Kuhn tet holding lattice point p: its path takes the axes in decreasing order of p's
// fractional coordinates.
TetId tet_holding(const FreudenthalGrid& grid, const glm::dvec3& p) {
  std::array<std::uint32_t, 3> cube{};
  std::array<double, 3> frac{};
  for (int a = 0; a < 3; ++a) {
    cube[a] = std::min(static_cast<std::uint32_t>(p[a]), grid.cells()[a] - 1);
    frac[a] = p[a] - cube[a];
  }
  std::array<int, 3> axes = {0, 1, 2};
  std::stable_sort(axes.begin(), axes.end(), [&](int x, int y) { return frac[x] > frac[y]; });
  return grid.tet(cube[0], cube[1], cube[2], perm_index(axes[0], axes[1]));
}

// A fixed pseudo-random choice of about (out_of - skipped) / out_of of the material tuples.
bool is_listed(std::initializer_list<std::int32_t> materials, std::uint64_t out_of, std::uint64_t skipped) {
  std::uint64_t key = kListingStream;
  for (std::int32_t m : materials) key = splitmix64(key ^ static_cast<std::uint32_t>(m));
  return key % out_of >= skipped;
}

void add_listed_interfaces(const CellJunctions& junctions, MeshData& mesh) {
  std::int32_t ref = kBoundaryRef;
  for (const Interface& f : junctions.interfaces) {
    if (!f.is_disc || !is_listed({f.lower, f.higher}, 4, 1)) continue;
    ++ref;
    for (std::uint32_t i = f.first_face; i < f.first_face + f.face_count; ++i) {
      const InterfaceFace& face = junctions.faces[i];
      mesh.triangles.push_back(tet_face(mesh, face.tet, face.face, face.inward, ref));
    }
  }
}

void add_listed_curves(const CellJunctions& junctions, MeshData& mesh) {
  std::int32_t ref = 0;
  for (const JunctionCurve& c : junctions.curves) {
    if (c.path.empty() || !is_listed({c.materials[0], c.materials[1], c.materials[2]}, 2, 1)) continue;
    ++ref;
    for (std::size_t i = 0; i + 1 < c.path.size(); ++i) mesh.segments.push_back({{c.path[i], c.path[i + 1]}, ref});
    mesh.corners.push_back(c.path.front());
    mesh.corners.push_back(c.path.back());
  }
}

}  // namespace

MeshData generate_polycrystal(std::uint64_t target_tets, std::uint64_t seed, std::uint32_t cells) {
  check_target("polycrystal", target_tets, kMinTets);
  const FreudenthalGrid grid(choose_cells(target_tets, {1.0, 1.0, 1.0}));
  const std::uint32_t count = cell_count(grid.tet_count(), cells);
  const double spacing = std::cbrt(static_cast<double>(grid.cube_count()) / count);
  const std::vector<glm::dvec3> sites =
      place_separated_sites(grid.cells(), count, kSeparation * spacing, kSiteStream ^ count);

  MeshData mesh;
  PreferredSite preferred_site(grid, sites, spacing);
  build_tets(
      grid, [&](const glm::dvec3& centroid) { return static_cast<std::int32_t>(preferred_site(centroid) + 1); }, mesh);
  std::vector<TetId> seeds;
  for (const glm::dvec3& s : sites) seeds.push_back(tet_holding(grid, s));
  std::vector<std::int32_t> grown;
  grow_ball_regions(grid, seeds, mesh.tet_material, sites, grown);
  mesh.tet_material.swap(grown);
  grown = {};

  set_jittered_positions(grid, seed, mesh);
  add_boundary_triangles(grid, kBoundaryRef, mesh);
  const CellJunctions junctions = find_cell_junctions(grid, mesh);
  add_listed_interfaces(junctions, mesh);
  add_listed_curves(junctions, mesh);
  add_box_corners(grid, mesh);
  std::sort(mesh.corners.begin(), mesh.corners.end());
  mesh.corners.erase(std::unique(mesh.corners.begin(), mesh.corners.end()), mesh.corners.end());
  add_feature_field(grid, mesh);
  return mesh;
}

}  // namespace topotet::gen
