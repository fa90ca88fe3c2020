// A small MEDIT ASCII (.mesh) reader and writer for the CGAL benchmark programs (bench/cgal/).
// Kept apart from topotet's io library on purpose: these programs link CGAL alone, so that they
// build in a minute and measure CGAL, not topotet. Read and written: Vertices, Tetrahedra,
// Triangles and Edges (with their refs), Ridges, Corners and RequiredVertices; the other sections
// of the format are skipped and counted (normals, tangents, other cells).
// Gzip'd files and other formats: convert them first (`topotet convert IN OUT.mesh`).
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace cgal_bench {

struct MeditMesh {
  std::vector<std::array<double, 3>> positions;
  std::vector<std::array<std::uint32_t, 4>> tets;  // 0-based
  std::vector<int> tet_ref;
  std::vector<std::array<std::uint32_t, 3>> triangles;  // 0-based
  std::vector<int> triangle_ref;
  std::vector<std::array<std::uint32_t, 2>> edges;  // 0-based
  std::vector<int> edge_ref;
  std::vector<std::uint32_t> ridges;            // 0-based indices into edges
  std::vector<std::uint32_t> corners;           // 0-based vertices
  std::vector<std::uint32_t> required_vertices; // 0-based vertices
  std::size_t skipped_entries = 0;  // entries of the sections this reader does not keep
};

namespace detail {

// Numbers of values per entry of the MEDIT sections this reader skips (dimension 3).
inline int skipped_section_width(const std::string& keyword) {
  static const std::pair<const char*, int> widths[] = {
      {"Quadrilaterals", 5},   {"Hexahedra", 9},          {"Prisms", 7},
      {"Pyramids", 6},       {"RequiredEdges", 1},  {"RequiredTriangles", 1}, {"Normals", 3},          {"NormalAtVertices", 2},
      {"Tangents", 3},       {"TangentAtVertices", 2}, {"TangentAtEdges", 3},    {"NormalAtTriangleVertices", 3},
      {"RequiredQuadrilaterals", 1}, {"RequiredTetrahedra", 1},
  };
  for (const auto& [name, width] : widths)
    if (keyword == name) return width;
  return -1;
}

}  // namespace detail

inline MeditMesh read_medit(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  if (path.size() > 3 && path.compare(path.size() - 3, 3, ".gz") == 0)
    throw std::runtime_error(path + ": gzip'd input; convert it first (topotet convert IN OUT.mesh)");
  // Tokens, comments (#...) removed.
  std::vector<std::string> tokens;
  {
    std::string line;
    while (std::getline(in, line)) {
      const auto hash = line.find('#');
      if (hash != std::string::npos) line.resize(hash);
      std::istringstream words(line);
      std::string w;
      while (words >> w) tokens.push_back(w);
    }
  }
  std::size_t at = 0;
  const auto next = [&](const char* what) -> const std::string& {
    if (at >= tokens.size()) throw std::runtime_error(path + ": file ends inside " + std::string(what));
    return tokens[at++];
  };
  const auto next_long = [&](const char* what) -> long long {
    const std::string& t = next(what);
    try {
      std::size_t used = 0;
      const long long v = std::stoll(t, &used);
      if (used != t.size()) throw std::invalid_argument(t);
      return v;
    } catch (const std::exception&) {
      throw std::runtime_error(path + ": '" + t + "' is not an integer (in " + what + ")");
    }
  };
  const auto next_double = [&](const char* what) -> double {
    const std::string& t = next(what);
    try {
      return std::stod(t);
    } catch (const std::exception&) {
      throw std::runtime_error(path + ": '" + t + "' is not a number (in " + what + ")");
    }
  };
  const auto count_of = [&](const char* what) -> std::size_t {
    const long long n = next_long(what);
    if (n < 0) throw std::runtime_error(path + ": negative count in " + std::string(what));
    return static_cast<std::size_t>(n);
  };
  MeditMesh m;
  std::size_t nv = 0;
  const auto vertex_index = [&](const char* what) -> std::uint32_t {
    const long long i = next_long(what);
    if (i < 1 || static_cast<std::size_t>(i) > nv)
      throw std::runtime_error(path + ": vertex index " + std::to_string(i) + " out of range in " + what);
    return static_cast<std::uint32_t>(i - 1);
  };
  bool seen_version = false;
  while (at < tokens.size()) {
    const std::string keyword = tokens[at++];
    if (keyword == "MeshVersionFormatted") {
      next_long("MeshVersionFormatted");
      seen_version = true;
    } else if (keyword == "Dimension") {
      if (next_long("Dimension") != 3) throw std::runtime_error(path + ": only Dimension 3 is read");
    } else if (keyword == "Vertices") {
      nv = count_of("Vertices");
      m.positions.resize(nv);
      for (auto& p : m.positions) {
        for (double& c : p) c = next_double("Vertices");
        next_long("Vertices");
      }
    } else if (keyword == "Tetrahedra") {
      const std::size_t n = count_of("Tetrahedra");
      m.tets.resize(n);
      m.tet_ref.resize(n);
      for (std::size_t t = 0; t < n; ++t) {
        for (auto& v : m.tets[t]) v = vertex_index("Tetrahedra");
        m.tet_ref[t] = static_cast<int>(next_long("Tetrahedra"));
      }
    } else if (keyword == "Triangles") {
      const std::size_t n = count_of("Triangles");
      m.triangles.resize(n);
      m.triangle_ref.resize(n);
      for (std::size_t t = 0; t < n; ++t) {
        for (auto& v : m.triangles[t]) v = vertex_index("Triangles");
        m.triangle_ref[t] = static_cast<int>(next_long("Triangles"));
      }
    } else if (keyword == "Edges") {
      const std::size_t n = count_of("Edges");
      m.edges.resize(n);
      m.edge_ref.resize(n);
      for (std::size_t t = 0; t < n; ++t) {
        for (auto& v : m.edges[t]) v = vertex_index("Edges");
        m.edge_ref[t] = static_cast<int>(next_long("Edges"));
      }
    } else if (keyword == "Corners" || keyword == "RequiredVertices") {
      auto& list = keyword == "Corners" ? m.corners : m.required_vertices;
      const std::size_t n = count_of(keyword.c_str());
      for (std::size_t t = 0; t < n; ++t) list.push_back(vertex_index(keyword.c_str()));
    } else if (keyword == "Ridges") {
      const std::size_t n = count_of("Ridges");
      for (std::size_t t = 0; t < n; ++t) {
        const long long e = next_long("Ridges");
        if (e < 1 || static_cast<std::size_t>(e) > m.edges.size())
          throw std::runtime_error(path + ": Ridges: edge " + std::to_string(e) + " out of range (Edges must come first)");
        m.ridges.push_back(static_cast<std::uint32_t>(e - 1));
      }
    } else if (keyword == "End") {
      break;
    } else {
      const int width = detail::skipped_section_width(keyword);
      if (width < 0) throw std::runtime_error(path + ": unknown MEDIT keyword '" + keyword + "'");
      const std::size_t n = count_of(keyword.c_str());
      for (std::size_t i = 0; i < n * static_cast<std::size_t>(width); ++i) next(keyword.c_str());
      m.skipped_entries += n;
    }
  }
  if (!seen_version) throw std::runtime_error(path + ": not a MEDIT file (no MeshVersionFormatted)");
  if (m.tets.empty()) throw std::runtime_error(path + ": no Tetrahedra");
  return m;
}

// Writes `m` (0-based) as MEDIT ASCII version 2 (full double precision), through a temporary file
// renamed over `path`.
inline void write_medit(const std::string& path, const MeditMesh& m) {
  const std::string tmp = path + ".part";
  std::FILE* f = std::fopen(tmp.c_str(), "w");
  if (!f) throw std::runtime_error(path + ": cannot write");
  std::fprintf(f, "MeshVersionFormatted 2\nDimension 3\nVertices\n%zu\n", m.positions.size());
  for (const auto& p : m.positions) std::fprintf(f, "%.17g %.17g %.17g 0\n", p[0], p[1], p[2]);
  std::fprintf(f, "Tetrahedra\n%zu\n", m.tets.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    std::fprintf(f, "%u %u %u %u %d\n", m.tets[t][0] + 1, m.tets[t][1] + 1, m.tets[t][2] + 1, m.tets[t][3] + 1,
                 m.tet_ref[t]);
  if (!m.triangles.empty()) {
    std::fprintf(f, "Triangles\n%zu\n", m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
      std::fprintf(f, "%u %u %u %d\n", m.triangles[t][0] + 1, m.triangles[t][1] + 1, m.triangles[t][2] + 1,
                   m.triangle_ref[t]);
  }
  if (!m.edges.empty()) {
    std::fprintf(f, "Edges\n%zu\n", m.edges.size());
    for (std::size_t t = 0; t < m.edges.size(); ++t)
      std::fprintf(f, "%u %u %d\n", m.edges[t][0] + 1, m.edges[t][1] + 1, m.edge_ref[t]);
  }
  if (!m.ridges.empty()) {
    std::fprintf(f, "Ridges\n%zu\n", m.ridges.size());
    for (std::uint32_t e : m.ridges) std::fprintf(f, "%u\n", e + 1);
  }
  if (!m.corners.empty()) {
    std::fprintf(f, "Corners\n%zu\n", m.corners.size());
    for (std::uint32_t v : m.corners) std::fprintf(f, "%u\n", v + 1);
  }
  if (!m.required_vertices.empty()) {
    std::fprintf(f, "RequiredVertices\n%zu\n", m.required_vertices.size());
    for (std::uint32_t v : m.required_vertices) std::fprintf(f, "%u\n", v + 1);
  }
  std::fprintf(f, "End\n");
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": write failed");
  }
}

}  // namespace cgal_bench
