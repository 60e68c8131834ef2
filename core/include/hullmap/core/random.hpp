#pragma once

// Portable random draws: the same 64 random bits give the same value with any standard library
// (std::uniform_real_distribution and friends do not promise that). The scene generators, the
// evaluation's sampling and the benchmarks draw through these.

#include <cstdint>

namespace hullmap::core {

/// splitmix64 (Steele, Lea and Flood 2014): a bijective mix of x + the golden-ratio increment.
/// Used to seed independent generators from one seed, and as a hash of a counter.
inline std::uint64_t splitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// A double in [0, 1) from the top 53 of 64 random bits (every value a multiple of 2^-53).
inline double unitInterval(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }

}  // namespace hullmap::core
