#pragma once

// nanoflann's k-d tree over a vector of Eigen points, searched on their first D coordinates (exact
// nearest neighbours, the squared distance summed per axis in axis order).

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <nanoflann.hpp>

namespace hullmap::core {

/// The points as nanoflann's dataset (referenced, not copied: they must outlive the tree).
struct PointsAdaptor {
  const std::vector<Eigen::Vector3d>& points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t axis) const { return points[i][static_cast<Eigen::Index>(axis)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

/// The tree on the first D coordinates; indices are std::uint32_t.
template <int D>
using PointKdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor>,
                                                        PointsAdaptor, D, std::uint32_t>;

}  // namespace hullmap::core
