// Gmsh .msh: reads MSH 4.1 and 2.x, ASCII and binary; writes MSH 4.1 (ASCII or binary).
//
// Refs. A 3D element's material is the first physical tag of its entity (4.1) or its physical
// tag (2.x), else the entity (elementary) tag; triangles and lines get their ref the same way;
// point elements (type 15) become corners. Nodes are renumbered 0..n-1 in file order (tags may
// be sparse). $NodeData with 1..9 components become VertexFields (last time step wins when a
// view repeats); $ElementData on the tets become CellFields (reals: kind intensive), written back
// with the tags the tets get in the file (a tag of another element is an error; with tets_only,
// the values of the left-out volume elements go with them). Higher-order elements are refused; hexahedra, prisms and pyramids are refused
// unless ReadOptions::tets_only (then left out and counted); quads are left out and counted;
// unknown sections are skipped.
//
// An entity in several physical groups: a volume's material is its first group; a line or
// triangle is listed once per group (each ref comes back out on it; see SharedRefs in
// tet_mesh.h). MSH 2.x writes an element once per physical group of its entity: such copies
// (same nodes, same elementary entity) are read as that, once per distinct group.
//
// Round trip conventions of write_gmsh (MeshData has more than plain Gmsh can say). All are
// physical-group names, so other tools just see ordinary named groups:
//  - "topotet:ref=<r>": a ref r <= 0 (Gmsh physical tags are positive); refs > 0 are the tags;
//  - "topotet:corners" (dim 0): point elements that are corners (any other point group too);
//  - "topotet:required_vertices" (dim 0): point elements that are required vertices; a vertex
//    that is both has two point entities, one in each group;
//  - "topotet:ridges" (dim 1): a second physical group on the curves holding ridge segments;
//  - $NodeData "topotet:vertex_ref": MEDIT vertex refs (written only when some are nonzero);
//  - a symmetric-tensor field (6 components) is written as a full 3x3 tensor (9, as Gmsh
//    wants) and a 9-component field that is exactly symmetric everywhere reads back as 6.
// $PhysicalNames: user names of groups (MeshData::group_names) are read and written back.
// Elements are written one block per entity (entities numbered in order of first use; within an
// entity, element order kept): a MeshData whose elements of each dimension are grouped that way,
// as every reader's output is, reads back identical; others come back with their elements
// regrouped by ref. write_gmsh can also write MSH 2.2 ASCII (WriteOptions::msh22) with the same
// groups: one element line per physical group of its entity, as Gmsh writes it.
#include <algorithm>
#include <array>
#include <charconv>
#include <limits>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>

#include <glm/common.hpp>

#include "mesh/glm_convert.h"
#include "io/atomic_file.h"
#include "io/formats.h"
#include "io/line_reader.h"
#include "topotet/error.h"
#include "topotet/mesh_stream.h"

namespace topotet::io {
namespace {

constexpr std::string_view kRefPrefix = "topotet:ref=";
constexpr std::string_view kCornersName = "topotet:corners";
constexpr std::string_view kRequiredName = "topotet:required_vertices";
constexpr std::string_view kRidgesName = "topotet:ridges";

constexpr int kLine = 1, kTriangle = 2, kTet = 4, kPoint = 15;

struct ElementType {
  int nodes = 0;  // 0: unknown type
  int order = 1;
  const char* name = "";
};

ElementType element_type(std::int64_t type) {
  switch (type) {
    case 1: return {2, 1, "2-node line"};
    case 2: return {3, 1, "3-node triangle"};
    case 3: return {4, 1, "4-node quadrangle"};
    case 4: return {4, 1, "4-node tetrahedron"};
    case 5: return {8, 1, "8-node hexahedron"};
    case 6: return {6, 1, "6-node prism"};
    case 7: return {5, 1, "5-node pyramid"};
    case 8: return {3, 2, "3-node line"};
    case 9: return {6, 2, "6-node triangle"};
    case 10: return {9, 2, "9-node quadrangle"};
    case 11: return {10, 2, "10-node tetrahedron"};
    case 12: return {27, 2, "27-node hexahedron"};
    case 13: return {18, 2, "18-node prism"};
    case 14: return {14, 2, "14-node pyramid"};
    case 15: return {1, 1, "point"};
    case 16: return {8, 2, "8-node quadrangle"};
    case 17: return {20, 2, "20-node hexahedron"};
    case 18: return {15, 2, "15-node prism"};
    case 19: return {13, 2, "13-node pyramid"};
    case 20: return {9, 3, "9-node triangle"};
    case 21: return {10, 3, "10-node triangle"};
    case 22: return {12, 4, "12-node triangle"};
    case 23: return {15, 4, "15-node triangle"};
    case 24: return {15, 5, "15-node triangle"};
    case 25: return {21, 5, "21-node triangle"};
    case 26: return {4, 3, "4-node line"};
    case 27: return {5, 4, "5-node line"};
    case 28: return {6, 5, "6-node line"};
    case 29: return {20, 3, "20-node tetrahedron"};
    case 30: return {35, 4, "35-node tetrahedron"};
    case 31: return {56, 5, "56-node tetrahedron"};
    case 92: return {64, 3, "64-node hexahedron"};
    case 93: return {125, 4, "125-node hexahedron"};
    default: return {};
  }
}

int element_dim(std::int64_t type) {
  switch (type) {
    case kPoint: return 0;
    case kLine: return 1;
    case kTriangle: return 2;
    default: return 3;
  }
}

// Node tag -> 0-based index. Dense while tags are reasonably compact (the usual 1..n), a hash
// map otherwise, so a file with a few huge tags cannot make us allocate gigabytes.
class NodeMap {
 public:
  // What the map will hold for `count` nodes with tags up to `max_tag` (the $Nodes header), for a
  // streaming reader's memory budget: dense, 4 bytes a tag up to the largest; sparse, a hash node
  // (key, value, link, the allocator's header) and a bucket per node.
  static std::uint64_t planned_bytes(std::uint64_t count, std::uint64_t max_tag) {
    return dense_fits(count, max_tag) ? 4 * (max_tag + 1) : kSparseBytesPerNode * count;
  }
  // Allocates that at once, once the counts were checked against a limit.
  void reserve(std::uint64_t count, std::uint64_t max_tag) {
    if (count_ != 0) return;
    if (dense_fits(count, max_tag)) {
      dense_.assign(static_cast<std::size_t>(max_tag + 1), kInvalid);
    } else {
      sparse_mode_ = true;
      sparse_.reserve(static_cast<std::size_t>(count));
    }
  }

  // False if the tag is already present.
  bool insert(std::uint64_t tag, VertId index) {
    if (!sparse_mode_) {
      if (tag < dense_.size()) {
        if (dense_[tag] != kInvalid) return false;
        dense_[tag] = index;
        ++count_;
        return true;
      }
      if (dense_fits(count_, tag)) {
        dense_.resize(static_cast<std::size_t>(std::min<std::uint64_t>(std::max<std::uint64_t>(tag + 1, 2 * dense_.size()), dense_limit(count_))),
                      kInvalid);
        dense_[tag] = index;
        ++count_;
        return true;
      }
      sparse_mode_ = true;
      for (std::size_t t = 0; t < dense_.size(); ++t)
        if (dense_[t] != kInvalid) sparse_.emplace(t, dense_[t]);
      dense_.clear();
      dense_.shrink_to_fit();
    }
    ++count_;
    return sparse_.emplace(tag, index).second;
  }
  VertId find(std::uint64_t tag) const {
    if (!sparse_mode_) return tag < dense_.size() ? dense_[tag] : kInvalid;
    const auto it = sparse_.find(tag);
    return it == sparse_.end() ? kInvalid : it->second;
  }

 private:
  static constexpr std::uint64_t kSparseBytesPerNode = 48;
  // Dense up to 16 slots a node (and a first 2^20): beyond, a hash map.
  static std::uint64_t dense_limit(std::uint64_t count) { return 16 * count + (std::uint64_t{1} << 20); }
  static bool dense_fits(std::uint64_t count, std::uint64_t tag) { return tag < dense_limit(count); }

  std::vector<VertId> dense_;
  std::unordered_map<std::uint64_t, VertId> sparse_;
  bool sparse_mode_ = false;
  std::uint64_t count_ = 0;
};

// A run of consecutive elements of one dimension that share their entity (and, in 2.x, their
// physical tag): refs are resolved per run once every section has been read.
struct Run {
  int dim;
  int entity;    // 4.1 entity tag, or 2.x elementary tag
  int physical;  // 2.x physical tag (0 = none); unused in 4.1
  std::size_t begin, end;
};

// A partitioned entity ($PartitionedEntities): the piece of model entity parent_tag.
struct Piece {
  int parent_dim = 0, parent_tag = 0;
  int partition = 0;  // the first of its partition tags
  std::vector<int> physicals;
};

struct Resolved {
  std::int32_t ref = 0;
  std::vector<std::int32_t> more_refs;  // further physical groups (lines, triangles: one copy each)
  bool has_ref = false;                 // false: only flag groups (ridges, required vertices) or none
  bool ridge = false, corner = false, required = false;
};

std::string unquote(std::string_view s) {
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return std::string(s);
}

class GmshReader {
 public:
  // With a visitor (stream_gmsh): nodes and tets go to it as they are read, never held; the
  // lines, triangles and points (surfaces: they grow like the boundary) are held, their refs
  // resolved, and given to it at the end; $NodeData and $ElementData views go to it as they are
  // read (if it takes them). MSH 4.1 only.
  GmshReader(const std::string& path, const ReadOptions& options, ReadNotes& notes, MeditVisitor* visitor = nullptr)
      : r_(path), options_(options), notes_(notes), visitor_(visitor) {}

  MeshData read() {
    parse();
    return std::move(m_);
  }

  void stream() {
    parse();
    visitor_->begin_triangles(m_.triangles.size());
    for (const Triangle& t : m_.triangles) visitor_->triangle(t);
    visitor_->begin_segments(m_.segments.size());
    for (const Segment& s : m_.segments) visitor_->segment(s);
    for (VertId v : m_.corners) visitor_->corner(v);
    for (VertId v : m_.required_vertices) visitor_->required_vertex(v);
    for (std::uint32_t s : m_.ridges) visitor_->ridge(s);
  }

 private:
  void parse() {
    read_format();
    for (;;) {
      const std::string_view tok = r_.next_token();
      if (tok.empty()) break;
      if (tok[0] != '$') r_.fail("expected a $Section, got '" + std::string(tok.substr(0, 40)) + "'");
      const std::string name(tok.substr(1));
      if (name == "PhysicalNames") {
        read_physical_names();
      } else if (name == "Entities" && v41_) {
        read_entities();
      } else if (name == "PartitionedEntities" && v41_) {
        read_partitioned_entities();
      } else if (name == "Nodes") {
        if (seen_nodes_) r_.fail("duplicate $Nodes section");
        v41_ ? read_nodes41() : read_nodes22();
        seen_nodes_ = true;
      } else if (name == "Elements") {
        if (!seen_nodes_) r_.fail("$Elements before $Nodes");
        if (seen_elements_) r_.fail("duplicate $Elements section");
        v41_ ? read_elements41() : read_elements22();
        seen_elements_ = true;
      } else if (name == "NodeData") {
        if (!seen_nodes_) r_.fail("$NodeData before $Nodes");
        read_node_data();
      } else if (name == "ElementData") {
        if (!seen_elements_) r_.fail("$ElementData before $Elements");
        read_element_data();
      } else if (name == "MeshFormat") {
        r_.fail("duplicate $MeshFormat section");
      } else {
        skip_section(name);
      }
    }
    resolve();
  }

  // ---- primitives: the same grammar in ASCII tokens or binary words ----
  std::int32_t int32(std::string_view what) {
    if (binary_) return r_.read_i32(what);
    return static_cast<std::int32_t>(
        r_.read_int(what, std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max()));
  }
  std::uint64_t size(std::string_view what) {  // size_t words of MSH 4.1 binary
    if (binary_) return r_.read_u64(what);
    return static_cast<std::uint64_t>(r_.read_int(what, 0, std::numeric_limits<std::int64_t>::max()));
  }
  double real(std::string_view what) { return binary_ ? r_.read_f64(what) : r_.read_double(what); }
  double bbox_real(std::string_view what) {
    if (!binary_) return r_.read_double_any(what);
    double v;
    r_.read_bytes(&v, sizeof v, what);
    return v;
  }
  std::uint64_t node_tag(std::string_view what) {
    if (!binary_) return static_cast<std::uint64_t>(r_.read_int(what, 1, std::numeric_limits<std::int64_t>::max()));
    const std::uint64_t t = v41_ ? r_.read_u64(what) : static_cast<std::uint64_t>(r_.read_i32(what));
    if (t == 0 || t > (std::uint64_t{1} << 62)) r_.fail(std::string(what) + ": invalid node tag " + std::to_string(t));
    return t;
  }
  // Binary data begins right after the newline that ends the section keyword or header line.
  void begin_binary() {
    if (binary_) r_.skip_line();
  }
  void expect_end(std::string_view name) {
    const std::string end = "$End" + std::string(name);
    const std::string_view tok = r_.next_token();
    if (tok != end) {
      r_.fail("expected " + end + ", got " + (tok.empty() ? std::string("end of file") : "'" + std::string(tok.substr(0, 40)) + "'"));
    }
  }
  VertId vertex(std::uint64_t tag, std::string_view what) {
    const VertId v = nodes_.find(tag);
    if (v == kInvalid) r_.fail(std::string(what) + ": unknown node tag " + std::to_string(tag));
    return v;
  }

  // ---- sections ----
  void read_format() {
    const std::string_view first = r_.next_token();
    if (first != "$MeshFormat") r_.fail("not a Gmsh file: expected $MeshFormat");
    const std::string version(r_.token("$MeshFormat version"));
    if (version == "4.1") {
      v41_ = true;
    } else if (version == "2" || version == "2.0" || version == "2.1" || version == "2.2") {
      v41_ = false;
    } else {
      r_.fail("MSH version " + version.substr(0, 20) + " is not supported (use 4.1 or 2.2)");
    }
    if (visitor_ != nullptr && !v41_)
      r_.fail("MSH " + version + " is not streamed (out of core reads MSH 4.1): convert it first (topotet convert IN.msh "
              "IN.mesh, or gmsh -save -format msh41)");
    binary_ = r_.read_int("$MeshFormat file type", 0, 1) == 1;
    const std::int64_t data_size = r_.read_int("$MeshFormat data size");
    if (binary_) {
      if (data_size != 8) r_.fail("binary MSH with data size " + std::to_string(data_size) + " is not supported");
      r_.skip_line();
      r_.set_binary_file(true);
      if (r_.read_i32("$MeshFormat byte-order word") != 1) r_.fail("big-endian binary MSH is not supported");
    }
    expect_end("MeshFormat");
  }

  void read_physical_names() {
    const auto n = r_.read_int("$PhysicalNames count", 0, 1 << 24);
    for (std::int64_t i = 0; i < n; ++i) {
      // Text even in binary files.
      const auto dim = static_cast<int>(r_.read_int("$PhysicalNames dimension", 0, 3));
      const auto tag = static_cast<int>(r_.read_int("$PhysicalNames tag", std::numeric_limits<std::int32_t>::min(),
                                                    std::numeric_limits<std::int32_t>::max()));
      names_[{dim, tag}] = unquote(r_.next_line_text("$PhysicalNames name"));
    }
    expect_end("PhysicalNames");
  }

  void read_entities() {
    begin_binary();
    std::array<std::uint64_t, 4> counts{};
    for (auto& c : counts) c = size("$Entities count");
    for (int dim = 0; dim < 4; ++dim) {
      for (std::uint64_t i = 0; i < counts[static_cast<std::size_t>(dim)]; ++i) {
        const std::int32_t tag = int32("$Entities tag");
        for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) bbox_real("$Entities bounding box");
        const std::uint64_t nphys = size("$Entities number of physical tags");
        std::vector<int>& phys = entity_phys_[static_cast<std::size_t>(dim)][tag];
        phys.clear();
        for (std::uint64_t k = 0; k < nphys; ++k) phys.push_back(int32("$Entities physical tag"));
        if (dim > 0) {
          const std::uint64_t nbound = size("$Entities number of bounding entities");
          for (std::uint64_t k = 0; k < nbound; ++k) int32("$Entities bounding entity");
        }
      }
    }
    expect_end("Entities");
  }

  // `gmsh -part N` puts the elements on partitioned entities, each a piece of a model entity (its
  // parent). Refs come from the model: the piece's physical tags (Gmsh copies the parent's), else
  // the parent's, else the parent's tag, never the piece's own tag. Pieces whose parent has a
  // higher dimension (the partition boundaries Gmsh creates inside volumes and on surfaces) are
  // not part of the model: their elements are skipped.
  void read_partitioned_entities() {
    begin_binary();
    notes_.partitions = size("$PartitionedEntities number of partitions");
    const std::uint64_t ghosts = size("$PartitionedEntities number of ghost entities");
    for (std::uint64_t i = 0; i < ghosts; ++i) {
      int32("$PartitionedEntities ghost entity tag");
      int32("$PartitionedEntities ghost partition");
    }
    std::array<std::uint64_t, 4> counts{};
    for (auto& c : counts) c = size("$PartitionedEntities count");
    for (int dim = 0; dim < 4; ++dim) {
      for (std::uint64_t i = 0; i < counts[static_cast<std::size_t>(dim)]; ++i) {
        const std::int32_t tag = int32("$PartitionedEntities tag");
        Piece piece;
        piece.parent_dim = int32("$PartitionedEntities parent dimension");
        piece.parent_tag = int32("$PartitionedEntities parent tag");
        const std::uint64_t parts = size("$PartitionedEntities number of partitions");
        for (std::uint64_t k = 0; k < parts; ++k) {
          const std::int32_t partition = int32("$PartitionedEntities partition tag");
          if (k == 0) piece.partition = partition;
        }
        for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) bbox_real("$PartitionedEntities bounding box");
        const std::uint64_t nphys = size("$PartitionedEntities number of physical tags");
        for (std::uint64_t k = 0; k < nphys; ++k) piece.physicals.push_back(int32("$PartitionedEntities physical tag"));
        if (dim > 0) {
          const std::uint64_t nbound = size("$PartitionedEntities number of bounding entities");
          for (std::uint64_t k = 0; k < nbound; ++k) int32("$PartitionedEntities bounding entity");
        }
        pieces_[static_cast<std::size_t>(dim)][tag] = std::move(piece);
      }
    }
    expect_end("PartitionedEntities");
  }

  // The piece of a partitioned file that `entity` is, or nullptr (a model entity).
  const Piece* piece_of(int dim, int entity) const {
    const auto& table = pieces_[static_cast<std::size_t>(dim)];
    const auto it = table.find(entity);
    return it == table.end() ? nullptr : &it->second;
  }

  void add_node(std::uint64_t tag, const std::array<double, 3>& p) {
    if (node_count_ >= kInvalid - 1) r_.fail("$Nodes: too many nodes");
    if (!nodes_.insert(tag, node_count_)) r_.fail("$Nodes: duplicate node tag " + std::to_string(tag));
    ++node_count_;
    if (visitor_ != nullptr) {
      visitor_->vertex(p, 0);
      return;
    }
    m_.positions.push_back(p);
    if (options_.keep_partitions && v41_) notes_.node_tags.push_back(tag);
  }

  void read_nodes41() {
    begin_binary();
    const std::uint64_t blocks = size("$Nodes number of blocks");
    const std::uint64_t total = size("$Nodes number of nodes");
    size("$Nodes min tag");
    const std::uint64_t max_tag = size("$Nodes max tag");
    if (visitor_ != nullptr) {
      if (visitor_->begin_vertices_holding(total, NodeMap::planned_bytes(total, max_tag))) nodes_.reserve(total, max_tag);
    } else
      m_.positions.reserve(r_.reserve_hint(total, binary_ ? 32 : 8));
    std::vector<std::uint64_t> tags;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::int32_t dim = int32("$Nodes entity dimension");
      int32("$Nodes entity tag");
      const std::int32_t parametric = int32("$Nodes parametric flag");
      const std::uint64_t n = size("$Nodes block size");
      if (dim < 0 || dim > 3) r_.fail("$Nodes: entity dimension " + std::to_string(dim) + " out of range");
      const int extra = parametric != 0 ? dim : 0;  // u, (v, (w)) after x y z
      tags.clear();
      tags.reserve(r_.reserve_hint(n, binary_ ? 8 : 2));
      for (std::uint64_t i = 0; i < n; ++i) tags.push_back(node_tag("$Nodes node tag"));
      for (std::uint64_t i = 0; i < n; ++i) {
        std::array<double, 3> p;
        for (double& x : p) x = real("$Nodes coordinate");
        for (int k = 0; k < extra; ++k) bbox_real("$Nodes parametric coordinate");
        add_node(tags[i], p);
      }
    }
    if (node_count_ != total) {
      r_.fail("$Nodes: header announces " + std::to_string(total) + " nodes, blocks hold " + std::to_string(node_count_));
    }
    expect_end("Nodes");
  }

  void read_nodes22() {
    const auto n = r_.read_int("$Nodes count", 0, kInvalid - 2);
    begin_binary();
    m_.positions.reserve(r_.reserve_hint(static_cast<std::uint64_t>(n), binary_ ? 28 : 8));
    for (std::int64_t i = 0; i < n; ++i) {
      const std::uint64_t tag = node_tag("$Nodes node tag");
      std::array<double, 3> p;
      for (double& x : p) x = real("$Nodes coordinate");
      add_node(tag, p);
    }
    expect_end("Nodes");
  }

  // Appends one element of `type` with node tags `tags`; returns false for ignored types.
  bool add_element(std::int64_t type, const std::uint64_t* tags) {
    switch (type) {
      case kTet: {
        std::array<VertId, 4> t;
        for (int k = 0; k < 4; ++k) t[static_cast<std::size_t>(k)] = vertex(tags[k], "$Elements");
        if (visitor_ != nullptr) {
          visitor_->tet(t, block_material_);
          ++streamed_tets_;
        } else {
          m_.tets.push_back(t);
        }
        return true;
      }
      case kTriangle: {
        Triangle t;
        for (int k = 0; k < 3; ++k) t.v[static_cast<std::size_t>(k)] = vertex(tags[k], "$Elements");
        m_.triangles.push_back(t);
        return true;
      }
      case kLine: {
        Segment s;
        for (int k = 0; k < 2; ++k) s.v[static_cast<std::size_t>(k)] = vertex(tags[k], "$Elements");
        m_.segments.push_back(s);
        return true;
      }
      case kPoint:
        points_.push_back(vertex(tags[0], "$Elements"));
        return true;
      default:
        return false;
    }
  }

  std::size_t count_of_dim(int dim) const {
    switch (dim) {
      case 0: return points_.size();
      case 1: return m_.segments.size();
      case 2: return m_.triangles.size();
      default: return visitor_ != nullptr ? streamed_tets_ : m_.tets.size();
    }
  }

  void add_to_run(int dim, int entity, int physical, std::size_t begin) {
    const std::size_t end = count_of_dim(dim);
    if (end == begin) return;
    std::size_t& last = last_run_[static_cast<std::size_t>(dim)];
    if (last != kNoRun) {
      Run& run = runs_[last];
      if (run.entity == entity && run.physical == physical && run.end == begin) {
        run.end = end;
        return;
      }
    }
    last = runs_.size();
    runs_.push_back({dim, entity, physical, begin, end});
  }

  // Hexahedra, prisms and pyramids are refused unless tets_only; quads are always left out (io.h).
  // `what` names them in the error: "12 hexahedra" or "element 7 (8-node hexahedron)".
  void note_non_tet(std::int64_t type, std::uint64_t n, const std::string& what) {
    std::uint64_t* count = nullptr;
    switch (type) {
      case 3: count = &notes_.quadrilaterals; break;
      case 5: count = &notes_.hexahedra; break;
      case 6: count = &notes_.prisms; break;
      case 7: count = &notes_.pyramids; break;
      default: return;
    }
    if (type != 3 && n > 0 && !options_.tets_only) r_.fail(mixed_mesh_message(what));
    *count += n;
  }

  ElementType checked_type(std::int64_t type) {
    const ElementType t = element_type(type);
    if (t.order > 1) {
      r_.fail("element type " + std::to_string(type) + " (" + t.name + "): second-order elements not supported");
    }
    return t;
  }

  void read_elements41() {
    begin_binary();
    const std::uint64_t blocks = size("$Elements number of blocks");
    const std::uint64_t total = size("$Elements number of elements");
    size("$Elements min tag");
    size("$Elements max tag");
    if (visitor_ != nullptr)
      visitor_->begin_tets(total);  // an upper bound: the elements of every type
    else
      m_.tets.reserve(r_.reserve_hint(total, binary_ ? 40 : 10));  // most elements are tets
    std::uint64_t seen = 0;
    std::array<std::uint64_t, 128> tags{};
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::int32_t entity_dim = int32("$Elements entity dimension");
      const std::int32_t entity = int32("$Elements entity tag");
      const std::int32_t type = int32("$Elements element type");
      const std::uint64_t n = size("$Elements block size");
      if (entity_dim < 0 || entity_dim > 3) r_.fail("$Elements: entity dimension " + std::to_string(entity_dim) + " out of range");
      const ElementType et = checked_type(type);
      seen += n;
      if (et.nodes == 0) {
        // Unknown type: its size is unknown too, but ASCII elements are one per line.
        if (binary_) r_.fail("$Elements: unknown element type " + std::to_string(type));
        r_.skip_line();
        for (std::uint64_t i = 0; i < n; ++i) r_.skip_line(true);
        continue;
      }
      static constexpr const char* kPlural[8] = {"", "", "", "quadrilaterals", "", "hexahedra", "prisms", "pyramids"};
      if (type >= 0 && type < 8) note_non_tet(type, n, std::to_string(n) + " " + kPlural[type]);
      const int dim = element_dim(type);
      const std::size_t begin = count_of_dim(dim);
      const Piece* piece = piece_of(entity_dim, entity);
      const bool partition_boundary = piece != nullptr && piece->parent_dim != entity_dim;
      // Streamed tets take their material now: $Entities came before (MSH 4.1 order), and the
      // rule is resolve()'s.
      if (visitor_ != nullptr && dim == 3) {
        int model_entity = entity;
        const std::vector<int> phys = physicals_of(3, entity, model_entity);
        block_material_ = resolve_refs(3, phys, model_entity).ref;
      }
      for (std::uint64_t i = 0; i < n; ++i) {
        const std::uint64_t element_tag = size("$Elements element tag");
        for (int k = 0; k < et.nodes; ++k) tags[static_cast<std::size_t>(k)] = node_tag("$Elements node tag");
        if (!partition_boundary && add_element(type, tags.data())) note_element_tag(type, element_tag);
        if (is_dropped_volume(type) && visitor_ == nullptr) dropped_tags_.push_back(element_tag);
      }
      if (visitor_ != nullptr && dim == 3) continue;  // given already; nothing to resolve
      if (options_.keep_partitions && dim == 3)
        notes_.tet_partition.resize(m_.tets.size(), piece != nullptr ? piece->partition : 0);
      add_to_run(dim, entity, 0, begin);
    }
    if (seen != total) {
      r_.fail("$Elements: header announces " + std::to_string(total) + " elements, blocks hold " + std::to_string(seen));
    }
    expect_end("Elements");
  }

  void read_elements22() {
    const auto total = r_.read_int("$Elements count", 0, std::numeric_limits<std::int32_t>::max());
    begin_binary();
    m_.tets.reserve(r_.reserve_hint(static_cast<std::uint64_t>(total), binary_ ? 28 : 14));
    std::array<std::uint64_t, 128> tags{};
    std::int64_t done = 0;
    while (done < total) {
      // ASCII: one element per line. Binary: blocks of elements sharing type and tag count.
      std::int64_t type = 0, count = 1, ntags = 0;
      if (binary_) {
        type = r_.read_i32("$Elements element type");
        count = r_.read_i32("$Elements block size");
        ntags = r_.read_i32("$Elements number of tags");
        if (count < 1 || count > total - done) r_.fail("$Elements: bad block size " + std::to_string(count));
        if (ntags < 0 || ntags > 1000) r_.fail("$Elements: bad number of tags " + std::to_string(ntags));
      }
      for (std::int64_t i = 0; i < count; ++i) {
        std::int64_t element_tag = 0;
        if (binary_) {
          element_tag = r_.read_i32("$Elements element tag");
        } else {
          element_tag = r_.read_int("$Elements element tag");
          type = r_.read_int("$Elements element type");
          ntags = r_.read_int("$Elements number of tags", 0, 1000);
        }
        const ElementType et = checked_type(type);
        note_non_tet(type, 1, "element " + std::to_string(element_tag) + " (" + et.name + ")");
        if (binary_ && et.nodes == 0) r_.fail("$Elements: unknown element type " + std::to_string(type));
        std::int32_t physical = 0, elementary = 0;
        for (std::int64_t k = 0; k < ntags; ++k) {
          const std::int32_t t = int32("$Elements tag");
          if (k == 0) physical = t;
          if (k == 1) elementary = t;
        }
        if (et.nodes == 0) {  // unknown ASCII type: skip the rest of its line
          r_.skip_line(true);
          continue;
        }
        for (int k = 0; k < et.nodes; ++k) tags[static_cast<std::size_t>(k)] = node_tag("$Elements node tag");
        const int dim = element_dim(type);
        const std::size_t begin = count_of_dim(dim);
        if (add_element(type, tags.data())) {
          add_to_run(dim, elementary, physical, begin);
          note_element_tag(type, static_cast<std::uint64_t>(element_tag));
        }
        if (is_dropped_volume(type)) dropped_tags_.push_back(static_cast<std::uint64_t>(element_tag));
      }
      done += count;
    }
    expect_end("Elements");
  }

  // The header of a $NodeData or $ElementData view: its name (the first string tag, else
  // `default_name`), components and value count (integer tags 2 and 3; real tags skipped).
  struct ViewHeader {
    std::string name;
    std::int64_t components = 0, count = 0;
  };
  ViewHeader read_view_header(const std::string& section, std::string default_name) {
    ViewHeader h;
    h.name = std::move(default_name);
    const auto nstrings = r_.read_int(section + " number of string tags", 0, 1000);
    for (std::int64_t i = 0; i < nstrings; ++i) {
      const std::string s = unquote(r_.next_line_text(section + " string tag"));
      if (i == 0) h.name = s;
    }
    const auto nreals = r_.read_int(section + " number of real tags", 0, 1000);
    for (std::int64_t i = 0; i < nreals; ++i) r_.read_double_any(section + " real tag");
    const auto nints = r_.read_int(section + " number of integer tags", 0, 1000);
    std::vector<std::int64_t> ints;
    for (std::int64_t i = 0; i < nints; ++i) ints.push_back(r_.read_int(section + " integer tag"));
    if (ints.size() < 3) r_.fail(section + ": expected at least 3 integer tags (time step, components, count)");
    h.components = ints[1];
    h.count = ints[2];
    if (h.components < 1 || h.components > 9)
      r_.fail(section + ": " + std::to_string(h.components) + " components not supported (1 to 9)");
    return h;
  }

  // Streamed, a view goes to the visitor only if it takes views of that kind; otherwise the stream
  // is refused here, saying how to convert the file.
  void refuse_streamed_fields(const std::string& section) {
    if (visitor_ != nullptr)
      r_.fail(section + ": the " + (section == "$NodeData" ? "node" : "cell") +
              " fields of a .msh are not streamed here (out of core); convert it first (topotet convert IN.msh "
              "IN.mesh writes them to IN.sol)");
  }

  // $NodeData into the visitor: the same header, checks and entries as below, nothing held.
  void stream_node_data() {
    const ViewHeader h = read_view_header("$NodeData", "field" + std::to_string(streamed_fields_.size()));
    if (!visitor_->begin_node_view(h.name, static_cast<int>(h.components))) refuse_streamed_fields("$NodeData");
    if (std::find(streamed_fields_.begin(), streamed_fields_.end(), h.name) == streamed_fields_.end())
      streamed_fields_.push_back(h.name);
    const std::int64_t comps = h.components, n = h.count;
    if (n < 0 || static_cast<std::uint64_t>(n) > node_count_)
      r_.fail("$NodeData: " + std::to_string(n) + " values for " + std::to_string(node_count_) + " nodes");
    begin_binary();
    double values[9];
    for (std::int64_t i = 0; i < n; ++i) {
      const VertId v = vertex(node_data_tag(), "$NodeData");
      for (std::int64_t c = 0; c < comps; ++c) values[c] = real("$NodeData value");
      visitor_->node_values(v, values);
    }
    expect_end("NodeData");
  }

  std::uint64_t node_data_tag() {
    return binary_ ? static_cast<std::uint64_t>(static_cast<std::uint32_t>(r_.read_i32("$NodeData node tag")))
                   : static_cast<std::uint64_t>(r_.read_int("$NodeData node tag", 1, std::numeric_limits<std::int64_t>::max()));
  }

  void read_node_data() {
    if (visitor_ != nullptr) return stream_node_data();
    const ViewHeader h = read_view_header("$NodeData", "field" + std::to_string(m_.fields.size()));
    const std::string& name = h.name;
    const std::int64_t comps = h.components, n = h.count;
    if (n < 0 || static_cast<std::uint64_t>(n) > m_.positions.size())
      r_.fail("$NodeData: " + std::to_string(n) + " values for " + std::to_string(m_.positions.size()) + " nodes");
    begin_binary();
    VertexField f;
    f.name = name;
    f.components = static_cast<int>(comps);
    // Nodes without a value (a partial view) get 0.
    f.values.assign(m_.positions.size() * static_cast<std::size_t>(comps), 0.0);
    for (std::int64_t i = 0; i < n; ++i) {
      const VertId v = vertex(node_data_tag(), "$NodeData");
      for (std::int64_t c = 0; c < comps; ++c)
        f.values[static_cast<std::size_t>(v) * static_cast<std::size_t>(comps) + static_cast<std::size_t>(c)] =
            real("$NodeData value");
    }
    expect_end("NodeData");
    const auto same = std::find_if(m_.fields.begin(), m_.fields.end(), [&](const VertexField& g) { return g.name == f.name; });
    if (same != m_.fields.end()) {
      *same = std::move(f);
    } else {
      m_.fields.push_back(std::move(f));
    }
  }

  // Element tags, for $ElementData: [tet] its tag (before the MSH 2 copies are merged), and the tags
  // of the volume elements --tets-only left out (their values go with them).
  void note_element_tag(std::int64_t type, std::uint64_t tag) {
    if (type != kTet) return;
    if (visitor_ == nullptr) return tet_tags_.push_back(tag);
    // Streamed: the tets' tags are kept as a range, when they are consecutive (add_element has
    // counted this tet already).
    if (streamed_tets_ == 1) first_tet_tag_ = tag;
    else if (tag != first_tet_tag_ + streamed_tets_ - 1) consecutive_tet_tags_ = false;
  }
  bool is_dropped_volume(std::int64_t type) const { return options_.tets_only && type >= 5 && type <= 7; }

  // $ElementData into the visitor: the tet of a tag is tag - first, which needs the tets' tags
  // consecutive (what Gmsh and topotet write); a tag -> tet map would hold 8 bytes a tet.
  void stream_element_data() {
    const ViewHeader h = read_view_header("$ElementData", "cellfield" + std::to_string(streamed_cell_fields_.size()));
    if (!visitor_->begin_cell_view(h.name, static_cast<int>(h.components))) refuse_streamed_fields("$ElementData");
    if (!consecutive_tet_tags_)
      r_.fail("$ElementData: the tetrahedra's element tags are not consecutive, so the cell fields of this .msh are not "
              "streamed (out of core); convert it first (topotet convert IN.msh IN.mesh writes them to IN.sol)");
    if (std::find(streamed_cell_fields_.begin(), streamed_cell_fields_.end(), h.name) == streamed_cell_fields_.end())
      streamed_cell_fields_.push_back(h.name);
    const std::int64_t comps = h.components, n = h.count;
    if (n < 0 || static_cast<std::uint64_t>(n) > streamed_tets_)
      r_.fail("$ElementData: " + std::to_string(n) + " values for " + std::to_string(streamed_tets_) + " tetrahedra");
    begin_binary();
    double values[9];
    for (std::int64_t i = 0; i < n; ++i) {
      const std::uint64_t tag = element_data_tag();
      if (tag < first_tet_tag_ || tag - first_tet_tag_ >= streamed_tets_)
        r_.fail("$ElementData '" + h.name + "': element tag " + std::to_string(tag) +
                " is not a tetrahedron of the mesh (topotet reads the cell data of tetrahedra)");
      for (std::int64_t c = 0; c < comps; ++c) values[c] = real("$ElementData value");
      visitor_->cell_values(tag - first_tet_tag_, values);
    }
    expect_end("ElementData");
  }

  std::uint64_t element_data_tag() {
    return binary_ ? static_cast<std::uint64_t>(static_cast<std::uint32_t>(r_.read_i32("$ElementData element tag")))
                   : static_cast<std::uint64_t>(r_.read_int("$ElementData element tag", 1, std::numeric_limits<std::int64_t>::max()));
  }

  // $ElementData: a view on the tets (tags of other elements are an error, those of left-out
  // volume elements are skipped); tets without a value get 0; last time step wins, as $NodeData.
  void read_element_data() {
    if (visitor_ != nullptr) return stream_element_data();
    const ViewHeader h = read_view_header("$ElementData", "cellfield" + std::to_string(m_.cell_fields.size()));
    const std::string& name = h.name;
    const std::int64_t comps = h.components, n = h.count;
    if (n < 0 || static_cast<std::uint64_t>(n) > tet_tags_.size() + dropped_tags_.size())
      r_.fail("$ElementData: " + std::to_string(n) + " values for " + std::to_string(tet_tags_.size()) + " tetrahedra");
    if (tag_index_.size() != tet_tags_.size()) {
      tag_index_.clear();
      for (std::size_t t = 0; t < tet_tags_.size(); ++t) tag_index_.emplace_back(tet_tags_[t], t);
      std::sort(tag_index_.begin(), tag_index_.end());
      std::sort(dropped_tags_.begin(), dropped_tags_.end());
    }
    begin_binary();
    CellField f;
    f.name = name;
    f.components = static_cast<int>(comps);
    f.values.assign(tet_tags_.size() * static_cast<std::size_t>(comps), 0.0);
    for (std::int64_t i = 0; i < n; ++i) {
      const std::uint64_t tag = element_data_tag();
      const auto at = std::lower_bound(tag_index_.begin(), tag_index_.end(), std::pair<std::uint64_t, std::size_t>(tag, 0));
      std::size_t tet = kNoRun;
      if (at != tag_index_.end() && at->first == tag) {
        tet = at->second;
      } else if (!std::binary_search(dropped_tags_.begin(), dropped_tags_.end(), tag)) {
        r_.fail("$ElementData '" + name + "': element tag " + std::to_string(tag) +
                " is not a tetrahedron of the mesh (topotet reads the cell data of tetrahedra)");
      }
      for (std::int64_t c = 0; c < comps; ++c) {
        const double x = real("$ElementData value");
        if (tet != kNoRun) f.values[tet * static_cast<std::size_t>(comps) + static_cast<std::size_t>(c)] = x;
      }
    }
    expect_end("ElementData");
    const auto same = std::find_if(m_.cell_fields.begin(), m_.cell_fields.end(), [&](const CellField& g) { return g.name == f.name; });
    if (same != m_.cell_fields.end()) {
      *same = std::move(f);
    } else {
      m_.cell_fields.push_back(std::move(f));
    }
  }

  // Unknown sections ($Periodic, $GhostElements, $Comments...) are skipped up to their end tag.
  void skip_section(const std::string& name) {
    const std::string end = "$End" + name;
    for (;;) {
      const std::string_view tok = r_.next_token();
      if (tok.empty()) r_.fail("missing " + end);
      if (tok == end) return;
    }
  }

  // ---- refs ----
  // The physical tags of the elements of MSH 4.1 entity (dim, entity), and in `model_entity` the
  // model entity they belong to: a partitioned piece's parent (its physical tags, else the
  // parent's), else the entity itself.
  std::vector<int> physicals_of(int dim, int entity, int& model_entity) const {
    const Piece* piece = piece_of(dim, entity);
    model_entity = piece != nullptr ? piece->parent_tag : entity;
    if (piece != nullptr && !piece->physicals.empty()) return piece->physicals;
    const auto& table = entity_phys_[static_cast<std::size_t>(dim)];
    const auto it = table.find(model_entity);
    return it == table.end() ? std::vector<int>() : it->second;
  }

  Resolved resolve_refs(int dim, const std::vector<int>& physicals, int fallback) const {
    Resolved out;
    bool have_ref = false, other_point_group = false;
    for (int p : physicals) {
      const auto it = names_.find({dim, p});
      const std::string_view name = it == names_.end() ? std::string_view() : std::string_view(it->second);
      if (dim == 1 && name == kRidgesName) {
        out.ridge = true;
        continue;
      }
      if (dim == 0 && name == kRequiredName) {
        out.required = true;
        continue;
      }
      other_point_group = true;
      std::int32_t ref = p;
      if (name.substr(0, kRefPrefix.size()) == kRefPrefix) {
        const std::string_view num = name.substr(kRefPrefix.size());
        std::int32_t v = 0;
        const auto [ptr, ec] = std::from_chars(num.data(), num.data() + num.size(), v);
        if (ec == std::errc() && ptr == num.data() + num.size()) ref = v;
      }
      if (have_ref) {
        if (ref != out.ref && std::find(out.more_refs.begin(), out.more_refs.end(), ref) == out.more_refs.end())
          out.more_refs.push_back(ref);
        continue;
      }
      have_ref = true;
      out.ref = ref;
    }
    out.has_ref = have_ref;
    if (!have_ref) out.ref = fallback;
    out.corner = physicals.empty() || other_point_group;
    return out;
  }

  void resolve() {
    std::vector<Resolved> resolved;
    resolved.reserve(runs_.size());
    std::vector<int> phys;
    for (const Run& run : runs_) {
      int entity = run.entity;
      if (v41_) {
        phys = physicals_of(run.dim, run.entity, entity);
      } else {
        phys.clear();
        if (run.physical != 0) phys.push_back(run.physical);
      }
      resolved.push_back(resolve_refs(run.dim, phys, entity));
    }
    std::vector<std::int32_t> seg_ref(m_.segments.size()), tri_ref(m_.triangles.size());
    std::vector<std::uint8_t> point_kind(points_.size());  // bit 0 corner, bit 1 required
    std::vector<std::uint8_t> seg_ridge(m_.segments.size());
    m_.tet_material.assign(m_.tets.size(), 0);
    for (std::size_t r = 0; r < runs_.size(); ++r) {
      const Run& run = runs_[r];
      const Resolved& res = resolved[r];
      for (std::size_t i = run.begin; i < run.end; ++i) {
        switch (run.dim) {
          case 0: point_kind[i] = static_cast<std::uint8_t>((res.corner ? 1 : 0) | (res.required ? 2 : 0)); break;
          case 1: seg_ref[i] = res.ref; seg_ridge[i] = res.ridge; break;
          case 2: tri_ref[i] = res.ref; break;
          default: m_.tet_material[i] = res.ref; break;
        }
      }
    }
    if (!v41_) drop_msh2_duplicates(resolved, point_kind, seg_ref, seg_ridge, tri_ref);
    // A line or triangle whose entity is in several physical groups belongs to each of them: one
    // copy per further group, after all others (the builder merges them into one face with every
    // ref, tet_mesh.h SharedRefs). A volume has one material: its first group.
    for (std::size_t r = 0; r < runs_.size(); ++r) {
      const Run& run = runs_[r];
      for (std::int32_t ref : resolved[r].more_refs) {
        for (std::size_t i = run.begin; i < run.end; ++i) {
          if (run.dim == 1) {
            m_.segments.push_back(m_.segments[i]);
            seg_ref.push_back(ref);
            seg_ridge.push_back(seg_ridge[i]);
          } else if (run.dim == 2) {
            m_.triangles.push_back(m_.triangles[i]);
            tri_ref.push_back(ref);
          }
        }
      }
    }
    for (std::size_t i = 0; i < m_.segments.size(); ++i) {
      m_.segments[i].ref = seg_ref[i];
      if (seg_ridge[i]) m_.ridges.push_back(static_cast<std::uint32_t>(i));
    }
    for (std::size_t i = 0; i < m_.triangles.size(); ++i) m_.triangles[i].ref = tri_ref[i];
    for (std::size_t i = 0; i < points_.size(); ++i) {
      if (point_kind[i] & 1) m_.corners.push_back(points_[i]);
      if (point_kind[i] & 2) m_.required_vertices.push_back(points_[i]);
    }
    // User names of curve, surface and volume groups (ours, "topotet:...", are conventions).
    for (const auto& [key, name] : names_)
      if (key.first >= 1 && name.rfind("topotet:", 0) != 0) m_.group_names.push_back({key.first, key.second, name});
    finish_fields();
  }

  // MSH 2.x repeats the elements of an entity that is in several physical groups, once per group.
  // A copy whose group gives a ref is a real listing: lines and triangles keep one copy per
  // distinct ref (the face is on several surfaces); a volume keeps its first copy (one material).
  // A copy whose group only carries a flag (ridge, corner, required vertex) is merged into the
  // element's first copy. Only entities seen with more than one physical tag are examined, so
  // ordinary files pay nothing. Runs are in file order, so this does not depend on anything else.
  void drop_msh2_duplicates(const std::vector<Resolved>& resolved, std::vector<std::uint8_t>& point_kind,
                            std::vector<std::int32_t>& seg_ref, std::vector<std::uint8_t>& seg_ridge,
                            std::vector<std::int32_t>& tri_ref) {
    std::map<std::pair<int, int>, std::set<int>> physicals;  // (dim, elementary) -> physical tags
    for (const Run& run : runs_) physicals[{run.dim, run.entity}].insert(run.physical);
    std::array<std::vector<std::uint8_t>, 4> keep;
    struct First {
      std::size_t index;  // the copy kept first
      bool has_ref;       // whether its ref came from a group (else it is the entity tag)
    };
    std::array<std::map<std::pair<int, std::array<VertId, 4>>, First>, 4> first;
    std::set<std::tuple<int, std::array<VertId, 4>, std::int32_t>> listed;  // lines, triangles: (entity, nodes, ref)
    for (std::size_t r = 0; r < runs_.size(); ++r) {
      const Run& run = runs_[r];
      if (physicals[{run.dim, run.entity}].size() < 2) continue;
      const Resolved& res = resolved[r];
      const auto d = static_cast<std::size_t>(run.dim);
      if (keep[d].empty()) keep[d].assign(count_of_dim(run.dim), 1);
      std::vector<std::int32_t>& refs = run.dim == 1 ? seg_ref : tri_ref;
      for (std::size_t i = run.begin; i < run.end; ++i) {
        std::array<VertId, 4> key{kInvalid, kInvalid, kInvalid, kInvalid};
        switch (run.dim) {
          case 0: key[0] = points_[i]; break;
          case 1: std::copy(m_.segments[i].v.begin(), m_.segments[i].v.end(), key.begin()); break;
          case 2: std::copy(m_.triangles[i].v.begin(), m_.triangles[i].v.end(), key.begin()); break;
          default: key = m_.tets[i]; break;
        }
        std::sort(key.begin(), key.end());
        const auto [it, fresh] = first[d].try_emplace({run.entity, key}, First{i, res.has_ref});
        const bool listing = (run.dim == 1 || run.dim == 2) && res.has_ref;
        if (listing) {
          if (!listed.insert({run.entity, key, res.ref}).second) {
            keep[d][i] = 0;  // the same group twice
            continue;
          }
          if (!fresh && !it->second.has_ref) {
            // The first copy only carried a flag: it takes this ref, and this copy goes.
            refs[it->second.index] = res.ref;
            it->second.has_ref = true;
            keep[d][i] = 0;
          }
          continue;  // another group: a copy of its own
        }
        if (fresh) continue;
        keep[d][i] = 0;
        if (run.dim == 0) point_kind[it->second.index] |= point_kind[i];
        if (run.dim == 1) seg_ridge[it->second.index] |= seg_ridge[i];
      }
    }
    const auto compact = [](auto& v, const std::vector<std::uint8_t>& k) {
      if (k.empty()) return;
      std::size_t j = 0;
      for (std::size_t i = 0; i < v.size(); ++i)
        if (k[i]) v[j++] = v[i];
      v.resize(j);
    };
    // Runs are not used after this: 2.x runs have one group each, so they make no further copies.
    compact(points_, keep[0]);
    compact(point_kind, keep[0]);
    compact(m_.segments, keep[1]);
    compact(seg_ref, keep[1]);
    compact(seg_ridge, keep[1]);
    compact(m_.triangles, keep[2]);
    compact(tri_ref, keep[2]);
    compact(m_.tets, keep[3]);
    compact(m_.tet_material, keep[3]);
    if (!keep[3].empty()) {
      for (CellField& f : m_.cell_fields) {
        const auto c = static_cast<std::size_t>(f.components);
        std::size_t j = 0;
        for (std::size_t i = 0; i < keep[3].size(); ++i)
          if (keep[3][i])
            for (std::size_t k = 0; k < c; ++k) f.values[j++] = f.values[i * c + k];
        f.values.resize(j);
      }
    }
  }

  void finish_fields() {
    std::vector<VertexField> kept;
    for (VertexField& f : m_.fields) {
      if (f.name == kVertexRefField && f.components == 1 && as_vertex_refs(f)) continue;
      if (f.components == 9) to_symmetric_if_exact(f);
      kept.push_back(std::move(f));
    }
    m_.fields = std::move(kept);
    for (CellField& f : m_.cell_fields)
      if (f.components == 9) to_symmetric_if_exact(f);
  }

  bool as_vertex_refs(const VertexField& f) {
    std::vector<std::int32_t> refs(f.values.size());
    for (std::size_t i = 0; i < refs.size(); ++i)
      if (!exact_int32(f.values[i], refs[i])) return false;
    if (std::any_of(refs.begin(), refs.end(), [](std::int32_t x) { return x != 0; })) m_.vertex_refs = std::move(refs);
    return true;
  }

  // Row-major 3x3 -> MEDIT symmetric order (xx, xy, yy, xz, yz, zz), only if exactly symmetric.
  template <class Field>
  static void to_symmetric_if_exact(Field& f) {
    const std::size_t n = f.values.size() / 9;
    for (std::size_t i = 0; i < n; ++i)
      if (!is_symmetric_3x3(&f.values[9 * i])) return;
    std::vector<double> sym(6 * n);
    for (std::size_t i = 0; i < n; ++i) symmetric_components(&f.values[9 * i], &sym[6 * i]);
    f.values = std::move(sym);
    f.components = 6;
  }

  LineReader r_;
  const ReadOptions& options_;
  ReadNotes& notes_;
  MeditVisitor* visitor_ = nullptr;  // streaming (stream_gmsh): see the constructor
  VertId node_count_ = 0;
  std::uint64_t streamed_tets_ = 0;
  std::vector<std::string> streamed_fields_;       // streaming: the node views' names so far (default names count them)
  std::vector<std::string> streamed_cell_fields_;  // and the cell views'
  std::uint64_t first_tet_tag_ = 0;                // streaming: the first tet's element tag
  bool consecutive_tet_tags_ = true;               // and whether the others follow it one by one
  std::int32_t block_material_ = 0;  // streaming: the material of the current block's tets
  MeshData m_;
  bool v41_ = false, binary_ = false;
  bool seen_nodes_ = false, seen_elements_ = false;
  NodeMap nodes_;
  std::map<std::pair<int, int>, std::string> names_;                // (dim, physical tag) -> name
  std::array<std::unordered_map<int, std::vector<int>>, 4> entity_phys_;  // [dim] entity -> physicals
  std::array<std::unordered_map<int, Piece>, 4> pieces_;                // [dim] partitioned entity -> piece
  std::vector<VertId> points_;                                      // point elements, in order
  std::vector<std::uint64_t> tet_tags_;                             // [tet] element tag (note_element_tag)
  std::vector<std::uint64_t> dropped_tags_;                         // left-out volume elements (tets_only)
  std::vector<std::pair<std::uint64_t, std::size_t>> tag_index_;    // (tag, tet), sorted: built by $ElementData
  std::vector<Run> runs_;
  static constexpr std::size_t kNoRun = ~std::size_t{0};
  std::array<std::size_t, 4> last_run_{kNoRun, kNoRun, kNoRun, kNoRun};  // per dim, to extend runs
};

// ---------------------------------------------------------------------------------------------
// Writer

// Text or binary MSH 4.1 words. In ASCII each value is followed by `sep`.
class MshOut {
 public:
  MshOut(AtomicFile& f, bool binary) : f_(f), binary_(binary) {}
  void size(std::uint64_t v, char sep = ' ') {
    if (binary_) return f_.put_raw(v);
    f_.put_int(v);
    f_.put(sep);
  }
  void i32(std::int32_t v, char sep = ' ') {
    if (binary_) return f_.put_raw(v);
    f_.put_int(v);
    f_.put(sep);
  }
  void f64(double v, char sep = ' ') {
    if (binary_) return f_.put_raw(v);
    f_.put_double(v);
    f_.put(sep);
  }
  void text(std::string_view s) { f_.put(s); }
  // Binary data ends with a newline before the $End tag; ASCII lines already ended.
  void end_section(std::string_view end_tag) {
    if (binary_) f_.put('\n');
    f_.put(end_tag);
    f_.put('\n');
  }
  bool binary() const { return binary_; }

 private:
  AtomicFile& f_;
  bool binary_;
};

struct Box {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
  void add(const std::array<double, 3>& p) {
    lo = glm::min(lo, to_glm(p));
    hi = glm::max(hi, to_glm(p));
  }
};

struct Entity {
  int tag;
  std::vector<int> physicals;
  Box box;
};

// Physical groups of one dimension: positive refs are their own tags, named by the mesh's group
// names (every name of the dimension is written, used or not, so names survive a round trip);
// other refs get free tags named "topotet:ref=<r>".
class PhysicalTags {
 public:
  PhysicalTags() = default;
  PhysicalTags(const std::set<std::int32_t>& refs, const std::vector<GroupName>& names, int dim) {
    for (std::int32_t r : refs) next_ = std::max<std::int64_t>(next_, std::int64_t{r} + 1);
    for (const GroupName& g : names) {
      if (g.dim != dim || g.ref <= 0) continue;
      next_ = std::max<std::int64_t>(next_, std::int64_t{g.ref} + 1);
      names_.emplace_back(g.ref, g.name);
    }
    for (std::int32_t r : refs) tags_[r] = r > 0 ? r : allocate(std::string(kRefPrefix) + std::to_string(r));
  }
  int tag(std::int32_t ref) const { return tags_.at(ref); }
  int allocate(std::string name) {
    if (next_ > std::numeric_limits<std::int32_t>::max()) throw InputError("Gmsh writer: no free physical tag left");
    names_.emplace_back(static_cast<int>(next_), std::move(name));
    return static_cast<int>(next_++);
  }
  const std::vector<std::pair<int, std::string>>& names() const { return names_; }

 private:
  std::map<std::int32_t, int> tags_;
  std::vector<std::pair<int, std::string>> names_;
  std::int64_t next_ = 1;
};

std::string quoted(std::string s) {
  std::replace(s.begin(), s.end(), '"', '\'');
  std::replace(s.begin(), s.end(), '\n', ' ');
  return "\"" + s + "\"";
}

// Element blocks: one per entity. Entity tags are numbered in order of first use, so grouping
// by tag keeps that order, and within an entity the elements keep theirs.
struct Block {
  int dim, entity, type;
  std::vector<std::size_t> elements;
};

void add_blocks(std::vector<Block>& blocks, int dim, int type, const std::vector<int>& entity_of) {
  const std::size_t first = blocks.size();
  for (std::size_t i = 0; i < entity_of.size(); ++i) {
    const std::size_t b = first + static_cast<std::size_t>(entity_of[i] - 1);
    while (blocks.size() <= b) blocks.push_back({dim, static_cast<int>(blocks.size() - first) + 1, type, {}});
    blocks[b].elements.push_back(i);
  }
}

// One view: $NodeData (entity i has tag i + 1) or $ElementData (entity i has tag tags[i]).
void write_data(AtomicFile& f, MshOut& out, std::string_view section, const std::string& name, int components,
                std::size_t n, const std::vector<std::uint64_t>* tags, const auto& value) {
  f.put("$");
  f.put(section);
  f.put("\n1\n");
  f.put(quoted(name));
  f.put("\n1\n0\n3\n0\n");
  f.put_int(components);
  f.put('\n');
  f.put_int(n);
  f.put('\n');
  for (std::size_t i = 0; i < n; ++i) {
    out.i32(static_cast<std::int32_t>(tags ? (*tags)[i] : i + 1));
    for (int c = 0; c < components; ++c) out.f64(value(i, c), c + 1 == components ? '\n' : ' ');
  }
  out.end_section("$End" + std::string(section));
}

void write_node_data(AtomicFile& f, MshOut& out, const std::string& name, int components, std::size_t n,
                     const auto& value) {
  write_data(f, out, "NodeData", name, components, n, nullptr, value);
}

// What write_gmsh puts in the file, indexed by dimension (0 points ... 3 volumes): physical
// groups, entities, and the entity of every element.
struct GmshPlan {
  std::array<PhysicalTags, 4> phys;
  std::array<std::vector<Entity>, 4> entities;
  std::vector<int> seg_entity, tri_entity, tet_entity;
  std::vector<VertId> point_vertex;  // one point entity each: corners, then required vertices
};

// Entity of `key` in `by_key`, created on first use (tags 1, 2, ... in order), its box grown by
// the element's vertices.
template <class Key, std::size_t N>
int entity_of(std::map<Key, int>& by_key, const Key& key, std::vector<Entity>& list, const std::vector<int>& physicals,
              const MeshData& m, const std::array<VertId, N>& verts) {
  const auto [it, fresh] = by_key.try_emplace(key, static_cast<int>(list.size()) + 1);
  if (fresh) list.push_back({it->second, physicals, {}});
  for (VertId v : verts) list[static_cast<std::size_t>(it->second - 1)].box.add(m.positions[v]);
  return it->second;
}

// One volume per material, one surface per triangle ref, one curve per (segment ref, ridge), one
// point per corner and per required vertex.
GmshPlan plan_gmsh(const MeshData& m) {
  const auto material = [&](std::size_t i) { return m.tet_material.empty() ? 0 : m.tet_material[i]; };
  std::vector<std::uint8_t> is_ridge(m.segments.size(), 0);
  for (std::uint32_t r : m.ridges) is_ridge[r] = 1;
  std::array<std::set<std::int32_t>, 4> refs;
  for (const Segment& x : m.segments) refs[1].insert(x.ref);
  for (const Triangle& x : m.triangles) refs[2].insert(x.ref);
  for (std::size_t i = 0; i < m.tets.size(); ++i) refs[3].insert(material(i));

  GmshPlan plan;
  for (int dim = 0; dim < 4; ++dim)
    plan.phys[static_cast<std::size_t>(dim)] = PhysicalTags(refs[static_cast<std::size_t>(dim)], m.group_names, dim);
  const int ridge_group = m.ridges.empty() ? 0 : plan.phys[1].allocate(std::string(kRidgesName));
  const int corner_group = m.corners.empty() ? 0 : plan.phys[0].allocate(std::string(kCornersName));
  const int required_group = m.required_vertices.empty() ? 0 : plan.phys[0].allocate(std::string(kRequiredName));

  std::map<std::pair<std::int32_t, bool>, int> curves;
  for (std::size_t i = 0; i < m.segments.size(); ++i) {
    const std::pair<std::int32_t, bool> key{m.segments[i].ref, is_ridge[i] != 0};
    std::vector<int> phys{plan.phys[1].tag(key.first)};
    if (key.second) phys.push_back(ridge_group);
    plan.seg_entity.push_back(entity_of(curves, key, plan.entities[1], phys, m, m.segments[i].v));
  }
  std::map<std::int32_t, int> surfaces, volumes;
  for (const Triangle& t : m.triangles)
    plan.tri_entity.push_back(entity_of(surfaces, t.ref, plan.entities[2], {plan.phys[2].tag(t.ref)}, m, t.v));
  for (std::size_t i = 0; i < m.tets.size(); ++i)
    plan.tet_entity.push_back(entity_of(volumes, material(i), plan.entities[3], {plan.phys[3].tag(material(i))}, m, m.tets[i]));
  if (plan.entities[3].empty()) plan.entities[3].push_back({1, {}, {}});  // hosts the nodes of a tet-less mesh

  plan.point_vertex = m.corners;
  plan.point_vertex.insert(plan.point_vertex.end(), m.required_vertices.begin(), m.required_vertices.end());
  for (std::size_t i = 0; i < plan.point_vertex.size(); ++i) {
    const int group = i < m.corners.size() ? corner_group : required_group;
    plan.entities[0].push_back({static_cast<int>(i) + 1, {group}, {}});
  }
  return plan;
}

void write_physical_names(AtomicFile& f, const GmshPlan& plan) {
  std::size_t count = 0;
  for (const PhysicalTags& tags : plan.phys) count += tags.names().size();
  if (count == 0) return;
  f.put("$PhysicalNames\n");
  f.put_int(count);
  f.put('\n');
  for (int dim = 0; dim < 4; ++dim) {
    for (const auto& [tag, name] : plan.phys[static_cast<std::size_t>(dim)].names()) {
      f.put_int(dim);
      f.put(' ');
      f.put_int(tag);
      f.put(' ');
      f.put(quoted(name));
      f.put('\n');
    }
  }
  f.put("$EndPhysicalNames\n");
}

void write_entities(AtomicFile& f, MshOut& out, const GmshPlan& plan, const MeshData& m) {
  f.put("$Entities\n");
  for (int dim = 0; dim < 4; ++dim) out.size(plan.entities[static_cast<std::size_t>(dim)].size(), dim == 3 ? '\n' : ' ');
  for (std::size_t i = 0; i < plan.entities[0].size(); ++i) {
    const std::array<double, 3>& p = m.positions[plan.point_vertex[i]];
    out.i32(plan.entities[0][i].tag);
    out.f64(p[0]);
    out.f64(p[1]);
    out.f64(p[2]);
    out.size(1);
    out.i32(plan.entities[0][i].physicals[0], '\n');
  }
  for (int dim = 1; dim < 4; ++dim) {
    for (const Entity& e : plan.entities[static_cast<std::size_t>(dim)]) {
      const bool empty = e.box.lo.x > e.box.hi.x;
      const glm::dvec3 lo = empty ? glm::dvec3(0) : e.box.lo, hi = empty ? glm::dvec3(0) : e.box.hi;
      out.i32(e.tag);
      for (double x : {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z}) out.f64(x);
      out.size(e.physicals.size());
      for (int p : e.physicals) out.i32(p);
      out.size(0, '\n');  // no bounding entities: the mesh does not carry the model topology
    }
  }
  out.end_section("$EndEntities");
}

// All nodes in one block, on the first volume entity, tagged 1..n in MeshData order.
void write_nodes(AtomicFile& f, MshOut& out, const GmshPlan& plan, const MeshData& m) {
  const std::size_t nv = m.positions.size();
  f.put("$Nodes\n");
  out.size(nv == 0 ? 0 : 1);
  out.size(nv);
  out.size(nv == 0 ? 0 : 1);
  out.size(nv, '\n');
  if (nv > 0) {
    out.i32(3);
    out.i32(plan.entities[3][0].tag);
    out.i32(0);
    out.size(nv, '\n');
    for (std::size_t i = 0; i < nv; ++i) out.size(i + 1, '\n');
    for (const std::array<double, 3>& p : m.positions) {
      out.f64(p[0]);
      out.f64(p[1]);
      out.f64(p[2], '\n');
    }
  }
  out.end_section("$EndNodes");
}

std::vector<Block> element_blocks(const GmshPlan& plan) {
  std::vector<Block> blocks;
  for (std::size_t i = 0; i < plan.point_vertex.size(); ++i) blocks.push_back({0, plan.entities[0][i].tag, kPoint, {i}});
  add_blocks(blocks, 1, kLine, plan.seg_entity);
  add_blocks(blocks, 2, kTriangle, plan.tri_entity);
  add_blocks(blocks, 3, kTet, plan.tet_entity);
  return blocks;
}

// The 1-based node tags of element i of a block.
template <class F>
void element_nodes(const Block& b, std::size_t i, const GmshPlan& plan, const MeshData& m, F&& f) {
  const VertId* v = nullptr;
  int k = 0;
  switch (b.type) {
    case kPoint: v = &plan.point_vertex[i]; k = 1; break;
    case kLine: v = m.segments[i].v.data(); k = 2; break;
    case kTriangle: v = m.triangles[i].v.data(); k = 3; break;
    default: v = m.tets[i].data(); k = 4; break;
  }
  for (int j = 0; j < k; ++j) f(std::uint64_t{v[j]} + 1, j + 1 == k);
}

// Both element writers return [tet] the tag it was written with (for $ElementData).
std::vector<std::uint64_t> write_elements(AtomicFile& f, MshOut& out, const GmshPlan& plan, const MeshData& m) {
  std::vector<std::uint64_t> tet_tags(m.tets.size());
  const std::vector<Block> blocks = element_blocks(plan);
  const std::size_t ne = plan.point_vertex.size() + m.segments.size() + m.triangles.size() + m.tets.size();
  f.put("$Elements\n");
  out.size(blocks.size());
  out.size(ne);
  out.size(ne == 0 ? 0 : 1);
  out.size(ne, '\n');
  std::uint64_t tag = 0;
  for (const Block& b : blocks) {
    out.i32(b.dim);
    out.i32(b.entity);
    out.i32(b.type);
    out.size(b.elements.size(), '\n');
    for (std::size_t i : b.elements) {
      out.size(++tag);
      if (b.type == kTet) tet_tags[i] = tag;
      element_nodes(b, i, plan, m, [&](std::uint64_t node, bool last) { out.size(node, last ? '\n' : ' '); });
    }
  }
  out.end_section("$EndElements");
  return tet_tags;
}

// MSH 2.2 ASCII: "tag type 2 physical elementary nodes...", one line per physical group of the
// element's entity (what Gmsh itself writes; our reader merges the copies back).
std::vector<std::uint64_t> write_elements22(AtomicFile& f, const GmshPlan& plan, const MeshData& m) {
  std::vector<std::uint64_t> tet_tags(m.tets.size());
  const std::vector<Block> blocks = element_blocks(plan);
  std::uint64_t count = 0;
  for (const Block& b : blocks)
    count += b.elements.size() * plan.entities[static_cast<std::size_t>(b.dim)][static_cast<std::size_t>(b.entity - 1)].physicals.size();
  f.put("$Elements\n");
  f.put_int(count);
  f.put('\n');
  std::uint64_t tag = 0;
  for (const Block& b : blocks) {
    const Entity& e = plan.entities[static_cast<std::size_t>(b.dim)][static_cast<std::size_t>(b.entity - 1)];
    for (int physical : e.physicals) {
      for (std::size_t i : b.elements) {
        f.put_int(++tag);
        if (b.type == kTet && tet_tags[i] == 0) tet_tags[i] = tag;  // a volume's first group: the copy read back
        f.put(' ');
        f.put_int(b.type);
        f.put(" 2 ");
        f.put_int(physical);
        f.put(' ');
        f.put_int(b.entity);
        f.put(' ');
        element_nodes(b, i, plan, m, [&](std::uint64_t node, bool last) {
          f.put_int(node);
          f.put(last ? '\n' : ' ');
        });
      }
    }
  }
  f.put("$EndElements\n");
  return tet_tags;
}

void write_nodes22(AtomicFile& f, const MeshData& m) {
  f.put("$Nodes\n");
  f.put_int(m.positions.size());
  f.put('\n');
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    f.put_int(i + 1);
    for (double x : m.positions[i]) {
      f.put(' ');
      f.put_double(x);
    }
    f.put('\n');
  }
  f.put("$EndNodes\n");
}

// 6-component symmetric tensors (MEDIT order xx, xy, yy, xz, yz, zz) go out as full row-major 3x3.
constexpr int kFullFromSymmetric[9] = {0, 1, 3, 1, 2, 4, 3, 4, 5};

void write_cell_fields(AtomicFile& f, MshOut& out, const MeshData& m, const std::vector<std::uint64_t>& tet_tags) {
  for (const CellField& cf : m.cell_fields) {
    const std::size_t c = static_cast<std::size_t>(cf.components);
    if (cf.components == 6) {
      write_data(f, out, "ElementData", cf.name, 9, m.tets.size(), &tet_tags, [&](std::size_t i, int k) {
        return cf.values[i * 6 + static_cast<std::size_t>(kFullFromSymmetric[k])];
      });
    } else {
      write_data(f, out, "ElementData", cf.name, cf.components, m.tets.size(), &tet_tags,
                 [&](std::size_t i, int k) { return cf.values[i * c + static_cast<std::size_t>(k)]; });
    }
  }
}

void write_fields(AtomicFile& f, MshOut& out, const MeshData& m) {
  const std::size_t nv = m.positions.size();
  if (std::any_of(m.vertex_refs.begin(), m.vertex_refs.end(), [](std::int32_t r) { return r != 0; })) {
    write_node_data(f, out, std::string(kVertexRefField), 1, nv,
                    [&](std::size_t i, int) { return static_cast<double>(m.vertex_refs[i]); });
  }
  for (const VertexField& fd : m.fields) {
    const std::size_t c = static_cast<std::size_t>(fd.components);
    if (fd.components == 6) {
      write_node_data(f, out, fd.name, 9, nv,
                      [&](std::size_t i, int k) { return fd.values[i * 6 + static_cast<std::size_t>(kFullFromSymmetric[k])]; });
    } else {
      write_node_data(f, out, fd.name, fd.components, nv,
                      [&](std::size_t i, int k) { return fd.values[i * c + static_cast<std::size_t>(k)]; });
    }
  }
}

}  // namespace

MeshData read_gmsh(const std::string& path, const ReadOptions& options, ReadNotes& notes) {
  return GmshReader(path, options, notes).read();
}

void stream_gmsh(const std::string& path, MeditVisitor& visitor, const ReadOptions& options, ReadNotes& notes) {
  GmshReader(path, options, notes, &visitor).stream();
}

void write_gmsh(const std::string& path, const MeshData& m, bool binary, bool msh22) {
  if (msh22 && binary) throw InputError(path + ": Gmsh 2.2 output is ASCII only (drop --binary)");
  for (const CellField& fd : m.cell_fields) {
    if (fd.components > 9) {
      throw InputError(path + ": cannot write cell field '" + fd.name + "' with " + std::to_string(fd.components) +
                       " components (Gmsh views have 1 to 9)");
    }
  }
  for (const VertexField& fd : m.fields) {
    if (fd.components > 9) {
      throw InputError(path + ": cannot write field '" + fd.name + "' with " + std::to_string(fd.components) +
                       " components (Gmsh views have 1 to 9)");
    }
  }
  const GmshPlan plan = plan_gmsh(m);
  AtomicFile f(path);
  MshOut out(f, binary);
  if (msh22) {
    f.put("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
    write_physical_names(f, plan);
    write_nodes22(f, m);
    const std::vector<std::uint64_t> tet_tags = write_elements22(f, plan, m);
    write_fields(f, out, m);
    write_cell_fields(f, out, m, tet_tags);
    f.commit();
    return;
  }
  f.put(binary ? "$MeshFormat\n4.1 1 8\n" : "$MeshFormat\n4.1 0 8\n");
  if (binary) {
    f.put_raw(std::int32_t{1});
    f.put('\n');
  }
  f.put("$EndMeshFormat\n");
  write_physical_names(f, plan);
  write_entities(f, out, plan, m);
  write_nodes(f, out, plan, m);
  const std::vector<std::uint64_t> tet_tags = write_elements(f, out, plan, m);
  write_fields(f, out, m);
  write_cell_fields(f, out, m, tet_tags);
  f.commit();
}

}  // namespace topotet::io

// read_mesh's rules for a .msh's views (topotet/mesh_stream.h), shared with stream visitors.
namespace topotet {

bool exact_int32(double x, std::int32_t& out) {
  if (!(x >= std::numeric_limits<std::int32_t>::min() && x <= std::numeric_limits<std::int32_t>::max())) return false;
  out = static_cast<std::int32_t>(x);
  return x == static_cast<double>(out);
}

bool is_symmetric_3x3(const double* a) { return a[1] == a[3] && a[2] == a[6] && a[5] == a[7]; }

void symmetric_components(const double* a, double* six) {
  const double s[6] = {a[0], a[1], a[4], a[2], a[5], a[8]};
  std::copy(s, s + 6, six);
}

}  // namespace topotet
