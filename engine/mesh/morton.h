// Morton (Z-order) codes: 21 bits per axis interleaved into 63. Neighbours in space get near codes,
// which is what reorder.cpp (memory locality) and the out-of-core cut (outofcore/cut.cpp: pieces
// as ranges of the curve) both want.
#pragma once

#include <cstdint>

namespace topotet {

// The low 21 bits of x, spread to every third bit.
constexpr std::uint64_t morton_spread(std::uint64_t x) {
  x &= 0x1FFFFFull;
  x = (x | x << 32) & 0x1F00000000FFFFull;
  x = (x | x << 16) & 0x1F0000FF0000FFull;
  x = (x | x << 8) & 0x100F00F00F00F00Full;
  x = (x | x << 4) & 0x10C30C30C30C30C3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

// The code of a cell (x, y, z), each below 2^21: x in the lowest bit of each triple.
constexpr std::uint64_t morton_code(std::uint64_t x, std::uint64_t y, std::uint64_t z) {
  return morton_spread(x) | morton_spread(y) << 1 | morton_spread(z) << 2;
}

}  // namespace topotet
