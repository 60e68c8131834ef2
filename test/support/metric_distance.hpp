#pragma once

#include <Eigen/Core>

#include "hullmap/clustering/dbscan.hpp"

namespace hullmap::test {

/// Squared distance under `metric` as dbscan.hpp states it (dx*dx + dy*dy, + dz*dz for xyz, in that
/// order): the distance the brute-force oracles of DBSCAN and of the cluster extension use.
inline double squaredDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b, clustering::Metric metric) {
  const double dx = a.x() - b.x();
  const double dy = a.y() - b.y();
  if (metric == clustering::Metric::kXy) return dx * dx + dy * dy;
  const double dz = a.z() - b.z();
  return dx * dx + dy * dy + dz * dz;
}

}  // namespace hullmap::test
