#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/collision/path_check.hpp"

namespace hullmap::cli {

/// The waypoints of a --path file (one "x y z" a line, map frame; io::readNumberTable's
/// rules: CSV, comments, a header line). One rule for check and plot: a path needs at least two
/// waypoints ("--path p.txt: a path needs at least two waypoints, got 1"). Throws hullmap::Error.
std::vector<Eigen::Vector3d> readPathFile(const std::string& path);

/// readPathFile, or when the first row holds four numbers, a timed path ("t x y z" a line, what
/// `plan --robots` writes): its positions. For plot, which draws both.
std::vector<Eigen::Vector3d> readPlainOrTimedPathFile(const std::string& path);

/// The segments of a --segments file (one "x0 y0 z0 x1 y1 z1" a line). Throws hullmap::Error.
std::vector<collision::Segment> readSegmentsFile(const std::string& path);

/// "--radius: must be >= 0, got -1" unless `radius` is finite and >= 0 (check and plot alike).
void checkRadius(double radius);

}  // namespace hullmap::cli
