#pragma once
// Helpers shared by collision/ground_truth.cpp, collision/heavy/ground_truth.cpp.

#include <gtest/gtest.h>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace hullmap::collision {

namespace {
using V3 = Eigen::Vector3d;
using sim::TruthShape;

/// Distance from p to the obstacle's solid (0 inside).
inline double distanceToSolid(const TruthShape& o, const V3& p) {
  const V3 half = 0.5 * o.size;
  if (o.shape == TruthShape::Shape::kBox) return ((p - o.center).cwiseAbs() - half).cwiseMax(0.0).norm();
  const double radial = std::max(0.0, std::hypot(p.x() - o.center.x(), p.y() - o.center.y()) - half.x());
  const double vertical = std::max(0.0, std::abs(p.z() - o.center.z()) - half.z());
  return std::hypot(radial, vertical);
}

/// A point of the inner part of the solid (the middle 60 % of each extent, or of the radius).
inline V3 innerPoint(const TruthShape& o, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  if (o.shape == TruthShape::Shape::kBox) return o.center + V3(u(rng), u(rng), u(rng)).cwiseProduct(o.size);
  const double angle = (u(rng) + 0.3) / 0.6 * 2 * M_PI;
  const double r = std::sqrt((u(rng) + 0.3) / 0.6) * 0.3 * o.size.x();
  return o.center + V3(r * std::cos(angle), r * std::sin(angle), u(rng) * o.size.z());
}

struct Built {
  sim::Scene scene;
  pipeline::BuildResult result;
};

/// `hullmap build MAP --trajectory TRAJ --up -y` with the given DBSCAN parameters.
inline Built build(const sim::SceneParams& params, const std::string& name, double eps, int min_pts) {
  Built b;
  b.scene = sim::generateScene(params);
  const auto dir = test::freshDir(name);
  sim::writeScene(b.scene, params, dir.string());
  pipeline::BuildParams options;
  options.inputs = {dir / "map_points.txt"};
  options.trajectory = dir / "KeyFrameTrajectory.txt";
  options.frame.up = mapper::UpAxis::kNegY;
  options.eps = eps;
  options.min_pts = min_pts;
  options.floor.mode = mapper::PlaneSetting::Mode::kNone;  // one hull per cluster, as this test is about
  options.convex_parts.reset();
  b.result = pipeline::build(options);
  return b;
}

/// Every ground-truth obstacle that holds a clustered voxel (within one voxel of its solid) is
/// observed; segments through its inner part, in all directions, must collide at every radius.
/// With `contact_before_inside`, also: the first contact comes no later than the point inside the
/// solid (true when each obstacle is one cluster; fragments may let a path in before it hits one).
inline int expectNoPathThroughAnObstacleIsClear(const Built& b, const std::vector<double>& radii, std::uint32_t seed,
                                                bool contact_before_inside = true) {
  const HullChecker checker(b.result.obstacles);
  const double voxel = b.result.map.resolution();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  int observed = 0, clear = 0, late = 0;
  std::string first_clear;
  const std::vector<TruthShape> truth = b.scene.truth.primitives();
  for (std::size_t k = 0; k < truth.size(); ++k) {
    const TruthShape& o = truth[k];
    bool seen = false;
    for (std::size_t i = 0; i < b.result.voxels.size() && !seen; ++i)
      seen = b.result.clusters.labels[i] >= 0 && distanceToSolid(o, b.result.voxels[i].center) <= voxel;
    if (!seen) continue;
    ++observed;
    for (int s = 0; s < 300; ++s) {
      const V3 p = innerPoint(o, rng);
      V3 d(u(rng), u(rng), 0.6 * u(rng));
      d.normalize();
      // From outside, through p, to outside: 2 m each way leaves every obstacle of the scene.
      const Segment segment{p - 2.0 * d, p + 2.0 * d};
      for (const double r : radii) {
        const SegmentCheck c = checker.check(segment, r);
        if (!c.collides) {
          if (clear++ == 0) {
            std::ostringstream what;
            what << "ground-truth obstacle " << k << " (centre " << o.center.transpose() << "), segment through "
                 << p.transpose() << " along " << d.transpose() << ", radius " << r << ", clearance " << c.clearance;
            first_clear = what.str();
          }
        } else if (contact_before_inside) {
          late += c.t > 0.5 + 1e-3;
        }
      }
    }
  }
  EXPECT_EQ(clear, 0) << "paths through an observed obstacle reported clear; the first: " << first_clear;
  EXPECT_EQ(late, 0) << "paths whose first contact is reported after they are inside an obstacle";
  return observed;
}

}  // namespace
}  // namespace hullmap::collision
