#pragma once
// A 2.5D height field: ground heights on a regular grid of nodes, piecewise linear between them.
// The terrain fit (mapper/terrain.hpp) makes one; the path checks (collision/path_check.hpp) take
// the solid under it as an obstacle; obstacles.json stores it.

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace hullmap {

/// Heights on a regular grid (z up, map frame): node (i, j) is the centre of cell (i, j), at
/// origin + step * (i + 0.5, j + 0.5). Between nodes the surface is the triangulation of the node
/// lattice that splits every square of four nodes along its diagonal from node (i, j) to (i + 1,
/// j + 1): linear on each triangle, so the solid under it is a union of convex prisms. Outside the
/// nodes' span it continues level with its edge (each edge node's height outward, each corner's in
/// its quadrant), which is also piecewise linear.
struct HeightField {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< lower corner of cell (0, 0)
  double step = 1.0;                                 ///< cell side, map units, > 0
  std::size_t nx = 0, ny = 0;                        ///< nodes along x and y, >= 1 each
  std::vector<double> heights;                       ///< nx * ny, x fastest, finite

  double at(std::size_t i, std::size_t j) const { return heights[j * nx + i]; }
  /// The node's (x, y).
  Eigen::Vector2d node(std::size_t i, std::size_t j) const {
    return origin + step * Eigen::Vector2d(double(i) + 0.5, double(j) + 0.5);
  }
  /// The surface's height at (x, y) (clamped outside the nodes' span).
  double height(double x, double y) const;
  /// Lowest and highest node.
  double lowest() const;
  double highest() const;
  /// Whether the field is usable: step finite and > 0, origin finite, nx, ny >= 1, nx * ny finite
  /// heights.
  bool valid() const;
};

}  // namespace hullmap
