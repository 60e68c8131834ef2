#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "hullmap/core/error.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/sim/sample_scene.hpp"

namespace hullmap::test {

/// The name of the parameter that the hullmap::Error thrown by `call` gives (its parameter()); a
/// failure when nothing or something else is thrown.
template <typename Call>
std::string refusedParameter(Call call) {
  try {
    call();
  } catch (const Error& e) {
    return e.parameter();
  }
  ADD_FAILURE() << "no hullmap::Error thrown";
  return "";
}

/// A convex prism obstacle: the counter-clockwise `polygon` extruded over [z0, z1], with an outward
/// triangulated hull and its footprint.
inline hulls::Obstacle prism(int id, const std::vector<Eigen::Vector2d>& polygon, double z0, double z1) {
  hulls::Obstacle o;
  o.id = id;
  const int n = static_cast<int>(polygon.size());
  for (const auto& p : polygon) o.hull.vertices.emplace_back(p.x(), p.y(), z0);
  for (const auto& p : polygon) o.hull.vertices.emplace_back(p.x(), p.y(), z1);
  for (int i = 1; i + 1 < n; ++i) {
    o.hull.triangles.push_back({0, i + 1, i});          // bottom, seen from below
    o.hull.triangles.push_back({n, n + i, n + i + 1});  // top
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    o.hull.triangles.push_back({i, j, n + j});
    o.hull.triangles.push_back({i, n + j, n + i});
  }
  o.footprint.polygon = polygon;
  o.footprint.z_min = z0;
  o.footprint.z_max = z1;
  o.aabb_min = Eigen::Vector3d(1e300, 1e300, z0);
  o.aabb_max = Eigen::Vector3d(-1e300, -1e300, z1);
  for (const auto& p : polygon) {
    o.aabb_min.head<2>() = o.aabb_min.head<2>().cwiseMin(p);
    o.aabb_max.head<2>() = o.aabb_max.head<2>().cwiseMax(p);
  }
  o.centroid = 0.5 * (o.aabb_min + o.aabb_max);
  return o;
}

/// The ground-truth solids of a generated scene as prisms that contain them: boxes exactly,
/// cylinders by the circumscribed 32-gon.
inline std::vector<hulls::Obstacle> truthObstacles(const sim::Scene& scene) {
  std::vector<hulls::Obstacle> out;
  for (const auto& s : scene.truth.primitives()) {
    const Eigen::Vector2d c = s.center.head<2>();
    const double z0 = s.center.z() - 0.5 * s.size.z(), z1 = s.center.z() + 0.5 * s.size.z();
    std::vector<Eigen::Vector2d> poly;
    if (s.shape == sim::TruthShape::Shape::kBox) {
      const Eigen::Vector2d h = 0.5 * s.size.head<2>();
      poly = {c + Eigen::Vector2d(-h.x(), -h.y()), c + Eigen::Vector2d(h.x(), -h.y()), c + h,
              c + Eigen::Vector2d(-h.x(), h.y())};
    } else {
      const double r = 0.5 * s.size.x() / std::cos(M_PI / 32);
      for (int k = 0; k < 32; ++k)
        poly.push_back(c + r * Eigen::Vector2d(std::cos(2 * M_PI * k / 32), std::sin(2 * M_PI * k / 32)));
    }
    out.push_back(prism(static_cast<int>(out.size()), poly, z0, z1));
  }
  return out;
}

/// Exact distance from p to a ground-truth solid, metres.
inline double distanceToSolid(const sim::TruthShape& o, const Eigen::Vector3d& p) {
  const Eigen::Vector3d half = 0.5 * o.size;
  if (o.shape == sim::TruthShape::Shape::kBox) return ((p - o.center).cwiseAbs() - half).cwiseMax(0.0).norm();
  const double radial = std::max(0.0, (p - o.center).head<2>().norm() - half.x());
  const double vertical = std::max(0.0, std::abs(p.z() - o.center.z()) - half.z());
  return std::hypot(radial, vertical);
}

}  // namespace hullmap::test
