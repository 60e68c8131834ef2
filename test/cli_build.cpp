// End-to-end tests of `hullmap build` and `hullmap info`, and of every bad input in the brief's list:
// one line on stderr naming the file and line (or the option), exit status 2, no partial output.
#include <filesystem>
#include <fstream>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hullmap/mapper/sample_scene.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using hullmap::test::freshDir;
using hullmap::test::lineCount;
using hullmap::test::runHullmap;
using hullmap::test::slurp;

namespace {

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

/// A small generated scene (ORB-SLAM frame) written to `dir`.
fs::path sampleScene(const fs::path& dir, std::size_t points = 6000) {
  hullmap::mapper::SceneParams params;
  params.points = points;
  params.seed = 7;
  hullmap::mapper::writeScene(hullmap::mapper::generateScene(params), params, dir.string());
  return dir;
}

nlohmann::json readJson(const fs::path& path) { return nlohmann::json::parse(slurp(path)); }

void expectOneLineError(const hullmap::test::CommandResult& r, const std::string& needle) {
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("hullmap: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << "expected '" << needle << "' in: " << r.err;
}

}  // namespace

TEST(CliBuild, SampleSceneEndToEndAccountsForEveryPoint) {
  const auto dir = freshDir("cli_build_sample");
  sampleScene(dir);
  const auto out = dir / "out";
  const auto r = runHullmap("build " + (dir / "map_points.txt").string() + " --trajectory " +
                            (dir / "KeyFrameTrajectory.txt").string() + " --up -y -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err, "") << "stderr is for errors (octomap's own progress lines are muted)";
  for (const char* name : {"map.bt", "voxels.csv", "obstacles.json", "obstacles.obj", "report.json"})
    EXPECT_TRUE(fs::exists(out / name)) << name;
  const auto report = readJson(out / "report.json");
  const std::size_t read = report["points"]["read"];
  std::size_t dropped = 0;
  for (const auto& [reason, count] : report["points"]["dropped"].items()) dropped += count.get<std::size_t>();
  EXPECT_EQ(read, 6000u);
  EXPECT_EQ(read, dropped + report["points"]["used"].get<std::size_t>());
  EXPECT_GT(report["points"]["dropped"].value("out_of_octree", 0), 0) << "gross outliers are dropped";
  EXPECT_GT(report["clusters"]["count"].get<int>(), 0);
  EXPECT_EQ(report["parameters"]["eps"].get<double>(), 0.1);
  EXPECT_EQ(report["parameters"]["min_pts"].get<int>(), 10);
  EXPECT_NE(report["frame"].get<std::string>().find("-y"), std::string::npos);
  for (const char* stage : {"read", "frame_and_filters", "octree", "dbscan", "obstacles"})
  {
    EXPECT_TRUE(report["timings_ms"].contains(stage)) << stage;
    EXPECT_GT(report["peak_rss_mb"].value(stage, 0.0), 1.0) << stage;
  }

  // voxels.csv: one row per occupied voxel, labels consistent with the report.
  std::ifstream csv(out / "voxels.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "x,y,z,weight,label,core");
  std::size_t rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, report["octree"]["occupied_voxels"].get<std::size_t>());

  // The map reads back with `info`, and `build` accepts it as input.
  const auto info = runHullmap("info --json " + (out / "map.bt").string());
  ASSERT_EQ(info.status, 0) << info.err;
  EXPECT_EQ(info.err, "");
  const auto j = nlohmann::json::parse(info.out);
  EXPECT_DOUBLE_EQ(j["resolution"].get<double>(), 0.05);
  EXPECT_GT(j["occupied_leaves"].get<std::size_t>(), 0u);
  EXPECT_GT(j["free_leaves"].get<std::size_t>(), 0u) << "the trajectory carves free space";
  const auto again = runHullmap("build " + (out / "map.bt").string() + " -o " + (dir / "again").string());
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(readJson(dir / "again" / "report.json")["octree"]["occupied_voxels"],
            report["octree"]["occupied_voxels"]);
}

TEST(CliBuild, RealOctomapGeb079ReadsBack) {
  HULLMAP_REQUIRE_REAL_DATA(bt, "octomap_geb079.bt");
  const auto r = runHullmap("info --json " + bt);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_DOUBLE_EQ(j["resolution"].get<double>(), 0.08);
}

TEST(CliBadInput, MalformedLineNamesFileAndLine) {
  const auto dir = freshDir("cli_bad_malformed");
  writeText(dir / "bad.txt", "0 0 0\n1 1 1\n2 2\n");
  expectOneLineError(runHullmap("build " + (dir / "bad.txt").string() + " -o " + (dir / "out").string()),
                     "bad.txt:3");
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(CliBadInput, NonFinitePointsAreDroppedAndCounted) {
  const auto dir = freshDir("cli_bad_nan");
  std::string text;
  for (int i = 0; i < 30; ++i) text += "0." + std::to_string(10 + i) + " 0 1\n";
  text += "nan 0 1\ninf 1 1\n0 -inf 1\n";
  writeText(dir / "nan.txt", text);
  const auto r = runHullmap("build " + (dir / "nan.txt").string() + " --min-pts 3 -o " + (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto report = readJson(dir / "out" / "report.json");
  EXPECT_EQ(report["points"]["read"].get<int>(), 33);
  EXPECT_EQ(report["points"]["dropped"]["non_finite"].get<int>(), 3);
  EXPECT_EQ(report["points"]["used"].get<int>(), 30);
}

TEST(CliBadInput, EmptyCloud) {
  const auto dir = freshDir("cli_bad_empty");
  writeText(dir / "empty.txt", "# nothing here\n");
  expectOneLineError(runHullmap("build " + (dir / "empty.txt").string() + " -o " + (dir / "out").string()),
                     "empty.txt: no points");
  writeText(dir / "allnan.txt", "nan nan nan\n");
  expectOneLineError(runHullmap("build " + (dir / "allnan.txt").string() + " -o " + (dir / "out").string()),
                     "no points");
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(CliBadInput, UnknownOptionAndBadValues) {
  const auto dir = freshDir("cli_bad_options");
  writeText(dir / "p.txt", "0 0 0\n");
  const std::string in = (dir / "p.txt").string();
  expectOneLineError(runHullmap("build " + in + " --bogus"), "--bogus");
  expectOneLineError(runHullmap("build " + in + " --resolution -1"), "--resolution");
  expectOneLineError(runHullmap("build " + in + " --eps 0"), "--eps");
  expectOneLineError(runHullmap("build " + in + " --up w"), "--up");
  expectOneLineError(runHullmap("build " + in + " --crop 1,2,3"), "--crop");
  expectOneLineError(runHullmap("build " + in + " --metric manhattan"), "--metric");
  expectOneLineError(runHullmap("frobnicate"), "frobnicate");
  expectOneLineError(runHullmap("build " + (dir / "missing.txt").string()), "missing.txt");
}

TEST(CliBadInput, CorruptOctomapFile) {
  const auto dir = freshDir("cli_bad_bt");
  writeText(dir / "bad.bt", "# Octomap OcTree binary file\nid OcTree\nsize 12\nres 0.1\ndata\nxx");
  expectOneLineError(runHullmap("info " + (dir / "bad.bt").string()), "bad.bt");
  expectOneLineError(runHullmap("build " + (dir / "bad.bt").string() + " -o " + (dir / "out").string()),
                     "bad.bt");
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(CliBadInput, DegenerateClustersStillMakeSolidObstacles) {
  // A single voxel, a single row of voxels and a flat wall: hulls of the voxels' corners are solids.
  const auto dir = freshDir("cli_degenerate");
  std::string text;
  for (int i = 0; i < 3; ++i) text += "5.02 5.02 1.02\n";                       // one voxel
  for (int i = 0; i < 20; ++i) text += std::to_string(0.025 + 0.05 * i) + " 0.025 1.025\n";  // a row
  for (int i = 0; i < 10; ++i)
    for (int k = 0; k < 10; ++k)
      text += "-3.025 " + std::to_string(0.025 + 0.05 * i) + " " + std::to_string(0.025 + 0.05 * k) + "\n";
  writeText(dir / "degenerate.txt", text);
  const auto r = runHullmap("build " + (dir / "degenerate.txt").string() + " --min-pts 2 -o " +
                            (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto obstacles = readJson(dir / "out" / "obstacles.json");
  ASSERT_EQ(obstacles["obstacles"].size(), 3u);
  for (const auto& o : obstacles["obstacles"]) EXPECT_GT(o["volume"].get<double>(), 0.0);
}

TEST(CliBuild, FailedRunLeavesPreviousOutputIntact) {
  const auto dir = freshDir("cli_atomic");
  writeText(dir / "good.txt", "0 0 0\n0.01 0 0\n");
  const auto out = dir / "out";
  ASSERT_EQ(runHullmap("build " + (dir / "good.txt").string() + " --min-pts 1 -o " + out.string()).status, 0);
  const std::string before = slurp(out / "report.json");
  writeText(dir / "bad.txt", "0 0 0\nx y z w\n");
  expectOneLineError(runHullmap("build " + (dir / "bad.txt").string() + " -o " + out.string()), "bad.txt:2");
  EXPECT_EQ(slurp(out / "report.json"), before);
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".out."), std::string::npos)
        << "left a temporary directory: " << entry.path();
}

// A run killed at any moment (SIGKILL: no handler runs) leaves OUT/ either as the previous run left
// it or as the new run's complete output, never half-written or missing; the next run sweeps away
// the staging directory the killed one left behind.
TEST(CliBuild, KilledRunsLeaveAWholeOutput) {
  const auto dir = freshDir("cli_killed");
  sampleScene(dir, 200000);
  writeText(dir / "small.txt", "0 0 0\n0.01 0 0\n");
  const auto out = dir / "out";
  const std::string big = "build " + (dir / "map_points.txt").string() + " --trajectory " +
                          (dir / "KeyFrameTrajectory.txt").string() + " --up -y -o " + out.string();
  int killed = 0;
  for (double after : {0.02, 0.1, 0.2, 0.3, 0.4, 0.6, 0.8, 1.2}) {
    SCOPED_TRACE("killed after " + std::to_string(after) + " s");
    // Back to the small output, then the big run, killed part way.
    ASSERT_EQ(runHullmap("build " + (dir / "small.txt").string() + " --min-pts 1 -o " + out.string()).status, 0);
    const std::string command = "timeout -s KILL " + std::to_string(after) + " '" + HULLMAP_BINARY + "' " + big +
                                " >/dev/null 2>&1";
    const int raw = std::system(command.c_str());
    killed += WIFEXITED(raw) && WEXITSTATUS(raw) == 137;
    for (const char* name : {"map.bt", "voxels.csv", "obstacles.json", "obstacles.obj", "report.json"})
      ASSERT_TRUE(fs::exists(out / name)) << name;
    // The small run's report or the big run's, whole.
    const std::size_t read = nlohmann::json::parse(slurp(out / "report.json"))["points"]["read"];
    EXPECT_TRUE(read == 2 || read == 200000) << read;
    EXPECT_EQ(lineCount(slurp(out / "voxels.csv")) - 1,
              nlohmann::json::parse(slurp(out / "report.json"))["octree"]["occupied_voxels"].get<int>());
  }
  EXPECT_GT(killed, 0) << "no run was killed part way; the test proved nothing";
  ASSERT_EQ(runHullmap("build " + (dir / "small.txt").string() + " --min-pts 1 -o " + out.string()).status, 0);
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".out."), std::string::npos)
        << "left a temporary directory: " << entry.path();
}

// A staging directory nobody holds a lock on is a killed run's leftover, even when the pid in its name
// belongs to a live process (pids are reused; here: this test's own pid). One a live run holds a lock on
// (here: this test, through flock) is another hullmap writing the same output, and is left alone.
TEST(CliBuild, StaleStagingIsToldByItsLockNotByItsPid) {
  const auto dir = freshDir("cli_stale_staging");
  writeText(dir / "small.txt", "0 0 0\n0.01 0 0\n");
  const auto out = dir / "out";
  const fs::path stale = dir / (".out.new" + std::to_string(::getpid()));
  const fs::path live = dir / ".out.new1";
  for (const auto& d : {stale, live}) {
    fs::create_directories(d);
    writeText(d / "report.json", "half-written");
  }
  const int fd = ::open(live.c_str(), O_RDONLY | O_DIRECTORY);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);
  ASSERT_EQ(runHullmap("build " + (dir / "small.txt").string() + " --min-pts 1 -o " + out.string()).status, 0);
  EXPECT_FALSE(fs::exists(stale)) << "an unlocked staging directory was kept because its pid is alive";
  EXPECT_TRUE(fs::exists(live / "report.json")) << "a locked staging directory was removed";
  ::close(fd);
  ASSERT_EQ(runHullmap("build " + (dir / "small.txt").string() + " --min-pts 1 -o " + out.string()).status, 0);
  EXPECT_FALSE(fs::exists(live)) << "the lock is gone, the directory is stale";
}
