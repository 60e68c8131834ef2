// docs/GUIDE.md's "Your own ORB-SLAM map" runs as written: its command block (after the
// `<!-- five-steps` marker) is extracted and run on the real ORB-SLAM2 EuRoC V1_01 map, given the
// name the guide uses (MapPoints.txt, a symbolic link to shared/data/real). The numbers the guide
// quotes from that run are checked too.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_hullmap.hpp"

namespace fs = std::filesystem;

TEST(GuideFiveSteps, RunAsWrittenOnTheRealV1_01Map) {
  HULLMAP_REQUIRE_REAL_DATA(map, "orbslam2_euroc_V1_01_MapPoints.txt");
  const std::string guide = hullmap::test::slurp(fs::path(HULLMAP_SOURCE_DIR) / "docs" / "GUIDE.md");
  const auto commands = hullmap::test::fencedBlockAfter(guide, "<!-- five-steps");
  ASSERT_GE(commands.size(), 5u) << "no five-steps block in docs/GUIDE.md";
  const auto dir = hullmap::test::freshDir("five_steps");
  fs::create_symlink(map, dir / "MapPoints.txt");
  std::string cluster_out;
  std::string build_err;
  std::vector<std::string> checks;
  for (const auto& command : commands) {
    SCOPED_TRACE(command);
    ASSERT_EQ(command.rfind("hullmap ", 0), 0u) << "each line is one hullmap command";
    const auto r = hullmap::test::runHullmapIn(dir, command.substr(8));
    const bool is_check = command.rfind("hullmap check ", 0) == 0;
    if (is_check) {
      EXPECT_TRUE(r.status == 0 || r.status == 1) << r.status << ": " << r.err;
      checks.push_back(r.out);
    } else {
      EXPECT_EQ(r.status, 0) << r.err;
    }
    if (command.rfind("hullmap cluster ", 0) == 0) cluster_out = r.out;
    if (command.rfind("hullmap build ", 0) == 0) build_err = r.err;
  }
  // What the guide says of this run.
  EXPECT_NE(cluster_out.find("eps suggestion: 0.146"), std::string::npos) << cluster_out;
  const auto report = nlohmann::json::parse(hullmap::test::slurp(dir / "v101" / "report.json"));
  EXPECT_EQ(report["obstacles"], 81);
  EXPECT_EQ(report["parts"]["count"], 107);
  EXPECT_EQ(report["clusters"]["noise_voxels"], 511);
  EXPECT_EQ(report["octree"]["occupied_voxels"], 4150);
  EXPECT_EQ(report["floor"]["voxels"], 1170);
  EXPECT_TRUE(report["floor"]["levelled"].get<bool>());
  EXPECT_NEAR(report["floor"]["search"]["tilt_deg"].get<double>(), 20.7, 0.05);
  EXPECT_EQ(build_err.find("degrees from level"), std::string::npos) << "levelled, so not warned: " << build_err;
  EXPECT_TRUE(fs::exists(dir / "v101_side.svg"));
  EXPECT_TRUE(fs::exists(dir / "v101_top.svg"));
  ASSERT_EQ(checks.size(), 2u);
  // In hull mode the floor (its voxels reach z = 0.1) is nearer than any hull.
  EXPECT_NE(checks[0].find("clear, clearance 0.2\n"), std::string::npos) << checks[0];
  EXPECT_NE(checks[1].find("clear, clearance 0.16"), std::string::npos) << checks[1];
}
