#include "vertex_map_log.h"

#include <algorithm>
#include <stdexcept>

#include "topotet/vertex_map_file.h"

namespace topotet::ooc {
namespace {

constexpr std::uint64_t kOutput = std::uint64_t{1} << 63;
constexpr std::size_t kWindow = std::size_t{1} << 16;  // entries read or written at once

}  // namespace

VertexMapLog::VertexMapLog(const std::string& path, std::uint64_t input_vertices) : file_(path), count_(input_vertices) {
  file_.resize(count_ * sizeof(std::uint64_t));  // sparse: unwritten entries read as 0
}

// Sorted by global id, runs of consecutive ids go out in one call (a piece's vertices come from
// nearby input lines more often than not).
void VertexMapLog::put(std::vector<std::pair<GlobalId, std::uint64_t>> entries) {
  std::sort(entries.begin(), entries.end());
  std::vector<std::uint64_t> run;
  for (std::size_t i = 0; i < entries.size();) {
    const GlobalId first = entries[i].first;
    run.clear();
    while (i < entries.size() && entries[i].first == first + run.size() && run.size() < kWindow) run.push_back(entries[i++].second);
    file_.write_at(run.data(), run.size() * sizeof(std::uint64_t), std::uint64_t{first} * sizeof(std::uint64_t));
  }
}

void VertexMapLog::record_merges(std::vector<std::pair<GlobalId, GlobalId>> merged) {
  std::vector<std::pair<GlobalId, std::uint64_t>> entries(merged.size());
  for (std::size_t i = 0; i < merged.size(); ++i) entries[i] = {merged[i].first, std::uint64_t{merged[i].second} + 1};
  put(std::move(entries));
}

void VertexMapLog::record_output_piece(const std::vector<GlobalId>& global_ids) {
  std::vector<std::pair<GlobalId, std::uint64_t>> entries(global_ids.size());
  for (std::size_t o = 0; o < global_ids.size(); ++o) entries[o] = {global_ids[o], kOutput | o};
  put(std::move(entries));
}

void VertexMapLog::record_output_index(const std::vector<VertId>& output_index) {
  std::vector<std::pair<GlobalId, std::uint64_t>> entries;
  for (std::size_t g = 0; g < output_index.size(); ++g) {
    if (output_index[g] != kInvalid) entries.push_back({static_cast<GlobalId>(g), kOutput | output_index[g]});
    if (entries.size() == kWindow || g + 1 == output_index.size()) {
      put(std::move(entries));
      entries.clear();
    }
  }
}

void VertexMapLog::write(const std::string& path, const std::vector<std::uint8_t>& used) const {
  const auto read = [&](std::uint64_t* into, std::uint64_t first, std::size_t n) {
    file_.read_at(into, n * sizeof(std::uint64_t), first * sizeof(std::uint64_t));
  };
  VertexMapWriter writer(path, count_);
  std::vector<std::uint64_t> window(kWindow);
  for (std::uint64_t base = 0; base < count_; base += kWindow) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kWindow, count_ - base));
    read(window.data(), base, n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t g = base + i;
      std::uint64_t e = window[i];
      if (e == 0) {
        if (used[g] != 0) throw std::logic_error("out-of-core vertex map: input vertex " + std::to_string(g) + " has no entry");
        writer.add(-1);
        continue;
      }
      // Each link is one level's merge: a chain longer than the levels (at most 13) is a cycle.
      for (int links = 0; (e & kOutput) == 0; ++links) {
        const std::uint64_t s = e - 1;
        if (links == 64 || s >= count_) throw std::logic_error("out-of-core vertex map: broken chain at input vertex " + std::to_string(g));
        if (s >= base && s < base + n) {
          e = window[s - base];
        } else {
          read(&e, s, 1);
        }
        if (e == 0) throw std::logic_error("out-of-core vertex map: input vertex " + std::to_string(g) + " merged into a vertex without an entry");
      }
      writer.add(static_cast<std::int64_t>(e & ~kOutput));
    }
  }
  writer.commit();
}

}  // namespace topotet::ooc
