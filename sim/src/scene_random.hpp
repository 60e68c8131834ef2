#pragma once

// Portable random numbers for the scene generators (sample_scene.cpp, sample_room.cpp,
// sample_outdoor.cpp), and their camera helpers. Not installed.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "hullmap/core/constants.hpp"
#include "hullmap/core/random.hpp"
#include "hullmap/sim/sample_scene.hpp"

namespace hullmap::sim::detail {

inline constexpr double kCameraHeight = 1.2;
inline constexpr std::size_t kChunk = 65536;  // points per independently seeded generator

using core::splitMix64;

// Portable random numbers: the same bits give the same values with any standard library.
class SceneRandom {
 public:
  explicit SceneRandom(std::uint64_t seed) : engine_(seed) {}

  double uniform() { return core::unitInterval(engine_()); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  std::size_t index(std::size_t n) {
    return static_cast<std::size_t>((static_cast<unsigned __int128>(engine_()) * n) >> 64);
  }
  // Box-Muller, both values used.
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
  // Three normal values, drawn one statement at a time, z first (the order maps/ was made in): the
  // arguments of one call are not sequenced, and gcc and clang draw them in opposite orders.
  Eigen::Vector3d normal3() {
    const double z = normal();
    const double y = normal();
    const double x = normal();
    return {x, y, z};
  }
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

/// The kRoom layout of generateScene (sample_room.cpp); parameters already checked.
Scene generateRoomScene(const SceneParams& params);

/// The kOutdoor layout of generateScene (sample_outdoor.cpp); parameters already checked.
Scene generateOutdoorScene(const SceneParams& params);

/// A camera's orientation in the map (ORB-SLAM's camera axes: z forward, x right, y down) looking
/// along `forward` (unit, not vertical), with no roll.
inline Eigen::Quaterniond cameraLookingAlong(const Eigen::Vector3d& forward) {
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d r;
  r.col(0) = right;
  r.col(1) = down;
  r.col(2) = forward;
  return Eigen::Quaterniond(r).normalized();
}

/// Calls draw(rng, i, c) for every i in [0, n), in chunks c of `chunk` items run in parallel, each
/// chunk drawing from its own SceneRandom seeded with splitMix64(seed ^ splitMix64(c + 1)): the same
/// values whatever the thread count.
template <class Draw>
void forEachSeeded(std::size_t n, std::uint64_t seed, std::size_t chunk, Draw&& draw) {
  tbb::parallel_for(std::size_t{0}, (n + chunk - 1) / chunk, [&](std::size_t c) {
    SceneRandom local(splitMix64(seed ^ splitMix64(c + 1)));
    const std::size_t end = std::min(n, (c + 1) * chunk);
    for (std::size_t i = c * chunk; i < end; ++i) draw(local, i, c);
  });
}

/// points[i] = f(points[i]) for every point, kChunk points at a time in parallel.
template <class F>
void transformPoints(std::vector<Eigen::Vector3d>& points, F&& f) {
  const std::size_t n = points.size();
  tbb::parallel_for(std::size_t{0}, (n + kChunk - 1) / kChunk, [&](std::size_t c) {
    const std::size_t end = std::min(n, (c + 1) * kChunk);
    for (std::size_t i = c * kChunk; i < end; ++i) points[i] = f(points[i]);
  });
}

}  // namespace hullmap::sim::detail
