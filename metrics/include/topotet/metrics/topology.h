// Independent topology checker: Betti numbers over Z2 of a tet mesh and of every embedded
// substructure, plus the geometric and combinatorial faults that simplification must never create.
//
// It reads only the plain MeshData and derives everything itself (no TetMesh, no kernel code), so
// it can referee the simplifier: property tests call compute_topology before and after random
// collapses and require same_topology(before, after).
//
// Complexes, each the closure of its top simplices (so every one is a simplicial complex):
//   mesh          all tets (K)
//   boundary      faces of exactly one tet
//   material m    tets with tet_material == m
//   surface ref r listed `triangles` with ref r
//   interface a,b faces shared by two tets of materials a < b (derived: they need not be listed)
//   all surfaces  listed triangles and all interfaces
//   polyline ref r listed `segments` with ref r
//   all polylines all listed segments
//   embedded      all surfaces, all polylines and the pinned vertices (corners, required vertices)
//   features      the boundary together with the embedded structure: catches a substructure that
//                 comes to touch the boundary (or the boundary pinching onto a substructure)
// Betti numbers: a complex certified to be a surface (every edge in at most 2 triangles, the
// triangles around every vertex one fan) or a solid (every triangle in at most 2 tets, the tets
// around every edge one fan, every vertex link a sphere or a disk) gets them from counts: Euler
// characteristic, components, closed components (surfaces), boundary components (solids, whose
// b2 = boundary components - components follows from Alexander duality in R^3: this path runs
// only when every tet is positively oriented, and it takes the mesh's coordinates as an
// embedding, which tets overlapping elsewhere would break). Every other complex is reduced and
// eliminated over Z2. metrics/manifold_betti.h has the details.
//
// Elements with a vertex index out of range or a repeated vertex are counted as invalid and left
// out of every complex; a tet with the same vertex set as an earlier one is counted as a duplicate
// and left out. Material ids, refs and vertex refs are otherwise taken as they are; `ridges` only
// flag segments and add no complex.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <utility>

#include "topotet/mesh_data.h"

namespace topotet {

inline constexpr std::int64_t kUnknownBetti = -1;

struct ComplexTopology {
  std::array<std::int64_t, 4> simplex_count{};  // vertices, edges, triangles, tets of the closure
  std::array<std::int64_t, 4> betti{};          // b0..b3 over Z2; kUnknownBetti when not computed
  std::int64_t euler_characteristic = 0;        // V - E + F - T (always exact)
  friend bool operator==(const ComplexTopology&, const ComplexTopology&) = default;
};

using MaterialPair = std::pair<std::int32_t, std::int32_t>;  // (a, b) with a < b

struct TopologyReport {
  bool is_fast = false;  // computed with TopologyOptions::fast
  ComplexTopology mesh;
  ComplexTopology boundary;
  std::map<std::int32_t, ComplexTopology> materials;
  std::map<std::int32_t, ComplexTopology> surfaces;
  std::map<MaterialPair, ComplexTopology> interfaces;
  ComplexTopology all_surfaces;
  std::map<std::int32_t, ComplexTopology> polylines;
  ComplexTopology all_polylines;
  ComplexTopology embedded;
  ComplexTopology features;

  std::uint64_t pinned_vertex_count = 0;        // distinct valid corners and required vertices
  std::uint64_t inverted_tet_count = 0;         // orientation determinant < 0 (exact sign)
  std::uint64_t degenerate_tet_count = 0;       // determinant exactly 0, or a repeated vertex
  std::uint64_t nonmanifold_face_count = 0;     // faces of more than two tets
  std::uint64_t unreferenced_vertex_count = 0;  // vertices of no valid tet (informative only)
  std::uint64_t duplicate_tet_count = 0;        // same vertex set as an earlier tet
  std::uint64_t invalid_element_count = 0;      // tets, triangles, segments, pinned vertices with
                                                // an index out of range or a repeated vertex
  std::uint64_t detached_triangle_count = 0;    // listed triangles that are not a face of any tet
  std::uint64_t detached_segment_count = 0;     // listed segments that are not an edge of any tet
  std::uint64_t certified_manifold_count = 0;   // complexes computed by the manifold fast path
                                                // (informative; same_topology ignores it)
  friend bool operator==(const TopologyReport&, const TopologyReport&) = default;
};

struct TopologyOptions {
  // Fast mode, for huge meshes: b0 by union-find and the Euler characteristic only. b1..b3 are
  // kUnknownBetti, except where the dimension decides them: b_k = 0 above the complex's
  // dimension, and b1 = b0 - chi for graphs (polylines, and the embedded structure when it has
  // no triangles).
  bool fast = false;
  // Exact Betti numbers without elimination for the complexes certified to be manifolds (see
  // below); false runs the reference reduction and elimination on every complex (the tests
  // compare both).
  bool manifold_fast_path = true;
};

// Computes every complex of the report. Never throws on bad input (faults are counted instead);
// throws std::bad_alloc when out of memory and std::length_error beyond 32-bit ids (meshes of
// more than about 300M tets). Thread-safe (scratch is per thread); runs the complexes in parallel
// for meshes of 20k tets or more, with the same result as sequentially.
TopologyReport compute_topology(const MeshData& mesh, const TopologyOptions& options = {});

// True iff `after` has the topology of `before`: same complexes (same material ids, refs,
// material pairs), same Betti numbers (compared where both reports know them) and Euler
// characteristics, same pinned vertex count; `after` has no inverted, degenerate, duplicate or
// invalid tets/elements and no face with more than two tets, and no more detached triangles or
// segments than `before` (inputs may carry some; simplification must not create any). When
// `differences` is given it receives one line per fault, e.g. "surface ref 2: b1 1 -> 2" (empty
// when the result is true).
bool same_topology(const TopologyReport& before, const TopologyReport& after, std::string* differences = nullptr);

// Human-readable table, one line per complex ("?" for unknown Betti numbers), then the counters.
std::string format_topology_table(const TopologyReport& report);

// The report as one JSON object (unknown Betti numbers are null). Keys of maps are strings:
// "3" for material/ref 3, "1,2" for the interface between materials 1 and 2.
std::string topology_to_json(const TopologyReport& report);

// The checker's first spelling, topotet::metrics::compute_topology and so on, kept so that code
// written against it still compiles. The public API is in namespace topotet, like the rest of
// the library; topotet::metrics holds the checker's internals.
namespace metrics {
using topotet::ComplexTopology;
using topotet::compute_topology;
using topotet::format_topology_table;
using topotet::kUnknownBetti;
using topotet::MaterialPair;
using topotet::same_topology;
using topotet::topology_to_json;
using topotet::TopologyOptions;
using topotet::TopologyReport;
}  // namespace metrics

}  // namespace topotet
