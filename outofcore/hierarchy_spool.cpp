// The out-of-core hierarchy file, on disk until the end (hierarchy_spool.h).
#include "hierarchy_spool.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "hierarchy/hierarchy_log.h"
#include "io/atomic_file.h"
#include "io/tth_layout.h"
#include "topotet/error.h"

namespace topotet::ooc {

// One scratch file per collapse array of the .tth, in the file's order.
struct HierarchySpool::Columns {
  enum Index { kU, kV, kUBefore, kUAfter, kVPosition, kFieldsBefore, kFieldsAfter, kCost, kBound, kOffsets, kParents, kCount };
  static constexpr const char* kNames[kCount] = {"tth-u.bin", "tth-v.bin", "tth-u-before.bin", "tth-u-after.bin",
                                                 "tth-v-position.bin", "tth-fields-before.bin", "tth-fields-after.bin",
                                                 "tth-cost.bin", "tth-bound.bin", "tth-offsets.bin", "tth-parents.bin"};
  explicit Columns(const ScratchFolder& s) {
    for (int c = 0; c < kCount; ++c) files[c] = std::make_unique<ScratchWriter>(s.file_path(kNames[c]));
  }
  ScratchWriter& operator[](Index c) { return *files[c]; }
  std::unique_ptr<ScratchWriter> files[kCount];
};

namespace {

// Copies a scratch file's bytes to the .tth.
void copy_into(io::AtomicFile& file, const std::string& path) {
  std::FILE* in = std::fopen(path.c_str(), "rb");
  if (in == nullptr) throw_scratch_error(path, "cannot open");
  std::vector<char> buffer(std::size_t{1} << 20);
  std::size_t got = 0;
  while ((got = std::fread(buffer.data(), 1, buffer.size(), in)) > 0) file.put(std::string_view(buffer.data(), got));
  const bool failed = std::ferror(in) != 0;
  std::fclose(in);
  if (failed) throw_scratch_error(path, "cannot read");
}

}  // namespace

HierarchySpool::HierarchySpool(const ScratchFolder& scratch)
    : scratch_(scratch),
      original_(std::make_unique<ScratchWriter>(scratch.file_path("tth-original.bin"))),
      columns_(std::make_unique<Columns>(scratch)) {
  (*columns_)[Columns::kOffsets].put<std::uint32_t>(0);
}

HierarchySpool::~HierarchySpool() = default;

void HierarchySpool::original_vertices(const std::vector<std::array<double, 3>>& positions,
                                       const std::vector<std::int32_t>& refs) {
  original_->put_counted(positions);
  original_->put_counted(refs);
}

void HierarchySpool::original_tet_count(std::uint64_t tets) {
  tets_ = tets;
  original_->put<std::uint64_t>(tets);
}

void HierarchySpool::original_tet(const std::array<VertId, 4>& v) {
  original_->write(v.data(), sizeof v);
  ++tets_written_;
}

void HierarchySpool::original_material(std::int32_t material) {
  original_->put(material);
  ++materials_written_;
}

void HierarchySpool::original_listed(const std::vector<Triangle>& triangles, const std::vector<Segment>& segments,
                                     const std::vector<std::uint32_t>& ridges, const std::vector<VertId>& corners,
                                     const std::vector<VertId>& required) {
  if (tets_written_ != tets_ || materials_written_ != tets_)
    throw std::logic_error("HierarchySpool: the original's tets and materials must precede its listed elements");
  original_->put<std::uint64_t>(triangles.size());
  for (const Triangle& t : triangles) {
    original_->write(t.v.data(), sizeof t.v);
    original_->put(t.ref);
  }
  original_->put<std::uint64_t>(segments.size());
  for (const Segment& s : segments) {
    original_->write(s.v.data(), sizeof s.v);
    original_->put(s.ref);
  }
  original_->put_counted(ridges);
  original_->put_counted(corners);
  original_->put_counted(required);
}

void HierarchySpool::original_fields(const std::vector<VertexField>& fields, const std::string& values, int stride,
                                     std::uint64_t vertices) {
  original_->put<std::uint64_t>(fields.size());
  int offset = 0;
  for (const VertexField& f : fields) {
    original_->put<std::uint32_t>(static_cast<std::uint32_t>(f.name.size()));
    original_->write(f.name.data(), f.name.size());
    original_->put<std::int32_t>(f.components);
    // One pass over the interleaved values per field: the .tth stores each field whole.
    ScratchReader in(values);
    std::vector<double> row(static_cast<std::size_t>(stride));
    for (std::uint64_t x = 0; x < vertices; ++x) {
      in.read(row.data(), row.size() * sizeof(double));
      original_->write(row.data() + offset, static_cast<std::size_t>(f.components) * sizeof(double));
    }
    offset += f.components;
  }
}

void HierarchySpool::original_done() {
  original_->put<std::uint64_t>(0);  // group names
  original_->close();
  original_done_ = true;
}

void HierarchySpool::append(const detail::CollapseLog& log, const std::vector<GlobalId>& global) {
  const std::size_t n = log.u.size();
  if (collapses_ + n > std::numeric_limits<std::uint32_t>::max() ||
      parents_ + log.parents.size() > std::numeric_limits<std::uint32_t>::max())
    throw InputError("the hierarchy file holds at most 2^32 - 1 collapses and parents (its ids are 32-bit)");
  Columns& c = *columns_;
  std::vector<GlobalId> ids(n);
  for (std::size_t i = 0; i < n; ++i) ids[i] = global[log.u[i]];
  c[Columns::kU].put_array(ids);
  for (std::size_t i = 0; i < n; ++i) ids[i] = global[log.v[i]];
  c[Columns::kV].put_array(ids);
  c[Columns::kUBefore].put_array(log.u_before);
  c[Columns::kUAfter].put_array(log.u_after);
  c[Columns::kVPosition].put_array(log.v_position);
  c[Columns::kFieldsBefore].put_array(log.fields_before);
  c[Columns::kFieldsAfter].put_array(log.fields_after);
  c[Columns::kCost].put_array(log.cost);
  c[Columns::kBound].put_array(log.error_bound);
  // The log's offsets start at 0 for its own parents; the file's continue the run's.
  for (std::size_t i = 1; i <= n; ++i)
    c[Columns::kOffsets].put<std::uint32_t>(static_cast<std::uint32_t>(parents_ + log.parent_offsets[i]));
  c[Columns::kParents].put_array(log.parents);  // already the run's ids (the log's first_id)
  collapses_ += n;
  parents_ += log.parents.size();
}

void HierarchySpool::write(const std::string& path, int field_stride) {
  if (!original_done_) throw std::logic_error("HierarchySpool::write before the original was written");
  for (auto& column : columns_->files) column->close();
  io::AtomicFile file(path);
  io::tth::write_header(file);
  copy_into(file, scratch_.file_path("tth-original.bin"));
  file.put_raw(std::uint64_t{collapses_});
  file.put_raw(static_cast<std::uint32_t>(field_stride));
  for (const char* name : Columns::kNames) copy_into(file, scratch_.file_path(name));
  io::tth::write_end(file);
  file.commit();
  bytes_written_ = io::tth::kHeaderBytes + original_->bytes() + 12 + io::tth::kEndBytes;  // 12: the count and stride
  for (const auto& column : columns_->files) bytes_written_ += column->bytes();
}

}  // namespace topotet::ooc
