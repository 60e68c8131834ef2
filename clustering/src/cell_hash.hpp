#pragma once

#include <cstdint>

namespace hullmap::clustering::detail {

/// Hash of integer cell (or block) coordinates: a polynomial in odd multipliers (distinct for any two
/// coordinates less than ~2^20 apart), then splitmix64's finaliser, so that every bit of the result,
/// the high ones a sort key uses and the low ones a table slot uses, depends on every bit of all three.
inline std::uint64_t hashCell(std::int64_t x, std::int64_t y, std::int64_t z) {
  std::uint64_t h = (static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(y)) *
                        0xC2B2AE3D27D4EB4FULL +
                    static_cast<std::uint64_t>(z);
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9ULL;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBULL;
  return h ^ (h >> 31);
}

}  // namespace hullmap::clustering::detail
