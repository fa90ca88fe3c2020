// Z2 homology by reduction, then elimination.
//
// Cells of all dimensions share one id space: vertices [0, V), edges [V, V+E), faces [V+E,
// V+E+F), tets [V+E+F, N). The algorithm (Mrozek & Batko, "Coreduction homology algorithm", 2009;
// Kaczynski, Mrozek & Slusarek, "Homology computation by reduction of chain complexes", 1998):
//
//   1. Union-find gives the components; remove one vertex per component.
//   2. Drain a queue of candidate cells, applying
//        coreduction: a cell a whose alive boundary is exactly one cell b -> remove a and b;
//        collapse:    a cell b with exactly one alive coface a         -> remove a and b;
//      until neither applies anywhere.
//   3. On the survivors, rank of each boundary matrix over Z2 by column reduction;
//      reduced b_k = n_k - rank d_k - rank d_{k+1}; b_0 += number of components.
//
// Why the homology is unchanged (all coefficients in Z2, so every nonzero coefficient is 1):
//  - Throughout, the alive cells form an "S-complex" whose boundary operator is the original one
//    restricted to alive cells (drop the coefficients of dead cells). Call it d'.
//  - Step 1: removing a set P of vertices, one per component, gives the relative complex C/C(P),
//    whose boundary is exactly the restriction; H_k(X, P) = direct sum over the components X_i of
//    the reduced homology of X_i. So b_k(X) = b_k(X, P) for k >= 1 and b_0(X) = b_0(X, P) + |P|.
//  - Step 2: a pair (a, b) with <d'a, b> = 1 is a reduction pair; removing it is a chain
//    equivalence onto the other cells with the new boundary (KMS98)
//        d''c = d'c - <d'c, b> d'a   for cells c of the dimension of a, and
//        d''c = d'c without its a-coefficient   for cells one dimension higher,
//    both then restricted to the remaining cells.
//      * coreduction: d'a = b, so d'c - <d'c,b> d'a only cancels c's b-coefficient: restriction.
//      * collapse: a is the only alive coface of b, so <d'c, b> = 0 for every other c: restriction.
//    In both cases d'' is again the restriction of the original boundary, so the invariant holds
//    and the homology (of the relative complex) is unchanged.
//  - Step 3 is the definition of Betti numbers over a field (rank-nullity on each d_k).
#include "z2_homology.h"

#include <algorithm>
#include <cassert>
#include <iterator>
#include <stdexcept>

namespace topotet::metrics::detail {
namespace {

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];  // path halving
    v = parent[v];
  }
  return v;
}

// Leaves scratch.parent[v] == v exactly for one root per component.
std::uint32_t union_components(const LocalComplex& complex, HomologyScratch& scratch) {
  auto& parent = scratch.parent;
  parent.resize(complex.vertex_count);
  for (std::uint32_t v = 0; v < complex.vertex_count; ++v) parent[v] = v;
  std::uint32_t components = complex.vertex_count;
  for (const auto& e : complex.edges) {
    std::uint32_t a = find_root(parent, e[0]);
    std::uint32_t b = find_root(parent, e[1]);
    if (a == b) continue;
    if (a < b) std::swap(a, b);
    parent[a] = b;
    --components;
  }
  return components;
}

// The reduction state over the unified cell ids; see the file comment.
class Reducer {
 public:
  Reducer(const LocalComplex& complex, HomologyScratch& scratch)
      : complex_(complex), s_(scratch) {
    offsets_[0] = 0;
    offsets_[1] = complex.vertex_count;
    offsets_[2] = offsets_[1] + static_cast<std::uint32_t>(complex.edges.size());
    offsets_[3] = offsets_[2] + static_cast<std::uint32_t>(complex.faces.size());
    offsets_[4] = offsets_[3] + static_cast<std::uint32_t>(complex.tets.size());
    const std::uint64_t incidence_count =
        2 * std::uint64_t{complex.edges.size()} + 3 * std::uint64_t{complex.faces.size()} + 4 * std::uint64_t{complex.tets.size()};
    const std::uint64_t cell_count = std::uint64_t{complex.vertex_count} + complex.edges.size() + complex.faces.size() + complex.tets.size();
    if (incidence_count >= ~std::uint32_t{0} || cell_count >= ~std::uint32_t{0})
      throw std::length_error("compute_topology: complex too large for 32-bit incidence ids");
    build_coboundaries();
  }

  // Step 1: the union-find roots are one vertex per component.
  void remove_base_vertices() {
    for (std::uint32_t v = 0; v < complex_.vertex_count; ++v)
      if (s_.parent[v] == v) remove(v);
  }

  // Step 2. The sweep from the base vertices first (mostly coreductions, which is what makes the
  // coreduction algorithm effective on full-dimensional sets), then every cell that admitted a
  // reduction then (free faces) joins. Draining reaches a fixpoint: counts only decrease, a cell
  // becomes reducible only when one of its counts drops to 1, which queues it, and every cell
  // reducible at the seeding scan was queued by it; each queued cell is examined after that.
  void reduce() {
    drain();
    for (std::uint32_t c = 0; c < offsets_[4]; ++c)
      if (s_.is_alive[c] && (s_.alive_face_count[c] == 1 || s_.alive_coface_count[c] == 1))
        s_.queue.push_back(c);
    drain();
  }

  // Step 3: Betti numbers of the surviving (relative) complex.
  std::array<std::int64_t, 4> survivor_betti() {
    // Compact index of each surviving cell within its dimension (alive_coface_count is no longer
    // needed, so it is reused).
    auto& compact = s_.alive_coface_count;
    std::array<std::int64_t, 4> alive_count{};
    for (int d = 0; d < 4; ++d) {
      std::uint32_t next = 0;
      for (std::uint32_t c = offsets_[d]; c < offsets_[d + 1]; ++c)
        if (s_.is_alive[c]) compact[c] = next++;
      alive_count[d] = next;
    }
    s_.last_remaining_cells = static_cast<std::uint64_t>(alive_count[0] + alive_count[1] +
                                                         alive_count[2] + alive_count[3]);
    // rank[k] = rank of d_k : C_k -> C_{k-1}; d_0 = 0 in the relative complex. From the top
    // down, so that each matrix tells the next which columns are zero (clearing, below).
    std::array<std::int64_t, 5> rank{};
    std::vector<std::uint8_t> is_cleared, is_pivot_row;
    for (int d = 3; d >= 1; --d) {
      is_cleared.swap(is_pivot_row);
      is_cleared.resize(static_cast<std::size_t>(alive_count[d]), 0);
      is_pivot_row.assign(static_cast<std::size_t>(alive_count[d - 1]), 0);
      rank[d] = boundary_rank(d, is_cleared, is_pivot_row);
    }
    std::array<std::int64_t, 4> betti{};
    for (int d = 0; d <= 3; ++d) betti[d] = alive_count[d] - rank[d] - rank[d + 1];
    return betti;
  }

 private:
  int dim_of(std::uint32_t c) const {
    return (c >= offsets_[1]) + (c >= offsets_[2]) + (c >= offsets_[3]);
  }

  template <class Fn>
  void for_each_face(std::uint32_t c, Fn&& fn) const {
    switch (dim_of(c)) {
      case 1:
        for (std::uint32_t f : complex_.edges[c - offsets_[1]]) fn(f + offsets_[0]);
        break;
      case 2:
        for (std::uint32_t f : complex_.faces[c - offsets_[2]]) fn(f + offsets_[1]);
        break;
      case 3:
        for (std::uint32_t f : complex_.tets[c - offsets_[3]]) fn(f + offsets_[2]);
        break;
      default:
        break;
    }
  }

  // fn(cell, face) for every incidence, as unified ids; one loop per dimension (no dim_of).
  template <class Fn>
  void for_each_incidence(Fn&& fn) const {
    for (std::uint32_t i = 0; i < complex_.edges.size(); ++i)
      for (std::uint32_t f : complex_.edges[i]) fn(offsets_[1] + i, f + offsets_[0]);
    for (std::uint32_t i = 0; i < complex_.faces.size(); ++i)
      for (std::uint32_t f : complex_.faces[i]) fn(offsets_[2] + i, f + offsets_[1]);
    for (std::uint32_t i = 0; i < complex_.tets.size(); ++i)
      for (std::uint32_t f : complex_.tets[i]) fn(offsets_[3] + i, f + offsets_[2]);
  }

  void build_coboundaries() {
    const std::uint32_t n = offsets_[4];
    auto& offsets = s_.c2cof_offsets;
    offsets.assign(n + 1, 0);
    for_each_incidence([&](std::uint32_t, std::uint32_t f) { ++offsets[f + 1]; });
    for (std::uint32_t c = 0; c < n; ++c) offsets[c + 1] += offsets[c];
    s_.c2cof.resize(offsets[n]);
    auto& cursor = s_.alive_coface_count;  // fill cursor first, then the count it starts as
    cursor.assign(offsets.begin(), offsets.end() - 1);
    for_each_incidence([&](std::uint32_t c, std::uint32_t f) { s_.c2cof[cursor[f]++] = c; });
    for (std::uint32_t c = 0; c < n; ++c) s_.alive_coface_count[c] = offsets[c + 1] - offsets[c];
    s_.is_alive.assign(n, 1);
    s_.alive_face_count.resize(n);
    for (int d = 0; d < 4; ++d)
      std::fill(s_.alive_face_count.begin() + offsets_[d], s_.alive_face_count.begin() + offsets_[d + 1],
                static_cast<std::uint8_t>(d == 0 ? 0 : d + 1));
    s_.queue.clear();
  }

  // Kills c and queues the alive faces and cofaces that it makes reducible. A cell can only become
  // reducible when one of its counts drops to 1, so those are the only ones queued (a cell that
  // was reducible already is in the queue since that count dropped, or since the seeding scan).
  void remove(std::uint32_t c) {
    assert(s_.is_alive[c]);
    s_.is_alive[c] = 0;
    for_each_face(c, [&](std::uint32_t f) {
      if (s_.is_alive[f] && --s_.alive_coface_count[f] == 1) s_.queue.push_back(f);
    });
    for (std::uint32_t i = s_.c2cof_offsets[c]; i < s_.c2cof_offsets[c + 1]; ++i) {
      const std::uint32_t a = s_.c2cof[i];
      if (s_.is_alive[a] && --s_.alive_face_count[a] == 1) s_.queue.push_back(a);
    }
  }

  void drain() {
    auto& queue = s_.queue;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::uint32_t c = queue[head];
      if (!s_.is_alive[c]) continue;
      if (s_.alive_face_count[c] == 1) {  // coreduction (c, its only alive face)
        std::uint32_t b = 0;
        for_each_face(c, [&](std::uint32_t f) { if (s_.is_alive[f]) b = f; });
        remove(c);
        remove(b);
      } else if (s_.alive_coface_count[c] == 1) {  // collapse (its only alive coface, c)
        std::uint32_t a = 0;
        for (std::uint32_t i = s_.c2cof_offsets[c]; i < s_.c2cof_offsets[c + 1]; ++i)
          if (s_.is_alive[s_.c2cof[i]]) a = s_.c2cof[i];
        remove(a);
        remove(c);
      }
    }
    queue.clear();
  }

  // Rank over Z2 of d_d restricted to survivors: persistence-style column reduction, each column
  // a sorted list of row ids; a column's pivot is its largest row id. Columns flagged in
  // `is_cleared` are skipped: they are the pivots of the reduced d_{d+1}, and such a column
  // reduces to zero ("clearing", Chen & Kerber 2011: if R_j = d(x) has lowest row i then
  // d(cell i) is a sum of earlier columns, since d R_j = 0). Marks the pivot rows it finds.
  std::int64_t boundary_rank(int d, const std::vector<std::uint8_t>& is_cleared, std::vector<std::uint8_t>& is_pivot_row) {
    const auto& compact = s_.alive_coface_count;
    std::vector<std::vector<std::uint32_t>> columns;
    std::vector<std::uint32_t> pivot_column(is_pivot_row.size(), ~0u);
    std::vector<std::uint32_t> merged;
    std::int64_t rank = 0;
    for (std::uint32_t c = offsets_[d]; c < offsets_[d + 1]; ++c) {
      if (!s_.is_alive[c] || is_cleared[compact[c]]) continue;
      std::vector<std::uint32_t> column;
      for_each_face(c, [&](std::uint32_t f) {
        if (s_.is_alive[f]) column.push_back(compact[f]);
      });
      std::sort(column.begin(), column.end());
      while (!column.empty()) {
        const std::uint32_t owner = pivot_column[column.back()];
        if (owner == ~0u) break;
        merged.clear();
        std::set_symmetric_difference(column.begin(), column.end(), columns[owner].begin(),
                                      columns[owner].end(), std::back_inserter(merged));
        column.swap(merged);
      }
      if (!column.empty()) {
        pivot_column[column.back()] = static_cast<std::uint32_t>(columns.size());
        is_pivot_row[column.back()] = 1;
        ++rank;
      }
      columns.push_back(std::move(column));
    }
    return rank;
  }

  const LocalComplex& complex_;
  HomologyScratch& s_;
  std::array<std::uint32_t, 5> offsets_{};
};

}  // namespace

std::uint32_t count_components(const LocalComplex& complex, HomologyScratch& scratch) {
  return union_components(complex, scratch);
}

std::array<std::int64_t, 4> z2_betti(const LocalComplex& complex, HomologyScratch& scratch) {
  const std::uint32_t components = union_components(complex, scratch);
  Reducer reducer(complex, scratch);
  reducer.remove_base_vertices();
  reducer.reduce();
  std::array<std::int64_t, 4> betti = reducer.survivor_betti();
  betti[0] += components;
  return betti;
}

}  // namespace topotet::metrics::detail
