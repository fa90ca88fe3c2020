// The .tth hierarchy file (docs/formats.md): binary, little-endian, versioned.
//
//   "TOPOTETH" u32 version(=1) u32 flags(=0)
//   original mesh:  u64 V, f64[3V] positions; u64 R (0 or V), i32[R] vertex refs;
//                   u64 T, u32[4T] tets, i32[T] materials;
//                   u64 S, {u32[3] v, i32 ref}[S] triangles; u64 G, {u32[2] v, i32 ref}[G] segments;
//                   u64, u32[] ridges; u64, u32[] corners; u64, u32[] required vertices;
//                   u64 F, F x {u32 n, char[n] name, i32 components, f64[V*components] values};
//                   u64 N, N x {i32 dim, i32 ref, u32 n, char[n] name} group names
//   collapses:      u64 C, u32 field stride K;
//                   u32[C] u, u32[C] v, f64[3C] u before, f64[3C] u after, f64[3C] v position,
//                   f64[C*K] fields before, f64[C*K] fields after, f64[C] cost, f32[C] error bound,
//                   u32[C+1] parent offsets, u32[offsets[C]] parents
//   "TTH_END!"
// Hierarchy::error is not stored: it is the running maximum of the costs.
// Reading checks every count against the bytes left before allocating, so a truncated or lying
// file is an InputError naming the file and the byte offset, never a crash or a huge allocation.
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>
#include <limits>

#include "hierarchy/hierarchy_log.h"
#include "io/atomic_file.h"
#include "io/tth_layout.h"
#include "topotet/error.h"
#include "topotet/hierarchy.h"

namespace topotet {
namespace {


using io::tth::kEnd;
using io::tth::kMagic;
using io::tth::kVersion;

class Writer {
 public:
  explicit Writer(io::AtomicFile& file) : file_(file) {}
  template <class T>
  void value(const T& x) {
    file_.put(std::string_view(reinterpret_cast<const char*>(&x), sizeof(T)));
  }
  template <class T>
  void raw(const T* data, std::size_t count) {
    file_.put(std::string_view(reinterpret_cast<const char*>(data), count * sizeof(T)));
  }
  template <class T>
  void counted(const std::vector<T>& v) {
    value<std::uint64_t>(v.size());
    raw(v.data(), v.size());
  }
  void text(const std::string& s) {
    value<std::uint32_t>(static_cast<std::uint32_t>(s.size()));
    raw(s.data(), s.size());
  }

 private:
  io::AtomicFile& file_;
};

// Reads the file as a stream, straight into the arrays (the file is as large as the hierarchy it
// holds: reading it whole first would hold it twice). Every count is checked against the bytes
// left before anything is allocated.
class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {
    auto file = std::make_unique<std::ifstream>(path_, std::ios::binary);
    if (!*file) throw InputError(path_ + ": cannot open");
    file->seekg(0, std::ios::end);
    const std::streamoff end = file->tellg();
    if (end >= 0 && file->seekg(0, std::ios::beg)) {
      size_ = static_cast<std::uint64_t>(end);
      in_ = std::move(file);
    } else {  // not seekable (a pipe): read it whole first
      file->clear();
      std::string bytes((std::istreambuf_iterator<char>(*file)), std::istreambuf_iterator<char>());
      if (file->bad()) throw InputError(path_ + ": read error");
      size_ = bytes.size();
      in_ = std::make_unique<std::istringstream>(std::move(bytes));
    }
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_ + ": byte " + std::to_string(offset_) + ": " + what);
  }
  void need(std::uint64_t count, std::uint64_t size, const char* what) {
    const std::uint64_t left = size_ - offset_;
    if (size != 0 && count > left / size)
      fail(std::string("truncated: ") + what + " needs " + std::to_string(count) + " x " + std::to_string(size) +
           " bytes, " + std::to_string(left) + " left");
  }
  template <class T>
  T value(const char* what) {
    T x;
    raw(&x, 1, what);
    return x;
  }
  template <class T>
  void raw(T* data, std::size_t count, const char* what) {
    need(count, sizeof(T), what);
    if (count == 0) return;
    const auto bytes = static_cast<std::streamsize>(count * sizeof(T));
    if (!in_->read(reinterpret_cast<char*>(data), bytes) || in_->gcount() != bytes)
      fail(std::string("read error in ") + what + " (was the file changed while it was read?)");
    offset_ += static_cast<std::uint64_t>(bytes);
  }
  template <class T>
  std::vector<T> array(std::uint64_t count, const char* what) {
    need(count, sizeof(T), what);
    std::vector<T> v(count);
    raw(v.data(), count, what);
    return v;
  }
  template <class T>
  std::vector<T> counted(const char* what) {
    return array<T>(value<std::uint64_t>(what), what);
  }
  std::string text(const char* what) {
    const auto n = value<std::uint32_t>(what);
    need(n, 1, what);
    std::string s(n, '\0');
    raw(s.data(), n, what);
    return s;
  }
  std::uint64_t offset() const { return offset_; }
  std::uint64_t size() const { return size_; }

 private:
  std::string path_;
  std::unique_ptr<std::istream> in_;
  std::uint64_t size_ = 0;
  std::uint64_t offset_ = 0;
};

}  // namespace

void write_hierarchy(const std::string& path, const Hierarchy& h) {
  validate_hierarchy(h, path);
  io::AtomicFile file(path);
  Writer w(file);
  const MeshData& m = h.original;
  io::tth::write_header(file);
  w.counted(m.positions);
  w.counted(m.vertex_refs);
  w.counted(m.tets);
  w.raw(m.tet_material.data(), m.tet_material.size());
  w.value<std::uint64_t>(m.triangles.size());
  for (const Triangle& t : m.triangles) {
    w.raw(t.v.data(), 3);
    w.value(t.ref);
  }
  w.value<std::uint64_t>(m.segments.size());
  for (const Segment& s : m.segments) {
    w.raw(s.v.data(), 2);
    w.value(s.ref);
  }
  w.counted(m.ridges);
  w.counted(m.corners);
  w.counted(m.required_vertices);
  w.value<std::uint64_t>(m.fields.size());
  for (const VertexField& f : m.fields) {
    w.text(f.name);
    w.value<std::int32_t>(f.components);
    w.raw(f.values.data(), f.values.size());
  }
  w.value<std::uint64_t>(m.group_names.size());
  for (const GroupName& g : m.group_names) {
    w.value<std::int32_t>(g.dim);
    w.value(g.ref);
    w.text(g.name);
  }
  const std::size_t n = h.collapse_count();
  w.value<std::uint64_t>(n);
  w.value<std::uint32_t>(static_cast<std::uint32_t>(h.field_stride));
  w.raw(h.u.data(), n);
  w.raw(h.v.data(), n);
  w.raw(h.u_before.data(), n);
  w.raw(h.u_after.data(), n);
  w.raw(h.v_position.data(), n);
  w.raw(h.fields_before.data(), h.fields_before.size());
  w.raw(h.fields_after.data(), h.fields_after.size());
  w.raw(h.cost.data(), n);
  w.raw(h.error_bound.data(), n);
  w.raw(h.parent_offsets.data(), n + 1);
  w.raw(h.parents.data(), h.parents.size());
  io::tth::write_end(file);
  file.commit();
}

std::uint64_t hierarchy_collapse_bytes(const Hierarchy& h) {
  const std::uint64_t n = h.collapse_count();
  const std::uint64_t per_collapse = 2 * sizeof(VertId) + 3 * sizeof(std::array<double, 3>) + sizeof(double) + sizeof(float) +
                                     2 * sizeof(double) * static_cast<std::uint64_t>(h.field_stride);
  return sizeof(std::uint64_t) + sizeof(std::uint32_t) + n * per_collapse + (n + 1) * sizeof(std::uint32_t) +
         h.parents.size() * sizeof(std::uint32_t);
}

Hierarchy read_hierarchy(const std::string& path) {
  Reader r(path);
  char magic[8];
  r.raw(magic, 8, "the magic number");
  if (std::memcmp(magic, kMagic, 8) != 0) r.fail("not a topotet hierarchy (.tth) file: bad magic number");
  const auto version = r.value<std::uint32_t>("the version");
  if (version != kVersion)
    r.fail("format version " + std::to_string(version) + ", this topotet reads version " + std::to_string(kVersion));
  r.value<std::uint32_t>("the flags");
  Hierarchy h;
  MeshData& m = h.original;
  m.positions = r.counted<std::array<double, 3>>("positions");
  m.vertex_refs = r.counted<std::int32_t>("vertex refs");
  m.tets = r.counted<std::array<VertId, 4>>("tets");
  m.tet_material = r.array<std::int32_t>(m.tets.size(), "tet materials");
  const auto triangle_count = r.value<std::uint64_t>("the triangle count");
  r.need(triangle_count, 16, "triangles");
  m.triangles.resize(triangle_count);
  for (Triangle& t : m.triangles) {
    r.raw(t.v.data(), 3, "triangles");
    t.ref = r.value<std::int32_t>("triangles");
  }
  const auto segment_count = r.value<std::uint64_t>("the segment count");
  r.need(segment_count, 12, "segments");
  m.segments.resize(segment_count);
  for (Segment& s : m.segments) {
    r.raw(s.v.data(), 2, "segments");
    s.ref = r.value<std::int32_t>("segments");
  }
  m.ridges = r.counted<std::uint32_t>("ridges");
  m.corners = r.counted<VertId>("corners");
  m.required_vertices = r.counted<VertId>("required vertices");
  const auto field_count = r.value<std::uint64_t>("the field count");
  r.need(field_count, 8, "fields");
  int stride = 0;
  for (std::uint64_t f = 0; f < field_count; ++f) {
    VertexField field;
    field.name = r.text("a field name");
    field.components = r.value<std::int32_t>("field components");
    if (field.components < 1 || field.components > 1024)
      r.fail("field '" + field.name + "': " + std::to_string(field.components) + " components");
    stride += field.components;
    field.values = r.array<double>(m.positions.size() * static_cast<std::uint64_t>(field.components), "field values");
    m.fields.push_back(std::move(field));
  }
  const auto group_count = r.value<std::uint64_t>("the group name count");
  r.need(group_count, 12, "group names");
  for (std::uint64_t g = 0; g < group_count; ++g) {
    GroupName name;
    name.dim = r.value<std::int32_t>("group names");
    name.ref = r.value<std::int32_t>("group names");
    name.name = r.text("group names");
    m.group_names.push_back(std::move(name));
  }
  const auto n = r.value<std::uint64_t>("the collapse count");
  h.field_stride = static_cast<int>(r.value<std::uint32_t>("the field stride"));
  if (h.field_stride != stride)
    r.fail("field stride " + std::to_string(h.field_stride) + " differs from the fields' " + std::to_string(stride) +
           " components");
  if (n >= std::numeric_limits<std::uint32_t>::max()) r.fail("too many collapses: " + std::to_string(n));
  const std::uint64_t sn = n * static_cast<std::uint64_t>(stride);
  h.u = r.array<VertId>(n, "collapse u");
  h.v = r.array<VertId>(n, "collapse v");
  h.u_before = r.array<std::array<double, 3>>(n, "u positions before");
  h.u_after = r.array<std::array<double, 3>>(n, "u positions after");
  h.v_position = r.array<std::array<double, 3>>(n, "v positions");
  h.fields_before = r.array<double>(sn, "fields before");
  h.fields_after = r.array<double>(sn, "fields after");
  h.cost = r.array<double>(n, "costs");
  h.error_bound = r.array<float>(n, "error bounds");
  h.parent_offsets = r.array<std::uint32_t>(n + 1, "parent offsets");
  h.parents = r.array<std::uint32_t>(h.parent_offsets.back(), "parents");
  char end[8];
  r.raw(end, 8, "the end marker");
  if (std::memcmp(end, kEnd, 8) != 0) r.fail("bad end marker (corrupt file)");
  if (r.offset() != r.size()) r.fail(std::to_string(r.size() - r.offset()) + " bytes after the end marker");
  detail::fill_running_error(h);
  validate_hierarchy(h, path);
  return h;
}

}  // namespace topotet
