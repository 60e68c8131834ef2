// `hullmap check` end to end, and the obstacles.json / OBJ writers and reader it relies on.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <octomap/OcTree.h>
#include <nlohmann/json.hpp>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "obstacle_io_fixtures.hpp"
#include "run_hullmap.hpp"

namespace hullmap::pipeline {

namespace {

TEST(CheckCommand, SegmentsPathsStatusAndJson) {
  const auto dir = test::freshDir("check_cli");
  std::vector<V3> voxels;
  const auto obstacles = twoBoxes(&voxels);
  writeObstaclesJson((dir / "obstacles.json").string(), obstacles, {});
  const std::string out = dir.string();

  auto clear = test::runHullmap("check " + out + " --radius 0.3 --segment 0,3,0.5,6,3,0.5");
  EXPECT_EQ(clear.status, 0) << clear.err;
  EXPECT_NE(clear.out.find("clear, clearance 1.7"), std::string::npos) << clear.out;

  auto hit = test::runHullmap("check " + out + " --radius 0.3 --segment 0,0.5,0.5,6,0.5,0.5 --json");
  EXPECT_EQ(hit.status, 1) << hit.err;
  const auto j = nlohmann::json::parse(hit.out);
  EXPECT_EQ(j["index"], 0);
  EXPECT_EQ(j["collides"], true);
  EXPECT_EQ(j["obstacle"], 0);
  EXPECT_NEAR(j["t"].get<double>(), 0.7 / 6.0, 1e-3);  // sphere touches x = 1 when its centre is at 0.7
  EXPECT_EQ(j["clearance"], 0.0);

  writeText(dir / "segs.txt", "# x0 y0 z0 x1 y1 z1\n0 3 0.5 6 3 0.5\n\n3 0.5 0.5 3.5 0.5 3\n4.5 -1 0.5 4.5 2 0.5\n");
  auto batch = test::runHullmap("check " + (dir / "obstacles.json").string() + " --radius 0.3 --segments " +
                                (dir / "segs.txt").string() + " --json");
  EXPECT_EQ(batch.status, 1) << batch.err;
  ASSERT_EQ(test::lineCount(batch.out), 3) << batch.out;
  std::istringstream lines(batch.out);
  std::string line;
  std::vector<nlohmann::json> rows;
  while (std::getline(lines, line)) rows.push_back(nlohmann::json::parse(line));
  EXPECT_EQ(rows[0]["collides"], false);
  EXPECT_EQ(rows[0]["obstacle"], nullptr);
  EXPECT_EQ(rows[1]["collides"], false);
  // Closest to obstacle 3's edge x = 4, z = 1: in the x-z plane, the distance from (4, 1) to the
  // line through (3, 0.5) along (0.5, 2.5) is |1 * 2.5 - 0.5 * 0.5| / sqrt(6.5); minus the radius.
  EXPECT_NEAR(rows[1]["clearance"].get<double>(), 2.25 / std::sqrt(6.5) - 0.3, 1e-9);
  EXPECT_EQ(rows[2]["collides"], true);
  EXPECT_EQ(rows[2]["obstacle"], 3);

  writeText(dir / "path.txt", "0 3 0.5\n3 3 0.5\n3 0.5 0.5\n4.5 0.5 0.5\n");
  auto path = test::runHullmap("check " + out + " --radius 0.3 --path " + (dir / "path.txt").string());
  EXPECT_EQ(path.status, 1) << path.err;
  EXPECT_EQ(test::lineCount(path.out), 4) << path.out;
  EXPECT_NE(path.out.find("segment 2: COLLIDES with obstacle 3"), std::string::npos) << path.out;
  EXPECT_NE(path.out.find("path: first collision in segment 2 at (3.7"), std::string::npos) << path.out;

  // Octree mode on the same voxels, from a map.bt in the directory.
  octomap::OcTree tree(0.1);
  for (const auto& c : voxels) tree.updateNode(octomap::point3d(float(c.x()), float(c.y()), float(c.z())), true);
  ASSERT_TRUE(tree.writeBinary((dir / "map.bt").string()));
  auto octree =
      test::runHullmap("check " + out + " --radius 0.3 --segment 0,0.5,0.5,6,0.5,0.5 --against octree --json");
  EXPECT_EQ(octree.status, 1) << octree.err;
  const auto o = nlohmann::json::parse(octree.out);
  EXPECT_EQ(o["collides"], true);
  EXPECT_NEAR(o["t"].get<double>(), 0.7 / 6.0, 2e-3);
}

TEST(CheckCommand, ErrorsExitTwoNamingTheFault) {
  const auto dir = test::freshDir("check_cli_errors");
  writeObstaclesJson((dir / "obstacles.json").string(), twoBoxes(), {});
  writeText(dir / "path.txt", "0 0 0\n1 2\n");
  auto bad = test::runHullmap("check " + dir.string() + " --radius 0.3 --path " + (dir / "path.txt").string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find((dir / "path.txt").string() + ":2: expected 3 numbers (x y z), got 2"), std::string::npos)
      << bad.err;
  writeText(dir / "path.txt", "0 0 0\n1 2 x3\n");
  bad = test::runHullmap("check " + dir.string() + " --radius 0.3 --path " + (dir / "path.txt").string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("path.txt:2: 'x3' is not a number"), std::string::npos) << bad.err;
  bad = test::runHullmap("check " + dir.string() + " --radius 0.3 --segment 1,2,3");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--segment: expected 6 comma-separated numbers, got 3"), std::string::npos) << bad.err;
  bad = test::runHullmap("check " + dir.string() + " --radius 0.3 --segment 0,0,0,1,1,1 --against octree");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("no map.bt"), std::string::npos) << bad.err;
  bad = test::runHullmap("check " + dir.string() + " --radius -1 --segment 0,0,0,1,1,1");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--radius"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace hullmap::pipeline
