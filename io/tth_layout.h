// The .tth file's framing, shared by its writers: write_hierarchy (io/tth.cpp, which has the whole
// layout) and an out-of-core run's, which assembles the file from sections kept on disk
// (outofcore/hierarchy_spool.cpp). docs/formats.md describes the format.
#pragma once

#include <cstdint>

namespace topotet::io::tth {

inline constexpr char kMagic[8] = {'T', 'O', 'P', 'O', 'T', 'E', 'T', 'H'};
inline constexpr char kEnd[8] = {'T', 'T', 'H', '_', 'E', 'N', 'D', '!'};
inline constexpr std::uint32_t kVersion = 1;

}  // namespace topotet::io::tth
