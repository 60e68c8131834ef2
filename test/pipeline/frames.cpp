// The user's frame: a metric z-up input keeps it (OctoMap's own tree for a real scan at the
// defaults), a camera's frame is levelled, report.input_to_output takes the input's coordinates to
// the outputs' (checked on the keyframes, which go through the same frame change as the points), GPS
// logs with lines without a fix align, and the floor's half-space holds every floor voxel.
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include "frames_fixtures.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/pipeline/map_obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/pipeline/report.hpp"
#include "octree_oracle.hpp"
#include "test_support.hpp"

namespace hullmap::pipeline {
namespace {

TEST(PipelineFrames, WhetherTheMapIsLevelled) {
  BuildParams params;
  const auto input = [](const std::string& path, const std::string& format) {
    io::InputStats stats;
    stats.path = path;
    stats.format = format;
    return std::vector<io::InputStats>{stats};
  };
  const auto xyz = input("scan.xyz", "text");
  EXPECT_FALSE(levelsMap(params, xyz));  // metric, z up
  EXPECT_FALSE(levelsMap(params, input("cloud.pcd", "pcd")));
  EXPECT_TRUE(levelsMap(params, input("dump.txt", "orbslam_echo")));  // ORB-SLAM's camera frame
  EXPECT_TRUE(levelsMap(params, input("MapPoints.txt", "text")));
  BuildParams up = params;
  up.frame.up = mapper::UpAxis::kNegY;
  EXPECT_TRUE(levelsMap(up, xyz));  // up other than z
  BuildParams keyframes = params;
  keyframes.trajectory = "KeyFrameTrajectory.txt";
  EXPECT_TRUE(levelsMap(keyframes, xyz));
  keyframes.trajectory = "poses.txt";
  EXPECT_FALSE(levelsMap(keyframes, xyz));
  BuildParams told = params;
  told.camera_frame = false;
  EXPECT_FALSE(levelsMap(told, input("dump.txt", "orbslam_echo")));
  told.camera_frame = true;
  EXPECT_TRUE(levelsMap(told, xyz));
  BuildParams on = params;
  on.level = Level::kOn;
  EXPECT_TRUE(levelsMap(on, xyz));
  BuildParams off = up;
  off.level = Level::kOff;
  EXPECT_FALSE(levelsMap(off, xyz));
  BuildParams none = up;
  none.floor.mode = mapper::PlaneSetting::Mode::kNone;
  EXPECT_FALSE(levelsMap(none, xyz));
  BuildParams aligned = up;
  aligned.align = AlignSettings{};
  EXPECT_FALSE(levelsMap(aligned, xyz));

  // on without a floor to level, or with align, is refused naming `level`.
  BuildParams no_floor = on;
  no_floor.floor.mode = mapper::PlaneSetting::Mode::kNone;
  BuildParams with_align = on;
  with_align.trajectory = sample("room/KeyFrameTrajectory.txt");
  with_align.align = alignTo(sample("room/reference_trajectory.txt"));
  for (BuildParams bad : {no_floor, with_align}) {
    bad.inputs = {sample("room/map_points.txt")};
    try {
      build(bad);
      ADD_FAILURE() << "level on accepted without a floor to level, or with align";
    } catch (const Error& e) {
      EXPECT_EQ(e.parameter(), "level") << e.what();
    }
  }
}

}  // namespace
}  // namespace hullmap::pipeline
