// End-to-end tests of `hullmap build` and `hullmap info`, and of every bad input in the brief's list:
// one line on stderr naming the file and line (or the option), exit status 2, no partial output.
#include <sys/stat.h>
#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "build_fixtures.hpp"
#include "hullmap/mapper/frame.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "run_hullmap.hpp"

// A run killed at any stage (SIGKILL: no handler runs) leaves OUT/ as the previous run left it, never
// half-written or missing; the next run sweeps away the staging directory the killed one left
// behind. The binary kills itself at the named stage (HULLMAP_TEST_KILL_AT, the pipeline's
// test-only stage hook): every stage is hit on every machine, however fast.
TEST(CliBuild, KilledRunsLeaveAWholeOutput) {
  const auto dir = freshDir("cli_killed");
  sampleScene(dir, 20000);
  writeText(dir / "small.txt", "0 0 0\n0.01 0 0\n");
  const auto out = dir / "out";
  const std::string big = "build " + (dir / "map_points.txt").string() + " --trajectory " +
                          (dir / "KeyFrameTrajectory.txt").string() + " --up -y -o " + out.string();
  ASSERT_EQ(runHullmap("build " + (dir / "small.txt").string() + " --min-pts 1 -o " + out.string()).status, 0);
  const std::string small_report = slurp(out / "report.json");
  for (const char* stage : {"read", "frame_and_filters", "octree", "dbscan", "obstacles", "write", "wrote_map",
                            "wrote_voxels", "wrote_obstacles", "move_into_place"}) {
    SCOPED_TRACE(std::string("killed at ") + stage);
    const std::string command =
        std::string("HULLMAP_TEST_KILL_AT=") + stage + " '" + HULLMAP_BINARY + "' " + big + " >/dev/null 2>&1";
    const int raw = std::system(command.c_str());
    const bool killed = (WIFSIGNALED(raw) && WTERMSIG(raw) == SIGKILL) ||
                        (WIFEXITED(raw) && WEXITSTATUS(raw) == 128 + SIGKILL);  // via the shell
    ASSERT_TRUE(killed) << "not killed: status " << raw;
    for (const char* name : {"map.bt", "voxels.csv", "obstacles.json", "obstacles.obj", "report.json"})
      ASSERT_TRUE(fs::exists(out / name)) << name;
    EXPECT_EQ(slurp(out / "report.json"), small_report);
    EXPECT_EQ(lineCount(slurp(out / "voxels.csv")) - 1,
              nlohmann::json::parse(small_report)["octree"]["occupied_voxels"].get<int>());
  }
  // Not killed: the big run's output replaces the small one whole.
  ASSERT_EQ(runHullmap(big).status, 0);
  EXPECT_EQ(nlohmann::json::parse(slurp(out / "report.json"))["points"]["read"].get<std::size_t>(), 20000u);
  ASSERT_EQ(runHullmap("build " + (dir / "small.txt").string() + " --min-pts 1 -o " + out.string()).status, 0);
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".out."), std::string::npos)
        << "left a temporary directory: " << entry.path();
}
