// trajectory.txt: the keyframes a build directory holds (issue 28: the viewer and plot draw them).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/pipeline/trajectory_file.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
namespace pipeline = hullmap::pipeline;
namespace mapper = hullmap::mapper;
namespace io = hullmap::io;

fs::path scene(const std::string& name) {
  hullmap::sim::SceneParams params;
  params.points = 4000;
  params.obstacles = 4;
  const fs::path dir = hullmap::test::freshDir(name);
  hullmap::sim::writeScene(hullmap::sim::generateScene(params), params, dir.string());
  return dir;
}

std::vector<std::string> markerFiles(const fs::path& dir) {
  std::ifstream in(dir / ".hullmap-output");
  std::vector<std::string> files;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) files.push_back(line);
  return files;
}

bool lists(const std::vector<std::string>& files, const std::string& name) {
  return std::find(files.begin(), files.end(), name) != files.end();
}

}  // namespace

TEST(TrajectoryFile, ABuildWithKeyframesWritesThemInTheOutputFrame) {
  const fs::path dir = scene("with");
  pipeline::BuildParams params;
  params.inputs = {dir / "map_points.txt"};
  params.trajectory = dir / "KeyFrameTrajectory.txt";
  params.frame.up = mapper::UpAxis::kNegY;
  const pipeline::BuildResult result = pipeline::build(params);
  ASSERT_FALSE(result.keyframes.empty());
  ASSERT_TRUE(result.report.floor.levelled) << "the test wants keyframes moved by the levelling";
  pipeline::write(result, dir / "out");
  EXPECT_TRUE(lists(markerFiles(dir / "out"), "trajectory.txt"));
  const auto read = pipeline::readBuildTrajectory(dir / "out");
  ASSERT_TRUE(read.has_value());
  ASSERT_EQ(read->size(), result.keyframes.size());
  const auto input = io::readTumTrajectory((dir / "KeyFrameTrajectory.txt").string());
  for (std::size_t i = 0; i < read->size(); ++i) {
    const auto& a = (*read)[i];
    const auto& b = result.keyframes[i];
    EXPECT_EQ(a.stamp, input[i].stamp);
    EXPECT_EQ(a.stamp, b.stamp);
    EXPECT_EQ(a.position, b.position) << i;  // shortest round-trip text: the same doubles
    EXPECT_LT((a.orientation.coeffs() - b.orientation.coeffs()).norm(), 1e-15) << i;
    // The output frame, not the input's: z up and levelled (the camera loop of a generated scene is
    // at about 1.2 m above the floor).
    EXPECT_GT(a.position.z(), 0.8) << i;
    EXPECT_LT(a.position.z(), 1.6) << i;
  }
}

TEST(TrajectoryFile, ABuildWithoutKeyframesWritesNoneAndReplacesOneThatDid) {
  const fs::path dir = scene("without");
  pipeline::BuildParams params;
  params.inputs = {dir / "map_points.txt"};
  params.frame.up = mapper::UpAxis::kNegY;
  params.trajectory = dir / "KeyFrameTrajectory.txt";
  pipeline::write(pipeline::build(params), dir / "out");
  ASSERT_TRUE(fs::exists(dir / "out" / "trajectory.txt"));
  params.trajectory.reset();
  pipeline::write(pipeline::build(params), dir / "out");  // a previous output: replaced whole
  EXPECT_FALSE(fs::exists(dir / "out" / "trajectory.txt"));
  EXPECT_FALSE(lists(markerFiles(dir / "out"), "trajectory.txt"));
  EXPECT_FALSE(pipeline::readBuildTrajectory(dir / "out").has_value());
}

TEST(TrajectoryFile, AMalformedFileIsNamedWithItsLine) {
  const fs::path dir = hullmap::test::freshDir("bad");
  hullmap::test::writeText(dir / "trajectory.txt", "# t tx ty tz qx qy qz qw\n0 1 2 3 0 0 0 1\n1 2 3\n");
  try {
    pipeline::readBuildTrajectory(dir);
    FAIL() << "expected an error";
  } catch (const hullmap::Error& e) {
    EXPECT_NE(std::string(e.what()).find("trajectory.txt:3:"), std::string::npos) << e.what();
  }
}
