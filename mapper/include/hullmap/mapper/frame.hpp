#pragma once

#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "hullmap/io/point_cloud.hpp"
#include "hullmap/io/readers.hpp"

namespace hullmap::mapper {

/// Which input axis points up. ORB-SLAM's frame is the first camera's (y down): use kNegY.
enum class UpAxis { kPosX, kNegX, kPosY, kNegY, kPosZ, kNegZ };

/// Parses "x", "-x", "y", "-y", "z", "-z" (also "+x"..., case-insensitive). Throws hullmap::Error
/// naming --up.
UpAxis parseUpAxis(const std::string& text);

/// "+x", "-x", "+y", "-y", "+z", "-z" (parseUpAxis reads them back).
std::string toString(UpAxis up);

/// The proper rotation (det = +1) that takes the input's `up` axis to +z:
/// - +z: identity;
/// - -z: 180 deg about x ((x, y, z) -> (x, -y, -z));
/// - +y: +90 deg about x ((x, y, z) -> (x, -z, y));
/// - -y: -90 deg about x ((x, y, z) -> (x, z, -y)): ORB-SLAM's camera frame (x right, y down,
///   z forward) becomes x right, y forward, z up;
/// - +x: -90 deg about y ((x, y, z) -> (-z, y, x));
/// - -x: +90 deg about y ((x, y, z) -> (z, y, -x)).
Eigen::Matrix3d upRotation(UpAxis up);

/// The map frame: input points are scaled by `scale` then rotated so `up` becomes +z.
struct FrameParams {
  UpAxis up = UpAxis::kPosZ;
  double scale = 1.0;
};

/// Axis-aligned box in the z-up map frame.
struct Box {
  Eigen::Vector3d min;
  Eigen::Vector3d max;
};

/// Bounds applied after the frame change.
struct FilterParams {
  std::optional<Box> crop;      ///< keep points inside (inclusive)
  std::optional<double> z_min;  ///< keep z >= z_min
  std::optional<double> z_max;  ///< keep z <= z_max
};

/// Applies the frame change in place: p -> R * (scale * p), R = upRotation(frame.up).
/// Throws hullmap::Error naming --scale unless scale is finite and > 0.
void toMapFrame(const FrameParams& frame, io::Points& points);

/// The same for keyframe poses (camera-to-map): position -> R * (scale * position),
/// orientation -> R * orientation.
void toMapFrame(const FrameParams& frame, std::vector<io::Keyframe>& keyframes);

/// Removes points outside the filter bounds, keeping the order of the rest. Each removed point is
/// counted once in `stats.dropped`, under the first test it fails in this order: "outside_crop"
/// (outside the inclusive crop box), "below_z_min" (z < z_min), "above_z_max" (z > z_max). A reason
/// appears in the map only when it removed at least one point.
void applyFilters(const FilterParams& filters, io::Points& points, io::InputStats& stats);

/// Parses "x,y,z" (three finite numbers, spaces allowed around the commas) for command-line
/// option `option` (e.g. "--origin"). Throws hullmap::Error naming the option and the text.
Eigen::Vector3d parseVector3(const std::string& option, const std::string& text);

/// Parses "x0,y0,z0,x1,y1,z1" (min corner then max corner; min <= max on each axis) for option
/// `option` (e.g. "--crop"). Throws hullmap::Error naming the option and the text.
Box parseBox(const std::string& option, const std::string& text);

}  // namespace hullmap::mapper
