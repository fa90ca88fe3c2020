// The streaming cut (cut.h has the steps).
#include "cut.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "mesh/morton.h"
#include "field_views.h"
#include "hierarchy_spool.h"
#include "piece.h"
#include "topotet/cell_fields.h"
#include "topotet/error.h"
#include "topotet/io.h"
#include "topotet/medit_stream.h"
#include "topotet/mesh_stream.h"

namespace topotet::ooc {

namespace {

constexpr int kBinBits = 18;

struct TetRecord {
  std::array<VertId, 4> v;
  std::int32_t material;
  std::uint32_t bin;  // the top kBinBits of the Morton code of its centroid
};

// The mesh pass: what the cut keeps of the input, and the tets spilled with their bins.
class MeshPass final : public MeditVisitor {
 public:
  MeshPass(const std::string& input, ScratchFolder& scratch)
      : node_views(scratch.file_path("node-data.bin")),
        cell_views(scratch.file_path("element-data.bin")),
        input_(input),
        tets_(scratch.file_path("tets.bin")) {}

  void begin_vertices(std::uint64_t count) override { begin_vertices_holding(count, 0); }
  bool begin_vertices_holding(std::uint64_t count, std::uint64_t reader_bytes) override {
    // A count checked against the memory limit (with what the reader holds beside: a .msh's node
    // tag map) is reserved whole: growing by doubling would hold the old and the new arrays at
    // once (three times the positions) and keep up to twice the room. Unchecked, the declared
    // count may lie (a truncated or hostile file): a bounded amount.
    const bool checked = on_vertex_count && on_vertex_count(count, reader_bytes);
    const std::uint64_t reserve = checked ? count : std::min<std::uint64_t>(count, 1u << 22);
    positions.reserve(reserve);
    refs.reserve(reserve);
    return checked;
  }
  void vertex(const std::array<double, 3>& p, std::int32_t ref) override {
    positions.push_back(p);
    refs.push_back(ref);
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  void begin_tets(std::uint64_t) override {
    for (int k = 0; k < 3; ++k) scale_[k] = hi[k] > lo[k] ? double(1u << 21) / (hi[k] - lo[k]) : 0.0;
  }
  void tet(const std::array<VertId, 4>& v, std::int32_t material) override {
    std::uint64_t code = 0;
    code_and_volume(v, code);
    TetRecord r{v, material, static_cast<std::uint32_t>(code >> (63 - kBinBits))};
    tets_.put(r);
    ++histogram[r.bin];
    ++tet_count;
  }
  void triangle(const Triangle& t) override { triangles.push_back(t); }
  void segment(const Segment& s) override { segments.push_back(s); }
  void corner(VertId v) override { corners.push_back(v); }
  void required_vertex(VertId v) override { required.push_back(v); }
  void ridge(std::uint32_t s) override { ridges.push_back(s); }
  // A .msh's $NodeData and $ElementData: spilled, read back in order after the pass (field_views.h).
  bool begin_node_view(const std::string& name, int components) override {
    node_views.begin(name, components, positions.size());
    return true;
  }
  void node_values(VertId v, const double* values) override { node_views.values(v, values); }
  bool begin_cell_view(const std::string& name, int components) override {
    cell_views.begin(name, components, tet_count);
    return true;
  }
  void cell_values(std::uint64_t t, const double* values) override { cell_views.values(t, values); }

  void finish() { tets_.close(); }

  std::function<bool(std::uint64_t, std::uint64_t)> on_vertex_count;
  std::vector<std::array<double, 3>> positions;
  std::vector<std::int32_t> refs;
  std::vector<Triangle> triangles;
  std::vector<Segment> segments;
  std::vector<VertId> corners, required;
  std::vector<std::uint32_t> ridges;
  FieldViews node_views, cell_views;
  std::vector<std::uint64_t> histogram = std::vector<std::uint64_t>(std::size_t{1} << kBinBits, 0);
  std::uint64_t tet_count = 0;
  double volume = 0.0;
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity()};

 private:
  // The Morton code of the tet's centroid, and its volume added to the total (the cost units' mean).
  void code_and_volume(const std::array<VertId, 4>& v, std::uint64_t& code) {
    const auto& a = positions[v[0]];
    const auto& b = positions[v[1]];
    const auto& c = positions[v[2]];
    const auto& d = positions[v[3]];
    std::uint64_t q[3];
    for (int k = 0; k < 3; ++k) {
      const double centre = 0.25 * (a[k] + b[k] + c[k] + d[k]);
      const double x = (centre - lo[k]) * scale_[k];
      q[k] = static_cast<std::uint64_t>(std::clamp(x, 0.0, double((1u << 21) - 1)));
    }
    code = morton_code(q[2], q[1], q[0]);  // the first axis in the highest bit of each triple
    const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double e3[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    volume += std::abs(e1[0] * (e2[1] * e3[2] - e2[2] * e3[1]) - e1[1] * (e2[0] * e3[2] - e2[2] * e3[0]) +
                       e1[2] * (e2[0] * e3[1] - e2[1] * e3[0])) /
              6.0;
  }

  std::string input_;
  ScratchWriter tets_;
  double scale_[3] = {0, 0, 0};
};

// Reads field values of sorted global vertices from the spilled vertex fields, a window at a time.
class FieldWindow {
 public:
  FieldWindow(const std::string& path, int stride) : path_(path), stride_(stride) {
    if (stride_ == 0) return;
    fd_ = ::open(path.c_str(), O_RDONLY);
    if (fd_ < 0) throw InputError("scratch file " + path + ": cannot open: " + std::strerror(errno));
  }
  ~FieldWindow() {
    if (fd_ >= 0) ::close(fd_);
  }
  // The values of vertex g (ids asked in increasing order).
  const double* at(std::uint64_t g) {
    if (g < first_ || g >= first_ + count_) {
      constexpr std::uint64_t kWindow = 4096;
      buf_.resize(kWindow * stride_);
      const ssize_t got = ::pread(fd_, buf_.data(), buf_.size() * sizeof(double),
                                  static_cast<off_t>(g * stride_ * sizeof(double)));
      if (got < static_cast<ssize_t>(stride_ * sizeof(double)))
        throw InputError("scratch file " + path_ + ": truncated (was it changed while the run went on?)");
      first_ = g;
      count_ = static_cast<std::uint64_t>(got) / (stride_ * sizeof(double));
    }
    return buf_.data() + (g - first_) * stride_;
  }

 private:
  std::string path_;
  int stride_;
  int fd_ = -1;
  std::vector<double> buf_;
  std::uint64_t first_ = 0, count_ = 0;
};

// The input as read, for a hierarchy file (hierarchy_spool.h): from what the mesh pass keeps, its
// tet spill (read twice: tets, then materials) and the spilled vertex fields.
void write_original(HierarchySpool& out, const MeshPass& pass, const ScratchFolder& scratch,
                    const std::vector<VertexField>& fields, const InputCounts& counts) {
  out.original_vertices(pass.positions, pass.refs);
  out.original_tet_count(counts.tets);
  for (int part = 0; part < 2; ++part) {
    ScratchReader tets(scratch.file_path("tets.bin"));
    for (std::uint64_t t = 0; t < counts.tets; ++t) {
      const TetRecord r = tets.get<TetRecord>();
      if (part == 0) out.original_tet(r.v);
      else out.original_material(r.material);
    }
  }
  out.original_listed(pass.triangles, pass.segments, pass.ridges, pass.corners, pass.required);
  out.original_fields(fields, scratch.file_path("vertex-fields.bin"), counts.vertex_stride, counts.vertices);
  out.original_done();
}

}  // namespace

CutResult cut_input(const std::string& input, ScratchFolder& scratch,
                    const std::function<std::uint32_t(const InputCounts&)>& choose_pieces,
                    const std::function<void(const std::string&)>& log,
                    const std::function<bool(std::uint64_t, std::uint64_t)>& on_vertex_count,
                    const CellRemapOptions& cell_kinds, HierarchySpool* original) {
  using Clock = std::chrono::steady_clock;
  const auto say = [&](const std::string& s) {
    if (log) log(s);
  };
  CutResult result;
  MeshPass pass(input, scratch);
  pass.on_vertex_count = on_vertex_count;
  {
    ReadOptions read_options;
    ReadNotes notes;
    const auto t0 = Clock::now();
    stream_mesh(input, pass, read_options, notes);
    pass.finish();
    say("read " + std::to_string(pass.positions.size()) + " vertices, " + std::to_string(pass.tet_count) + " tets in " +
        std::to_string(std::chrono::duration<double>(Clock::now() - t0).count()) + " s");
  }
  InputCounts& counts = result.counts;
  counts.vertices = pass.positions.size();
  counts.tets = pass.tet_count;
  counts.triangles = pass.triangles.size();
  counts.segments = pass.segments.size();
  if (counts.tets == 0) throw InputError(input + ": no tetrahedra");
  if (counts.vertices >= std::numeric_limits<GlobalId>::max())
    throw InputError(input + ": more than 2^32 - 1 vertices");

  // The fields, spilled in vertex (tet) order: a MEDIT file's from its .sol, streamed too; a
  // .msh's views from their spill, as read_mesh gives them (field_views.h).
  std::unique_ptr<SolStream> sol;
  std::function<void(double*)> next_vertex_values, next_tet_values;
  if (format_from_path(input) == MeshFormat::kMedit) sol = std::make_unique<SolStream>(input, counts.vertices, counts.tets);
  if (sol != nullptr && sol->has_sol()) {
    result.vertex_fields = sol->vertex_fields();
    result.cell_fields = sol->cell_fields();
    counts.vertex_stride = sol->vertex_stride();
    counts.cell_stride = sol->cell_stride();
    next_vertex_values = [&sol](double* values) { sol->next_vertex(values); };
    next_tet_values = [&sol](double* values) { sol->next_tet(values); };
  }
  if (!pass.node_views.empty()) {
    pass.node_views.finish(&pass.refs);
    for (const FieldViews::Layout& l : pass.node_views.fields()) result.vertex_fields.push_back({l.name, l.components, {}});
    counts.vertex_stride = pass.node_views.stride();
    next_vertex_values = [&pass](double* values) { pass.node_views.next(values); };
  }
  if (!pass.cell_views.empty()) {
    pass.cell_views.finish(nullptr);
    for (const FieldViews::Layout& l : pass.cell_views.fields())
      result.cell_fields.push_back({l.name, l.components, CellFieldKind::kIntensive, {}});
    counts.cell_stride = pass.cell_views.stride();
    next_tet_values = [&pass](double* values) { pass.cell_views.next(values); };
  }
  apply_cell_kinds(result.cell_fields, cell_kinds);  // an unknown name fails here, before the pieces
  std::vector<double> fmin(counts.vertex_stride, std::numeric_limits<double>::infinity());
  std::vector<double> fmax(counts.vertex_stride, -std::numeric_limits<double>::infinity());
  if (counts.vertex_stride > 0) {
    ScratchWriter out(scratch.file_path("vertex-fields.bin"));
    std::vector<double> values(counts.vertex_stride);
    for (std::uint64_t v = 0; v < counts.vertices; ++v) {
      next_vertex_values(values.data());
      for (int k = 0; k < counts.vertex_stride; ++k) {
        fmin[k] = std::min(fmin[k], values[k]);
        fmax[k] = std::max(fmax[k], values[k]);
      }
      out.write(values.data(), values.size() * sizeof(double));
    }
    out.close();
  }
  if (counts.cell_stride > 0) {
    ScratchWriter out(scratch.file_path("tet-fields.bin"));
    std::vector<double> values(counts.cell_stride);
    for (std::uint64_t t = 0; t < counts.tets; ++t) {
      next_tet_values(values.data());
      out.write(values.data(), values.size() * sizeof(double));
    }
    out.close();
  }

  if (original != nullptr) write_original(*original, pass, scratch, result.vertex_fields, counts);

  // Units of the whole input (CostUnits; field order = field_stride order = the .sol's).
  CostUnits& units = result.units;
  for (int k = 0; k < 3; ++k) units.origin[k] = pass.lo[k];
  result.diagonal = std::sqrt((pass.hi[0] - pass.lo[0]) * (pass.hi[0] - pass.lo[0]) +
                              (pass.hi[1] - pass.lo[1]) * (pass.hi[1] - pass.lo[1]) +
                              (pass.hi[2] - pass.lo[2]) * (pass.hi[2] - pass.lo[2]));
  units.diagonal = result.diagonal;
  units.mean_tet_volume = pass.volume / static_cast<double>(counts.tets);
  for (int k = 0; k < counts.vertex_stride; ++k) {
    units.field_min.push_back(fmin[k]);
    units.field_range.push_back(fmax[k] - fmin[k]);
  }
  if (!(units.diagonal > 0.0) || !(units.mean_tet_volume > 0.0))
    throw InputError(input + ": the mesh has no volume (every tet is flat)");

  // Split the Morton bins into ranges of about equal tet counts.
  const std::uint32_t pieces = choose_pieces(counts);
  result.pieces = pieces;
  std::vector<std::uint32_t> first_bin_after(pieces);  // [piece] one past its last bin
  {
    std::uint64_t seen = 0;
    std::uint32_t piece = 0;
    for (std::uint32_t b = 0; b < pass.histogram.size(); ++b) {
      seen += pass.histogram[b];
      while (piece + 1 < pieces && seen * pieces >= (piece + 1) * counts.tets) first_bin_after[piece++] = b + 1;
    }
    for (; piece < pieces; ++piece) first_bin_after[piece] = static_cast<std::uint32_t>(pass.histogram.size());
  }
  pass.histogram = {};

  // Distribute the tets (and their field values) to the pieces' buckets.
  result.piece_tets.assign(pieces, 0);
  {
    std::vector<std::unique_ptr<ScratchWriter>> buckets(pieces);
    for (std::uint32_t p = 0; p < pieces; ++p) buckets[p] = std::make_unique<ScratchWriter>(scratch.bucket_path(p));
    ScratchReader tets(scratch.file_path("tets.bin"));
    std::unique_ptr<ScratchReader> cells;
    if (counts.cell_stride > 0) cells = std::make_unique<ScratchReader>(scratch.file_path("tet-fields.bin"));
    std::vector<double> values(counts.cell_stride);
    for (std::uint64_t t = 0; t < counts.tets; ++t) {
      const TetRecord r = tets.get<TetRecord>();
      if (cells) cells->read(values.data(), values.size() * sizeof(double));
      const std::uint32_t p = static_cast<std::uint32_t>(
          std::upper_bound(first_bin_after.begin(), first_bin_after.end(), r.bin) - first_bin_after.begin());
      buckets[p]->put(r);
      buckets[p]->write(values.data(), values.size() * sizeof(double));
      ++result.piece_tets[p];
    }
    for (auto& b : buckets) b->close();
  }
  ::unlink(scratch.file_path("tets.bin").c_str());
  ::unlink(scratch.file_path("tet-fields.bin").c_str());

  // Build the pieces.
  result.holders.assign(counts.vertices, 0);
  result.used_min.assign(counts.vertex_stride, std::numeric_limits<double>::infinity());
  result.used_max.assign(counts.vertex_stride, -std::numeric_limits<double>::infinity());
  result.used_magnitude.assign(counts.vertex_stride, 0.0);
  std::vector<VertId> local(counts.vertices, kInvalid);
  std::vector<std::uint8_t> triangle_held(pass.triangles.size(), 0), segment_held(pass.segments.size(), 0);
  FieldWindow vertex_fields(counts.vertex_stride > 0 ? scratch.file_path("vertex-fields.bin") : std::string(),
                            counts.vertex_stride);
  for (std::uint32_t p = 0; p < pieces; ++p) {
    Piece piece;
    MeshData& m = piece.mesh;
    std::vector<double> cell_values;
    {
      ScratchReader bucket(scratch.bucket_path(p));
      std::vector<double> values(counts.cell_stride);
      m.tets.reserve(result.piece_tets[p]);
      for (std::uint64_t t = 0; t < result.piece_tets[p]; ++t) {
        const TetRecord r = bucket.get<TetRecord>();
        bucket.read(values.data(), values.size() * sizeof(double));
        m.tets.push_back(r.v);
        m.tet_material.push_back(r.material);
        cell_values.insert(cell_values.end(), values.begin(), values.end());
      }
    }
    ::unlink(scratch.bucket_path(p).c_str());
    // Its vertices, in global order.
    for (const auto& t : m.tets) piece.global_ids.insert(piece.global_ids.end(), t.begin(), t.end());
    std::sort(piece.global_ids.begin(), piece.global_ids.end());
    piece.global_ids.erase(std::unique(piece.global_ids.begin(), piece.global_ids.end()), piece.global_ids.end());
    for (VertId v = 0; v < piece.global_ids.size(); ++v) {
      const GlobalId g = piece.global_ids[v];
      local[g] = v;
      if (result.holders[g] == 255) throw InputError(input + ": vertex " + std::to_string(g + 1) + " is in too many pieces");
      ++result.holders[g];
      m.positions.push_back(pass.positions[g]);
      m.vertex_refs.push_back(pass.refs[g]);
    }
    for (auto& t : m.tets)
      for (VertId& v : t) v = local[v];
    for (std::size_t f = 0, offset = 0; f < result.vertex_fields.size(); ++f) {
      VertexField field = result.vertex_fields[f];
      field.values.reserve(piece.global_ids.size() * field.components);
      for (GlobalId g : piece.global_ids) {
        const double* values = vertex_fields.at(g) + offset;
        field.values.insert(field.values.end(), values, values + field.components);
        for (int k = 0; k < field.components; ++k) {
          const std::size_t c = offset + static_cast<std::size_t>(k);
          result.used_min[c] = std::min(result.used_min[c], values[k]);
          result.used_max[c] = std::max(result.used_max[c], values[k]);
          result.used_magnitude[c] = std::max(result.used_magnitude[c], std::fabs(values[k]));
        }
      }
      offset += field.components;
      m.fields.push_back(std::move(field));
    }
    for (std::size_t f = 0, offset = 0; f < result.cell_fields.size(); ++f) {
      CellField field = result.cell_fields[f];
      field.values.reserve(m.tets.size() * field.components);
      for (std::size_t t = 0; t < m.tets.size(); ++t)
        for (int k = 0; k < field.components; ++k)
          field.values.push_back(cell_values[t * counts.cell_stride + offset + k]);
      offset += field.components;
      m.cell_fields.push_back(std::move(field));
    }
    cell_values = {};
    // Listed triangles and edges that are faces (edges) of the piece's tets: found through each
    // vertex's tets (a local incidence, freed with the piece).
    const VertexTets at(m);
    for (std::size_t i = 0; i < pass.triangles.size(); ++i) {
      const Triangle& tri = pass.triangles[i];
      const VertId a = local[tri.v[0]], b = local[tri.v[1]], c = local[tri.v[2]];
      if (a == kInvalid || b == kInvalid || c == kInvalid || !at.has_face(m, a, b, c)) continue;
      triangle_held[i] = 1;
      m.triangles.push_back({{a, b, c}, tri.ref});
    }
    std::vector<std::uint32_t> segment_local(pass.segments.size(), kInvalid);
    for (std::size_t i = 0; i < pass.segments.size(); ++i) {
      const Segment& s = pass.segments[i];
      const VertId a = local[s.v[0]], b = local[s.v[1]];
      if (a == kInvalid || b == kInvalid || !at.has_edge(m, a, b)) continue;
      segment_held[i] = 1;
      segment_local[i] = static_cast<std::uint32_t>(m.segments.size());
      m.segments.push_back({{a, b}, s.ref});
    }
    for (std::uint32_t r : pass.ridges)
      if (r < segment_local.size() && segment_local[r] != kInvalid) m.ridges.push_back(segment_local[r]);
    for (VertId v : pass.corners)
      if (local[v] != kInvalid) m.corners.push_back(local[v]);
    for (VertId v : pass.required)
      if (local[v] != kInvalid) m.required_vertices.push_back(local[v]);
    if (std::all_of(m.vertex_refs.begin(), m.vertex_refs.end(), [](std::int32_t r) { return r == 0; })) m.vertex_refs.clear();
    for (GlobalId g : piece.global_ids) local[g] = kInvalid;
    save_piece(scratch.piece_path(p), piece);
  }
  for (std::size_t i = 0; i < triangle_held.size(); ++i)
    if (!triangle_held[i]) {
      const Triangle& t = pass.triangles[i];
      throw InputError(input + ": triangle " + std::to_string(i + 1) + " (vertices " + std::to_string(t.v[0] + 1) + " " +
                       std::to_string(t.v[1] + 1) + " " + std::to_string(t.v[2] + 1) + ", ref " + std::to_string(t.ref) +
                       ") is not a face of any tet");
    }
  for (std::size_t i = 0; i < segment_held.size(); ++i)
    if (!segment_held[i]) {
      const Segment& s = pass.segments[i];
      throw InputError(input + ": edge " + std::to_string(i + 1) + " (vertices " + std::to_string(s.v[0] + 1) + " " +
                       std::to_string(s.v[1] + 1) + ", ref " + std::to_string(s.ref) + ") is not an edge of any tet");
    }
  ::unlink(scratch.file_path("vertex-fields.bin").c_str());
  return result;
}

}  // namespace topotet::ooc
