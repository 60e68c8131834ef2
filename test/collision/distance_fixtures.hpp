#pragma once
// Helpers shared by collision/distance.cpp, collision/heavy/distance.cpp.

#include <gtest/gtest.h>
#include <array>

#include "collision_oracle.hpp"
#include "hullmap/collision/convex_distance.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::collision {

namespace {
using test::V3;

inline std::vector<hulls::ConvexHull> randomHulls(std::mt19937& rng, int count) {
  const auto blobs = test::randomBlobs(rng, count, 120, 0.1, 3);
  std::vector<hulls::ConvexHull> hulls;
  for (const auto& o : hulls::buildObstacles(blobs.centers, blobs.weights, blobs.labels, 0.1))
    hulls.push_back(test::moved(o.hull, rng, 0.5));
  return hulls;
}

inline V3 randomPoint(std::mt19937& rng, double spread) {
  std::uniform_real_distribution<double> u(-spread, spread);
  return {u(rng), u(rng), u(rng)};
}

}  // namespace
}  // namespace hullmap::collision
