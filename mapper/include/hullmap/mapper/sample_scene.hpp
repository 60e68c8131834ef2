#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hullmap/mapper/point_cloud.hpp"
#include "hullmap/mapper/readers.hpp"

namespace hullmap::mapper {

/// A ground-truth obstacle of a generated scene, in the z-up map frame (metres).
/// Obstacles stand on the floor (z = 0) and are axis-aligned.
struct SceneObstacle {
  enum class Shape { kBox, kCylinder } shape = Shape::kBox;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< box centre; cylinder axis centre
  Eigen::Vector3d size = Eigen::Vector3d::Ones();     ///< box extents; cylinder (2r, 2r, height)
};

/// Parameters of the synthetic ORB-SLAM-like scene. Same seed, same scene, on every machine
/// (hullmap draws from std::mt19937_64 with its own uniform and normal transforms, since the
/// std distributions differ between standard libraries).
///
/// The scene: `obstacles` boxes and cylinders standing in a square room of `room_size` (centred
/// on the origin, floor at z = 0), at least kSceneObstacleGap metres apart (so DBSCAN at eps 0.1
/// separates them) and clear of the camera loop. No walls or floor are sampled: every surface
/// point belongs to an obstacle. Map points imitate ORB-SLAM: about half lie near edges (corners
/// are what ORB features find), the rest on visible faces (no bottom faces), each with Gaussian
/// noise of `noise_sigma` per axis. Keyframes run one loop around the room at about 1.2 m height,
/// each camera looking at the room's vertical axis.
struct SceneParams {
  std::uint64_t seed = 42;
  std::size_t points = 20000;         ///< map points, outliers included
  std::size_t obstacles = 8;          ///< boxes and cylinders in the room
  double room_size = 10.0;            ///< square room side, metres
  double room_height = 3.0;
  double noise_sigma = 0.01;          ///< centimetre noise
  double outlier_fraction = 0.03;     ///< uniform outliers in the room
  std::size_t gross_outliers = 5;     ///< points far away (1e5 to 1e6 m from the origin)
  std::size_t keyframes = 60;
  bool orbslam_frame = true;          ///< write in ORB-SLAM's frame (y down): read back with --up -y
};

/// Smallest distance between two obstacles' axis-aligned footprints, and between an obstacle and
/// the camera loop, metres.
inline constexpr double kSceneObstacleGap = 0.5;

struct Scene {
  Points points;                       ///< in the output frame (ORB-SLAM's if orbslam_frame)
  std::vector<Keyframe> keyframes;     ///< camera-to-frame poses, in the output frame
  std::vector<SceneObstacle> obstacles;  ///< always z-up map frame
};

/// The rotation taking the z-up map frame to ORB-SLAM's camera frame (y down, z forward):
/// (x, y, z)_map -> (x, -z, y)_orbslam, the inverse of upRotation(UpAxis::kNegY).
Eigen::Matrix3d mapToOrbSlamRotation();

/// Generates the scene. Throws hullmap::Error naming the parameter when the parameters are out of
/// range or the obstacles cannot be placed with the required gaps.
Scene generateScene(const SceneParams& params);

/// Writes points as ORB-SLAM2 map-point text, the trajectory as TUM, the ground truth as JSON,
/// into `dir` (map_points.txt, KeyFrameTrajectory.txt, ground_truth.json), each atomically.
/// `dir` is created when missing.
void writeScene(const Scene& scene, const SceneParams& params, const std::string& dir);

}  // namespace hullmap::mapper
