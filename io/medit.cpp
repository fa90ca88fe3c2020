// MEDIT ASCII .mesh and .sol (the Gamma Mesh Format as written by Mmg, CGAL, Gmsh, TetGen...).
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
#include "topotet/error.h"

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

bool is_keyword_token(std::string_view tok) {
  const char c = tok.empty() ? '\0' : tok[0];
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}

std::uint32_t read_count(LineReader& r, std::string_view section) {
  const std::int64_t n = r.read_int(section);
  if (n < 0) r.fail(std::string(section) + ": negative count " + std::to_string(n));
  if (n >= static_cast<std::int64_t>(kInvalid)) r.fail(std::string(section) + ": count " + std::to_string(n) + " too large");
  return static_cast<std::uint32_t>(n);
}

std::int32_t read_ref(LineReader& r, std::string_view what) {
  return static_cast<std::int32_t>(
      r.read_int(what, std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max()));
}

void skip_tokens(LineReader& r, std::uint64_t n, std::string_view section) {
  for (std::uint64_t i = 0; i < n; ++i) r.token(section);
}

// Skips a section we do not use, or refuses it.
void skip_section(LineReader& r, std::string_view keyword) {
  const Keyword* k = find_keyword(keyword);
  const std::string name(keyword);
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
      std::string_view tok = r.token(name);
      // A quoted string may contain blanks: skip tokens up to the closing quote.
      if (tok.front() == '"') {
        while (tok.size() < 2 || tok.back() != '"') tok = r.token(name);
      }
      return;
    }
    case Kind::kSol: {
      const std::uint32_t n = read_count(r, name);
      const auto types = r.read_int(name + ": number of solutions", 1, 1000);
      std::uint64_t per_entry = 0;
      for (std::int64_t t = 0; t < types; ++t)
        per_entry += static_cast<std::uint64_t>(kSolComponents[static_cast<std::size_t>(r.read_int(name + ": type", 1, 4))]);
      skip_tokens(r, n * per_entry, name);
      return;
    }
    case Kind::kHighOrder:
      r.fail("section '" + name + "': second-order elements not supported");
  }
}

void read_dimension(LineReader& r) {
  const std::int64_t d = r.read_int("Dimension");
  if (d != 3) r.fail("Dimension " + std::to_string(d) + " is not supported (only 3D meshes)");
}

void read_version(LineReader& r) {
  const std::int64_t v = r.read_int("MeshVersionFormatted");
  if (v < 1 || v > 4) r.fail("MeshVersionFormatted " + std::to_string(v) + " is not supported (expected 1 to 4)");
}

// SolAtVertices or SolAtTetrahedra (keyword already read): appends one field per solution, named
// "<prefix><k>" ("sol0", ... for vertices, "cellsol0", ... for tets), k counting from the fields
// already there. `count`, when known, is the number of entities the section must have.
template <class Field>
void read_sol_section(LineReader& r, const std::string& keyword, std::optional<std::size_t> count, const char* entities,
                      const char* prefix, std::vector<Field>& fields) {
  const std::uint32_t n = read_count(r, keyword);
  if (count && n != *count) {
    r.fail(keyword + ": " + std::to_string(n) + " entries but the mesh has " + std::to_string(*count) + " " + entities);
  }
  const auto types = r.read_int(keyword + ": number of solutions", 1, 1000);
  const std::size_t first = fields.size();
  int per_entry = 0;
  for (std::int64_t t = 0; t < types; ++t) {
    const auto type = r.read_int(keyword + ": type (1 scalar, 2 vector, 3 symmetric tensor, 4 matrix)", 1, 4);
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

void read_sol_at_vertices(LineReader& r, std::optional<std::size_t> vertex_count, std::vector<VertexField>& fields) {
  read_sol_section(r, "SolAtVertices", vertex_count, "vertices", "sol", fields);
}

void read_sol_at_tets(LineReader& r, std::optional<std::size_t> tet_count, std::vector<CellField>& fields) {
  read_sol_section(r, "SolAtTetrahedra", tet_count, "tetrahedra", "cellsol", fields);
}

class MeditReader {
 public:
  MeditReader(const std::string& path, const ReadOptions& options, ReadNotes& notes)
      : r_(path), options_(options), notes_(notes) {
    r_.set_comment_char('#');
  }

  MeshData read() {
    for (;;) {
      const std::string_view tok = r_.next_token();
      if (tok.empty() || iequals(tok, "End")) break;
      if (!is_keyword_token(tok)) r_.fail("expected a section keyword, got '" + std::string(tok.substr(0, 40)) + "'");
      const std::string kw(tok);  // the view dies with the next read
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
    if (!have_vertices_) deferred_.push_back({std::string(name), r_.line()});
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
    const std::size_t hint = r_.reserve_hint(n, 8);
    m_.positions.reserve(hint);
    m_.vertex_refs.reserve(hint);
    for (std::uint32_t i = 0; i < n; ++i) {
      const double x = r_.read_double("Vertices coordinate");
      const double y = r_.read_double("Vertices coordinate");
      const double z = r_.read_double("Vertices coordinate");
      m_.positions.push_back({x, y, z});
      m_.vertex_refs.push_back(read_ref(r_, "Vertices reference"));
    }
    have_vertices_ = true;
    nv_ = n;
  }

  void read_tets() {
    begin_section("Tetrahedra", seen_tets_);
    const std::uint32_t n = read_count(r_, "Tetrahedra");
    const std::size_t hint = r_.reserve_hint(n, 10);
    m_.tets.reserve(hint);
    m_.tet_material.reserve(hint);
    for (std::uint32_t i = 0; i < n; ++i) {
      std::array<VertId, 4> t;
      for (VertId& v : t) v = read_vertex("Tetrahedra");
      m_.tets.push_back(t);
      m_.tet_material.push_back(read_ref(r_, "Tetrahedra reference"));
    }
  }

  void read_triangles() {
    begin_section("Triangles", seen_triangles_);
    const std::uint32_t n = read_count(r_, "Triangles");
    m_.triangles.reserve(r_.reserve_hint(n, 8));
    for (std::uint32_t i = 0; i < n; ++i) {
      Triangle t;
      for (VertId& v : t.v) v = read_vertex("Triangles");
      t.ref = read_ref(r_, "Triangles reference");
      m_.triangles.push_back(t);
    }
  }

  void read_edges() {
    begin_section("Edges", seen_edges_);
    const std::uint32_t n = read_count(r_, "Edges");
    m_.segments.reserve(r_.reserve_hint(n, 6));
    for (std::uint32_t i = 0; i < n; ++i) {
      Segment s;
      for (VertId& v : s.v) v = read_vertex("Edges");
      s.ref = read_ref(r_, "Edges reference");
      m_.segments.push_back(s);
    }
  }

  // TetGen's -g .mesh lists Corners by input point index, some beyond the mesh's vertices: an
  // out-of-range corner pins nothing, so it is left out and counted (ReadNotes), not refused.
  void read_vertex_list(std::vector<VertId>& out, std::string_view name) {
    const bool corners = name == "Corners";
    begin_section(name, corners ? seen_corners_ : seen_required_);
    const std::uint32_t n = read_count(r_, name);
    out.reserve(r_.reserve_hint(n, 2));
    for (std::uint32_t i = 0; i < n; ++i) {
      if (corners) {
        const std::int64_t v = r_.read_int(name);
        if (v < 1 || v > (have_vertices_ ? static_cast<std::int64_t>(nv_) : std::int64_t{kInvalid} - 1)) {
          ++notes_.dropped_corners;
          continue;
        }
        out.push_back(static_cast<VertId>(v - 1));
      } else {
        out.push_back(read_vertex(name));
      }
    }
  }

  void read_ridges() {
    if (seen_ridges_) r_.fail("duplicate section Ridges");
    seen_ridges_ = true;
    ridges_line_ = r_.line();
    const std::uint32_t n = read_count(r_, "Ridges");
    m_.ridges.reserve(r_.reserve_hint(n, 2));
    // Ridges index Edges; before Edges is read we can only bound them, and check them at the end.
    const std::int64_t hi = seen_edges_ ? static_cast<std::int64_t>(m_.segments.size()) : kInvalid - 1;
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::int64_t e = r_.read_int("Ridges");
      if (e < 1 || e > hi)
        r_.fail("Ridges: edge index " + std::to_string(e) + " out of range [1, " + std::to_string(hi) + "]");
      m_.ridges.push_back(static_cast<std::uint32_t>(e - 1));
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

  LineReader r_;
  const ReadOptions& options_;
  ReadNotes& notes_;
  MeshData m_;
  bool have_vertices_ = false;
  std::size_t nv_ = 0;
  bool seen_tets_ = false, seen_triangles_ = false, seen_edges_ = false;
  bool seen_corners_ = false, seen_required_ = false, seen_ridges_ = false;
  std::size_t ridges_line_ = 0;
  std::vector<std::pair<std::string, std::size_t>> deferred_;  // section, line
};

void read_sol_file(const std::string& path, const MeshData& mesh, std::vector<VertexField>& fields,
                   std::vector<CellField>& cell_fields) {
  LineReader r(path);
  r.set_comment_char('#');
  for (;;) {
    const std::string_view tok = r.next_token();
    if (tok.empty() || iequals(tok, "End")) break;
    if (!is_keyword_token(tok)) r.fail("expected a section keyword, got '" + std::string(tok.substr(0, 40)) + "'");
    const std::string kw(tok);
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

// A SolAt... section of `fields` (count entries); `where` names the file in errors.
template <class Field>
void put_sol_section(AtomicFile& sol, const char* keyword, std::size_t count, const std::vector<Field>& fields) {
  if (fields.empty()) return;
  sol.put(keyword);
  sol.put('\n');
  sol.put_int(count);
  sol.put('\n');
  sol.put_int(fields.size());
  for (const Field& f : fields) {
    const auto type = std::find(kSolComponents.begin() + 1, kSolComponents.end(), f.components);
    if (type == kSolComponents.end()) {
      throw InputError(sol.path() + ": cannot write field '" + f.name + "' with " + std::to_string(f.components) +
                       " components (.sol supports 1, 3, 6 or 9)");
    }
    sol.put(' ');
    sol.put_int(type - kSolComponents.begin());
  }
  sol.put("\n\n");
  for (std::size_t i = 0; i < count; ++i) {
    bool first = true;
    for (const Field& f : fields) {
      const std::size_t c = static_cast<std::size_t>(f.components);
      for (std::size_t k = 0; k < c; ++k) {
        if (!first) sol.put(' ');
        first = false;
        sol.put_double(f.values[i * c + k]);
      }
    }
    sol.put('\n');
  }
  sol.put("\n");
}

void put_vertex_ids(AtomicFile& out, const VertId* v, int n) {
  for (int k = 0; k < n; ++k) {
    out.put_int(std::uint64_t{v[k]} + 1);
    out.put(' ');
  }
}

}  // namespace

MeshData read_medit(const std::string& path, const ReadOptions& options, ReadNotes& notes) {
  MeshData mesh = MeditReader(path, options, notes).read();
  if (path == "-") return mesh;  // stdin has no folder with a .sol beside it
  bool gz = false;
  const std::string stem = mesh_stem(path, gz);
  // The .sol beside the mesh: prefer the same compression as the mesh, accept the other.
  const std::string candidates[2] = {stem + (gz ? ".sol.gz" : ".sol"), stem + (gz ? ".sol" : ".sol.gz")};
  std::error_code ec;
  for (const std::string& sol : candidates) {
    if (!std::filesystem::is_regular_file(sol, ec)) continue;
    const std::size_t first = mesh.fields.size(), first_cell = mesh.cell_fields.size();
    read_sol_file(sol, mesh, mesh.fields, mesh.cell_fields);
    const std::string names_path = stem + ".sol.fields.txt";
    if (std::filesystem::is_regular_file(names_path, ec)) {
      SolNames names = read_field_names(names_path);
      // A file of names that knows no SolAtTetrahedra line names the vertex columns only.
      if (names.vertex.size() != mesh.fields.size() - first ||
          (!names.cell.empty() && names.cell.size() != mesh.cell_fields.size() - first_cell)) {
        throw InputError(names_path + ": " + std::to_string(names.vertex.size()) + " + " + std::to_string(names.cell.size()) +
                         " names for the " + std::to_string(mesh.fields.size() - first) + " SolAtVertices + " +
                         std::to_string(mesh.cell_fields.size() - first_cell) + " SolAtTetrahedra solutions of " + sol);
      }
      for (std::size_t i = 0; i < names.vertex.size(); ++i) mesh.fields[first + i].name = names.vertex[i];
      for (std::size_t i = 0; i < names.cell.size(); ++i) {
        CellField& f = mesh.cell_fields[first_cell + i];
        f.name = names.cell[i];
        if (f.name.size() > kCategoricalSuffix.size() && f.name.ends_with(kCategoricalSuffix)) {
          f.name.resize(f.name.size() - kCategoricalSuffix.size());
          f.kind = CellFieldKind::kCategorical;
        }
      }
    }
    break;
  }
  return mesh;
}

void write_medit(const std::string& path, const MeshData& m) {
  // A stream or device has no folder for the companion .sol: fields cannot go with it.
  const bool direct = is_direct_output(path);
  if (direct && (!m.fields.empty() || !m.cell_fields.empty()))
    throw InputError(path + ": cannot write the fields' .sol beside a stream or device (write .msh, which keeps "
                     "fields inline, or a regular file)");
  AtomicFile out(path);
  out.put("MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n");
  out.put_int(m.positions.size());
  out.put('\n');
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const std::array<double, 3>& p = m.positions[i];
    out.put_double(p[0]);
    out.put(' ');
    out.put_double(p[1]);
    out.put(' ');
    out.put_double(p[2]);
    out.put(' ');
    out.put_int(m.vertex_refs.empty() ? 0 : m.vertex_refs[i]);
    out.put('\n');
  }
  if (!m.tets.empty()) {
    out.put("\nTetrahedra\n");
    out.put_int(m.tets.size());
    out.put('\n');
    for (std::size_t i = 0; i < m.tets.size(); ++i) {
      put_vertex_ids(out, m.tets[i].data(), 4);
      out.put_int(m.tet_material.empty() ? 0 : m.tet_material[i]);
      out.put('\n');
    }
  }
  if (!m.triangles.empty()) {
    out.put("\nTriangles\n");
    out.put_int(m.triangles.size());
    out.put('\n');
    for (const Triangle& t : m.triangles) {
      put_vertex_ids(out, t.v.data(), 3);
      out.put_int(t.ref);
      out.put('\n');
    }
  }
  if (!m.segments.empty()) {
    out.put("\nEdges\n");
    out.put_int(m.segments.size());
    out.put('\n');
    for (const Segment& s : m.segments) {
      put_vertex_ids(out, s.v.data(), 2);
      out.put_int(s.ref);
      out.put('\n');
    }
  }
  const auto put_list = [&](const char* name, const std::vector<std::uint32_t>& list) {
    if (list.empty()) return;
    out.put("\n");
    out.put(name);
    out.put('\n');
    out.put_int(list.size());
    out.put('\n');
    for (std::uint32_t x : list) {
      out.put_int(std::uint64_t{x} + 1);
      out.put('\n');
    }
  };
  put_list("Ridges", m.ridges);
  put_list("Corners", m.corners);
  put_list("RequiredVertices", m.required_vertices);
  out.put("\nEnd\n");

  bool gz = false;
  const std::string stem = mesh_stem(path, gz);
  const std::string sol_path = stem + ".sol", names_path = stem + ".sol.fields.txt";
  // The companion files of <stem>.mesh are replaced with it: whatever this write does not produce
  // is removed afterwards, or the next read would attach a stale .sol to the new mesh.
  const auto remove_stale = [&](std::initializer_list<std::string> paths) {
    std::error_code ec;
    for (const std::string& p : paths) std::filesystem::remove(p, ec);
  };
  if (m.fields.empty() && m.cell_fields.empty()) {
    out.commit();
    if (!direct) remove_stale({sol_path, stem + ".sol.gz", names_path});
    return;
  }
  AtomicFile sol(sol_path);
  sol.put("MeshVersionFormatted 2\n\nDimension 3\n\n");
  put_sol_section(sol, "SolAtVertices", m.positions.size(), m.fields);
  put_sol_section(sol, "SolAtTetrahedra", m.tets.size(), m.cell_fields);
  sol.put("End\n");
  // Names go to <stem>.sol.fields.txt, unless they are the defaults a reader would give anyway.
  if (default_field_names(m)) {
    commit_all({&sol, &out});
    remove_stale({stem + ".sol.gz", names_path});
    return;
  }
  AtomicFile names(names_path);
  names.put(fields_file_text(m));
  commit_all({&sol, &names, &out});
  remove_stale({stem + ".sol.gz"});
}

}  // namespace topotet::io
