// Obstacles: the hull of a cluster contains every voxel completely and is no bigger than the hull
// of the voxels' corners; footprints and volumes against direct computations.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>
#include <tuple>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "obstacles_fixtures.hpp"
#include "test_support.hpp"

namespace hullmap::hulls {
namespace {

TEST(Obstacles, HullsOfGeneratedMapsContainEveryClusteredVoxel) {
  for (const std::uint64_t seed : {42u, 7u}) {
    sim::SceneParams params;
    params.seed = seed;
    params.points = 40000;
    const auto dir = test::freshDir("scene_" + std::to_string(seed));
    sim::writeScene(sim::generateScene(params), params, dir.string());
    pipeline::BuildParams options;
    options.eps = 0.1;  // the classic setting: many clusters to check
    options.min_pts = 10;
    options.inputs = {dir / "map_points.txt"};
    options.trajectory = dir / "KeyFrameTrajectory.txt";
    options.frame.up = mapper::UpAxis::kNegY;
    SCOPED_TRACE("seed " + std::to_string(seed));
    expectBuildWrapsEveryCluster(options);
  }
}

}  // namespace
}  // namespace hullmap::hulls
