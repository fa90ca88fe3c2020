// The vertex map as a file (`topotet simplify --vertex-map FILE`, OutOfCoreOptions::vertex_map_path):
// for every input vertex, in input order, the 0-based index of the output vertex it became or merged
// into, -1 for a vertex that no tet uses. A solver transfers its vertex data back and forth with it.
// The format goes by the extension:
//   .npy  a NumPy array of little-endian int64 (numpy.load reads it);
//   .txt  text: one comment line (starting with '#'), then one index per line (numpy.loadtxt reads it).
// Written streaming (the out-of-core run writes one entry at a time) and atomically: the file
// appears under its name only at commit() (io/atomic_file.h), so a failed run leaves none.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet {

// Throws InputError unless `path` ends in .npy or .txt (checked before any work).
void check_vertex_map_path(const std::string& path);

class VertexMapWriter {
 public:
  // `count` entries will follow. Throws InputError (extension, folder not writable).
  VertexMapWriter(const std::string& path, std::uint64_t count);
  ~VertexMapWriter();  // without commit(), nothing appears
  VertexMapWriter(const VertexMapWriter&) = delete;
  VertexMapWriter& operator=(const VertexMapWriter&) = delete;

  void add(std::int64_t output_vertex);  // -1 = used by no tet
  // Throws std::logic_error if another number of entries than `count` was added; InputError on a
  // write error (disk full: the message names the file).
  void commit();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The whole map at once: kInvalid (a vertex no tet uses) is written as -1.
void write_vertex_map(const std::string& path, const std::vector<VertId>& map);

// Reads what VertexMapWriter writes (tools, tests). Throws InputError naming the file (and the
// line, for text) on anything else: another dtype or shape, a truncated file, a bad number.
std::vector<std::int64_t> read_vertex_map(const std::string& path);

}  // namespace topotet
