// How an out-of-core run spends its memory limit, decided from counts (the pieces, and so the
// output, must not vary from run to run as a measured RSS does).
//
//   baseline      the process before the run (code, libraries, oneTBB and Embree, and whatever a
//                 calling program holds): its resident size at the start, rounded up to a multiple
//                 of kBaselineStep, so that the few MiB it varies by between runs (and between
//                 thread counts) do not change the piece count;
//   cut phase     per input vertex: position and ref (28 bytes), the cut's local index (4) and
//                 the holder count (1); per listed triangle (edge) 16 (12) bytes; while the mesh
//                 streams, what the reader holds beside (a .msh's node tag map: 4 bytes a tag
//                 up to the largest, or 48 bytes a node when the tags are sparse);
//   levels        per input vertex: the holder count (1 byte; the seams' level adds a bit: the
//                 headroom's); per piece tet: kBytesPerPieceTet,
//                 what the engine needs to simplify a piece with the default guarantees (the
//                 model, the tolerance's reference and coverage, the piece's own arrays in and
//                 out; docs/performance.md "Out of core" has the measurements it comes from),
//                 plus the carried quadrics: three copies (the piece's, the engine's renumbered
//                 input, its output) of quadric_size(3 + vertex field components) doubles per
//                 vertex, at most one vertex per kTetsPerVertex tets;
//   field bounds  with field error bounds (SimplifyOptions::max_field_error...), every input vertex
//                 is a sample carried through the levels, and the last merge holds them all:
//                 bytes_per_field_sample per input vertex (position, values and tet: 28 + 8k; in
//                 the engine a list link and the released tet, + 8; a merge copies one array at a
//                 time, + the largest: 24 or 8k), plus 4 + 12 k bytes per piece tet (its list head
//                 and its bounds in the piece, the engine and the output), k = vertex field
//                 components;
//   hierarchy     with a hierarchy file, per piece tet: its last collapse in the piece, the log and
//                 the output, and the global id of its vertices (13 bytes); and the log's records
//                 until they go to disk, kHierarchyBatch collapses at a time, each 2 x (148 + 16k)
//                 bytes (u, v, three positions, cost, bound, offset, ~10 parents, fields before
//                 and after; twice, as the arrays grow by doubling); the original goes to disk too;
//   headroom      kHeadroom of the limit for the allocator's slack and the I/O buffers.
// A limit that leaves fewer than kMinPieceTets per piece is refused before any work, with the
// smallest limit that would do.
#pragma once

#include <cstdint>
#include <string>

namespace topotet::ooc {

struct InputCounts;

inline constexpr std::uint64_t kCutBytesPerVertex = 33;
inline constexpr std::uint64_t kLevelBytesPerVertex = 1;
inline constexpr std::uint64_t kBytesPerPieceTet = 320;
inline constexpr std::uint64_t kTetsPerVertex = 4;  // a tet mesh has ~5-6; fewer is conservative
inline constexpr std::uint64_t kMinPieceTets = 20000;
inline constexpr double kHeadroom = 0.15;
inline constexpr std::uint64_t kBaselineStep = 64ull << 20;
inline constexpr std::uint64_t kHierarchyBytesPerTet = 13;
inline constexpr std::uint64_t kHierarchyBatch = 1u << 14;  // collapses a piece's log holds at most

// The resident size `rss` as the budget counts it: rounded up to kBaselineStep (at least one step).
std::uint64_t budget_baseline(std::uint64_t rss);

struct MemoryBudget {
  std::uint64_t limit = 0;     // bytes
  std::uint64_t baseline = 0;  // bytes (resident at the start)
  bool field_samples = false;  // field error bounds kept (see the top)
  bool hierarchy = false;      // a hierarchy file recorded (see the top)

  // The most tets a piece may have once the input's counts are known; throws InputError with the
  // limit that would be needed when it is below kMinPieceTets.
  std::uint64_t piece_tets(const InputCounts& counts) const;
  // The first check, as soon as the vertex count is known (the cut holds them, and the reader
  // holds reader_bytes beside them while it streams: a .msh's node tag map): throws likewise.
  void check_vertices(std::uint64_t vertices, std::uint64_t reader_bytes, const std::string& input) const;
  std::uint64_t usable() const;
};

// Resident bytes now (VmRSS) and at the peak so far (VmHWM), from /proc/self/status; 0 if unknown.
std::uint64_t resident_bytes();
std::uint64_t peak_resident_bytes();

std::string format_bytes(std::uint64_t bytes);  // "1.50 GiB", "256 MiB"

// kBytesPerPieceTet and the carried quadrics' share per tet, for this input's fields.
std::uint64_t bytes_per_piece_tet(const InputCounts& counts);
// What one field error sample costs at the peak (see the top).
std::uint64_t bytes_per_field_sample(const InputCounts& counts);
// What recording a hierarchy adds once: a batch of records (see the top; per piece tet it adds
// kHierarchyBytesPerTet).
std::uint64_t hierarchy_batch_bytes(const InputCounts& counts);

}  // namespace topotet::ooc
