// The out-of-core hierarchy file, on disk until the end (hierarchy_spool.h).
#include "hierarchy_spool.h"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "hierarchy/hierarchy_log.h"
#include "io/atomic_file.h"
#include "io/tth_layout.h"
#include "topotet/error.h"

namespace topotet::ooc {

static_assert(std::endian::native == std::endian::little, "the .tth stores the host's little-endian layout");

// One scratch file per collapse array of the .tth, in its order.
struct HierarchySpool::Columns {
  explicit Columns(const ScratchFolder& s)
      : u(s.file_path("tth-u.bin")),
        v(s.file_path("tth-v.bin")),
        u_before(s.file_path("tth-u-before.bin")),
        u_after(s.file_path("tth-u-after.bin")),
        v_position(s.file_path("tth-v-position.bin")),
        fields_before(s.file_path("tth-fields-before.bin")),
        fields_after(s.file_path("tth-fields-after.bin")),
        cost(s.file_path("tth-cost.bin")),
        bound(s.file_path("tth-bound.bin")),
        offsets(s.file_path("tth-offsets.bin")),
        parents(s.file_path("tth-parents.bin")) {}
  ScratchWriter u, v, u_before, u_after, v_position, fields_before, fields_after, cost, bound, offsets, parents;
  ScratchWriter* all[11] = {&u, &v, &u_before, &u_after, &v_position, &fields_before, &fields_after, &cost, &bound, &offsets, &parents};
  static constexpr const char* kNames[11] = {"tth-u.bin", "tth-v.bin", "tth-u-before.bin", "tth-u-after.bin",
                                             "tth-v-position.bin", "tth-fields-before.bin", "tth-fields-after.bin",
                                             "tth-cost.bin", "tth-bound.bin", "tth-offsets.bin", "tth-parents.bin"};
};

namespace {

template <class T>
void put_array(ScratchWriter& out, const std::vector<T>& v) {
  out.write(v.data(), v.size() * sizeof(T));
}

template <class T>
void put_counted(ScratchWriter& out, const std::vector<T>& v) {
  out.put<std::uint64_t>(v.size());
  put_array(out, v);
}

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
  columns_->offsets.put<std::uint32_t>(0);
}

HierarchySpool::~HierarchySpool() = default;

void HierarchySpool::original_vertices(const std::vector<std::array<double, 3>>& positions,
                                       const std::vector<std::int32_t>& refs) {
  put_counted(*original_, positions);
  put_counted(*original_, refs);
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
  put_counted(*original_, ridges);
  put_counted(*original_, corners);
  put_counted(*original_, required);
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
  put_array(c.u, ids);
  for (std::size_t i = 0; i < n; ++i) ids[i] = global[log.v[i]];
  put_array(c.v, ids);
  put_array(c.u_before, log.u_before);
  put_array(c.u_after, log.u_after);
  put_array(c.v_position, log.v_position);
  put_array(c.fields_before, log.fields_before);
  put_array(c.fields_after, log.fields_after);
  put_array(c.cost, log.cost);
  put_array(c.bound, log.error_bound);
  // The log's offsets start at 0 for its own parents; the file's continue the run's.
  for (std::size_t i = 1; i <= n; ++i) c.offsets.put<std::uint32_t>(static_cast<std::uint32_t>(parents_ + log.parent_offsets[i]));
  put_array(c.parents, log.parents);  // already the run's ids (the log's first_id)
  collapses_ += n;
  parents_ += log.parents.size();
}

void HierarchySpool::write(const std::string& path, int field_stride) {
  if (!original_done_) throw std::logic_error("HierarchySpool::write before the original was written");
  for (ScratchWriter* w : columns_->all) w->close();
  io::AtomicFile file(path);
  file.put(std::string_view(io::tth::kMagic, 8));
  const std::uint32_t version = io::tth::kVersion, flags = 0;
  file.put(std::string_view(reinterpret_cast<const char*>(&version), 4));
  file.put(std::string_view(reinterpret_cast<const char*>(&flags), 4));
  copy_into(file, scratch_.file_path("tth-original.bin"));
  const std::uint64_t n = collapses_;
  const auto k = static_cast<std::uint32_t>(field_stride);
  file.put(std::string_view(reinterpret_cast<const char*>(&n), 8));
  file.put(std::string_view(reinterpret_cast<const char*>(&k), 4));
  for (const char* name : Columns::kNames) copy_into(file, scratch_.file_path(name));
  file.put(std::string_view(io::tth::kEnd, 8));
  file.commit();
  bytes_written_ = 0;
  for (ScratchWriter* w : columns_->all) bytes_written_ += w->bytes();
  bytes_written_ += original_->bytes() + 8 + 8 + 12 + 8;
}

}  // namespace topotet::ooc
