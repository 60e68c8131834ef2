// evaluate: truth geometry against brute-force oracles; hand-built cases with known answers; the
// CLI's exit codes.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/evaluate.hpp"
#include "run_hullmap.hpp"

namespace hullmap::pipeline {
namespace {

using V3 = Eigen::Vector3d;
using test::expectOneLineError;

TEST(EvaluateCli, ScoresABuildAndRefusesBadTruth) {
  const auto dir = test::freshDir("cli");
  const std::string truth = std::string(HULLMAP_SOURCE_DIR) + "/maps/simple/ground_truth.json";
  const auto build = test::runHullmap("build " + std::string(HULLMAP_SOURCE_DIR) +
                                      "/maps/simple/map_points.txt --up -y -o " + (dir / "out").string());
  ASSERT_EQ(build.status, 0) << build.err;
  const auto ok =
      test::runHullmap("evaluate " + (dir / "out").string() + " --truth " + truth + " --segments 300 --json");
  ASSERT_EQ(ok.status, 0) << ok.err;
  const auto doc = nlohmann::json::parse(ok.out);
  EXPECT_EQ(doc["truth"].size(), 8u);
  EXPECT_EQ(doc["segments"]["count"], 300);
  EXPECT_EQ(doc["segments"]["missed"], 0);
  // Each hull represents at most one true obstacle.
  std::size_t representing = 0;
  for (const auto& t : doc["truth"]) {
    ASSERT_TRUE(t["parts"].is_array());
    representing += t["parts"].size();
  }
  EXPECT_GT(representing, 0u);
  EXPECT_LE(representing, doc["parts"].get<std::size_t>());

  std::ofstream(dir / "bad.json") << "{\"obstacles\": [{\"shape\": \"cone\", \"center\": [0,0,0], \"size\": [1,1,1]}]}";
  expectOneLineError(test::runHullmap("evaluate " + (dir / "out").string() + " --truth " + (dir / "bad.json").string()),
                     "bad.json: obstacles[0].shape: expected \"box\" or \"cylinder\"");
  std::ofstream(dir / "broken.json") << "{\"obstacles\": [";
  expectOneLineError(
      test::runHullmap("evaluate " + (dir / "out").string() + " --truth " + (dir / "broken.json").string()),
      "broken.json: not valid JSON");
  std::ofstream(dir / "bad.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 9\n";
  expectOneLineError(test::runHullmap("evaluate " + (dir / "out").string() + " --truth " + (dir / "bad.obj").string()),
                     "bad.obj:3: face index 9 out of range");
  expectOneLineError(
      test::runHullmap("evaluate " + (dir / "out").string() + " --truth " + (dir / "none.json").string()),
      "none.json: cannot open");
  expectOneLineError(test::runHullmap("evaluate " + (dir / "out").string() + " --truth " + truth + " --radius -1"),
                     "--radius");
  std::ofstream(dir / "union.json") << "{\"obstacles\": [{\"shape\": \"union\", \"parts\": [{\"shape\": \"cone\"}]}]}";
  expectOneLineError(
      test::runHullmap("evaluate " + (dir / "out").string() + " --truth " + (dir / "union.json").string()),
      "union.json: obstacles[0].parts[0].shape: expected \"box\" or \"cylinder\"");
}

}  // namespace
}  // namespace hullmap::pipeline
