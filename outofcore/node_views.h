// The $NodeData views of a .msh streamed by the cut (MeditVisitor::begin_node_view): they come
// after the elements, in node tag order, a view at a time, and the cut needs them per vertex in
// vertex order (the .sol's order, what it spills for a MEDIT input). Each view is a region of one
// scratch file, vertices x components doubles, written in place as its entries come (runs of
// consecutive vertices in one call; the file is sparse, so what a partial view leaves out reads 0),
// and read back per vertex, a window at a time, as the fields read_mesh gives:
//   - one field per name, in the order of the names' first views, with the values of the last
//     view of that name (the last time step wins);
//   - "topotet:vertex_ref" with one component and integer values: the vertex refs, not a field;
//   - a 9-component view exactly symmetric at every vertex it lists (the others are 0): 6
//     components in MEDIT's order (xx, xy, yy, xz, yz, zz).
// Memory: a run buffer and a window per field (a few hundred kB), whatever the input's size.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet::ooc {

class NodeViews {
 public:
  explicit NodeViews(std::string path) : path_(std::move(path)) {}
  ~NodeViews();
  NodeViews(const NodeViews&) = delete;
  NodeViews& operator=(const NodeViews&) = delete;

  bool empty() const { return views_.empty(); }
  // A view of `vertices` vertices begins (the scratch file is created at the first).
  void begin(const std::string& name, int components, std::uint64_t vertices);
  void values(VertId v, const double* values);

  // After the stream: the fields as read_mesh gives them (layouts; values empty), the vertex refs
  // written into `refs` when a vertex-ref view holds integers. Then next_vertex() gives every
  // vertex's values in order (stride() doubles: the fields' components, in order).
  void finish(std::vector<std::int32_t>& refs);
  const std::vector<VertexField>& fields() const { return fields_; }
  int stride() const { return stride_; }
  void next_vertex(double* out);

 private:
  struct View {
    std::string name;
    int components = 0;
    std::uint64_t offset = 0;  // bytes into the file
    bool symmetric = true;     // every entry given so far is a symmetric 3x3 (9 components only)
  };
  struct Window {
    const View* view = nullptr;
    bool to_symmetric = false;
    std::vector<double> buffer;  // kWindow vertices of the view's components
  };
  void flush();
  void read(void* into, std::uint64_t offset, std::size_t bytes) const;

  std::string path_;
  int fd_ = -1;
  std::uint64_t vertices_ = 0, file_end_ = 0;
  std::vector<View> views_;
  // The current run: consecutive vertices of the current view, written in one call.
  std::uint64_t run_first_ = 0;
  std::vector<double> run_;
  std::vector<VertexField> fields_;
  std::vector<Window> windows_;  // [field]
  int stride_ = 0;
  std::uint64_t next_ = 0;  // next vertex of next_vertex()
};

}  // namespace topotet::ooc
