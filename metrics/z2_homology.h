// Z2 Betti numbers of a small-to-huge simplicial complex, private to the topology checker.
//
// Input is a LocalComplex: a closed simplicial complex (every face of a simplex is present) with
// local ids per dimension, as extracted by extract_closure (simplex_index.h).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace topotet::metrics::detail {

struct LocalComplex {
  std::uint32_t vertex_count = 0;
  std::vector<std::array<std::uint32_t, 2>> edges;  // [edge] -> its 2 local vertex ids
  std::vector<std::array<std::uint32_t, 3>> faces;  // [face] -> its 3 local edge ids
  std::vector<std::array<std::uint32_t, 4>> tets;   // [tet]  -> its 4 local face ids

  void clear() {
    vertex_count = 0;
    edges.clear();
    faces.clear();
    tets.clear();
  }
};

// Buffers reused across calls so that checking many small complexes allocates nothing.
struct HomologyScratch {
  std::vector<std::uint32_t> parent;     // union-find
  std::vector<std::uint32_t> c2cof_offsets, c2cof;  // coboundary CSR over unified cell ids
  std::vector<std::uint8_t> is_alive;
  std::vector<std::uint8_t> alive_face_count;
  std::vector<std::uint32_t> alive_coface_count;  // later reused as compact index of survivors
  std::vector<std::uint32_t> queue;
  std::uint64_t last_remaining_cells = 0;  // cells left after the reductions (diagnostics, tests)
};

// Number of connected components (union-find over the edges).
std::uint32_t count_components(const LocalComplex& complex, HomologyScratch& scratch);

// Betti numbers b0..b3 over Z2: reductions (coreductions and elementary collapses) shrink the
// complex without changing its homology, then the ranks of the remaining boundary matrices are
// computed by sparse column reduction. See z2_homology.cpp for why each step is sound. Throws
// std::length_error when the incidences do not fit 32-bit ids (complexes of ~300M tets).
std::array<std::int64_t, 4> z2_betti(const LocalComplex& complex, HomologyScratch& scratch);

}  // namespace topotet::metrics::detail
