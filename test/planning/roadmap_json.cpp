// readRoadmapJson: what writeRoadmapJson wrote comes back the same; broken files are named.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/planning/roadmap_json.hpp"
#include "planning_support.hpp"
#include "test_support.hpp"

namespace hp = hullmap::planning;

TEST(PlanningRoadmapJson, ReadsBackWhatWasWritten) {
  using hullmap::test::prism;
  const std::vector<hullmap::hulls::Obstacle> obstacles{prism(0, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 0, 2),
                                                        prism(1, {{2, 0.5}, {3, 0}, {3, 2}}, 0, 2),
                                                        prism(2, {{0, 3}, {1, 3}, {0.5, 4}}, 0, 2)};
  hp::RoadmapParams params;
  params.z0 = 0.5;
  params.z1 = 1.5;
  const hp::Roadmap map = hp::buildRoadmap(obstacles, params);
  ASSERT_FALSE(map.edges.empty());
  const auto dir = hullmap::test::freshDir("planning_roadmap_json");
  const std::string file = (dir / "roadmap.json").string();
  hp::writeRoadmapJson(file, map);
  const hp::Roadmap back = hp::readRoadmapJson(file);
  EXPECT_EQ(hp::roadmapJson(back), hp::roadmapJson(map));
  ASSERT_EQ(back.edges.size(), map.edges.size());
  EXPECT_EQ(back.edges.front().polyline, map.edges.front().polyline);
  EXPECT_EQ(back.edges.front().site_a.obstacle, map.edges.front().site_a.obstacle);

  std::ofstream(dir / "other.json") << "{\"format\": \"hullmap-obstacles/2\"}";
  std::ofstream(dir / "broken.json") << "{\"format\": \"hullmap-roadmap/1\", \"bounds\": [0, 0, 1, 1], \"band\": [0]}";
  std::ofstream(dir / "text.json") << "nodes: 3";
  for (const char* name : {"other.json", "broken.json", "text.json", "missing.json"}) {
    const std::string path = (dir / name).string();
    try {
      hp::readRoadmapJson(path);
      ADD_FAILURE() << name << " was read";
    } catch (const hullmap::Error& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}
