// MEDIT .mesh and .sol (the Gamma Mesh Format as written by Mmg, CGAL, Gmsh, TetGen...), ASCII, and
// binary .meshb / .solb through the same parser: MeditInput (io/medit_input.h) gives it tokens or
// binary words, and the writer spells the same sections in either.
//
// A file is a sequence of sections "Keyword [count] entries...", in any order, keywords
// case-insensitive, '#' starting a comment anywhere. We read Vertices, Tetrahedra, Triangles,
// Edges, Ridges, Corners, RequiredVertices, SolAtVertices and SolAtTetrahedra; every other section of the format
// is skipped by its known entry size (libMeshb's keyword table). A keyword whose size we do not
// know cannot be skipped safely (entries are not line-delimited), so it is an error naming it.
//
// Indices are checked as they are read when Vertices (or Edges, for Ridges) came first, as every
// writer does; sections that come earlier are checked once the file is read.
#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>

#include "io/atomic_file.h"
#include "io/formats.h"
#include "io/line_reader.h"
#include "io/medit_input.h"
#include "topotet/error.h"
#include "topotet/medit_stream.h"

namespace topotet::io {
namespace {

enum class Kind {
  kCounted,    // count, then count entries of `tokens` tokens
  kInfo,       // exactly `tokens` tokens, no count
  kString,     // one (possibly quoted) string
  kSol,        // count, number of types, types, then values (SolAt...)
  kHighOrder,  // curved elements: refused rather than silently dropped
};

struct Keyword {
  std::string_view name;
  Kind kind;
  int tokens;
};

// Sections we skip, with their entry sizes in 3D (libMeshb's GmfKwdFmt).
constexpr Keyword kOtherKeywords[] = {
    {"Quadrilaterals", Kind::kCounted, 5},
    {"Prisms", Kind::kCounted, 7},
    {"Pentahedra", Kind::kCounted, 7},
    {"Hexahedra", Kind::kCounted, 9},
    {"Pyramids", Kind::kCounted, 6},
    {"RequiredEdges", Kind::kCounted, 1},
    {"RequiredTriangles", Kind::kCounted, 1},
    {"RequiredQuadrilaterals", Kind::kCounted, 1},
    {"RequiredTetrahedra", Kind::kCounted, 1},
    {"TangentAtEdgeVertices", Kind::kCounted, 3},
    {"NormalAtVertices", Kind::kCounted, 2},
    {"NormalAtTriangleVertices", Kind::kCounted, 3},
    {"NormalAtQuadrilateralVertices", Kind::kCounted, 4},
    {"Normals", Kind::kCounted, 3},
    {"Tangents", Kind::kCounted, 3},
    {"TangentAtVertices", Kind::kCounted, 2},
    {"VertexOnGeometricVertex", Kind::kCounted, 2},
    {"VertexOnGeometricEdge", Kind::kCounted, 3},
    {"VertexOnGeometricTriangle", Kind::kCounted, 4},
    {"VertexOnGeometricQuadrilateral", Kind::kCounted, 4},
    {"EdgeOnGeometricEdge", Kind::kCounted, 2},
    {"TriangleOnGeometricTriangle", Kind::kCounted, 2},
    {"TriangleOnGeometricQuadrilateral", Kind::kCounted, 2},
    {"QuadrilateralOnGeometricTriangle", Kind::kCounted, 2},
    {"QuadrilateralOnGeometricQuadrilateral", Kind::kCounted, 2},
    {"PeriodicVertices", Kind::kCounted, 2},
    {"PeriodicEdges", Kind::kCounted, 2},
    {"PeriodicTriangles", Kind::kCounted, 2},
    {"PeriodicQuadrilaterals", Kind::kCounted, 2},
    {"ISolAtVertices", Kind::kCounted, 1},
    {"AngleOfCornerBound", Kind::kInfo, 1},
    {"BoundingBox", Kind::kInfo, 6},
    {"Iterations", Kind::kInfo, 1},
    {"Time", Kind::kInfo, 1},
    {"Geometry", Kind::kString, 0},
    {"Identifier", Kind::kString, 0},
    {"MeshSupportOfVertices", Kind::kString, 0},
    {"SolAtVertices", Kind::kSol, 0},  // only reached for .sol-only sections we skip
    {"SolAtEdges", Kind::kSol, 0},
    {"SolAtTriangles", Kind::kSol, 0},
    {"SolAtQuadrilaterals", Kind::kSol, 0},
    {"SolAtTetrahedra", Kind::kSol, 0},
    {"SolAtPrisms", Kind::kSol, 0},
    {"SolAtHexahedra", Kind::kSol, 0},
    {"SolAtPyramids", Kind::kSol, 0},
    {"EdgesP2", Kind::kHighOrder, 0},
    {"TrianglesP2", Kind::kHighOrder, 0},
    {"TetrahedraP2", Kind::kHighOrder, 0},
    {"QuadrilateralsQ2", Kind::kHighOrder, 0},
    {"HexahedraQ2", Kind::kHighOrder, 0},
    {"TrianglesP3", Kind::kHighOrder, 0},
    {"TetrahedraP3", Kind::kHighOrder, 0},
};

const Keyword* find_keyword(std::string_view name) {
  for (const Keyword& k : kOtherKeywords)
    if (iequals(k.name, name)) return &k;
  return nullptr;
}

// Components of a .sol type in 3D: scalar, vector, symmetric tensor, full matrix.
constexpr std::array<int, 5> kSolComponents = {0, 1, 3, 6, 9};

// .meshb / .solb (optionally .gz): the binary GMF (io/medit_input.h).
bool is_binary_medit(std::string_view path) {
  if (iends_with(path, ".gz")) path.remove_suffix(3);
  return iends_with(path, ".meshb") || iends_with(path, ".solb");
}

std::uint32_t read_count(MeditInput& r, std::string_view section) {
  const std::int64_t n = r.read_int(section);
  if (n < 0) r.fail(std::string(section) + ": negative count " + std::to_string(n));
  if (n >= static_cast<std::int64_t>(kInvalid)) r.fail(std::string(section) + ": count " + std::to_string(n) + " too large");
  return static_cast<std::uint32_t>(n);
}

std::int32_t read_ref(MeditInput& r, std::string_view what) {
  return static_cast<std::int32_t>(
      r.read_int(what, std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max()));
}

void skip_tokens(MeditInput& r, std::uint64_t n, std::string_view section) {
  for (std::uint64_t i = 0; i < n; ++i) r.tokens().token(section);
}

// Skips a section we do not use, or refuses it. A binary file says where the next keyword is:
// any section can be skipped there, but curved elements are refused all the same.
void skip_section(MeditInput& r, std::string_view keyword) {
  const Keyword* k = find_keyword(keyword);
  const std::string name(keyword);
  if (r.binary() && (k == nullptr || k->kind != Kind::kHighOrder)) return r.skip_to_next_keyword(name);
  if (k == nullptr) {
    r.fail("unknown section '" + name + "': cannot skip it (its entry size is unknown)");
  }
  switch (k->kind) {
    case Kind::kCounted:
      skip_tokens(r, std::uint64_t{read_count(r, name)} * static_cast<std::uint64_t>(k->tokens), name);
      return;
    case Kind::kInfo:
      skip_tokens(r, static_cast<std::uint64_t>(k->tokens), name);
      return;
    case Kind::kString: {
      std::string_view tok = r.tokens().token(name);
      // A quoted string may contain blanks: skip tokens up to the closing quote.
      if (tok.front() == '"') {
        while (tok.size() < 2 || tok.back() != '"') tok = r.tokens().token(name);
      }
      return;
    }
    case Kind::kSol: {
      const std::uint32_t n = read_count(r, name);
      const auto types = r.read_word(name + ": number of solutions", 1, 1000);
      std::uint64_t per_entry = 0;
      for (std::int64_t t = 0; t < types; ++t)
        per_entry += static_cast<std::uint64_t>(kSolComponents[static_cast<std::size_t>(r.read_word(name + ": type", 1, 4))]);
      skip_tokens(r, n * per_entry, name);
      return;
    }
    case Kind::kHighOrder:
      r.fail("section '" + name + "': second-order elements not supported");
  }
}

void read_dimension(MeditInput& r) {
  const std::int64_t d = r.read_word("Dimension", std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max());
  if (d != 3) r.fail("Dimension " + std::to_string(d) + " is not supported (only 3D meshes)");
}

void read_version(MeditInput& r) {
  const std::int64_t v = r.read_int("MeshVersionFormatted");
  if (v < 1 || v > 4) r.fail("MeshVersionFormatted " + std::to_string(v) + " is not supported (expected 1 to 4)");
}

// SolAtVertices or SolAtTetrahedra (keyword already read): appends one field per solution, named
// "<prefix><k>" ("sol0", ... for vertices, "cellsol0", ... for tets), k counting from the fields
// already there. `count`, when known, is the number of entities the section must have.
template <class Field>
void read_sol_section(MeditInput& r, const std::string& keyword, std::optional<std::size_t> count, const char* entities,
                      const char* prefix, std::vector<Field>& fields) {
  const std::uint32_t n = read_count(r, keyword);
  if (count && n != *count) {
    r.fail(keyword + ": " + std::to_string(n) + " entries but the mesh has " + std::to_string(*count) + " " + entities);
  }
  const auto types = r.read_word(keyword + ": number of solutions", 1, 1000);
  const std::size_t first = fields.size();
  int per_entry = 0;
  for (std::int64_t t = 0; t < types; ++t) {
    const auto type = r.read_word(keyword + ": type (1 scalar, 2 vector, 3 symmetric tensor, 4 matrix)", 1, 4);
    Field f;
    f.name = prefix + std::to_string(fields.size());
    f.components = kSolComponents[static_cast<std::size_t>(type)];
    per_entry += f.components;
    fields.push_back(std::move(f));
  }
  const std::size_t hint = r.reserve_hint(n, 2 * static_cast<std::size_t>(per_entry));
  for (std::size_t k = first; k < fields.size(); ++k)
    fields[k].values.reserve(hint * static_cast<std::size_t>(fields[k].components));
  const std::string value = keyword + " value";
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::size_t k = first; k < fields.size(); ++k)
      for (int c = 0; c < fields[k].components; ++c) fields[k].values.push_back(r.read_double(value));
}

void read_sol_at_vertices(MeditInput& r, std::optional<std::size_t> vertex_count, std::vector<VertexField>& fields) {
  read_sol_section(r, "SolAtVertices", vertex_count, "vertices", "sol", fields);
}

void read_sol_at_tets(MeditInput& r, std::optional<std::size_t> tet_count, std::vector<CellField>& fields) {
  read_sol_section(r, "SolAtTetrahedra", tet_count, "tetrahedra", "cellsol", fields);
}

// One parser for both readers: into a MeshData (read_mesh: sections in any order, indices of
// sections before Vertices checked at the end), or through a MeditVisitor (stream_medit: nothing
// kept, so sections that index vertices must follow Vertices, and fields must be in the .sol).
class MeditReader {
 public:
  MeditReader(const std::string& path, const ReadOptions& options, ReadNotes& notes, MeditVisitor* visitor = nullptr)
      : r_(path, is_binary_medit(path)), options_(options), notes_(notes), visitor_(visitor) {}

  MeshData read() {
    for (;;) {
      const std::string kw = r_.keyword();
      if (kw.empty()) break;
      if (iequals(kw, "MeshVersionFormatted")) {
        read_version(r_);
      } else if (iequals(kw, "Dimension")) {
        read_dimension(r_);
      } else if (iequals(kw, "Vertices")) {
        read_vertices();
      } else if (iequals(kw, "Tetrahedra")) {
        read_tets();
      } else if (iequals(kw, "Triangles")) {
        read_triangles();
      } else if (iequals(kw, "Edges")) {
        read_edges();
      } else if (iequals(kw, "Corners")) {
        read_vertex_list(m_.corners, "Corners");
      } else if (iequals(kw, "RequiredVertices")) {
        read_vertex_list(m_.required_vertices, "RequiredVertices");
      } else if (iequals(kw, "Ridges")) {
        read_ridges();
      } else if (visitor_ && (iequals(kw, "SolAtVertices") || iequals(kw, "SolAtTetrahedra"))) {
        r_.fail(kw + " inside the .mesh: a streamed mesh takes its fields from the .sol beside it (write them there)");
      } else if (iequals(kw, "SolAtVertices")) {
        read_sol_at_vertices(r_, have_vertices_ ? std::optional<std::size_t>(nv_) : std::nullopt, m_.fields);
      } else if (iequals(kw, "SolAtTetrahedra")) {
        if (!seen_tets_) r_.fail("SolAtTetrahedra before Tetrahedra (its values are in the order of the tetrahedra)");
        read_sol_at_tets(r_, m_.tets.size(), m_.cell_fields);
      } else if (std::uint64_t* count = non_tet_count(kw)) {
        skip_non_tets(kw, *count);
      } else {
        skip_section(r_, kw);
      }
    }
    check_deferred();
    if (std::all_of(m_.vertex_refs.begin(), m_.vertex_refs.end(), [](std::int32_t x) { return x == 0; }))
      m_.vertex_refs.clear();  // "empty = all 0": keeps read -> write -> read comparisons exact
    return std::move(m_);
  }

 private:
  // Where a section of cells we leave out is counted, or nullptr.
  std::uint64_t* non_tet_count(std::string_view kw) {
    if (iequals(kw, "Hexahedra")) return &notes_.hexahedra;
    if (iequals(kw, "Prisms") || iequals(kw, "Pentahedra")) return &notes_.prisms;
    if (iequals(kw, "Pyramids")) return &notes_.pyramids;
    if (iequals(kw, "Quadrilaterals")) return &notes_.quadrilaterals;
    return nullptr;
  }

  // Hexahedra, prisms and pyramids are refused unless tets_only (io.h); quads are always skipped.
  void skip_non_tets(const std::string& kw, std::uint64_t& count) {
    const std::size_t line = r_.line();
    const Keyword* k = find_keyword(kw);
    const std::uint32_t n = read_count(r_, kw);
    if (n > 0 && !iequals(kw, "Quadrilaterals") && !options_.tets_only) {
      std::string kind = kw;
      for (char& c : kind) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
      if (kind == "pentahedra") kind = "prisms";
      r_.fail_at_line(line, mixed_mesh_message(std::to_string(n) + " " + kind));
    }
    skip_tokens(r_, std::uint64_t{n} * static_cast<std::uint64_t>(k->tokens), kw);
    count += n;
  }

  void begin_section(std::string_view name, bool& seen) {
    if (seen) r_.fail("duplicate section " + std::string(name));
    seen = true;
    if (have_vertices_) return;
    if (visitor_) r_.fail(std::string(name) + " before Vertices: a streamed mesh needs its Vertices first");
    deferred_.push_back({std::string(name), r_.line()});
  }

  VertId read_vertex(std::string_view what) {
    const std::int64_t i = r_.read_int(what);
    const std::int64_t hi = have_vertices_ ? static_cast<std::int64_t>(nv_) : static_cast<std::int64_t>(kInvalid) - 1;
    if (i < 1 || i > hi) {
      r_.fail(std::string(what) + ": vertex index " + std::to_string(i) + " out of range [1, " + std::to_string(hi) + "]");
    }
    return static_cast<VertId>(i - 1);
  }

  void read_vertices() {
    if (have_vertices_) r_.fail("duplicate section Vertices");
    const std::uint32_t n = read_count(r_, "Vertices");
    if (visitor_) visitor_->begin_vertices(n);
    const std::size_t hint = visitor_ ? 0 : r_.reserve_hint(n, 8);
    m_.positions.reserve(hint);
    m_.vertex_refs.reserve(hint);
    for (std::uint32_t i = 0; i < n; ++i) {
      const double x = r_.read_double("Vertices coordinate");
      const double y = r_.read_double("Vertices coordinate");
      const double z = r_.read_double("Vertices coordinate");
      const std::int32_t ref = read_ref(r_, "Vertices reference");
      if (visitor_) {
        visitor_->vertex({x, y, z}, ref);
      } else {
        m_.positions.push_back({x, y, z});
        m_.vertex_refs.push_back(ref);
      }
    }
    have_vertices_ = true;
    nv_ = n;
  }

  void read_tets() {
    begin_section("Tetrahedra", seen_tets_);
    const std::uint32_t n = read_count(r_, "Tetrahedra");
    if (visitor_) visitor_->begin_tets(n);
    const std::size_t hint = visitor_ ? 0 : r_.reserve_hint(n, 10);
    m_.tets.reserve(hint);
    m_.tet_material.reserve(hint);
    for (std::uint32_t i = 0; i < n; ++i) {
      std::array<VertId, 4> t;
      for (VertId& v : t) v = read_vertex("Tetrahedra");
      const std::int32_t material = read_ref(r_, "Tetrahedra reference");
      if (visitor_) {
        visitor_->tet(t, material);
      } else {
        m_.tets.push_back(t);
        m_.tet_material.push_back(material);
      }
    }
  }

  void read_triangles() {
    begin_section("Triangles", seen_triangles_);
    const std::uint32_t n = read_count(r_, "Triangles");
    if (visitor_) visitor_->begin_triangles(n);
    m_.triangles.reserve(visitor_ ? 0 : r_.reserve_hint(n, 8));
    for (std::uint32_t i = 0; i < n; ++i) {
      Triangle t;
      for (VertId& v : t.v) v = read_vertex("Triangles");
      t.ref = read_ref(r_, "Triangles reference");
      if (visitor_) visitor_->triangle(t);
      else m_.triangles.push_back(t);
    }
  }

  void read_edges() {
    begin_section("Edges", seen_edges_);
    const std::uint32_t n = read_count(r_, "Edges");
    if (visitor_) visitor_->begin_segments(n);
    m_.segments.reserve(visitor_ ? 0 : r_.reserve_hint(n, 6));
    segment_count_ = n;
    for (std::uint32_t i = 0; i < n; ++i) {
      Segment s;
      for (VertId& v : s.v) v = read_vertex("Edges");
      s.ref = read_ref(r_, "Edges reference");
      if (visitor_) visitor_->segment(s);
      else m_.segments.push_back(s);
    }
  }

  // TetGen's -g .mesh lists Corners by input point index, some beyond the mesh's vertices: an
  // out-of-range corner pins nothing, so it is left out and counted (ReadNotes), not refused.
  void read_vertex_list(std::vector<VertId>& out, std::string_view name) {
    const bool corners = name == "Corners";
    begin_section(name, corners ? seen_corners_ : seen_required_);
    const std::uint32_t n = read_count(r_, name);
    out.reserve(visitor_ ? 0 : r_.reserve_hint(n, 2));
    for (std::uint32_t i = 0; i < n; ++i) {
      if (corners) {
        const std::int64_t v = r_.read_int(name);
        if (v < 1 || v > (have_vertices_ ? static_cast<std::int64_t>(nv_) : std::int64_t{kInvalid} - 1)) {
          ++notes_.dropped_corners;
          continue;
        }
        if (visitor_) visitor_->corner(static_cast<VertId>(v - 1));
        else out.push_back(static_cast<VertId>(v - 1));
      } else {
        const VertId v = read_vertex(name);
        if (visitor_) visitor_->required_vertex(v);
        else out.push_back(v);
      }
    }
  }

  void read_ridges() {
    if (seen_ridges_) r_.fail("duplicate section Ridges");
    seen_ridges_ = true;
    ridges_line_ = r_.line();
    const std::uint32_t n = read_count(r_, "Ridges");
    if (visitor_ && !seen_edges_ && n > 0) r_.fail("Ridges before Edges: a streamed mesh needs its Edges first");
    m_.ridges.reserve(visitor_ ? 0 : r_.reserve_hint(n, 2));
    // Ridges index Edges; before Edges is read we can only bound them, and check them at the end.
    const std::int64_t hi = seen_edges_ ? static_cast<std::int64_t>(segment_count_) : kInvalid - 1;
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::int64_t e = r_.read_int("Ridges");
      if (e < 1 || e > hi)
        r_.fail("Ridges: edge index " + std::to_string(e) + " out of range [1, " + std::to_string(hi) + "]");
      if (visitor_) visitor_->ridge(static_cast<std::uint32_t>(e - 1));
      else m_.ridges.push_back(static_cast<std::uint32_t>(e - 1));
    }
  }

  // Sections read before Vertices (or Ridges before Edges) are checked here, by entry number.
  void check_deferred() {
    const auto bad = [&](const std::string& section, std::size_t line, std::size_t entry, std::int64_t index,
                         std::size_t n) {
      r_.fail_at_line(line, section + " entry " + std::to_string(entry + 1) + ": index " + std::to_string(index + 1) +
                                " out of range [1, " + std::to_string(n) + "]");
    };
    for (const auto& deferred : deferred_) {
      const std::string& section = deferred.first;
      const auto check = [&](VertId v, std::size_t entry) {
        if (v >= nv_) bad(section, deferred.second, entry, v, nv_);
      };
      if (section == "Tetrahedra") {
        for (std::size_t i = 0; i < m_.tets.size(); ++i)
          for (VertId v : m_.tets[i]) check(v, i);
      } else if (section == "Triangles") {
        for (std::size_t i = 0; i < m_.triangles.size(); ++i)
          for (VertId v : m_.triangles[i].v) check(v, i);
      } else if (section == "Edges") {
        for (std::size_t i = 0; i < m_.segments.size(); ++i)
          for (VertId v : m_.segments[i].v) check(v, i);
      } else if (section == "Corners") {
        const auto out = std::remove_if(m_.corners.begin(), m_.corners.end(), [&](VertId v) { return v >= nv_; });
        notes_.dropped_corners += static_cast<std::uint64_t>(m_.corners.end() - out);
        m_.corners.erase(out, m_.corners.end());
      } else if (section == "RequiredVertices") {
        for (std::size_t i = 0; i < m_.required_vertices.size(); ++i) check(m_.required_vertices[i], i);
      }
    }
    for (std::size_t i = 0; i < m_.ridges.size(); ++i)
      if (m_.ridges[i] >= m_.segments.size()) bad("Ridges", ridges_line_, i, m_.ridges[i], m_.segments.size());
  }

  MeditInput r_;
  const ReadOptions& options_;
  ReadNotes& notes_;
  MeditVisitor* visitor_;  // null: into m_
  MeshData m_;
  std::size_t segment_count_ = 0;  // entries of Edges
  bool have_vertices_ = false;
  std::size_t nv_ = 0;
  bool seen_tets_ = false, seen_triangles_ = false, seen_edges_ = false;
  bool seen_corners_ = false, seen_required_ = false, seen_ridges_ = false;
  std::size_t ridges_line_ = 0;
  std::vector<std::pair<std::string, std::size_t>> deferred_;  // section, line
};

void read_sol_file(const std::string& path, const MeshData& mesh, std::vector<VertexField>& fields,
                   std::vector<CellField>& cell_fields) {
  MeditInput r(path, is_binary_medit(path));
  for (;;) {
    const std::string kw = r.keyword();
    if (kw.empty()) break;
    if (iequals(kw, "MeshVersionFormatted")) {
      read_version(r);
    } else if (iequals(kw, "Dimension")) {
      read_dimension(r);
    } else if (iequals(kw, "SolAtVertices")) {
      read_sol_at_vertices(r, mesh.vertex_count(), fields);
    } else if (iequals(kw, "SolAtTetrahedra")) {
      read_sol_at_tets(r, mesh.tet_count(), cell_fields);
    } else {
      skip_section(r, kw);
    }
  }
}

// "<stem>.sol.fields.txt" lists the solution names, comma- or line-separated, optionally after a
// "description:" prefix, e.g. "columns of SolAtVertices in order: Pressure, VelocityMagnitude".
// The names of the SolAtTetrahedra columns follow on a line "columns of SolAtTetrahedra in order:
// ..." (a line with "SolAtTetrahedra" before a colon); a label (categorical cell field: .sol
// stores reals) carries " [categorical]" after its name.
struct SolNames {
  std::vector<std::string> vertex, cell;
};

std::vector<std::string> split_names(std::string text) {
  const auto first_nl = text.find('\n');
  const auto colon = text.find(':');
  if (colon != std::string::npos && colon < first_nl) text.erase(0, colon + 1);
  std::vector<std::string> names;
  std::string cur;
  const auto flush = [&] {
    const auto b = cur.find_first_not_of(" \t\r\"");
    const auto e = cur.find_last_not_of(" \t\r\"");
    if (b != std::string::npos) names.push_back(cur.substr(b, e - b + 1));
    cur.clear();
  };
  for (char c : text) {
    if (c == ',' || c == '\n') {
      flush();
    } else {
      cur += c;
    }
  }
  flush();
  return names;
}

SolNames read_field_names(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  SolNames names;
  std::size_t cells = std::string::npos;
  for (std::size_t at = text.find("SolAtTetrahedra"); at != std::string::npos; at = text.find("SolAtTetrahedra", at + 1)) {
    const std::size_t line = text.rfind('\n', at);
    const std::size_t start = line == std::string::npos ? 0 : line + 1;
    const std::size_t colon = text.find(':', at), end = text.find('\n', at);
    if (colon != std::string::npos && colon < end && start > 0) {
      cells = start;
      break;
    }
  }
  names.vertex = split_names(text.substr(0, cells));
  if (cells != std::string::npos) names.cell = split_names(text.substr(cells));
  return names;
}

constexpr std::string_view kCategoricalSuffix = " [categorical]";

// "box.mesh" -> "box", "box.mesh.gz" -> "box"; gz tells whether the mesh was compressed.
std::string mesh_stem(const std::string& path, bool& gz) {
  std::string stem = path;
  gz = iends_with(stem, ".gz");
  if (gz) stem.resize(stem.size() - 3);
  if (iends_with(stem, ".mesh")) stem.resize(stem.size() - 5);
  else if (iends_with(stem, ".meshb")) stem.resize(stem.size() - 6);
  return stem;
}

std::string clean_name(std::string name, const std::string& fallback) {
  for (char& c : name)
    if (c == ',' || c == '\n' || c == '\r') c = '_';  // the separators of this file
  if (name.find_first_not_of(" \t\"") == std::string::npos) name = fallback;
  return name;
}

// The vertex line is written even when there are no vertex fields: the cell line is found as the
// second one.
std::string fields_file_text(const MeshData& m) {
  std::string s = "columns of SolAtVertices in order: ";
  for (std::size_t i = 0; i < m.fields.size(); ++i) s += (i ? ", " : "") + clean_name(m.fields[i].name, "sol" + std::to_string(i));
  s += "\n";
  if (m.cell_fields.empty()) return s;
  s += "columns of SolAtTetrahedra in order: ";
  for (std::size_t i = 0; i < m.cell_fields.size(); ++i) {
    const CellField& f = m.cell_fields[i];
    s += (i ? ", " : "") + clean_name(f.name, "cellsol" + std::to_string(i));
    if (f.kind == CellFieldKind::kCategorical) s += kCategoricalSuffix;
  }
  return s + "\n";
}

bool default_field_names(const MeshData& m) {
  for (std::size_t i = 0; i < m.fields.size(); ++i)
    if (m.fields[i].name != "sol" + std::to_string(i)) return false;
  for (std::size_t i = 0; i < m.cell_fields.size(); ++i)
    if (m.cell_fields[i].name != "cellsol" + std::to_string(i) || m.cell_fields[i].kind == CellFieldKind::kCategorical)
      return false;
  return true;
}

void put_vertex_ids(AtomicFile& out, const VertId* v, int n) {
  for (int k = 0; k < n; ++k) {
    out.put_int(std::uint64_t{v[k]} + 1);
    out.put(' ');
  }
}

}  // namespace

namespace {

// The .sol beside the mesh at `path` (prefer the same compression as the mesh, accept the other);
// empty when there is none (or the mesh is stdin, which has no folder).
std::string sol_beside(const std::string& path, std::string* stem_out) {
  if (path == "-") return {};
  bool gz = false;
  const std::string stem = mesh_stem(path, gz);
  if (stem_out) *stem_out = stem;
  std::error_code ec;
  // Its own kind only (.sol beside a .mesh, .solb beside a .meshb): a .mesh and a .meshb of one
  // stem are two meshes, each with its own companions.
  const std::string kind = is_binary_medit(path) ? ".solb" : ".sol";
  for (const std::string& sol : {stem + kind + (gz ? ".gz" : ""), stem + kind + (gz ? "" : ".gz")})
    if (std::filesystem::is_regular_file(sol, ec)) return sol;
  return {};
}

// Names from <stem>.sol.fields.txt (<stem>.solb.fields.txt beside a .solb), when present, for the solutions read from `sol` after the
// first `first` (`first_cell`) ones.
void apply_field_names(const std::string& stem, const std::string& sol, std::vector<VertexField>& fields,
                       std::size_t first, std::vector<CellField>& cell_fields, std::size_t first_cell) {
  std::error_code ec;
  const std::string names_path = stem + (is_binary_medit(sol) ? ".solb" : ".sol") + ".fields.txt";
  if (!std::filesystem::is_regular_file(names_path, ec)) return;
  SolNames names = read_field_names(names_path);
  // A file of names that knows no SolAtTetrahedra line names the vertex columns only.
  if (names.vertex.size() != fields.size() - first ||
      (!names.cell.empty() && names.cell.size() != cell_fields.size() - first_cell)) {
    throw InputError(names_path + ": " + std::to_string(names.vertex.size()) + " + " + std::to_string(names.cell.size()) +
                     " names for the " + std::to_string(fields.size() - first) + " SolAtVertices + " +
                     std::to_string(cell_fields.size() - first_cell) + " SolAtTetrahedra solutions of " + sol);
  }
  for (std::size_t i = 0; i < names.vertex.size(); ++i) fields[first + i].name = names.vertex[i];
  for (std::size_t i = 0; i < names.cell.size(); ++i) {
    CellField& f = cell_fields[first_cell + i];
    f.name = names.cell[i];
    if (f.name.size() > kCategoricalSuffix.size() && f.name.ends_with(kCategoricalSuffix)) {
      f.name.resize(f.name.size() - kCategoricalSuffix.size());
      f.kind = CellFieldKind::kCategorical;
    }
  }
}

}  // namespace

MeshData read_medit(const std::string& path, const ReadOptions& options, ReadNotes& notes) {
  MeshData mesh = MeditReader(path, options, notes).read();
  std::string stem;
  const std::string sol = sol_beside(path, &stem);
  if (sol.empty()) return mesh;
  const std::size_t first = mesh.fields.size(), first_cell = mesh.cell_fields.size();
  read_sol_file(sol, mesh, mesh.fields, mesh.cell_fields);
  apply_field_names(stem, sol, mesh.fields, first, mesh.cell_fields, first_cell);
  return mesh;
}

void write_medit(const std::string& path, const MeshData& m) {
  MeditStreamWriter out(path, m.fields, m.cell_fields);
  int vstride = 0, cstride = 0;
  for (const VertexField& f : m.fields) vstride += f.components;
  for (const CellField& f : m.cell_fields) cstride += f.components;
  std::vector<double> values(static_cast<std::size_t>(std::max(vstride, cstride)));
  // One entity's values of every field, interleaved as the stream takes them.
  const auto gather = [&](const auto& fields, std::size_t i) {
    std::size_t at = 0;
    for (const auto& f : fields) {
      const std::size_t c = static_cast<std::size_t>(f.components);
      for (std::size_t k = 0; k < c; ++k) values[at++] = f.values[i * c + k];
    }
    return values.data();
  };
  out.begin_vertices(m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i)
    out.vertex(m.positions[i], m.vertex_refs.empty() ? 0 : m.vertex_refs[i], vstride ? gather(m.fields, i) : nullptr);
  out.begin_tets(m.tets.size());
  for (std::size_t i = 0; i < m.tets.size(); ++i)
    out.tet(m.tets[i], m.tet_material.empty() ? 0 : m.tet_material[i], cstride ? gather(m.cell_fields, i) : nullptr);
  out.begin_triangles(m.triangles.size());
  for (const Triangle& t : m.triangles) out.triangle(t);
  out.begin_segments(m.segments.size());
  for (const Segment& s : m.segments) out.segment(s);
  out.begin_ridges(m.ridges.size());
  for (std::uint32_t r : m.ridges) out.ridge(r);
  out.begin_corners(m.corners.size());
  for (VertId v : m.corners) out.corner(v);
  out.begin_required_vertices(m.required_vertices.size());
  for (VertId v : m.required_vertices) out.required_vertex(v);
  out.commit();
}

}  // namespace topotet::io

// ---- streaming (topotet/medit_stream.h) ----
namespace topotet {

using namespace io;

void stream_medit(const std::string& path, MeditVisitor& visitor, const ReadOptions& options, ReadNotes& notes) {
  MeditReader(path, options, notes, &visitor).read();
}

// Two readers of one .sol: one at the SolAtVertices values, one at the SolAtTetrahedra values.
struct SolStream::Readers {
  std::unique_ptr<MeditInput> vertices, tets;
};

namespace {

// Opens `sol` and moves to the values of section `wanted` (SolAtVertices or SolAtTetrahedra),
// appending its layout to `fields`; null when the file has no such section.
template <class Field>
std::unique_ptr<MeditInput> open_sol_section(const std::string& sol, const char* wanted, std::uint64_t count,
                                             const char* entities, const char* prefix, std::vector<Field>& fields) {
  auto r = std::make_unique<MeditInput>(sol, is_binary_medit(sol));
  for (;;) {
    const std::string kw = r->keyword();
    if (kw.empty()) return nullptr;
    if (iequals(kw, "MeshVersionFormatted")) {
      read_version(*r);
    } else if (iequals(kw, "Dimension")) {
      read_dimension(*r);
    } else if (iequals(kw, wanted)) {
      const std::uint32_t n = read_count(*r, kw);
      if (n != count)
        r->fail(kw + ": " + std::to_string(n) + " entries but the mesh has " + std::to_string(count) + " " + entities);
      const auto types = r->read_word(kw + ": number of solutions", 1, 1000);
      for (std::int64_t t = 0; t < types; ++t) {
        const auto type = r->read_word(kw + ": type (1 scalar, 2 vector, 3 symmetric tensor, 4 matrix)", 1, 4);
        Field f;
        f.name = prefix + std::to_string(fields.size());
        f.components = kSolComponents[static_cast<std::size_t>(type)];
        fields.push_back(std::move(f));
      }
      return r;
    } else {
      skip_section(*r, kw);
    }
  }
}

}  // namespace

SolStream::SolStream(const std::string& mesh_path, std::uint64_t vertex_count, std::uint64_t tet_count)
    : readers_(std::make_unique<Readers>()) {
  std::string stem;
  const std::string sol = sol_beside(mesh_path, &stem);
  if (sol.empty()) return;
  readers_->vertices = open_sol_section(sol, "SolAtVertices", vertex_count, "vertices", "sol", vertex_fields_);
  readers_->tets = open_sol_section(sol, "SolAtTetrahedra", tet_count, "tetrahedra", "cellsol", cell_fields_);
  apply_field_names(stem, sol, vertex_fields_, 0, cell_fields_, 0);
  for (const VertexField& f : vertex_fields_) vertex_stride_ += f.components;
  for (const CellField& f : cell_fields_) cell_stride_ += f.components;
}

SolStream::~SolStream() = default;

void SolStream::next_vertex(double* values) {
  for (int k = 0; k < vertex_stride_; ++k) values[k] = readers_->vertices->read_double("SolAtVertices value");
}

void SolStream::next_tet(double* values) {
  for (int k = 0; k < cell_stride_; ++k) values[k] = readers_->tets->read_double("SolAtTetrahedra value");
}

// The sections in the order they are written (MeditStreamWriter::begin's `section`).
enum Section : int { kVertices, kTets, kTriangles, kSegments, kRidges, kCorners, kRequired, kSections };

// A .meshb / .solb (binary GMF, io/medit_input.h) is written as libMeshb writes version 3: int32
// integers, float64 reals, int64 positions; version 4 (int64 integers) when the vertex count needs
// it. The header waits for begin_vertices, which knows that count.
struct BinaryOut {
  AtomicFile& file;
  std::uint64_t& at;  // bytes written: the position of what comes next
  int version;
  void word(std::int32_t v) { put(v); }
  void integer(std::int64_t v) {
    if (version >= 4) put(v);
    else put(static_cast<std::int32_t>(v));
  }
  void real(double v) { put(v); }
  int integer_bytes() const { return version >= 4 ? 8 : 4; }
  // A keyword with `count` entries of `entry_bytes` and `header_words` int32 words after the count.
  void keyword(std::int32_t code, std::uint64_t count, std::uint64_t entry_bytes, int header_words = 0) {
    word(code);
    const std::uint64_t end = at + 8 + static_cast<std::uint64_t>(integer_bytes()) + 4u * static_cast<unsigned>(header_words) +
                              count * entry_bytes;
    put(static_cast<std::int64_t>(end));
    integer(static_cast<std::int64_t>(count));
  }
  void header() {  // code 1, version, Dimension 3
    word(1);
    word(version);
    word(3);
    put(static_cast<std::int64_t>(at + 8 + 4));
    word(3);
  }
  void end() {
    word(54);
    put(std::int64_t{0});
  }
  template <class T>
  void put(const T& v) {
    file.put_raw(v);
    at += sizeof v;
  }
};

constexpr std::int32_t kCodeVertices = 4, kCodeEdges = 5, kCodeTriangles = 6, kCodeTetrahedra = 8, kCodeCorners = 13,
                       kCodeRidges = 14, kCodeRequiredVertices = 15, kCodeSolAtVertices = 62, kCodeSolAtTetrahedra = 66;

struct MeditStreamWriter::Files {
  std::string path, stem;
  bool direct = false;
  bool binary = false;  // .meshb + .solb
  int version = 3;      // binary: 4 when the vertex count needs int64 indices
  std::uint64_t mesh_at = 0, sol_at = 0;
  std::vector<VertexField> vertex_fields;
  std::vector<CellField> cell_fields;
  std::optional<AtomicFile> mesh, sol;
  int section = -1;  // the last begun
  std::uint64_t declared = 0, written = 0;
  std::uint64_t vertex_count = 0, tet_count = 0;
  bool sol_tets_begun = false;
  BinaryOut mesh_out() { return {*mesh, mesh_at, version}; }
  // An element: its vertices (1-based in the file) and its ref.
  void put_entry(const VertId* v, int n, std::int32_t ref) {
    if (binary) {
      BinaryOut out = mesh_out();
      for (int k = 0; k < n; ++k) out.integer(std::int64_t{v[k]} + 1);
      out.integer(ref);
      return;
    }
    put_vertex_ids(*mesh, v, n);
    mesh->put_int(ref);
    mesh->put('\n');
  }
  // An entry of Ridges, Corners, RequiredVertices: one 1-based index.
  void put_index(std::uint64_t i) {
    if (binary) return mesh_out().integer(static_cast<std::int64_t>(i + 1));
    mesh->put_int(i + 1);
    mesh->put('\n');
  }
  BinaryOut sol_out() { return {*sol, sol_at, version}; }
  const char* sol_extension() const { return binary ? ".solb" : ".sol"; }
  void put_sol_header(const char* keyword, std::uint64_t count, const auto& fields) {
    if (binary) {
      int stride = 0;
      for (const auto& f : fields) stride += f.components;
      BinaryOut out = sol_out();
      out.keyword(std::string_view(keyword) == "SolAtVertices" ? kCodeSolAtVertices : kCodeSolAtTetrahedra, count,
                  8u * static_cast<unsigned>(stride), 1 + static_cast<int>(fields.size()));
      out.word(static_cast<std::int32_t>(fields.size()));
      for (const auto& f : fields)
        out.word(static_cast<std::int32_t>(std::find(kSolComponents.begin() + 1, kSolComponents.end(), f.components) - kSolComponents.begin()));
      return;
    }
    sol->put(keyword);
    sol->put('\n');
    sol->put_int(count);
    sol->put('\n');
    sol->put_int(fields.size());
    for (const auto& f : fields) {
      sol->put(' ');
      sol->put_int(std::find(kSolComponents.begin() + 1, kSolComponents.end(), f.components) - kSolComponents.begin());
    }
    sol->put("\n\n");
  }
  void put_values(const double* values, const auto& fields) {
    if (binary) {
      BinaryOut out = sol_out();
      for (const auto& f : fields)
        for (int k = 0; k < f.components; ++k) out.real(*values++);
      return;
    }
    bool first = true;
    for (const auto& f : fields)
      for (int k = 0; k < f.components; ++k) {
        if (!first) sol->put(' ');
        first = false;
        sol->put_double(*values++);
      }
    sol->put('\n');
  }
};

MeditStreamWriter::MeditStreamWriter(const std::string& path, std::vector<VertexField> vertex_fields,
                                     std::vector<CellField> cell_fields)
    : files_(std::make_unique<Files>()) {
  Files& f = *files_;
  f.path = path;
  f.direct = is_direct_output(path);
  f.vertex_fields = std::move(vertex_fields);
  f.cell_fields = std::move(cell_fields);
  for (auto& x : f.vertex_fields) x.values.clear();
  for (auto& x : f.cell_fields) x.values.clear();
  const bool fields = !f.vertex_fields.empty() || !f.cell_fields.empty();
  // A stream or device has no folder for the companion .sol: fields cannot go with it.
  if (f.direct && fields)
    throw InputError(path + ": cannot write the fields' .sol beside a stream or device (write .msh, which keeps "
                            "fields inline, or a regular file)");
  bool gz = false;
  f.stem = mesh_stem(path, gz);
  f.binary = is_binary_medit(path);
  const auto check_layout = [&](const auto& list) {
    for (const auto& x : list)
      if (std::find(kSolComponents.begin() + 1, kSolComponents.end(), x.components) == kSolComponents.end())
        throw InputError(f.stem + f.sol_extension() + ": cannot write field '" + x.name + "' with " +
                         std::to_string(x.components) + " components (.sol supports 1, 3, 6 or 9)");
  };
  check_layout(f.vertex_fields);
  check_layout(f.cell_fields);
  f.mesh.emplace(path);
  if (!f.binary) f.mesh->put("MeshVersionFormatted 2\n\nDimension 3\n\n");
  if (fields) {
    f.sol.emplace(f.stem + f.sol_extension());
    if (!f.binary) f.sol->put("MeshVersionFormatted 2\n\nDimension 3\n\n");
  }
}

MeditStreamWriter::~MeditStreamWriter() = default;

void MeditStreamWriter::begin(int section, const char* keyword, std::uint64_t count) {
  Files& f = *files_;
  if (section <= f.section) throw std::logic_error(std::string("MeditStreamWriter: section ") + keyword + " out of order");
  if (f.written != f.declared)
    throw std::logic_error("MeditStreamWriter: " + std::to_string(f.written) + " entries written for " +
                           std::to_string(f.declared) + " declared");
  f.section = section;
  f.declared = count;
  f.written = 0;
  // Vertices is always written (write_mesh always did); other sections only with entries.
  if (count == 0 && section != kVertices) return;
  if (f.binary) {
    // Entry sizes in integers and reals: Vertices 1 + 3 reals, Tetrahedra 5, Triangles 4, Edges 3, lists 1.
    static constexpr std::int32_t kCodes[] = {kCodeVertices, kCodeTetrahedra, kCodeTriangles, kCodeEdges,
                                              kCodeRidges, kCodeCorners, kCodeRequiredVertices};
    static constexpr int kIntegers[] = {1, 5, 4, 3, 1, 1, 1};
    BinaryOut out = f.mesh_out();
    const auto i = static_cast<std::size_t>(section);
    out.keyword(kCodes[i], count, static_cast<std::uint64_t>(kIntegers[i] * out.integer_bytes() + (section == kVertices ? 24 : 0)));
    return;
  }
  if (section != kVertices) f.mesh->put('\n');
  f.mesh->put(keyword);
  f.mesh->put('\n');
  f.mesh->put_int(count);
  f.mesh->put('\n');
}

void MeditStreamWriter::entry(int section) {
  Files& f = *files_;
  if (f.section != section) throw std::logic_error("MeditStreamWriter: entry outside its section");
  if (++f.written > f.declared) throw std::logic_error("MeditStreamWriter: more entries than declared");
}

void MeditStreamWriter::begin_vertices(std::uint64_t count) {
  Files& f = *files_;
  if (f.binary && f.section < kVertices) {
    // The indices are written + 1: int32 holds them up to 2^31 - 1 vertices.
    f.version = count + 1 > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()) ? 4 : 3;
    f.mesh_out().header();
    if (f.sol) f.sol_out().header();
  }
  begin(kVertices, "Vertices", count);
  files_->vertex_count = count;
  if (files_->sol && !files_->vertex_fields.empty()) files_->put_sol_header("SolAtVertices", count, files_->vertex_fields);
}

void MeditStreamWriter::vertex(const std::array<double, 3>& p, std::int32_t ref, const double* field_values) {
  entry(kVertices);
  if (files_->binary) {
    BinaryOut out = files_->mesh_out();
    for (double x : p) out.real(x);
    out.integer(ref);
    if (!files_->vertex_fields.empty()) files_->put_values(field_values, files_->vertex_fields);
    return;
  }
  AtomicFile& out = *files_->mesh;
  out.put_double(p[0]);
  out.put(' ');
  out.put_double(p[1]);
  out.put(' ');
  out.put_double(p[2]);
  out.put(' ');
  out.put_int(ref);
  out.put('\n');
  if (!files_->vertex_fields.empty()) files_->put_values(field_values, files_->vertex_fields);
}

void MeditStreamWriter::begin_tets(std::uint64_t count) {
  Files& f = *files_;
  begin(kTets, "Tetrahedra", count);
  f.tet_count = count;
  if (f.sol && !f.vertex_fields.empty() && !f.binary) f.sol->put("\n");  // ends SolAtVertices
  if (f.sol && !f.cell_fields.empty()) f.put_sol_header("SolAtTetrahedra", count, f.cell_fields);
  f.sol_tets_begun = true;
}

void MeditStreamWriter::tet(const std::array<VertId, 4>& v, std::int32_t material, const double* cell_values) {
  entry(kTets);
  files_->put_entry(v.data(), 4, material);
  if (!files_->cell_fields.empty()) files_->put_values(cell_values, files_->cell_fields);
}

void MeditStreamWriter::begin_triangles(std::uint64_t count) {
  if (!files_->sol_tets_begun) begin_tets(0);
  begin(kTriangles, "Triangles", count);
}

void MeditStreamWriter::triangle(const Triangle& t) {
  entry(kTriangles);
  files_->put_entry(t.v.data(), 3, t.ref);
}

void MeditStreamWriter::begin_segments(std::uint64_t count) {
  if (!files_->sol_tets_begun) begin_tets(0);
  begin(kSegments, "Edges", count);
}

void MeditStreamWriter::segment(const Segment& s) {
  entry(kSegments);
  files_->put_entry(s.v.data(), 2, s.ref);
}

void MeditStreamWriter::begin_ridges(std::uint64_t count) {
  if (!files_->sol_tets_begun) begin_tets(0);
  begin(kRidges, "Ridges", count);
}
void MeditStreamWriter::ridge(std::uint32_t segment_index) {
  entry(kRidges);
  files_->put_index(segment_index);
}
void MeditStreamWriter::begin_corners(std::uint64_t count) {
  if (!files_->sol_tets_begun) begin_tets(0);
  begin(kCorners, "Corners", count);
}
void MeditStreamWriter::corner(VertId v) {
  entry(kCorners);
  files_->put_index(v);
}
void MeditStreamWriter::begin_required_vertices(std::uint64_t count) {
  if (!files_->sol_tets_begun) begin_tets(0);
  begin(kRequired, "RequiredVertices", count);
}
void MeditStreamWriter::required_vertex(VertId v) {
  entry(kRequired);
  files_->put_index(v);
}

void MeditStreamWriter::commit() {
  Files& f = *files_;
  if (f.section < kVertices) begin_vertices(0);
  if (!f.sol_tets_begun) begin_tets(0);
  if (f.written != f.declared)
    throw std::logic_error("MeditStreamWriter: " + std::to_string(f.written) + " entries written for " +
                           std::to_string(f.declared) + " declared");
  if (f.binary) f.mesh_out().end();
  else f.mesh->put("\nEnd\n");
  const std::string sol_path = f.stem + f.sol_extension(), names_path = sol_path + ".fields.txt";
  // The companion files of <stem>.mesh are replaced with it: whatever this write does not produce
  // is removed afterwards, or the next read would attach a stale .sol to the new mesh.
  const auto remove_stale = [&](std::initializer_list<std::string> paths) {
    std::error_code ec;
    for (const std::string& p : paths) std::filesystem::remove(p, ec);
  };
  if (!f.sol) {
    f.mesh->commit();
    if (!f.direct) remove_stale({sol_path, sol_path + ".gz", names_path});
    return;
  }
  if (f.binary) {
    f.sol_out().end();
  } else {
    if (!f.cell_fields.empty()) f.sol->put("\n");  // ends SolAtTetrahedra
    f.sol->put("End\n");
  }
  MeshData layout;  // names only, for the defaults test and the names file
  layout.fields = f.vertex_fields;
  layout.cell_fields = f.cell_fields;
  // Names go to <stem>.sol.fields.txt, unless they are the defaults a reader would give anyway.
  if (default_field_names(layout)) {
    commit_all({&*f.sol, &*f.mesh});
    remove_stale({sol_path + ".gz", names_path});
    return;
  }
  AtomicFile names(names_path);
  names.put(fields_file_text(layout));
  commit_all({&*f.sol, &names, &*f.mesh});
  remove_stale({sol_path + ".gz"});
}

}  // namespace topotet
