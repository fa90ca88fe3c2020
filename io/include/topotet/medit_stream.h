// MEDIT .mesh (+ .sol), ASCII or binary (.meshb + .solb), read and written as a stream: memory independent of the file's size, for
// meshes larger than memory (topotet/out_of_core.h) and generators that write as they go.
// read_mesh and write_mesh (topotet/io.h) are built on the same parser and writer, so the three
// accept, refuse and write exactly the same text.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "topotet/io.h"
#include "topotet/mesh_data.h"

namespace topotet {

// Receives a MEDIT file's entities in file order; vertex ids 0-based. A section's begin_* call
// gives its declared count before its entries. Every callback does nothing by default.
struct MeditVisitor {
  virtual ~MeditVisitor() = default;
  virtual void begin_vertices(std::uint64_t /*count*/) {}
  // A reader that holds memory of its own while it streams (a .msh's node tag -> index map, which
  // lives until the fields after the elements are read) begins the vertices through this instead,
  // with the bytes it will hold: a visitor that checks the counts against a memory limit counts
  // them too and returns true, and the reader then allocates them at once (no growth by doubling).
  // The default begins the vertices and returns false (the reader grows as it reads).
  virtual bool begin_vertices_holding(std::uint64_t count, std::uint64_t /*reader_bytes*/) {
    begin_vertices(count);
    return false;
  }
  virtual void vertex(const std::array<double, 3>& /*p*/, std::int32_t /*ref*/) {}
  virtual void begin_tets(std::uint64_t /*count*/) {}
  virtual void tet(const std::array<VertId, 4>& /*v*/, std::int32_t /*material*/) {}
  virtual void begin_triangles(std::uint64_t /*count*/) {}
  virtual void triangle(const Triangle& /*t*/) {}
  virtual void begin_segments(std::uint64_t /*count*/) {}  // MEDIT "Edges"
  virtual void segment(const Segment& /*s*/) {}
  virtual void corner(VertId /*v*/) {}
  virtual void required_vertex(VertId /*v*/) {}
  virtual void ridge(std::uint32_t /*segment_index*/) {}
  // The fields of a streamed .msh ($NodeData and $ElementData, after the elements;
  // topotet/mesh_stream.h): a view begins with its name and component count, then gives (0-based
  // vertex or tet, values) entries in file order; the entities it does not list have 0 there, and
  // a view whose name came before replaces that field's values (the last time step wins), as
  // read_mesh reads them. A visitor that does not take them returns false (the default): the
  // stream is then refused, saying so.
  virtual bool begin_node_view(const std::string& /*name*/, int /*components*/) { return false; }
  virtual void node_values(VertId /*v*/, const double* /*values*/) {}
  virtual bool begin_cell_view(const std::string& /*name*/, int /*components*/) { return false; }
  virtual void cell_values(std::uint64_t /*tet*/, const double* /*values*/) {}
};

// Streams a .mesh / .meshb (optionally .gz) through `visitor` with read_mesh's checks and messages (FILE:LINE,
// NaN, indices out of range, truncation, mixed meshes unless options.tets_only; ReadNotes counts).
// Keeping nothing, it needs Vertices before any section that indexes vertices and Edges before
// Ridges (every writer does so), and fields in the .sol (SolStream), not in the .mesh: otherwise an
// InputError says so. Does not read the .sol.
void stream_medit(const std::string& path, MeditVisitor& visitor, const ReadOptions& options, ReadNotes& notes);

// The .sol beside a .mesh, read an entity at a time: the SolAtVertices values of each vertex in
// turn (all solutions of a vertex together, in vertex_fields() order), and those of
// SolAtTetrahedra, from two positions in the file. Names and kinds as read_mesh gives them
// (<stem>.sol.fields.txt, else sol0.. / cellsol0..). Throws InputError like read_mesh.
class SolStream {
 public:
  // mesh_path: the .mesh (.mesh.gz); the .sol is looked for beside it as read_mesh does. The
  // counts are the mesh's (a section with another count is an error).
  SolStream(const std::string& mesh_path, std::uint64_t vertex_count, std::uint64_t tet_count);
  ~SolStream();
  SolStream(const SolStream&) = delete;
  SolStream& operator=(const SolStream&) = delete;

  bool has_sol() const { return !vertex_fields_.empty() || !cell_fields_.empty(); }
  const std::vector<VertexField>& vertex_fields() const { return vertex_fields_; }  // layouts: values empty
  const std::vector<CellField>& cell_fields() const { return cell_fields_; }
  int vertex_stride() const { return vertex_stride_; }
  int cell_stride() const { return cell_stride_; }
  void next_vertex(double* values);  // vertex_stride() values
  void next_tet(double* values);     // cell_stride() values

 private:
  struct Readers;
  std::unique_ptr<Readers> readers_;
  std::vector<VertexField> vertex_fields_;
  std::vector<CellField> cell_fields_;
  int vertex_stride_ = 0, cell_stride_ = 0;
};

// Writes a .mesh (or a binary .meshb: by the extension), and its .sol (.solb) (+ .sol.fields.txt unless the names are the defaults) when there are
// fields, section by section, the bytes write_mesh writes. Nothing appears at the paths before
// commit() (io/atomic_file.h: temporary names, renamed together; destroyed without commit, the
// temporaries are removed). Counts are declared by begin_*; commit() throws std::logic_error when
// a section got another number of entries. Sections go in this order, each at most once, empty
// ones left out: vertices, tets, triangles, segments, ridges, corners, required vertices.
class MeditStreamWriter {
 public:
  // Field layouts (names, components, kinds; values ignored). Throws InputError for a layout .sol
  // cannot hold, or fields with an output that is a stream or device.
  MeditStreamWriter(const std::string& path, std::vector<VertexField> vertex_fields = {},
                    std::vector<CellField> cell_fields = {});
  ~MeditStreamWriter();
  MeditStreamWriter(const MeditStreamWriter&) = delete;
  MeditStreamWriter& operator=(const MeditStreamWriter&) = delete;

  void begin_vertices(std::uint64_t count);
  // field_values: the vertex's values of every vertex field, in order (null when there are none).
  void vertex(const std::array<double, 3>& p, std::int32_t ref, const double* field_values);
  void begin_tets(std::uint64_t count);
  void tet(const std::array<VertId, 4>& v, std::int32_t material, const double* cell_values);
  void begin_triangles(std::uint64_t count);
  void triangle(const Triangle& t);
  void begin_segments(std::uint64_t count);
  void segment(const Segment& s);
  void begin_ridges(std::uint64_t count);
  void ridge(std::uint32_t segment_index);
  void begin_corners(std::uint64_t count);
  void corner(VertId v);
  void begin_required_vertices(std::uint64_t count);
  void required_vertex(VertId v);
  void commit();

 private:
  struct Files;
  void begin(int section, const char* keyword, std::uint64_t count);
  void entry(int section);
  std::unique_ptr<Files> files_;
};

}  // namespace topotet
