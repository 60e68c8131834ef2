// levelWarning (the floor of mapper::findBoundingPlane, tested in floor.cpp) and the ORB-SLAM hint.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "hullmap/core/constants.hpp"
#include "hullmap/mapper/level_check.hpp"

namespace {

using hullmap::kPi;

/// A 6 m x 6 m floor tilted `degrees` about the x axis (its normal (0, -sin, cos)), 0.05 m apart,
/// plus `clutter` uniform points in a 6 m cube.
std::vector<Eigen::Vector3d> floorScene(double degrees, int clutter) {
  std::vector<Eigen::Vector3d> points;
  const double a = degrees * kPi / 180.0;
  for (int i = 0; i < 120; ++i)
    for (int j = 0; j < 120; ++j) {
      const double x = 0.05 * i;
      const double y = 0.05 * j;
      points.emplace_back(x, y * std::cos(a), y * std::sin(a));
    }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 6.0);
  for (int k = 0; k < clutter; ++k) points.emplace_back(u(rng), u(rng), u(rng));
  return points;
}

}  // namespace

TEST(MapperLevelCheck, AVerticalWallAloneGivesNoWarning) {
  std::vector<Eigen::Vector3d> wall;
  for (int i = 0; i < 100; ++i)
    for (int k = 0; k < 50; ++k) wall.emplace_back(0.05 * i, 2.0, 0.05 * k);
  EXPECT_FALSE(hullmap::mapper::levelWarning(wall, 0.05, "z"));
  EXPECT_FALSE(hullmap::mapper::levelWarning({{0, 0, 0}, {1, 0, 0}}, 0.05, "z"));
}

TEST(MapperLevelCheck, LevelWarningSpeaksAboveTenDegrees) {
  EXPECT_FALSE(hullmap::mapper::levelWarning(floorScene(5.0, 500), 0.05, "z"));
  const auto warning = hullmap::mapper::levelWarning(floorScene(21.0, 500), 0.05, "-y");
  ASSERT_TRUE(warning);
  EXPECT_EQ(warning->code, hullmap::Warning::Code::kMapLooksTilted);
  EXPECT_EQ(warning->subject, "-y");
  EXPECT_NEAR(warning->number("tilt_deg"), 21.0, 0.05);
  const std::string text = hullmap::warningText(*warning);
  EXPECT_NE(text.find("is 21.0 degrees from level after up=-y"), std::string::npos) << text;
  // A plane of too few points is no floor.
  EXPECT_FALSE(hullmap::mapper::levelWarning(floorScene(21.0, 200000), 0.05, "z"));
}

TEST(MapperLevelCheck, OrbSlamInputsAreRecognised) {
  using hullmap::io::InputStats;
  InputStats echo;
  echo.path = "dump.txt";
  echo.format = "orbslam_echo";
  InputStats named;
  named.path = "/data/run1/MapPoints.txt";
  named.format = "text";
  InputStats plain;
  plain.path = "cloud.xyz";
  plain.format = "text";
  EXPECT_TRUE(hullmap::mapper::looksLikeOrbSlam(echo));
  EXPECT_TRUE(hullmap::mapper::looksLikeOrbSlam(named));
  EXPECT_FALSE(hullmap::mapper::looksLikeOrbSlam(plain));
  EXPECT_TRUE(hullmap::mapper::orbSlamUpHint({plain, named}, false));
  EXPECT_FALSE(hullmap::mapper::orbSlamUpHint({plain, named}, true));
  EXPECT_FALSE(hullmap::mapper::orbSlamUpHint({plain}, false));
}
