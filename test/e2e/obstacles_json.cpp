// obstacles.json /2: parts round-trip exactly, /1 files still read, errors name the JSON path;
// the OBJ has one object per part.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "obstacles_json_fixtures.hpp"
#include "run_hullmap.hpp"

namespace hullmap::pipeline {
namespace {}  // namespace
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
