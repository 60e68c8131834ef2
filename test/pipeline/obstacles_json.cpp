// obstacles.json /2: parts round-trip exactly, /1 files still read, errors name the JSON path;
// the OBJ has one object per part.
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "obstacles_json_fixtures.hpp"
#include "test_support.hpp"

namespace hullmap::pipeline {
namespace {

TEST(ObstaclesJson, V2RoundTripsPartsExactly) {
  auto obstacles = lAndBox();
  ASSERT_EQ(obstacles[0].parts.size(), 2u);
  ASSERT_EQ(obstacles[1].parts.size(), 1u);
  obstacles[0].parts[0].flat = true;
  obstacles[0].parts[1].faces = true;
  obstacles[1].parts[0].filled = true;
  ObstaclesMeta meta;
  meta.frame = "z-up map, test";
  meta.parameters = {{"concavity", 0.15}};
  // Through text, as a file would be.
  const nlohmann::json doc = nlohmann::json::parse(obstaclesToJson(obstacles, meta).dump(1));
  EXPECT_EQ(doc["format"], "hullmap-obstacles/2");
  ObstaclesMeta back_meta;
  const auto back = obstaclesFromJson(doc, "mem", &back_meta);
  EXPECT_EQ(back_meta.format, kObstaclesFormatV2);
  EXPECT_EQ(back_meta.frame, meta.frame);
  EXPECT_EQ(back_meta.parameters, meta.parameters);
  ASSERT_EQ(back.size(), obstacles.size());
  for (std::size_t o = 0; o < obstacles.size(); ++o) {
    EXPECT_EQ(back[o].id, obstacles[o].id);
    EXPECT_EQ(back[o].hull.vertices, obstacles[o].hull.vertices);
    ASSERT_EQ(back[o].parts.size(), obstacles[o].parts.size());
    for (std::size_t p = 0; p < obstacles[o].parts.size(); ++p) {
      const auto& a = obstacles[o].parts[p];
      const auto& b = back[o].parts[p];
      EXPECT_EQ(b.voxel_count, a.voxel_count);
      EXPECT_EQ(b.point_weight, a.point_weight);
      EXPECT_EQ(b.aabb_min, a.aabb_min);
      EXPECT_EQ(b.aabb_max, a.aabb_max);
      EXPECT_EQ(b.centroid, a.centroid);
      EXPECT_EQ(b.volume, a.volume);
      EXPECT_EQ(b.hull.vertices, a.hull.vertices);
      EXPECT_EQ(b.hull.triangles, a.hull.triangles);
      EXPECT_EQ(b.footprint.polygon, a.footprint.polygon);
      EXPECT_EQ(b.footprint.z_min, a.footprint.z_min);
      EXPECT_EQ(b.footprint.z_max, a.footprint.z_max);
      EXPECT_EQ(b.concavity_bound, a.concavity_bound);
      EXPECT_EQ(b.free_voxels_inside, a.free_voxels_inside);
      EXPECT_EQ(b.free_voxels_off_surface, a.free_voxels_off_surface);
      EXPECT_EQ(b.flat, a.flat);
      EXPECT_EQ(b.filled, a.filled);
      EXPECT_EQ(b.faces, a.faces);
    }
  }
}

TEST(ObstaclesJson, ReadsVersion1WithoutParts) {
  const auto obstacles = lAndBox();
  const auto dir = test::freshDir("v1");
  const std::string path = (dir / "obstacles.json").string();
  // A /1 document: /2's without the parts (what hullmap wrote before parts existed).
  nlohmann::json doc = obstaclesToJson(obstacles, {});
  doc["format"] = kObstaclesFormatV1;
  for (auto& o : doc["obstacles"]) o.erase("parts");
  std::ofstream(path) << doc.dump(1);
  ObstaclesMeta meta;
  const auto back = readObstaclesJson(path, &meta);
  EXPECT_EQ(meta.format, kObstaclesFormatV1);
  ASSERT_EQ(back.size(), obstacles.size());
  for (std::size_t o = 0; o < back.size(); ++o) {
    EXPECT_TRUE(back[o].parts.empty());
    EXPECT_EQ(back[o].hull.vertices, obstacles[o].hull.vertices);
  }
}

std::string errorOf(const nlohmann::json& doc) {
  try {
    obstaclesFromJson(doc, "f.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(ObstaclesJson, ErrorsNameTheJsonPath) {
  const nlohmann::json good = obstaclesToJson(lAndBox(), {});
  nlohmann::json bad = good;
  bad["format"] = "hullmap-obstacles/3";
  EXPECT_NE(errorOf(bad).find("f.json: format: expected \"hullmap-obstacles/2\" or \"hullmap-obstacles/1\""),
            std::string::npos)
      << errorOf(bad);
  bad = good;
  bad["obstacles"][0].erase("parts");
  EXPECT_EQ(errorOf(bad), "f.json: obstacles[0]: missing \"parts\"");
  bad = good;
  bad["obstacles"][0]["parts"][1]["hull"]["triangles"][2][1] = 999;
  EXPECT_NE(errorOf(bad).find("f.json: obstacles[0].parts[1].hull.triangles[2]: vertex index out of range"),
            std::string::npos)
      << errorOf(bad);
  bad = good;
  bad["obstacles"][1]["parts"][0]["concavity_bound"] = "x";
  EXPECT_EQ(errorOf(bad), "f.json: obstacles[1].parts[0].concavity_bound: expected a number");
  bad = good;
  bad["obstacles"][0]["parts"][0]["faces"] = 1;
  EXPECT_EQ(errorOf(bad), "f.json: obstacles[0].parts[0].faces: expected true or false");
  EXPECT_THROW(readObstaclesJson("/nonexistent/obstacles.json"), Error);
}

TEST(ObstaclesJson, FileIsTheDocumentsOneSpaceDump) {
  // writeObstaclesJson dumps the obstacles in parallel and stitches them into the head's list: its
  // bytes must be those of the whole document's dump(1), with and without obstacles, parts and the
  // frame change.
  auto obstacles = lAndBox();
  obstacles[0].parts[1].flat = true;
  obstacles[0].parts[0].faces = true;
  obstacles[0].parts[0].filled = true;
  obstacles[0].parts[0].free_voxels_off_surface = 12345678901ull;
  // Numbers of every form the writer spells: signs, zeros, exponents, integral floats, non-finite.
  obstacles[0].hull.vertices[0] = {-0.0, 1e-7, 1e21};
  obstacles[0].hull.vertices[1] = {123456789.123, -1e-5, 0.1 + 0.2};
  obstacles[0].centroid = {1e300, 5e-324, -2.0};
  obstacles[0].volume = std::numeric_limits<double>::quiet_NaN();
  obstacles[0].parts[1].concavity_bound = std::numeric_limits<double>::infinity();
  obstacles[0].id = -3;
  obstacles[1].footprint.polygon.clear();
  hulls::Obstacle no_parts = obstacles[1];
  no_parts.id = 7;
  no_parts.parts.clear();
  obstacles.push_back(no_parts);
  ObstaclesMeta meta;
  meta.frame = "z-up map, \"quoted\"\nand a line break";
  meta.parameters = {{"concavity", 0.15}, {"obstacles", nlohmann::json::array()}, {"nested", {{"a", {1, 2}}}}};
  meta.surfaces.push_back(collision::Surface::plane("floor", Eigen::Vector3d::UnitZ(), 0.25));
  mapper::Similarity s;
  s.scale = 2.5;
  s.translation = {1e-7, -3.0, 1e12};
  const auto dir = test::freshDir("obstacles_json_bytes");
  for (const bool with_frame_change : {false, true}) {
    meta.input_to_output = with_frame_change ? std::optional<mapper::Similarity>(s) : std::nullopt;
    for (const std::size_t count : {std::size_t(0), std::size_t(1), obstacles.size()}) {
      const std::vector<hulls::Obstacle> some(obstacles.begin(), obstacles.begin() + std::ptrdiff_t(count));
      const auto path = dir / "obstacles.json";
      writeObstaclesJson(path.string(), some, meta);
      EXPECT_EQ(test::slurp(path), obstaclesToJson(some, meta).dump(1) + "\n")
          << count << " obstacles, frame change " << with_frame_change;
    }
  }
}

TEST(ObstaclesJson, ObjNumbersAreTheStreamsSeventeenDigits) {
  // The OBJ writer formats numbers itself: each line must read as an ostream set to max_digits10
  // writes it, on values with and without exponents, signs, and integers.
  hulls::Obstacle o;
  o.id = 3;
  o.hull.vertices = {{0.1, -0.0, 1e-7}, {123456789.123, 1e21, -2.5}, {1.0 / 3.0, 1e-320, 1e300}, {0.0, 42.0, -1e-5}};
  o.hull.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  std::ostringstream out;
  writeObstaclesObj(out, {o, o});
  std::ostringstream expected;
  expected << "# hullmap obstacles: convex hulls (one object per convex part), z-up map frame\n";
  expected << std::setprecision(std::numeric_limits<double>::max_digits10);
  std::size_t base = 1;
  for (int copy = 0; copy < 2; ++copy) {
    expected << "o obstacle_3\n";
    for (const auto& v : o.hull.vertices) expected << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    for (const auto& t : o.hull.triangles)
      expected << "f " << base + t[0] << ' ' << base + t[1] << ' ' << base + t[2] << '\n';
    base += o.hull.vertices.size();
  }
  EXPECT_EQ(out.str(), expected.str());
}

TEST(ObstaclesJson, ObjHasOneObjectPerPart) {
  std::ostringstream out;
  writeObstaclesObj(out, lAndBox());
  std::istringstream in(out.str());
  std::vector<std::string> names;
  std::size_t faces = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("o ", 0) == 0) names.push_back(line.substr(2));
    if (line.rfind("f ", 0) == 0) ++faces;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"obstacle_0_part_0", "obstacle_0_part_1", "obstacle_1_part_0"}));
  EXPECT_EQ(faces, 3u * 12u);  // three boxes, two triangles a face
}

}  // namespace
}  // namespace hullmap::pipeline

namespace hullmap::pipeline {}  // namespace hullmap::pipeline
