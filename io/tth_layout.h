// The .tth file's framing, shared by its writers: write_hierarchy (io/tth.cpp, which has the whole
// layout) and an out-of-core run's, which assembles the file from sections kept on disk
// (outofcore/hierarchy_spool.cpp). docs/formats.md describes the format.
#pragma once

#include <bit>
#include <cstdint>

#include "io/atomic_file.h"

namespace topotet::io::tth {

// Its writers store the host's memory layout of the arrays.
static_assert(std::endian::native == std::endian::little, "the .tth stores the host's little-endian layout");

inline constexpr char kMagic[8] = {'T', 'O', 'P', 'O', 'T', 'E', 'T', 'H'};
inline constexpr char kEnd[8] = {'T', 'T', 'H', '_', 'E', 'N', 'D', '!'};
inline constexpr std::uint32_t kVersion = 1;
inline constexpr std::uint64_t kHeaderBytes = 16, kEndBytes = 8;

// The magic number, the version and the flags (0); and the end marker.
inline void write_header(AtomicFile& file) {
  file.put_bytes(kMagic, 8);
  file.put_raw(kVersion);
  file.put_raw(std::uint32_t{0});
}
inline void write_end(AtomicFile& file) { file.put_bytes(kEnd, 8); }

}  // namespace topotet::io::tth
