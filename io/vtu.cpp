// VTK XML output for ParaView: <path>.vtu (tets, "material" and the cell fields as cell data, one
// point array per field) and, when the mesh lists substructures, <stem>_substructures.vtp (Lines = segments,
// Polys = triangles, "ref" cell data; only the vertices they use); without substructures, a
// companion left from an earlier write is removed. The VTK component (io/vtk/) reads both back.
//
// Binary data either inline as base64 (default: a self-contained, valid XML file) or, with
// WriteOptions::binary, appended raw after the XML (smaller and faster). Both use UInt64 block
// headers; for base64 the header is encoded together with the data, as VTK's own writer does.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <functional>
#include <string>
#include <unordered_map>

#include "io/atomic_file.h"
#include "io/formats.h"
#include "io/xml_escape.h"

namespace topotet::io {
namespace {

static_assert(sizeof(std::array<double, 3>) == 24, "positions are written as packed xyz doubles");

// Where array bytes go: straight to the file, or through a base64 encoder.
class ByteSink {
 public:
  virtual ~ByteSink() = default;
  virtual void put(const void* data, std::size_t n) = 0;
  template <class T>
  void put_value(T v) {
    put(&v, sizeof v);
  }
};

class RawSink final : public ByteSink {
 public:
  explicit RawSink(AtomicFile& f) : f_(f) {}
  void put(const void* data, std::size_t n) override { f_.put_bytes(data, n); }

 private:
  AtomicFile& f_;
};

class Base64Sink final : public ByteSink {
 public:
  explicit Base64Sink(AtomicFile& f) : f_(f) {}
  ~Base64Sink() override = default;
  void put(const void* data, std::size_t n) override {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) {
      carry_[carried_++] = p[i];
      if (carried_ == 3) emit(3);
    }
  }
  // Pads the last group; call once, at the end of the encoded block.
  void finish() {
    if (carried_ > 0) emit(carried_);
    if (len_ > 0) f_.put(std::string_view(out_.data(), len_));
    len_ = 0;
  }

 private:
  void emit(int n) {
    static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (int k = n; k < 3; ++k) carry_[k] = 0;
    const unsigned v = (unsigned{carry_[0]} << 16) | (unsigned{carry_[1]} << 8) | carry_[2];
    out_[len_++] = kAlphabet[(v >> 18) & 63];
    out_[len_++] = kAlphabet[(v >> 12) & 63];
    out_[len_++] = n > 1 ? kAlphabet[(v >> 6) & 63] : '=';
    out_[len_++] = n > 2 ? kAlphabet[v & 63] : '=';
    carried_ = 0;
    if (len_ == out_.size()) {
      f_.put(std::string_view(out_.data(), len_));
      len_ = 0;
    }
  }

  AtomicFile& f_;
  std::array<unsigned char, 3> carry_{};
  int carried_ = 0;
  std::array<char, 4096> out_{};  // a multiple of 4
  std::size_t len_ = 0;
};

struct DataArray {
  std::string type;  // VTK type name
  std::string name;  // empty for Points
  int components;
  std::uint64_t bytes;
  std::function<void(ByteSink&)> emit;
};

// Writes one XML file whose arrays are grouped under the given section tags.
class VtkXmlWriter {
 public:
  VtkXmlWriter(AtomicFile& f, bool appended) : f_(f), appended_(appended) {}

  void array(const DataArray& a) {
    f_.put("        <DataArray type=\"" + a.type + "\"");
    if (!a.name.empty()) f_.put(" Name=\"" + a.name + "\"");
    if (a.components != 1) f_.put(" NumberOfComponents=\"" + std::to_string(a.components) + "\"");
    if (appended_) {
      f_.put(" format=\"appended\" offset=\"" + std::to_string(offset_) + "\"/>\n");
      offset_ += 8 + a.bytes;
      pending_.push_back(&a);
      return;
    }
    f_.put(" format=\"binary\">\n          ");
    // Header and data form one base64 stream: VTK seeks into it by decoded byte offset (poly
    // data cell arrays are read in parts), which only works when nothing pads the header.
    Base64Sink sink(f_);
    sink.put_value(a.bytes);
    a.emit(sink);
    sink.finish();
    f_.put("\n        </DataArray>\n");
  }

  // Appended data goes after the XML tree, before </VTKFile>.
  void finish() {
    if (appended_ && !pending_.empty()) {
      f_.put("  <AppendedData encoding=\"raw\">\n   _");
      RawSink sink(f_);
      for (const DataArray* a : pending_) {
        sink.put_value(a->bytes);
        a->emit(sink);
      }
      f_.put("\n  </AppendedData>\n");
    }
    f_.put("</VTKFile>\n");
  }

 private:
  AtomicFile& f_;
  bool appended_;
  std::uint64_t offset_ = 0;
  std::vector<const DataArray*> pending_;  // must outlive finish()
};


std::string header(const char* type) {
  return std::string("<?xml version=\"1.0\"?>\n<VTKFile type=\"") + type +
         "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
}

void write_vtp(AtomicFile& f, const MeshData& m, bool appended) {
  // Only the vertices the substructures use, renumbered in order of first use.
  std::unordered_map<VertId, std::int64_t> local;
  std::vector<VertId> used;
  const auto id = [&](VertId v) {
    auto [it, fresh] = local.try_emplace(v, static_cast<std::int64_t>(used.size()));
    if (fresh) used.push_back(v);
    return it->second;
  };
  std::vector<std::int64_t> lines, polys;
  lines.reserve(2 * m.segments.size());
  polys.reserve(3 * m.triangles.size());
  for (const Segment& s : m.segments)
    for (VertId v : s.v) lines.push_back(id(v));
  for (const Triangle& t : m.triangles)
    for (VertId v : t.v) polys.push_back(id(v));

  const auto offsets = [](std::size_t count, std::int64_t per) {
    return [count, per](ByteSink& s) {
      for (std::size_t i = 0; i < count; ++i) s.put_value(static_cast<std::int64_t>(i + 1) * per);
    };
  };
  const DataArray ref{"Int32", "ref", 1, 4 * (m.segments.size() + m.triangles.size()), [&](ByteSink& s) {
                        // Cell order in a vtp: verts, lines, polys, strips.
                        for (const Segment& x : m.segments) s.put_value(x.ref);
                        for (const Triangle& x : m.triangles) s.put_value(x.ref);
                      }};
  const DataArray points{"Float64", "", 3, 24 * used.size(), [&](ByteSink& s) {
                           for (VertId v : used) s.put(&m.positions[v], 24);
                         }};
  const DataArray line_conn{"Int64", "connectivity", 1, 8 * lines.size(),
                            [&](ByteSink& s) { s.put(lines.data(), 8 * lines.size()); }};
  const DataArray line_off{"Int64", "offsets", 1, 8 * m.segments.size(), offsets(m.segments.size(), 2)};
  const DataArray poly_conn{"Int64", "connectivity", 1, 8 * polys.size(),
                            [&](ByteSink& s) { s.put(polys.data(), 8 * polys.size()); }};
  const DataArray poly_off{"Int64", "offsets", 1, 8 * m.triangles.size(), offsets(m.triangles.size(), 3)};

  VtkXmlWriter w(f, appended);
  f.put(header("PolyData"));
  f.put("  <PolyData>\n    <Piece NumberOfPoints=\"" + std::to_string(used.size()) + "\" NumberOfVerts=\"0\" NumberOfLines=\"" +
        std::to_string(m.segments.size()) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
        std::to_string(m.triangles.size()) + "\">\n");
  f.put("      <CellData Scalars=\"ref\">\n");
  w.array(ref);
  f.put("      </CellData>\n      <Points>\n");
  w.array(points);
  f.put("      </Points>\n");
  if (!m.segments.empty()) {
    f.put("      <Lines>\n");
    w.array(line_conn);
    w.array(line_off);
    f.put("      </Lines>\n");
  }
  if (!m.triangles.empty()) {
    f.put("      <Polys>\n");
    w.array(poly_conn);
    w.array(poly_off);
    f.put("      </Polys>\n");
  }
  f.put("    </Piece>\n  </PolyData>\n");
  w.finish();
}

}  // namespace

void write_vtu(const std::string& path, const MeshData& m, bool binary) {
  const std::size_t nv = m.positions.size(), nt = m.tets.size();
  std::vector<DataArray> fields;
  for (const VertexField& fd : m.fields) {
    fields.push_back({"Float64", io::xml_escape(fd.name), fd.components, 8 * fd.values.size(),
                      [&fd](ByteSink& s) { s.put(fd.values.data(), 8 * fd.values.size()); }});
  }
  // Cell fields: labels as Int32 (VTK readers make integer arrays categorical again), the others as
  // Float64; a label with a value that is not an int32 stays Float64.
  std::vector<DataArray> cell_arrays;
  for (const CellField& cf : m.cell_fields) {
    const bool as_int = cf.kind == CellFieldKind::kCategorical &&
                        std::all_of(cf.values.begin(), cf.values.end(), [](double x) {
                          return x == std::trunc(x) && x >= std::numeric_limits<std::int32_t>::min() &&
                                 x <= std::numeric_limits<std::int32_t>::max();
                        });
    if (as_int) {
      cell_arrays.push_back({"Int32", io::xml_escape(cf.name), cf.components, 4 * cf.values.size(), [&cf](ByteSink& s) {
                               for (double x : cf.values) s.put_value(static_cast<std::int32_t>(x));
                             }});
    } else {
      cell_arrays.push_back({"Float64", io::xml_escape(cf.name), cf.components, 8 * cf.values.size(),
                             [&cf](ByteSink& s) { s.put(cf.values.data(), 8 * cf.values.size()); }});
    }
  }
  const DataArray material{"Int32", "material", 1, 4 * nt, [&](ByteSink& s) {
                             if (m.tet_material.empty()) {
                               for (std::size_t i = 0; i < nt; ++i) s.put_value(std::int32_t{0});
                             } else {
                               s.put(m.tet_material.data(), 4 * nt);
                             }
                           }};
  const DataArray points{"Float64", "", 3, 24 * nv, [&](ByteSink& s) { s.put(m.positions.data(), 24 * nv); }};
  const DataArray conn{"Int64", "connectivity", 1, 32 * nt, [&](ByteSink& s) {
                         for (const auto& t : m.tets)
                           for (VertId v : t) s.put_value(static_cast<std::int64_t>(v));
                       }};
  const DataArray offsets{"Int64", "offsets", 1, 8 * nt, [&](ByteSink& s) {
                            for (std::size_t i = 0; i < nt; ++i) s.put_value(static_cast<std::int64_t>(4 * (i + 1)));
                          }};
  const DataArray types{"UInt8", "types", 1, nt, [&](ByteSink& s) {
                          for (std::size_t i = 0; i < nt; ++i) s.put_value(std::uint8_t{10});  // VTK_TETRA
                        }};

  AtomicFile f(path);
  VtkXmlWriter w(f, binary);
  f.put(header("UnstructuredGrid"));
  f.put("  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" + std::to_string(nv) + "\" NumberOfCells=\"" +
        std::to_string(nt) + "\">\n");
  if (!fields.empty()) {
    f.put("      <PointData>\n");
    for (const DataArray& a : fields) w.array(a);
    f.put("      </PointData>\n");
  }
  f.put("      <CellData Scalars=\"material\">\n");
  w.array(material);
  for (const DataArray& a : cell_arrays) w.array(a);
  f.put("      </CellData>\n      <Points>\n");
  w.array(points);
  f.put("      </Points>\n      <Cells>\n");
  w.array(conn);
  w.array(offsets);
  w.array(types);
  f.put("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n");
  w.finish();

  // A stream or device has no folder for the companion .vtp: the substructures stay out of it.
  if (f.is_direct()) {
    f.commit();
    return;
  }
  std::string stem = path;
  if (iends_with(stem, ".vtu")) stem.resize(stem.size() - 4);
  const std::string companion = stem + "_substructures.vtp";
  if (m.triangles.empty() && m.segments.empty()) {
    f.commit();
    // A companion left from an earlier write of this stem would be read back with the new mesh
    // (the VTK reader, topotet/io_vtk.h, attaches it).
    std::error_code ec;
    std::filesystem::remove(companion, ec);
    return;
  }
  AtomicFile sub(companion);
  write_vtp(sub, m, binary);
  commit_all({&f, &sub});
}

}  // namespace topotet::io
