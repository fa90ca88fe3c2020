#include "memory_budget.h"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "cut.h"
#include "topotet/error.h"

namespace topotet::ooc {

namespace {

std::uint64_t status_field(const char* key) {
  std::ifstream status("/proc/self/status");
  std::string word;
  while (status >> word)
    if (word == key) {
      std::uint64_t kb = 0;
      status >> kb;
      return kb * 1024;
    }
  return 0;
}

}  // namespace

std::uint64_t resident_bytes() { return status_field("VmRSS:"); }
std::uint64_t peak_resident_bytes() { return status_field("VmHWM:"); }

std::string format_bytes(std::uint64_t bytes) {
  char buf[64];
  if (bytes >= (1ull << 30))
    std::snprintf(buf, sizeof buf, "%.2f GiB", static_cast<double>(bytes) / (1ull << 30));
  else
    std::snprintf(buf, sizeof buf, "%.0f MiB", static_cast<double>(bytes) / (1ull << 20));
  return buf;
}

std::uint64_t budget_baseline(std::uint64_t rss) {
  return std::max<std::uint64_t>(1, (rss + kBaselineStep - 1) / kBaselineStep) * kBaselineStep;
}

std::uint64_t bytes_per_piece_tet(const InputCounts& counts) {
  const std::uint64_t n = 3 + static_cast<std::uint64_t>(std::max(counts.vertex_stride, 0));
  const std::uint64_t quadric_bytes = 8 * (n * (n + 1) / 2 + n + 1);
  return kBytesPerPieceTet + (3 * quadric_bytes + kTetsPerVertex - 1) / kTetsPerVertex;
}

std::uint64_t bytes_per_field_sample(const InputCounts& counts) {
  const auto k = static_cast<std::uint64_t>(std::max(counts.vertex_stride, 0));
  // Position (24), values (8k), tet (4) and, in the engine, a list link and the released tet
  // (4 + 4 over the carried 28 + 8k); a merge copies one array at a time: + the largest array.
  return std::max(36 + 8 * k, 28 + 8 * k + std::max<std::uint64_t>(24, 8 * k));
}

std::uint64_t hierarchy_batch_bytes(const InputCounts& counts) {
  const auto k = static_cast<std::uint64_t>(std::max(counts.vertex_stride, 0));
  return kHierarchyBatch * 2 * (148 + 16 * k);
}

std::uint64_t MemoryBudget::usable() const {
  const auto after_headroom = static_cast<std::uint64_t>(static_cast<double>(limit) * (1.0 - kHeadroom));
  return after_headroom > baseline ? after_headroom - baseline : 0;
}

void MemoryBudget::check_vertices(std::uint64_t vertices, std::uint64_t reader_bytes, const std::string& input) const {
  const std::uint64_t cut = vertices * kCutBytesPerVertex + reader_bytes + kMinPieceTets * kBytesPerPieceTet / 8;
  if (cut > usable()) {
    const auto needed = static_cast<std::uint64_t>(static_cast<double>(baseline + cut) / (1.0 - kHeadroom)) + 1;
    throw InputError(input + ": --memory-limit " + format_bytes(limit) + " is below what cutting " +
                     std::to_string(vertices) + " vertices out of core needs: at least " + format_bytes(needed) +
                     " (" + format_bytes(baseline) + " of it counted for the process itself" +
                     (reader_bytes > 0 ? ", " + format_bytes(reader_bytes) + " for the reader's node tag map" : std::string()) +
                     ")");
  }
}

std::uint64_t MemoryBudget::piece_tets(const InputCounts& counts) const {
  // The cut phase and the levels do not overlap: a piece must fit beside what each holds. A piece
  // built during the cut costs its arrays only (~1/8 of a simplification's bytes per tet).
  const std::uint64_t cut_held = counts.vertices * kCutBytesPerVertex + counts.triangles * 16 + counts.segments * 12;
  const bool samples = field_samples && counts.vertex_stride > 0;  // a mesh without fields has nothing to bound
  const std::uint64_t samples_held = samples ? counts.vertices * bytes_per_field_sample(counts) : 0;
  const std::uint64_t level_held =
      counts.vertices * kLevelBytesPerVertex + samples_held + (hierarchy ? hierarchy_batch_bytes(counts) : 0);
  const std::uint64_t u = usable();
  const auto k = static_cast<std::uint64_t>(std::max(counts.vertex_stride, 0));
  const std::uint64_t per_tet =
      bytes_per_piece_tet(counts) + (samples ? 4 + 12 * k : 0) + (hierarchy ? kHierarchyBytesPerTet : 0);
  const std::uint64_t during_cut = u > cut_held ? (u - cut_held) * 8 / kBytesPerPieceTet : 0;
  const std::uint64_t during_levels = u > level_held ? (u - level_held) / per_tet : 0;
  const std::uint64_t tets = std::min(during_cut, during_levels);
  if (tets < kMinPieceTets) {
    const std::uint64_t need = std::max(cut_held + kMinPieceTets * kBytesPerPieceTet / 8,
                                        level_held + kMinPieceTets * per_tet);
    const auto needed = static_cast<std::uint64_t>(static_cast<double>(baseline + need) / (1.0 - kHeadroom)) + 1;
    throw InputError("--memory-limit " + format_bytes(limit) + " leaves room for pieces of " + std::to_string(tets) +
                     " tets; out of core needs at least " + std::to_string(kMinPieceTets) + ": give at least " +
                     format_bytes(needed) +
                     (samples ? " (the field error bounds keep every input vertex as a sample: " +
                                          format_bytes(samples_held) + " for " + std::to_string(counts.vertices) +
                                          " vertices; without --max-field-error / --field-bounds they are not needed)"
                                    : std::string()));
  }
  return tets;
}

}  // namespace topotet::ooc
