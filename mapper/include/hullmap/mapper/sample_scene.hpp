#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hullmap/mapper/point_cloud.hpp"
#include "hullmap/mapper/readers.hpp"

namespace hullmap::mapper {

/// A ground-truth obstacle of a generated scene, in the z-up map frame (metres).
struct SceneObstacle {
  enum class Shape { kBox, kCylinder } shape = Shape::kBox;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< box centre; cylinder axis centre
  Eigen::Vector3d size = Eigen::Vector3d::Ones();     ///< box extents; cylinder (2r, 2r, height)
};

/// Parameters of the synthetic ORB-SLAM-like scene. Same seed, same scene, on every machine.
struct SceneParams {
  std::uint64_t seed = 42;
  std::size_t points = 20000;         ///< map points, outliers included
  std::size_t obstacles = 8;          ///< boxes and cylinders in the room
  double room_size = 10.0;            ///< square room side, metres
  double room_height = 3.0;
  double noise_sigma = 0.01;          ///< centimetre noise
  double outlier_fraction = 0.03;     ///< uniform outliers in the room
  std::size_t gross_outliers = 5;     ///< points far away (hundreds of km)
  std::size_t keyframes = 60;
  bool orbslam_frame = true;          ///< write in ORB-SLAM's frame (y down): read back with --up -y
};

struct Scene {
  Points points;                       ///< in the output frame (ORB-SLAM's if orbslam_frame)
  std::vector<Keyframe> keyframes;
  std::vector<SceneObstacle> obstacles;  ///< always z-up map frame
};

Scene generateScene(const SceneParams& params);

/// Writes points as ORB-SLAM2 map-point text, the trajectory as TUM, the ground truth as JSON,
/// into `dir` (map_points.txt, KeyFrameTrajectory.txt, ground_truth.json).
void writeScene(const Scene& scene, const SceneParams& params, const std::string& dir);

}  // namespace hullmap::mapper
