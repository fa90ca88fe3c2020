// The hierarchy file (.tth, topotet/hierarchy.h) of an out-of-core run, kept on disk while the run
// goes on, so that recording it costs no memory that grows with the input.
//
// What is recorded. The .tth's original mesh is the input as read (global ids = input order); the
// cut writes it here while it holds the input's vertices (write_original). Each piece's run records
// its collapses in a CollapseLog (engine/hierarchy/hierarchy_log.h) whose ids continue the run's
// (first_id = collapses so far, pieces in their fixed order: deterministic), seeded with the id
// of the collapse that last changed each of the piece's tets (Piece::last_collapse), so a
// collapse at a merge level finds its parents in the levels before, in both merged pieces. Its
// records go to one column file per array of the .tth (append), u and v in global ids.
//
// Why the records are a valid hierarchy: a piece's collapses touch neither its border vertices
// (frozen: never u, never v) nor any tet outside it, so St(u) and St(v) lie in the piece, its log
// sees every tet they hold, and the parents are exactly the in-core definition's (the collapses
// that last changed a tet of the patch). The pieces of one level share no tet, so the order in
// which their records are appended is a valid sequence, as a round's winners are in core.
// tests/unit_out_of_core_hierarchy.cpp extracts closed subsets and checks their topology.
//
// write() assembles the .tth (io/tth.cpp's layout, docs/formats.md) from the sections, through an
// AtomicFile: the file appears only when complete.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "piece.h"
#include "scratch.h"
#include "topotet/mesh_data.h"

namespace topotet::detail {
class CollapseLog;
}

namespace topotet::ooc {

class HierarchySpool {
 public:
  explicit HierarchySpool(const ScratchFolder& scratch);
  ~HierarchySpool();
  HierarchySpool(const HierarchySpool&) = delete;
  HierarchySpool& operator=(const HierarchySpool&) = delete;

  // The original mesh's section, in the .tth's order; called once, by the cut, in this order.
  void original_vertices(const std::vector<std::array<double, 3>>& positions, const std::vector<std::int32_t>& refs);
  void original_tet_count(std::uint64_t tets);
  void original_tet(const std::array<VertId, 4>& v);
  void original_material(std::int32_t material);  // after every tet, one per tet in the same order
  void original_listed(const std::vector<Triangle>& triangles, const std::vector<Segment>& segments,
                       const std::vector<std::uint32_t>& ridges, const std::vector<VertId>& corners,
                       const std::vector<VertId>& required);
  // `values` holds `stride` doubles per vertex (the fields interleaved, in `fields`' order).
  void original_fields(const std::vector<VertexField>& fields, const std::string& values, int stride,
                       std::uint64_t vertices);
  void original_done();  // no group names: an out-of-core run does not keep them

  // The id the next piece's log starts at.
  std::uint32_t next_id() const { return static_cast<std::uint32_t>(collapses_); }
  // A piece's records; global[x] is the global id of the log's vertex x.
  void append(const detail::CollapseLog& log, const std::vector<GlobalId>& global);
  std::uint64_t collapses() const { return collapses_; }

  void write(const std::string& path, int field_stride);  // field_stride: the input's vertex field components
  std::uint64_t bytes_written() const { return bytes_written_; }

 private:
  struct Columns;
  const ScratchFolder& scratch_;
  std::unique_ptr<ScratchWriter> original_;
  std::unique_ptr<Columns> columns_;
  std::uint64_t tets_ = 0, tets_written_ = 0, materials_written_ = 0;
  bool original_done_ = false;
  std::uint64_t collapses_ = 0, parents_ = 0, bytes_written_ = 0;
};

}  // namespace topotet::ooc
