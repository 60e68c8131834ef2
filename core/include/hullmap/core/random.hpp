#pragma once

// Portable random draws: the same 64 random bits give the same value with any standard library
// (std::uniform_real_distribution and friends do not promise that). The scene generators, the
// evaluation's sampling, the floor's RANSAC, the automatic parameters' sample and the benchmarks
// draw through these.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>

#include <Eigen/Core>

#include "hullmap/core/constants.hpp"

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

/// A stream of portable random draws from std::mt19937_64(seed): uniform, index, normal and unit
/// vector. Not thread-safe: one per thread (or per seeded chunk).
class RandomDraws {
 public:
  explicit RandomDraws(std::uint64_t seed) : engine_(seed) {}

  /// In [0, 1), from the top 53 bits of a draw.
  double uniform() { return unitInterval(engine_()); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// In [0, n): the top 64 bits of draw * n (128-bit product).
  std::size_t index(std::size_t n) {
    return static_cast<std::size_t>((static_cast<unsigned __int128>(engine_()) * n) >> 64);
  }
  /// Standard normal, by Box-Muller (both values used).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u = 0.0;
    do u = uniform();
    while (u <= 0.0);
    const double r = std::sqrt(-2.0 * std::log(u));
    const double a = 2.0 * kPi * uniform();
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }
  /// Three normal values, drawn z first (maps/ was made in that order), one statement at a time.
  Eigen::Vector3d normal3() {
    const double z = normal();
    const double y = normal();
    const double x = normal();
    return {x, y, z};
  }
  /// Uniform on the unit sphere.
  Eigen::Vector3d unitVector() {
    Eigen::Vector3d v;
    do v = normal3();
    while (v.norm() < 1e-9);
    return v.normalized();
  }

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace hullmap::core
