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

  /// kOutdoor only (see SceneLayout and generateScene's kOutdoor notes; outdoorSceneParams() gives
  /// its defaults for the fields it shares with kRoom). The area is track_width x track_length
  /// metres (x across, y along the street, centred on the origin; each rounded up to whole metres).
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
/// kOutdoor, exactly (z-up map frame, metres; x east, y north):
/// - Terrain: z = slope_across x + slope_along y + the sum of `bumps` Gaussians (amplitude uniform
///   in [-bump_height, bump_height], sigma in [5, 15] m, centres anywhere in the area), sampled every
///   1 m (heights rounded to 0.1 mm) and triangulated: the truth's height field IS the terrain.
/// - Street: 10 m wide, its centreline x = 3 sin(2 pi y / track_length) (with 1.5 m in an area under
///   40 m wide). Keyframes are evenly spaced along it (by arc length) from 10 m after the area's
///   start to 10 m before its end, kOutdoorCameraHeight above the terrain, each looking along the
///   street, pitched down by camera_pitch_deg; stamps 1, 1.5, 2, ... s.
/// - Objects, axis-aligned, kSceneObstacleGap apart (footprints), kOutdoorPathMargin from the path,
///   inside the area: buildings (8-20 m along the street, 6-12 m deep, 5-15 m high, 4-8 m back from
///   the street's edge), trees (a trunk 0.25-0.45 m wide, 1.8-3 m high, under a crown cylinder or
///   box 2.5-4.5 m wide and 2-4 m high, 1 to 5 m beyond the street's edge), cars (3.8-4.8 x
///   1.7-1.9 x 1.4-1.7 m, 0.3 m in from the street's edge), posts (0.1-0.2 m wide, 2.5-5 m high,
///   0.3-0.8 m beyond the edge). Each stands on the lowest terrain under its foot (a tree's trunk,
///   else its footprint) and reaches below it there: by 0.5 m a building, 0.3 m the others. Throws
///   naming the count that does not fit.
/// - Points: the visible surfaces (the terrain, objects' sides and tops; no bottoms) drawn with
///   `density` tries per m^2; a try is kept when some keyframe sees it: within 40 m, in its 90 x 70
///   degree view, on the front of the surface, the line of sight clear of every object (the terrain
///   hides nothing) and the point not under the terrain or inside another object. `edge_fraction` of
///   the tries on objects lie on face edges. Then Gaussian noise (noise_sigma per axis), outliers
///   (outlier_fraction of all points, 0 to 12 m above the terrain anywhere in the area) and
///   gross_outliers far away.
/// - Scale drift: keyframe k, at arc length a_k of the A-long keyframe polyline, has the scale s_k =
///   monocular_scale (1 + scale_drift a_k / A). With R0, c0 the first camera's rotation and
///   position, keyframe positions are written as w_0 = 0, w_k+1 = w_k + (s_k + s_k+1) / 2 R0^T
///   (c_k+1 - c_k), orientations as R0^T R_k. A point p is written from its nearest polyline segment
///   in (x, y) [c_k, c_k+1], at the fraction f of the segment's point q nearest p (clamped to [0, 1]):
///   w = (1 - f) w_k + f w_k+1 + ((1 - f) s_k + f s_k+1) R0^T (p - q). So near keyframe k the map is
///   the similarity of scale s_k; near the first, the room layout's first camera frame.
///   Without orbslam_frame points and keyframes stay in the map frame, unscaled.
/// - GPS: for each keyframe, its true position plus Gaussian noise of gps_sigma per axis (east,
///   north, up), converted to WGS84 around kOutdoorGeodeticOrigin; round(gps_dropout x keyframes)
///   lines, chosen at random, hold no fix.
Scene generateScene(const SceneParams& params);

/// Writes points as ORB-SLAM2 map-point text, the trajectory as TUM, the ground truth as JSON,
/// into `dir` (map_points.txt, KeyFrameTrajectory.txt, ground_truth.json), each atomically; a kRoom
/// or kOutdoor scene also gets reference_trajectory.txt (TUM `t x y z qx qy qz qw`, z-up metres, the
/// keyframes' stamps: `--align` input), a kOutdoor scene gps.txt (`t lat lon alt` a line, `t 0 0 0`
/// without a fix: `--align-format gps` input). The files are described in maps/README.md.
/// `dir` is created when missing.
void writeScene(const Scene& scene, const SceneParams& params, const std::string& dir);

}  // namespace hullmap::sim
