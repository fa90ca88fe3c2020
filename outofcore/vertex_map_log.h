// The vertex map of an out-of-core run (OutOfCoreOptions::vertex_map_path), kept on disk in the
// scratch folder while the levels run, since it has one entry per input vertex (the input does
// not fit in memory, and neither may its map).
//
// Each piece's run gives a local map (the engine's: every vertex of the piece -> the vertex of the
// piece it became or merged into). A vertex that survives keeps its global id, so the global
// record of one run is "g merged into s" for each vertex it removed; s may itself merge at a later
// level, in a larger piece. The file holds one 8-byte entry per global id, written in place
// (pwrite), read back at the end:
//   0              nothing written: a vertex no tet uses (the only such one; write() checks)
//   s + 1          g merged into the vertex with global id s (at most one entry per vertex: a
//                  vertex is removed once, and a frozen border vertex never)
//   kOutput | o    g is output vertex o
// write() follows each chain of merges (at most one link per level) to its output vertex and
// writes the user's file (topotet/vertex_map_file.h), streaming. Memory: one piece's records while
// they are written (16 bytes per vertex merged, while the piece is in memory anyway) and a window
// of 64k entries at the end.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "piece.h"
#include "scratch.h"

namespace topotet::ooc {

class VertexMapLog {
 public:
  // Creates (sparse) `path`, a scratch file; throws InputError naming the scratch folder.
  VertexMapLog(const std::string& path, std::uint64_t input_vertices);

  // One piece's run: `merged` pairs (removed vertex, the vertex it merged into), global ids.
  void record_merges(std::vector<std::pair<GlobalId, GlobalId>> merged);
  // The output: output_index[g] = the output vertex of global id g (kInvalid: none), for every g.
  void record_output_index(const std::vector<VertId>& output_index);
  // The output when it is one piece: its vertex o has global id global_ids[o].
  void record_output_piece(const std::vector<GlobalId>& global_ids);
  // Resolves every input vertex and writes `path` (.npy or .txt). used[g] != 0 for the vertices a
  // tet uses: those must resolve (else std::logic_error), the others are -1.
  void write(const std::string& path, const std::vector<std::uint8_t>& used) const;

 private:
  void put(std::vector<std::pair<GlobalId, std::uint64_t>> entries);  // sorted in place, then written
  ScratchFile file_;
  std::uint64_t count_ = 0;
};

}  // namespace topotet::ooc
