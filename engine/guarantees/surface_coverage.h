// The original -> simplified half of the tolerance guarantee: every point of the original
// surfaces stays within h of the simplified surface of its label, for the whole run, not only at
// the moment a vertex is removed (issue #12: "the drift of vertices absorbed by earlier
// collapses").
//
// Polylines (listed ones and detected feature curves) are kept the same way: every original
// polyline segment, or a piece of one, is held by a polyline edge of its label within h of both
// its ends (the distance to a segment is convex too); pieces are cut where the plane through p
// that bisects two new edges at p separates their ends.
//
// Invariant. Every original special triangle (a triangle of SurfaceReference's soup), or a piece
// of one, is an *item* held by exactly one live face of the same label (a tet and a local face),
// and all three corners of the item are within h of that face. The distance to a triangle is
// convex, so then EVERY point of the item is within h of it: the invariant covers the original
// surface everywhere, not at samples.
//
// How it is kept. At the start every original triangle is held by itself (distance 0). A collapse
// u <- v changes exactly the faces through u or v (the others keep their vertices and positions),
// and each of those becomes a face through p, which the tolerance check lists (SurfaceStencil::
// NewFace); a face whose tets all die lives on in the face it merges with, whose surviving tet
// then holds it (gather_surface_stencil). So the items held by faces through u or v are the only
// ones to re-check:
//   - first on the face its face becomes (same two other vertices): the face u x y becomes p x y,
//     and the item's stored bound + dist(u, p x y) still bounds it (distance to a convex set is
//     convex), so when that stays within h no distance to the item is computed; the face of an
//     item whose face u v x vanishes is guessed as the nearer new face through p x;
//   - else on the closest new face of its label within h of its three corners;
//   - else it is cut: along the plane that bisects two adjacent new faces and separates its
//     corners (the two sides usually fit one face each), or at its edge midpoints, and each piece
//     is placed on its own, down to kMaxDepth cuts and kMaxPieces pieces per placement;
//   - pieces heal: when a new face holds the whole original triangle, its pieces are replaced by
//     the triangle.
// A corner, centre or edge midpoint of an item that no new face holds, or a piece that exhausts
// the limits, refuses the placement (kTolerance): the new fan would leave that part of the
// original farther than h (or closer to a face outside the fan, which this check does not look
// at: a conservative refusal). Every choice is geometric (orders, ties), so the items do not
// depend on how the mesh is numbered.
//
// Concurrency. Items are kept in per-tet lists; a collapse reads and writes only the lists of the
// tets of its stencil St(u) ∪ St(v) (the faces through u or v, before and after, are faces of
// those tets), so collapses with disjoint stencils may run concurrently, and the lists come out
// the same for every schedule.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "guarantees/surface_tolerance.h"
#include "mesh/mesh_model.h"

namespace topotet {

// An original triangle, or a piece of one cut off by a re-placement (corners explicit: pieces
// are cut along the planes that bisect two new faces, see surface_coverage.cpp).
struct CoverageItem {
  std::array<glm::dvec3, 3> corners;
  std::uint32_t triangle;  // the soup triangle it is (part of): its label
  // An upper bound of the distance from its corners to the face that holds it (rounded up). When
  // that face's corner u moves to p, bound + dist(u, new face) still bounds it: most
  // re-placements then need no distance at all.
  float bound;
  std::uint8_t depth;      // cuts from the whole triangle
  std::uint8_t local;      // the local face of the holding tet
};

// The same for a polyline segment of the original (or a piece of one), held by a polyline edge.
struct CoverageSegment {
  std::array<glm::dvec3, 2> ends;
  std::uint32_t segment;  // the soup segment it is (part of): its label
  std::uint8_t depth;
  std::uint8_t local;     // the local edge (kTetEdges) of the holding tet
};

// Per-thread working memory; keeps capacity between calls.
struct CoverageScratch {
  struct Target {  // a distinct new face with a tet that keeps it
    std::array<glm::dvec3, 3> pts;
    std::array<VertId, 2> others;
    int label;
    FaceHolder holder;
    glm::dvec3 centre;  // a bounding sphere, to skip the exact distance for faces far away
    double radius;
    // The prism over the face: its normal (unnormalised, with 1 / |normal|^2; 0 = degenerate) and
    // its inward edge normals. A point inside it is at its plane distance from the face, which
    // spares the general closest-point search for most queries (items lie over their faces).
    glm::dvec3 normal;
    double inv_normal2;
    std::array<glm::dvec3, 3> edge_in;
    // 1 / |edge_in[k]|^2: a point on the outer side of edge k is at least its distance to that
    // edge's line from the face, which rejects most faces a point is not near without the
    // closest-point search.
    std::array<double, 3> inv_edge_in2;
  };
  std::vector<Target> targets;
  // Pairs of new faces of one label that share an edge p-x, with the plane bisecting them (cut()):
  // found once per placement, when its first item is cut (cut() ran the pairs of targets for
  // every item it cut: 14% of a placement's instructions).
  struct Hinge {
    glm::dvec3 p, x, normal;  // the normal oriented towards targets[first]
    double normal_length;
    int label;
    std::uint8_t first, second;
  };
  std::vector<Hinge> hinges;
  bool hinges_found = false;
  std::vector<double> moved_by;  // [2 * target + (0: u, 1: v)] dist(old end, target); < 0: not yet
  std::vector<CoverageItem> pending;  // items and pieces to place
  std::vector<CoverageItem> placed;   // placed items; `local` indexes `targets` until commit
  std::vector<std::pair<std::uint32_t, std::uint32_t>> order;  // (triangle, pending index)
  std::vector<CoverageItem> healed_items;  // triangles made whole again in this placement
  struct SegmentTarget {
    std::array<glm::dvec3, 2> pts;
    VertId other;
    int label;
    FaceHolder holder;
  };
  std::vector<SegmentTarget> segment_targets;
  std::vector<CoverageSegment> segment_pending, segment_placed;
};

class SurfaceCoverage {
  class Records;  // a tet's items (below)

 public:
  // Every original triangle held by the face it was taken from (reference.triangle_holders()).
  SurfaceCoverage(const MeshModel& mesh, const SurfaceReference& reference, double h);
  double tolerance() const { return h_; }
  // A larger h from here on (a run relaxing its tolerance to reach its target: SimplifyOptions::
  // relax_tolerance). Every item is within the old h of its face, so within the new one: the
  // invariant holds as it is. Never lowered: that would need every item checked again.
  void raise_tolerance(double h) {
    if (h > h_) h_ = h;
  }
  const SurfaceReference& reference() const { return reference_; }

  // Can every item held by a face through u or v be placed on the new faces of `stencil` (filled by
  // placement_within_tolerance for this placement)? Pure; the placement is left in `s` for commit().
  bool place(const MeshModel& mesh, VertId u, VertId v, const std::vector<TetId>& star_u,
             const std::vector<TetId>& star_v, const std::vector<TetId>& star_uv, const SurfaceStencil& stencil,
             CoverageScratch& s) const;

  // Stores what the last successful place() left in `s`: removes the re-placed items from the
  // stencil's lists and appends them to their new faces' tets. Call before the mesh changes.
  void commit(const MeshModel& mesh, VertId u, VertId v, const std::vector<TetId>& star_u,
              const std::vector<TetId>& star_v, const std::vector<TetId>& star_uv, CoverageScratch& s);

  // A collapse u <- v removes the tets of St(uv); the segments one of them holds at its edge xy
  // opposite uv (its faces are all through u or v, and move with them) stay where they are, on
  // the same edge, held by the first tet of the new star (by id) with that edge. Left in the dead
  // tet, no later collapse of x or y would see them (a collapse reads its stencil's lists). Called
  // by commit(), and by collapse() for a collapse that commits nothing (u inside a material, next
  // to a curve). Call before the mesh changes.
  void keep_segments_of_removed_tets(const MeshModel& mesh, const std::vector<TetId>& star_u,
                                     const std::vector<TetId>& star_v, const std::vector<TetId>& star_uv);

  // Edges of polyline `ref` stopped being polyline edges (drop_features_below, features.h: feature
  // curves a run that relaxed its tolerance no longer keeps): the original segments they held are
  // dropped, the curve they were on is no substructure any more. Every other item keeps its face
  // (or edge); the invariant holds for every curve and surface left.
  void drop_unheld_segments(const MeshModel& mesh, std::int32_t ref);

  // Flips at a stall (engine/flip_at_stall.h) retriangulate inside one material and compact the
  // tets: tet ids change, but every face and edge that holds an item is a face (edge) of the new
  // tets, with the same vertices, which do not move. detach() takes every list with the vertices of
  // its tet before the flips; attach() gives each item to the face with the same vertices after,
  // seen from the same side (the tets keep their orientation: the outward face of the new tet on
  // that side has the same cyclic order), and each segment to the first live tet (by id) that has
  // its edge as a polyline edge. The items keep their corners and bounds (no vertex moved), so the
  // invariant holds as it did; the lists come out in an order set by the mesh alone.
  struct Detached {
    std::vector<std::array<VertId, 4>> tets;  // the vertices of the tet that held lists[i]
    std::vector<Records> lists;
  };
  Detached detach(const MeshModel& mesh);
  // Throws std::logic_error if a face or edge that held an item is gone (the flips may not remove
  // one: optimize/swap.h).
  void attach(const MeshModel& mesh, Detached&& detached);

  // The original triangles (soup indices, once each, in the stars' order) that the tets of
  // St(u) ∪ St(v) hold whole or in pieces: the original surface near the stencil (surface_
  // tolerance.h, SurfaceStencil::near_triangles). False, and `out` empty, when there are more than
  // `most` (the walk stops there).
  bool held_triangles(const std::vector<TetId>& star_u, const std::vector<TetId>& star_v,
                      const std::vector<TetId>& star_uv, std::size_t most, std::vector<std::uint32_t>& out) const;

  // Items and pieces held now, and the bytes their lists take.
  std::size_t item_count() const;
  std::size_t memory_bytes() const;

  // For the tests: calls f(item) for every item (triangle piece) held by tet t.
  template <class F>
  void for_each_item(TetId t, F&& f) const {
    const Records& list = held_[t];
    for (std::size_t i = 0; i < list.size(); i += records_of(list[i]))
      if (!is_segment(list[i])) f(decode(&list[i]));
  }

  // For the tests: calls f(segment) for every polyline segment (or piece) held by tet t.
  template <class F>
  void for_each_segment(TetId t, F&& f) const {
    const Records& list = held_[t];
    for (std::size_t i = 0; i < list.size(); i += records_of(list[i]))
      if (is_segment(list[i])) f(decode_segment(&list[i]));
  }

  // Cuts of one item in one re-placement, and pieces per re-placement, before it is refused.
  static constexpr int kMaxDepth = 16;
  static constexpr std::size_t kMaxPieces = 2048;

 private:
  void cut(const CoverageItem& item, int label, CoverageScratch& s) const;
  void cut(const CoverageSegment& item, int label, CoverageScratch& s) const;
  bool place_segments(const MeshModel& mesh, VertId u, VertId v, const std::vector<TetId>& star_u,
                      const std::vector<TetId>& star_v, const std::vector<TetId>& star_uv,
                      const SurfaceStencil& stencil, CoverageScratch& s) const;

  // How a tet's list stores an item: 12 bytes. A whole original triangle (depth 0: most items) is
  // its index, its corners are the soup's; a piece is followed by its three corners, in
  // kCornerRecords more records. A polyline segment (kSegment in `local`) is followed by its two
  // ends, in kEndRecords records. Items stored with their corners took 88 bytes each, and moving
  // them from tet to tet left as much heap again free but held (slab 1M: 26 MB of items, 46 MB
  // free in the heap at the end of the run).
  struct ItemRecord {
    std::uint32_t triangle;  // or the segment
    float bound;
    std::uint8_t depth;
    std::uint8_t local;
  };
  static constexpr std::uint8_t kSegment = 0x80;
  static constexpr std::size_t kCornerRecords = sizeof(std::array<glm::dvec3, 3>) / sizeof(ItemRecord);
  static constexpr std::size_t kEndRecords = sizeof(std::array<glm::dvec3, 2>) / sizeof(ItemRecord);
  static_assert(sizeof(ItemRecord) == 12 && kCornerRecords * sizeof(ItemRecord) == sizeof(std::array<glm::dvec3, 3>) &&
                kEndRecords * sizeof(ItemRecord) == sizeof(std::array<glm::dvec3, 2>));
  static bool is_segment(const ItemRecord& head) { return (head.local & kSegment) != 0; }
  static std::size_t records_of(const ItemRecord& head) {
    return is_segment(head) ? 1 + kEndRecords : head.depth == 0 ? 1 : 1 + kCornerRecords;
  }

  // A tet's records in one allocation, 8 bytes when empty: a header record (count and capacity)
  // then the records. The 137k tets of a 1M slab that hold one triangle at the start took a
  // 48-byte object of two vectors behind a pointer, and a block for the vector: 96 bytes of heap
  // each where this takes 32.
  class Records {
   public:
    explicit operator bool() const { return data_ != nullptr; }
    std::size_t size() const { return data_ ? header().size : 0; }
    std::size_t capacity() const { return data_ ? header().capacity : 0; }
    ItemRecord& operator[](std::size_t i) { return data_[i + 1]; }
    const ItemRecord& operator[](std::size_t i) const { return data_[i + 1]; }
    void resize(std::size_t n);  // keeps the first min(n, size()) records
    void shrink_to_fit();        // frees the block when empty

   private:
    struct Header {
      std::uint32_t size, capacity, unused;
    };
    static_assert(sizeof(Header) == sizeof(ItemRecord));
    Header header() const;
    void set_header(std::uint32_t size, std::uint32_t capacity);
    void reallocate(std::size_t capacity);  // a block of that capacity, the records kept
    std::unique_ptr<ItemRecord[]> data_;
  };
  // Removes from `list` the items (with their corner or end records) whose head `erase` says so,
  // keeping the others in order; returns whether any went. `erase(head)` sees each head once, in
  // order, and may read the records after it (decode, decode_segment).
  template <class Erase>
  static bool erase_records_if(Records& list, Erase&& erase) {
    std::size_t out = 0;
    const std::size_t size = list.size();
    for (std::size_t i = 0; i < size;) {
      const std::size_t n = records_of(list[i]);
      if (!erase(&list[i])) {
        if (out != i) std::copy_n(&list[i], n, &list[out]);  // out < i: a forward copy is safe
        out += n;
      }
      i += n;
    }
    list.resize(out);
    return out != size;
  }
  static void append(Records& list, const CoverageItem& item);
  static void append(Records& list, const CoverageSegment& item);
  CoverageItem decode(const ItemRecord* head) const;  // the item whose records start at head
  static CoverageSegment decode_segment(const ItemRecord* head);

  const SurfaceReference& reference_;
  double h_;
  std::vector<Records> held_;  // [tet] what its faces and edges hold
};

}  // namespace topotet
