// Path checks against the generator's ground truth: a path that flies through an obstacle the map
// observed must never be reported clear. The whole pipeline runs (hullmap build's pipeline::build: frame,
// octree with free space from the keyframes, weighted DBSCAN, hulls), then HullChecker.
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "ground_truth_fixtures.hpp"
#include "hullmap/collision/path_check.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace hullmap::collision {
namespace {

TEST(GroundTruth, NoPathThroughAnObservedObstacleIsReportedClear) {
  // Scenes dense enough for the seed report's reference parameters (eps 0.1, minPts 10) to find each
  // obstacle whole; several seeds, and one scene of 30 obstacles in a larger room.
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    sim::SceneParams params;
    params.seed = seed;
    params.points = 60000;
    const Built b = build(params, "scene_" + std::to_string(seed), 0.1, 10);
    EXPECT_EQ(expectNoPathThroughAnObstacleIsClear(b, {0.0, 0.1, 0.3}, std::uint32_t(seed)), int(params.obstacles));
  }
  sim::SceneParams params;
  params.seed = 4;
  params.points = 200000;
  params.obstacles = 30;
  params.room_size = 20.0;
  const Built b = build(params, "scene_30", 0.1, 10);
  EXPECT_EQ(expectNoPathThroughAnObstacleIsClear(b, {0.0, 0.1, 0.3}, 4), 30);
}

}  // namespace
}  // namespace hullmap::collision
