// obstacles.json /2: parts round-trip exactly, /1 files still read, errors name the JSON path;
// the OBJ has one object per part.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "run_hullmap.hpp"

namespace hullmap::pipeline {
namespace {

using V3 = Eigen::Vector3d;

/// An L (two parts) and a box (one part), 5 cm voxels.
std::vector<hulls::Obstacle> lAndBox() {
  std::vector<V3> centers;
  std::vector<std::int32_t> labels;
  const auto add = [&](int i0, int i1, int j0, int j1, int k1, std::int32_t label) {
    for (int i = i0; i < i1; ++i)
      for (int j = j0; j < j1; ++j)
        for (int k = 0; k < k1; ++k) {
          centers.push_back(V3(i + 0.5, j + 0.5, k + 0.5) * 0.05);
          labels.push_back(label);
        }
  };
  add(0, 30, 0, 4, 10, 0);
  add(0, 4, 4, 20, 10, 0);
  add(50, 60, 0, 5, 5, 1);
  auto obstacles = hulls::buildObstacles(centers, {}, labels, 0.05);
  hulls::addConvexParts(obstacles, centers, {}, labels, 0.05, {});
  return obstacles;
}

}  // namespace
}  // namespace hullmap::pipeline

namespace hullmap::pipeline {
namespace {

TEST(ObstaclesJson, CheckReadsVersion2AndNamesThePart) {
  const auto dir = test::freshDir("check");
  const std::string path = (dir / "obstacles.json").string();
  std::ofstream(path) << obstaclesToJson(lAndBox(), {}).dump(1);
  // Through the L's notch (free with parts), then into the far end of its x arm.
  const auto notch = test::runHullmap("check " + path + " --radius 0.05 --segment 0.8,0.6,0.1,0.8,0.6,0.4");
  EXPECT_EQ(notch.status, 0) << notch.err;
  const auto hit = test::runHullmap("check " + path + " --radius 0.05 --segment 1.4,0.6,0.25,1.4,0.1,0.25 --json");
  EXPECT_EQ(hit.status, 1) << hit.err;
  const auto line = nlohmann::json::parse(hit.out.substr(0, hit.out.find('\n')));
  EXPECT_EQ(line["obstacle"], 0);
  ASSERT_TRUE(line.contains("part"));
  EXPECT_GT(lAndBox()[0].parts.at(line["part"].get<std::size_t>()).aabb_max.x(), 1.0);
  const auto text = test::runHullmap("check " + path + " --radius 0.05 --segment 1.4,0.6,0.25,1.4,0.1,0.25");
  EXPECT_NE(text.out.find("with obstacle 0 part "), std::string::npos) << text.out;
}

}  // namespace
}  // namespace hullmap::pipeline
