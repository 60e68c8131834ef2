#pragma once

#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "hullmap/mapper/point_cloud.hpp"
#include "hullmap/mapper/readers.hpp"

namespace hullmap::mapper {

/// Which input axis points up. ORB-SLAM's frame is the first camera's (y down): use kNegY.
enum class UpAxis { kPosX, kNegX, kPosY, kNegY, kPosZ, kNegZ };

/// Parses "x", "-x", "y", "-y", "z", "-z" (also "+x"...). Throws hullmap::Error naming --up.
UpAxis parseUpAxis(const std::string& text);
std::string toString(UpAxis up);

/// The proper rotation that takes the input's `up` axis to +z (det = +1).
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
  std::optional<Box> crop;        ///< keep points inside (inclusive)
  std::optional<double> z_min;    ///< keep z >= z_min
  std::optional<double> z_max;    ///< keep z <= z_max
};

/// Applies the frame change in place to points (and keyframes, poses rotated too).
void toMapFrame(const FrameParams& frame, Points& points);
void toMapFrame(const FrameParams& frame, std::vector<Keyframe>& keyframes);

/// Removes points outside the filter bounds; counts them in `stats.dropped` under "outside_crop",
/// "below_z_min", "above_z_max". Keeps order.
void applyFilters(const FilterParams& filters, Points& points, InputStats& stats);

}  // namespace hullmap::mapper
