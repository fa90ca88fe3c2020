// TetGen output files, read as one mesh: <stem>.node and <stem>.ele (required), <stem>.face and
// <stem>.edge (when present). The path may name any of the four (e.g. "box.1.ele").
//
//   .node  header: count, dimension (3), attribute count, marker flag (0/1)
//          rows:   index x y z [attributes] [marker]          -> positions, marker = vertex ref
//   .ele   header: count, nodes per tet (4), attribute count  -> tets; the first attribute (the
//          region attribute of -A) is the material, which must be an integer; none = material 0
//   .face  header: count, marker flag                         -> triangles with a nonzero marker
//   .edge  header: count, marker flag                         -> segments with a nonzero marker
//
// Indices start at the first .node row's index (0 or 1, TetGen's -z) in every file. Faces and
// edges with marker 0 (TetGen's "no marker") or without markers are not listed: they carry no
// ref, and the boundary is derived from the tets anyway. Extra columns (the adjacent tets of -nn)
// are ignored. '#' starts a comment. Second-order tets (10 nodes, -o2) are refused.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>

#include "io/formats.h"
#include "io/line_reader.h"
#include "topotet/error.h"

namespace topotet::io {
namespace {

constexpr std::string_view kExtensions[] = {".node", ".ele", ".face", ".edge"};

std::string tetgen_stem(const std::string& path) {
  for (std::string_view ext : kExtensions)
    if (iends_with(path, ext)) return path.substr(0, path.size() - ext.size());
  throw InputError(path + ": not a TetGen file (expected .node, .ele, .face or .edge)");
}

class TetgenReader {
 public:
  explicit TetgenReader(std::string stem) : stem_(std::move(stem)) {}

  MeshData read() {
    read_node();
    read_ele();
    std::error_code ec;
    if (std::filesystem::is_regular_file(stem_ + ".face", ec)) read_face();
    if (std::filesystem::is_regular_file(stem_ + ".edge", ec)) read_edge();
    if (std::all_of(m_.vertex_refs.begin(), m_.vertex_refs.end(), [](std::int32_t x) { return x == 0; }))
      m_.vertex_refs.clear();
    return std::move(m_);
  }

 private:
  static std::uint32_t count(LineReader& r, std::string_view what) {
    return static_cast<std::uint32_t>(r.read_int(what, 0, std::int64_t{kInvalid} - 1));
  }

  VertId vertex(LineReader& r, std::string_view what) {
    const std::int64_t i = r.read_int(what);
    const std::int64_t n = static_cast<std::int64_t>(m_.positions.size());
    if (i < base_ || i >= base_ + n)
      r.fail(std::string(what) + ": node index " + std::to_string(i) + " out of range [" + std::to_string(base_) +
             ", " + std::to_string(base_ + n - 1) + "]");
    return static_cast<VertId>(i - base_);
  }

  static std::int32_t integer_attribute(LineReader& r, std::string_view what) {
    const double x = r.read_double(what);
    if (x != std::floor(x) || x < std::numeric_limits<std::int32_t>::min() || x > std::numeric_limits<std::int32_t>::max())
      r.fail(std::string(what) + ": " + std::to_string(x) + " is not an integer (materials are integers)");
    return static_cast<std::int32_t>(x);
  }

  void read_node() {
    LineReader r(stem_ + ".node");
    r.set_comment_char('#');
    const std::uint32_t n = count(r, ".node count");
    if (r.read_int(".node dimension") != 3) r.fail(".node: only 3D meshes are supported");
    const std::int64_t attributes = r.read_int(".node attribute count", 0, 1000);
    const bool markers = r.read_int(".node marker flag", 0, 1) == 1;
    m_.positions.reserve(r.reserve_hint(n, 8));
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::int64_t index = r.read_int(".node index");
      if (i == 0) {
        if (index != 0 && index != 1) r.fail(".node: the first index is " + std::to_string(index) + ", not 0 or 1");
        base_ = index;
      }
      if (index != base_ + i)
        r.fail(".node: index " + std::to_string(index) + " where " + std::to_string(base_ + i) + " was expected");
      std::array<double, 3> p;
      for (double& x : p) x = r.read_double(".node coordinate");
      m_.positions.push_back(p);
      for (std::int64_t a = 0; a < attributes; ++a) r.read_double(".node attribute");
      m_.vertex_refs.push_back(markers ? static_cast<std::int32_t>(r.read_int(".node marker", std::numeric_limits<std::int32_t>::min(),
                                                                              std::numeric_limits<std::int32_t>::max()))
                                       : 0);
      r.skip_rest_of_line();
    }
  }

  void read_ele() {
    LineReader r(stem_ + ".ele");
    r.set_comment_char('#');
    const std::uint32_t n = count(r, ".ele count");
    const std::int64_t nodes = r.read_int(".ele nodes per tetrahedron");
    if (nodes == 10) r.fail(".ele: second-order (10-node) tetrahedra are not supported");
    if (nodes != 4) r.fail(".ele: " + std::to_string(nodes) + " nodes per tetrahedron (expected 4)");
    const std::int64_t attributes = r.read_int(".ele attribute count", 0, 1000);
    m_.tets.reserve(r.reserve_hint(n, 10));
    m_.tet_material.reserve(r.reserve_hint(n, 10));
    for (std::uint32_t i = 0; i < n; ++i) {
      r.read_int(".ele index");
      std::array<VertId, 4> t;
      for (VertId& v : t) v = vertex(r, ".ele");
      m_.tets.push_back(t);
      std::int32_t material = 0;
      for (std::int64_t a = 0; a < attributes; ++a) {
        if (a == 0) {
          material = integer_attribute(r, ".ele region attribute");
        } else {
          r.read_double(".ele attribute");
        }
      }
      m_.tet_material.push_back(material);
      r.skip_rest_of_line();
    }
  }

  void read_face() {
    LineReader r(stem_ + ".face");
    r.set_comment_char('#');
    const std::uint32_t n = count(r, ".face count");
    const bool markers = r.read_int(".face marker flag", 0, 1) == 1;
    for (std::uint32_t i = 0; i < n; ++i) {
      r.read_int(".face index");
      Triangle t;
      for (VertId& v : t.v) v = vertex(r, ".face");
      t.ref = markers ? static_cast<std::int32_t>(r.read_int(".face marker", std::numeric_limits<std::int32_t>::min(),
                                                             std::numeric_limits<std::int32_t>::max()))
                      : 0;
      if (t.ref != 0) m_.triangles.push_back(t);
      r.skip_rest_of_line();
    }
  }

  void read_edge() {
    LineReader r(stem_ + ".edge");
    r.set_comment_char('#');
    const std::uint32_t n = count(r, ".edge count");
    const bool markers = r.read_int(".edge marker flag", 0, 1) == 1;
    for (std::uint32_t i = 0; i < n; ++i) {
      r.read_int(".edge index");
      Segment s;
      for (VertId& v : s.v) v = vertex(r, ".edge");
      s.ref = markers ? static_cast<std::int32_t>(r.read_int(".edge marker", std::numeric_limits<std::int32_t>::min(),
                                                             std::numeric_limits<std::int32_t>::max()))
                      : 0;
      if (s.ref != 0) m_.segments.push_back(s);
      r.skip_rest_of_line();
    }
  }

  std::string stem_;
  std::int64_t base_ = 1;
  MeshData m_;
};

}  // namespace

bool is_tetgen_path(std::string_view path) {
  for (std::string_view ext : kExtensions)
    if (iends_with(path, ext)) return true;
  return false;
}

MeshData read_tetgen(const std::string& path) { return TetgenReader(tetgen_stem(path)).read(); }

}  // namespace topotet::io
