#pragma once

#include <array>
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
/// - kOutdoor: a street as a car's monocular ORB-SLAM maps it: a terrain that is no plane (a slope
///   and smooth bumps, the truth a height field), buildings, trees, parked cars and posts beside the
///   street, sparse points mostly on the ground, written in the first camera's frame at a monocular
///   scale that drifts along the street, with a metric reference trajectory and a GPS log.
enum class SceneLayout { kObstacles, kRoom, kOutdoor };

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

  /// The scene kind; the fields below are kRoom's (`points` is then ignored; the room's geometry and
  /// frames: docs/DESIGN_NOTES.md, "sample_scene.hpp: the kRoom scene").
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

  /// kOutdoor only (see generateScene; outdoorSceneParams() gives its defaults): the area is track_width x
  /// track_length metres, x across, y along the street, centred on the origin, rounded up to whole metres.
  double track_length = 200.0;  ///< the area along the street (y), metres, >= 40
  double track_width = 60.0;    ///< the area across the street (x), metres, >= 30
  double slope_along = 0.03;    ///< the terrain's grade along y (rise over run), [-0.2, 0.2]
  double slope_across = 0.02;   ///< the terrain's grade along x, [-0.2, 0.2]
  std::size_t bumps = 12;       ///< Gaussian bumps and dips on the slope (0 allowed)
  double bump_height = 1.0;     ///< largest bump amplitude, metres, [0, 5]
  std::size_t buildings = 16;   ///< boxes beside the street (each count: 0 allowed)
  std::size_t trees = 16;       ///< a trunk and a crown on the verges
  std::size_t cars = 10;        ///< boxes parked on the street's sides
  std::size_t posts = 12;       ///< thin cylinders at the kerbs
  /// The monocular scale grows along the path from monocular_scale to monocular_scale * (1 +
  /// scale_drift) at its end, (-1, 10]; 0: no drift.
  double scale_drift = 0.15;
  double gps_sigma = 3.0;    ///< GPS noise, metres, per axis (east, north, up), >= 0
  double gps_dropout = 0.1;  ///< the share of GPS lines without a fix, [0, 1]
};

/// kOutdoor's defaults: SceneParams's, with layout kOutdoor and the fields it shares with kRoom
/// set for a street (100 keyframes, 3 points per m^2, 5 cm noise, pitch 10 degrees, monocular scale
/// 0.0145 map units per metre: one unit is 69 m, as an outdoor ORB-SLAM map aligned to GPS).
SceneParams outdoorSceneParams();

/// Smallest distance between two obstacles' axis-aligned footprints, and between an obstacle and
/// the camera loop, metres.
inline constexpr double kSceneObstacleGap = 0.5;

/// kOutdoor: the cameras' height above the terrain, metres (a car's roof).
inline constexpr double kOutdoorCameraHeight = 1.6;
/// kOutdoor: smallest horizontal distance between an object's footprint (its parts' axis-aligned
/// rectangles) and the camera path (the polyline through the keyframes), metres.
inline constexpr double kOutdoorPathMargin = 2.0;
/// kOutdoor: where the map frame's origin is on Earth: WGS84 latitude, longitude (degrees) and
/// altitude (metres above the ellipsoid); the map's x points east, y north, z up.
inline constexpr std::array<double, 3> kOutdoorGeodeticOrigin{47.3769, 8.5417, 408.0};

/// One line of a kOutdoor scene's gps.txt.
struct GpsFix {
  double stamp = 0.0;  ///< the keyframe's stamp, seconds
  bool fix = true;     ///< false: no fix, written `t 0 0 0` as receivers do
  double latitude_deg = 0.0, longitude_deg = 0.0, altitude_m = 0.0;  ///< WGS84, when fix
};

struct Scene {
  io::Points points;                    ///< in the output frame (ORB-SLAM's if orbslam_frame)
  std::vector<io::Keyframe> keyframes;  ///< camera-to-frame poses, in the output frame
  /// The true obstacles, z-up map frame, metres, as readGroundTruth reads ground_truth.json; kinds
  /// per layout: docs/DESIGN_NOTES.md, "sample_scene.hpp: Scene::truth".
  GroundTruth truth;
  /// kRoom, kOutdoor: the same keyframes in the z-up map frame, metres.
  std::vector<io::Keyframe> reference;
  /// kRoom: output frame from the z-up map frame, p_out = scale * rotation * p + translation
  /// (identity when not orbslam_frame). kOutdoor: that similarity at the first keyframe only.
  double output_scale = 1.0;
  Eigen::Matrix3d output_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d output_translation = Eigen::Vector3d::Zero();
  /// kOutdoor: `points` in the z-up map frame, metres, in the same order (noise and outliers
  /// included); empty for the other layouts.
  std::vector<Eigen::Vector3d> map_points;
  /// kOutdoor: each keyframe's monocular scale, map units per metre (1 without orbslam_frame).
  std::vector<double> keyframe_scales;
  std::vector<GpsFix> gps;  ///< kOutdoor: gps.txt's lines, one per keyframe, in order
};

/// The rotation taking the z-up map frame to ORB-SLAM's camera frame (y down, z forward):
/// (x, y, z)_map -> (x, -z, y)_orbslam, the inverse of upRotation(UpAxis::kNegY).
Eigen::Matrix3d mapToOrbSlamRotation();

/// Generates the scene. Throws hullmap::Error naming the parameter when the parameters are out of
/// range or the obstacles cannot be placed with the required gaps.
///
/// kOutdoor: a terrain with a slope and bumps, a winding 10 m street with keyframes along it, buildings,
/// trees, cars and posts beside it, points seen from the keyframes, a drifting monocular scale and a GPS
/// log; the exact recipe: docs/DESIGN_NOTES.md, "sample_scene.hpp: the kOutdoor scene".
Scene generateScene(const SceneParams& params);

/// Writes points as ORB-SLAM2 map-point text, the trajectory as TUM, the ground truth as JSON,
/// into `dir` (map_points.txt, KeyFrameTrajectory.txt, ground_truth.json), each atomically; a kRoom
/// or kOutdoor scene also gets reference_trajectory.txt (TUM `t x y z qx qy qz qw`, z-up metres, the
/// keyframes' stamps: `--align` input), a kOutdoor scene gps.txt (`t lat lon alt` a line, `t 0 0 0`
/// without a fix: `--align-format gps` input). The files are described in maps/README.md.
/// `dir` is created when missing.
void writeScene(const Scene& scene, const SceneParams& params, const std::string& dir);

}  // namespace hullmap::sim
