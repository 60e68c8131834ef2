// hullmap generate --layout room: the files it writes, and its bad input (exit 2, one line).
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hullmap/mapper/align.hpp"
#include "hullmap/io/readers.hpp"
#include "run_hullmap.hpp"

namespace {

using hullmap::test::runHullmap;

TEST(GenerateCommand, RoomLayoutWritesPointsTrajectoriesAndTruth) {
  const auto dir = hullmap::test::freshDir("generate_room");
  const auto r = runHullmap("generate --layout room --density 20 --scale 2.5 --obstacles 4 -o '" + dir.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("9 objects (floor, 4 walls, 4 pieces of furniture)"), std::string::npos) << r.out;
  const auto kf = hullmap::io::readTumTrajectory((dir / "KeyFrameTrajectory.txt").string());
  const auto ref = hullmap::io::readReferenceTrajectory((dir / "reference_trajectory.txt").string(),
                                                        hullmap::io::ReferenceFormat::kTum);
  const auto a = hullmap::mapper::alignTrajectory(kf, ref);
  EXPECT_NEAR(a.transform.scale, 1.0 / 2.5, 1e-6);
  std::ifstream in(dir / "ground_truth.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("obstacles").size(), 9u);
  EXPECT_EQ(j.at("obstacles")[0].at("kind"), "floor");
  EXPECT_GT(hullmap::io::readPointFile((dir / "map_points.txt").string()).points.size(), 4000u);
}

TEST(GenerateCommand, BadRoomOptionsExitTwoWithOneLine) {
  const auto dir = hullmap::test::freshDir("generate_bad");
  const std::pair<const char*, const char*> cases[] = {{"--layout rooom", "--layout"},
                                                       {"--layout room --density 0", "--density"},
                                                       {"--layout room --scale -1", "--scale"},
                                                       {"--layout room --pitch 95", "--pitch"},
                                                       {"--layout room --edge-fraction 1.5", "--edge-fraction"},
                                                       {"--layout room --keyframes 2", "--keyframes"},
                                                       {"--layout room --obstacles 100", "obstacles"}};
  for (const auto& [args, name] : cases) {
    const auto r = runHullmap(std::string("generate ") + args + " -o '" + (dir / "x").string() + "'");
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_NE(r.err.find(name), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
  }
}

}  // namespace
