#pragma once

#include <vector>

#include <Eigen/Core>

namespace hullmap::core {

/// 2D convex hull by Andrew's monotone chain: counter-clockwise, no collinear points, duplicates
/// dropped; fewer than 3 distinct points come back as they are (sorted). Does not check for NaN.
std::vector<Eigen::Vector2d> convexHull2d(std::vector<Eigen::Vector2d> points);

}  // namespace hullmap::core
