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
#include "test_support.hpp"

namespace hullmap::pipeline {

namespace {

TEST(ObstacleIo, JsonRoundTripAndObj) {
  const auto dir = test::freshDir("obstacle_io");
  const auto obstacles = twoBoxes();
  ObstaclesMeta meta;
  meta.frame = "z-up map, up=-y of input";
  meta.parameters = {{"eps", 0.15}, {"min_pts", 10}};
  writeObstaclesJson((dir / "obstacles.json").string(), obstacles, meta);
  ObstaclesMeta back_meta;
  const auto back = readObstaclesJson((dir / "obstacles.json").string(), &back_meta);
  EXPECT_EQ(back_meta.frame, meta.frame);
  EXPECT_EQ(back_meta.parameters, meta.parameters);
  ASSERT_EQ(back.size(), obstacles.size());
  for (std::size_t k = 0; k < back.size(); ++k) {
    EXPECT_EQ(back[k].id, obstacles[k].id);
    EXPECT_EQ(back[k].voxel_count, obstacles[k].voxel_count);
    EXPECT_EQ(back[k].point_weight, obstacles[k].point_weight);
    EXPECT_EQ(back[k].volume, obstacles[k].volume);  // exact: shortest round-trip numbers
    EXPECT_EQ(back[k].hull.vertices, obstacles[k].hull.vertices);
    EXPECT_EQ(back[k].hull.triangles, obstacles[k].hull.triangles);
    EXPECT_EQ(back[k].footprint.polygon, obstacles[k].footprint.polygon);
    EXPECT_EQ(back[k].aabb_min, obstacles[k].aabb_min);
    EXPECT_EQ(back[k].centroid, obstacles[k].centroid);
  }
  writeObstaclesObj((dir / "obstacles.obj").string(), obstacles);
  std::ifstream obj(dir / "obstacles.obj");
  std::string line;
  int objects = 0, vertices = 0, faces = 0;
  std::size_t max_index = 0;
  while (std::getline(obj, line)) {
    if (line.rfind("o obstacle_", 0) == 0) ++objects;
    if (line.rfind("v ", 0) == 0) ++vertices;
    if (line.rfind("f ", 0) == 0) {
      ++faces;
      std::istringstream in(line.substr(2));
      std::size_t i;
      while (in >> i) {
        EXPECT_GE(i, 1u);
        max_index = std::max(max_index, i);
      }
    }
  }
  EXPECT_EQ(objects, 2);
  EXPECT_EQ(vertices, 16);
  EXPECT_EQ(faces, 24);
  EXPECT_EQ(max_index, 16u);  // 1-based global indices
}

TEST(ObstacleIo, ReaderNamesFileAndFault) {
  const auto dir = test::freshDir("obstacle_io_bad");
  const auto path = (dir / "obstacles.json").string();
  auto expectError = [&](const std::string& text, const std::string& part) {
    writeText(path, text);
    try {
      readObstaclesJson(path);
      ADD_FAILURE() << "no error for " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expectError("{", "not valid JSON");
  expectError(R"({"format": "other/2", "obstacles": []})", "format");
  expectError(R"({"format": "hullmap-obstacles/1"})", "obstacles");
  expectError(R"({"format": "hullmap-obstacles/1", "frame": "", "parameters": {}, "obstacles": [{"id": 1}]})",
              "obstacles[0]");
  writeObstaclesJson(path, twoBoxes(), {});
  auto doc = nlohmann::json::parse(std::ifstream(path));
  doc["obstacles"][1]["hull"]["triangles"][2][1] = 99;
  expectError(doc.dump(), "obstacles[1].hull.triangles[2]");
}

}  // namespace
}  // namespace hullmap::pipeline
