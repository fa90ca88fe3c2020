// The $NodeData (or $ElementData) views of a .msh streamed by the cut (MeditVisitor::begin_node_view,
// begin_cell_view): they come after the elements, in tag order, a view at a time, and the cut needs
// them per entity in entity order (the .sol's order, what it spills for a MEDIT input). Each view is
// a region of one scratch file, entities x components doubles, written in place as its entries come
// (runs of consecutive entities in one call; the file is sparse, so what a partial view leaves out
// reads 0), and read back per entity, a window at a time, as the fields read_mesh gives:
//   - one field per name, in the order of the names' first views, with the values of the last
//     view of that name (the last time step wins);
//   - node views: "topotet:vertex_ref" with one component and integer values is the vertex refs,
//     not a field;
//   - a 9-component view exactly symmetric at every entity it lists (the others are 0): 6
//     components in MEDIT's order (xx, xy, yy, xz, yz, zz).
// Memory: a run buffer and a window per field (a few hundred kB), whatever the input's size.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "scratch.h"

namespace topotet::ooc {

class FieldViews {
 public:
  explicit FieldViews(std::string path) : path_(std::move(path)) {}

  bool empty() const { return views_.empty(); }
  // A view of `entities` vertices (tets) begins (the scratch file is created at the first).
  void begin(const std::string& name, int components, std::uint64_t entities);
  void values(std::uint64_t entity, const double* values);

  struct Layout {
    std::string name;
    int components = 0;
  };
  // After the stream: the fields as read_mesh gives them (names and components); with `vertex_refs`
  // (node views), the vertex refs written there when a vertex-ref view holds integers. Then next()
  // gives every entity's values in order (stride() doubles: the fields' components, in order).
  void finish(std::vector<std::int32_t>* vertex_refs);
  const std::vector<Layout>& fields() const { return fields_; }
  int stride() const { return stride_; }
  void next(double* out);

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

  std::string path_;
  std::optional<ScratchFile> file_;  // created by the first view
  std::uint64_t entities_ = 0, file_end_ = 0;
  std::vector<View> views_;
  // The current run: consecutive entities of the current view, written in one call.
  std::uint64_t run_first_ = 0;
  std::vector<double> run_;
  std::vector<Layout> fields_;
  std::vector<Window> windows_;  // [field]
  int stride_ = 0;
  std::uint64_t next_ = 0;  // the entity next() gives
};

}  // namespace topotet::ooc
