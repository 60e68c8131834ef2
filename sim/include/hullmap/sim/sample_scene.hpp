#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hullmap/io/point_cloud.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/sim/ground_truth.hpp"

namespace hullmap::sim {

/// What a generated scene holds.
/// - kObstacles: boxes and cylinders standing on an unseen floor, no walls (the original scene; the
///   tests, benchmarks and maps/simple use it).
/// - kRoom: a realistic room as ORB-SLAM maps it: walls and floor, furniture that is not convex
///   (L-shaped shelves, tables on legs) beside boxes and cylinders, sparse points (`density` per
///   square metre of visible surface), written in the first camera's frame at a monocular scale,
///   with a metric reference trajectory to align it.
enum class SceneLayout { kObstacles, kRoom };

/// Where a kRoom scene's furniture stands.
/// - kInsideLoop: inside the camera loop, kSceneObstacleGap from it and from each other (the room
///   of maps/room and the tests).
/// - kAnywhere: a cluttered room: anywhere in the room, inside or outside the camera loop,
///   kSceneObstacleGap from the loop and from each other; a share (SceneParams::wall_fraction) of
///   the pieces stand against a wall (their back 3 to 10 cm from its face, in a corner when it falls
///   there), the others kSceneObstacleGap from the walls.
enum class FurniturePlacement { kInsideLoop, kAnywhere };

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
  std::size_t points = 20000;  ///< map points, outliers included
  std::size_t obstacles = 8;   ///< boxes and cylinders in the room
  double room_size = 10.0;     ///< square room side (kRoom: its side along x), metres
  double room_height = 3.0;
  double noise_sigma = 0.01;       ///< centimetre noise
  double outlier_fraction = 0.03;  ///< uniform outliers in the room
  std::size_t gross_outliers = 5;  ///< points far away (1e5 to 1e6 m from the origin)
  std::size_t keyframes = 60;
  bool orbslam_frame = true;  ///< write in ORB-SLAM's frame (y down): read back with --up -y

  /// kRoom only (see SceneLayout). The room is room_size x room_width x room_height, floor at z = 0,
  /// walls' inner faces at x = +-room_size / 2, y = +-room_width / 2; `obstacles` pieces of furniture
  /// (0 allowed), placed as `placement` says. `points` is ignored:
  /// visible surfaces get `density` points per m^2 (ORB-SLAM maps of EuRoC hold about 50 to 500,
  /// see maps/README.md), `edge_fraction` of them on face edges; outlier_fraction is of all points.
  /// With orbslam_frame the output frame is the first keyframe's camera frame (x right, y down,
  /// z forward; that camera looks toward the room's axis, pitched down by camera_pitch_deg),
  /// scaled by monocular_scale (map units per metre); otherwise the z-up map frame in metres.
  SceneLayout layout = SceneLayout::kObstacles;
  double density = 80.0;           ///< map points per m^2 of visible surface (> 0)
  double edge_fraction = 0.3;      ///< share of surface points on face edges, [0, 1]
  double monocular_scale = 0.37;   ///< map units per metre in the ORB-SLAM frame (> 0)
  double camera_pitch_deg = 20.0;  ///< cameras look down by this, [0, 80]
  /// kRoom: the room's side along y, metres (>= 4); 0: room_size (a square room). The walls' inner
  /// faces are then at x = +-room_size / 2 and y = +-room_width / 2.
  double room_width = 0.0;
  /// kRoom: the camera loop is an ellipse at about kCameraHeight whose semi-axes are this fraction
  /// of the room's sides, in (0, 0.5) (0.4: 0.8 m from the walls of an 8 m room).
  double loop_fraction = 0.4;
  FurniturePlacement placement = FurniturePlacement::kInsideLoop;  ///< kRoom: where furniture stands
  /// kRoom with kAnywhere: the chance that a piece is placed against a wall, [0, 1].
  double wall_fraction = 0.5;
};

/// Smallest distance between two obstacles' axis-aligned footprints, and between an obstacle and
/// the camera loop, metres.
inline constexpr double kSceneObstacleGap = 0.5;

struct Scene {
  io::Points points;                    ///< in the output frame (ORB-SLAM's if orbslam_frame)
  std::vector<io::Keyframe> keyframes;  ///< camera-to-frame poses, in the output frame
  /// The true obstacles, z-up map frame, metres, labelled as readGroundTruth labels the written
  /// ground_truth.json: kObstacles: the boxes and cylinders (kind "box" or "cylinder"); kRoom: the
  /// floor, 4 walls and the furniture ("box", "cylinder", "l_shelf", "table"; unions when of several
  /// parts). All axis-aligned; obstacles and furniture stand on the floor (z = 0).
  GroundTruth truth;
  std::vector<io::Keyframe> reference;  ///< kRoom: the same keyframes in the z-up map frame, metres
  /// kRoom: output frame from the z-up map frame, p_out = scale * rotation * p + translation
  /// (identity when not orbslam_frame).
  double output_scale = 1.0;
  Eigen::Matrix3d output_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d output_translation = Eigen::Vector3d::Zero();
};

/// The rotation taking the z-up map frame to ORB-SLAM's camera frame (y down, z forward):
/// (x, y, z)_map -> (x, -z, y)_orbslam, the inverse of upRotation(UpAxis::kNegY).
Eigen::Matrix3d mapToOrbSlamRotation();

/// Generates the scene. Throws hullmap::Error naming the parameter when the parameters are out of
/// range or the obstacles cannot be placed with the required gaps.
Scene generateScene(const SceneParams& params);

/// Writes points as ORB-SLAM2 map-point text, the trajectory as TUM, the ground truth as JSON,
/// into `dir` (map_points.txt, KeyFrameTrajectory.txt, ground_truth.json), each atomically; a kRoom
/// scene also gets reference_trajectory.txt (TUM `t x y z qx qy qz qw`, z-up metres, the
/// keyframes' stamps: `--align` input). The JSON is described in maps/README.md.
/// `dir` is created when missing.
void writeScene(const Scene& scene, const SceneParams& params, const std::string& dir);

}  // namespace hullmap::sim
