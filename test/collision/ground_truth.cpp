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

TEST(GroundTruth, SparseSampleAtReferenceParametersFragmentsButDronesDoNotSlipThrough) {
  // maps/simple (20,000 points, seed 42) at eps 0.1, minPts 10 splits its 8 obstacles into ~90
  // clusters; a line (radius 0) can pass between two fragments' hulls, a sphere of 0.1 m cannot.
  // At eps 0.12, minPts 5 each obstacle is one cluster and not even a line gets through.
  sim::SceneParams params;  // the generator's defaults are maps/simple's
  const Built fragmented = build(params, "sample_reference", 0.1, 10);
  EXPECT_GT(fragmented.result.obstacles.size(), 2 * params.obstacles);
  EXPECT_EQ(expectNoPathThroughAnObstacleIsClear(fragmented, {0.1, 0.3}, 42, false), int(params.obstacles));
  const Built whole = build(params, "sample_whole", 0.12, 5);
  EXPECT_EQ(whole.result.obstacles.size(), params.obstacles);
  EXPECT_EQ(expectNoPathThroughAnObstacleIsClear(whole, {0.0, 0.1, 0.3}, 43), int(params.obstacles));
}

}  // namespace
}  // namespace hullmap::collision
