#pragma once

// Integer cells of a regular grid, and their hash. DBSCAN's grid, the cluster extension, the
// outlier trim and the eps choice all index points by the cell they fall in.

#include <cstddef>
#include <cstdint>

namespace hullmap::core {

/// Integer coordinates of a grid cell (or block).
struct Cell {
  std::int64_t x = 0, y = 0, z = 0;
  bool operator==(const Cell& o) const { return x == o.x && y == o.y && z == o.z; }
  bool operator!=(const Cell& o) const { return !(*this == o); }
  /// Lexicographic (x, then y, then z).
  bool operator<(const Cell& o) const {
    if (x != o.x) return x < o.x;
    if (y != o.y) return y < o.y;
    return z < o.z;
  }
  std::int64_t operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
};

/// Hash of integer cell (or block) coordinates: a polynomial in odd multipliers (distinct for any two
/// coordinates less than ~2^20 apart), then splitmix64's finaliser, so that every bit of the result,
/// the high ones a sort key uses and the low ones a table slot uses, depends on every bit of all three.
inline std::uint64_t hashCell(std::int64_t x, std::int64_t y, std::int64_t z) {
  std::uint64_t h =
      (static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(y)) * 0xC2B2AE3D27D4EB4FULL +
      static_cast<std::uint64_t>(z);
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9ULL;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBULL;
  return h ^ (h >> 31);
}

/// hashCell as a hash functor for unordered containers and hand-made tables.
struct CellHash {
  std::size_t operator()(const Cell& c) const { return static_cast<std::size_t>(hashCell(c.x, c.y, c.z)); }
};

}  // namespace hullmap::core
