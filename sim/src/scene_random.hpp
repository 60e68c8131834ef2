#pragma once

// The scene generators' shared helpers (sample_scene.cpp, sample_room.cpp, sample_outdoor.cpp):
// seeded chunks of random draws, and cameras. Not installed.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/parallel_for.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "hullmap/core/constants.hpp"
#include "hullmap/core/random.hpp"
#include "hullmap/sim/sample_scene.hpp"

namespace hullmap::sim::detail {

inline constexpr double kCameraHeight = 1.2;
inline constexpr std::size_t kChunk = 65536;  // points per independently seeded generator

using core::splitMix64;

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

/// `count` keyframes on one loop (x, y) = (radius_x cos a, radius_y sin a), a = 2 pi i / count, at
/// about kCameraHeight, 0.5 s apart from stamp 1; keyframe i looks along forward(a, its position).
template <class Forward>
std::vector<io::Keyframe> cameraLoop(std::size_t count, double radius_x, double radius_y, Forward&& forward) {
  std::vector<io::Keyframe> keyframes(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double a = 2.0 * kPi * static_cast<double>(i) / static_cast<double>(count);
    io::Keyframe& k = keyframes[i];
    k.stamp = 1.0 + 0.5 * static_cast<double>(i);
    k.position =
        Eigen::Vector3d(radius_x * std::cos(a), radius_y * std::sin(a), kCameraHeight + 0.05 * std::sin(3.0 * a));
    k.orientation = cameraLookingAlong(forward(a, k.position));
  }
  return keyframes;
}

/// Calls draw(rng, i, c) for every i in [0, n), in chunks c of `chunk` items run in parallel, each
/// chunk drawing from its own core::RandomDraws seeded with splitMix64(seed ^ splitMix64(c + 1)): the same
/// values whatever the thread count.
template <class Draw>
void forEachSeeded(std::size_t n, std::uint64_t seed, std::size_t chunk, Draw&& draw) {
  tbb::parallel_for(std::size_t{0}, (n + chunk - 1) / chunk, [&](std::size_t c) {
    core::RandomDraws local(splitMix64(seed ^ splitMix64(c + 1)));
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
