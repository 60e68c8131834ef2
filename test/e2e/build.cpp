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

using hullmap::test::expectOneLineError;

TEST(CliBuild, SampleSceneEndToEndAccountsForEveryPoint) {
  const auto dir = freshDir("cli_build_sample");
  sampleScene(dir);
  const auto out = dir / "out";
  const auto r = runHullmap("build " + (dir / "map_points.txt").string() + " --trajectory " +
                            (dir / "KeyFrameTrajectory.txt").string() +
                            " --up -y --eps 0.1 --min-pts 10 --floor none --concavity none -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  // stderr is for errors and warnings (octomap's own progress lines are muted); the default eps and
  // min-pts leave most voxels of this scene as noise, which build says.
  std::istringstream err_lines(r.err);
  for (std::string line; std::getline(err_lines, line);) EXPECT_EQ(line.rfind("hullmap: warning: ", 0), 0u) << line;
  EXPECT_NE(r.err.find("are noise and in no obstacle"), std::string::npos) << r.err;
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
  for (const char* stage : {"read", "frame_and_filters", "octree", "dbscan", "obstacles"}) {
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
  // The text form says the same, one "key: value" a line, bounds as "x y z".
  const auto text = runHullmap("info " + (out / "map.bt").string());
  ASSERT_EQ(text.status, 0) << text.err;
  std::istringstream lines(text.out);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, (out / "map.bt").string());
  std::map<std::string, std::string> fields;
  while (std::getline(lines, line)) {
    const auto colon = line.find(':');
    ASSERT_NE(colon, std::string::npos) << line;
    const auto value = line.find_first_not_of(' ', colon + 1);
    fields[line.substr(line.find_first_not_of(' '), colon - line.find_first_not_of(' '))] = line.substr(value);
  }
  EXPECT_EQ(fields["occupied leaves"], std::to_string(j["occupied_leaves"].get<std::size_t>()));
  EXPECT_EQ(fields["free leaves"], std::to_string(j["free_leaves"].get<std::size_t>()));
  for (const char* key : {"bounds min", "bounds max"}) {
    std::istringstream xyz(fields[key]);
    const auto& expected = j[std::string(key) == "bounds min" ? "min" : "max"];
    double v = 0;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      ASSERT_TRUE(xyz >> v) << key << ": " << fields[key];
      EXPECT_NEAR(v, expected[axis].get<double>(), 1e-5) << key;
    }
    EXPECT_EQ(fields[key].find("  "), std::string::npos) << key << " is padded: " << fields[key];
  }
  const auto again = runHullmap("build " + (out / "map.bt").string() + " -o " + (dir / "again").string());
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(readJson(dir / "again" / "report.json")["octree"]["occupied_voxels"], report["octree"]["occupied_voxels"]);
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
  expectOneLineError(runHullmap("build " + (dir / "bad.txt").string() + " -o " + (dir / "out").string()), "bad.txt:3");
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

TEST(CliBadInput, NoPointWithinTheOctreesReachIsAnEmptyCloud) {
  // 16-bit keys reach +-1638.4 m at 0.05 m: a map of gross outliers alone has nothing to build.
  const auto dir = freshDir("cli_bad_unreachable");
  writeText(dir / "far.txt", "5000 0 1\n0 -9000 1\nnan 0 0\n");
  const std::string cmd = "build " + (dir / "far.txt").string() + " -o " + (dir / "out").string();
  expectOneLineError(runHullmap(cmd),
                     "no point the octree can address: 3 read, 2 out of its reach at resolution 0.05 (about "
                     "+-1638.4 map units around the origin");
  EXPECT_FALSE(fs::exists(dir / "out"));
  // With --origin (a scan) the same.
  expectOneLineError(runHullmap(cmd + " --origin 0,0,0"), "2 out of its reach");
  // One reachable point is a map.
  writeText(dir / "far.txt", "5000 0 1\n1 1 1\n");
  const auto one = runHullmap(cmd);
  EXPECT_EQ(one.status, 0) << one.err;
}

TEST(CliBadInput, OutputThatCannotBeMadeIsNamedBeforeTheWork) {
  // The error names the -o the user gave, and comes before the input is read: the input here is
  // malformed too, and the -o is what the error names.
  const auto dir = freshDir("cli_bad_output");
  writeText(dir / "good.txt", "1 1 1\n");
  writeText(dir / "bad.txt", "1 2 3\n4 five 6\n");
  const std::string file = (dir / "good.txt").string();
  expectOneLineError(runHullmap("build " + (dir / "bad.txt").string() + " -o " + file),
                     "-o " + file + ": exists and is not a directory");
  expectOneLineError(runHullmap("build " + (dir / "bad.txt").string() + " -o " + file + "/a/out"),
                     "-o " + file + "/a/out: cannot create it: " + file + " is not a directory");
  EXPECT_EQ(hullmap::test::slurp(dir / "good.txt"), "1 1 1\n");
  const auto ok = runHullmap("build " + file + " -p -o " + (dir / "new" / "a" / "out").string());
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_TRUE(fs::exists(dir / "new" / "a" / "out" / "map.bt"));
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
  // A misspelt option is what the error names, not the required option or the file it left out.
  expectOneLineError(runHullmap("build --resolutoin 0.1 " + in), "unknown option --resolutoin");
  expectOneLineError(runHullmap("check " + dir.string() + " --radus 0.3"), "unknown option --radus");
  expectOneLineError(runHullmap("build " + in + " --up -y --crop -1,-1,-1,1,1,1 -q"), "unknown option -q");
  expectOneLineError(runHullmap("--frobnicate"), "unknown option --frobnicate");
  expectOneLineError(runHullmap("build " + (dir / "missing.txt").string()), "missing.txt");
}

TEST(CliBadInput, CorruptOctomapFile) {
  const auto dir = freshDir("cli_bad_bt");
  writeText(dir / "bad.bt", "# Octomap OcTree binary file\nid OcTree\nsize 12\nres 0.1\ndata\nxx");
  expectOneLineError(runHullmap("info " + (dir / "bad.bt").string()), "bad.bt");
  expectOneLineError(runHullmap("build " + (dir / "bad.bt").string() + " -o " + (dir / "out").string()), "bad.bt");
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(CliBadInput, DegenerateClustersStillMakeSolidObstacles) {
  // A single voxel, a single row of voxels and a flat wall: hulls of the voxels' corners are solids.
  const auto dir = freshDir("cli_degenerate");
  std::string text;
  for (int i = 0; i < 3; ++i) text += "5.02 5.02 1.02\n";                                    // one voxel
  for (int i = 0; i < 20; ++i) text += std::to_string(0.025 + 0.05 * i) + " 0.025 1.025\n";  // a row
  for (int i = 0; i < 10; ++i)
    for (int k = 0; k < 10; ++k)
      text += "-3.025 " + std::to_string(0.025 + 0.05 * i) + " " + std::to_string(0.025 + 0.05 * k) + "\n";
  writeText(dir / "degenerate.txt", text);
  const auto r = runHullmap("build " + (dir / "degenerate.txt").string() +
                            " --min-pts 2 --eps 0.1 --floor none --concavity none -o " + (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto obstacles = readJson(dir / "out" / "obstacles.json");
  ASSERT_EQ(obstacles["obstacles"].size(), 3u);
  for (const auto& o : obstacles["obstacles"]) EXPECT_GT(o["volume"].get<double>(), 0.0);
}

TEST(CliBuild, FailedRunLeavesPreviousOutputIntact) {
  const auto dir = freshDir("cli_atomic");
  writeText(dir / "good.txt", "0 0 0\n0.01 0 0\n");
  const auto out = dir / "out";
  ASSERT_EQ(runHullmap("build " + (dir / "good.txt").string() +
                       " --min-pts 1 --eps 0.1 --floor none --concavity none -o " + out.string())
                .status,
            0);
  const std::string before = slurp(out / "report.json");
  writeText(dir / "bad.txt", "0 0 0\nx y z w\n");
  expectOneLineError(runHullmap("build " + (dir / "bad.txt").string() +
                                " --eps 0.1 --min-pts 10 --floor none --concavity none -o " + out.string()),
                     "bad.txt:2");
  EXPECT_EQ(slurp(out / "report.json"), before);
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

namespace {

/// `build` of points alone the way it was done before it streamed: every input read whole
/// (readPointFiles), then the frame change, the filters and buildFromPoints on all points, then
/// DBSCAN and the obstacles, written by writeBuild. `params` gives eps and minPts, no floor and no
/// convex parts.
void buildWholeFile(const hullmap::pipeline::BuildParams& params, const fs::path& output_dir) {
  using namespace hullmap;
  pipeline::BuildResult result;
  result.params = params;
  std::vector<std::string> inputs;
  for (const auto& p : params.inputs) inputs.push_back(p.string());
  io::PointSet set = pipeline::readInputPoints(inputs);
  result.report.inputs = set.inputs;
  auto& account = result.report.points;
  for (const auto& in : set.inputs) {
    account.read += in.read;
    for (const auto& [reason, n] : in.dropped) account.dropped[reason] += n;
  }
  mapper::toMapFrame(params.frame, set.points);
  result.report.input_to_output.scale = params.frame.scale;
  result.report.input_to_output.rotation = mapper::upRotation(params.frame.up);
  io::InputStats dropped;
  mapper::applyFilters(params.filters, set.points, dropped);
  result.map = mapper::buildFromPoints(set.points, params.octree, dropped);
  for (const auto& [reason, n] : dropped.dropped) account.dropped[reason] += n;
  account.used = account.read;
  for (const auto& [reason, n] : account.dropped) account.used -= n;
  result.voxels = result.map.occupiedVoxels();
  std::vector<Eigen::Vector3d> centers;
  std::vector<std::uint32_t> weights;
  for (const auto& v : result.voxels) {
    centers.push_back(v.center);
    weights.push_back(v.weight);
  }
  clustering::DbscanParams dbscan;
  dbscan.eps = *params.eps;
  dbscan.min_pts = *params.min_pts;
  dbscan.metric = params.metric;
  result.report.cluster_params.used = dbscan;
  result.clusters = clustering::dbscan(centers, weights, dbscan);
  result.obstacles = hulls::buildObstacles(centers, weights, result.clusters.labels, result.map.resolution());
  for (const char* stage : {"read", "frame_and_filters", "octree", "dbscan", "obstacles"}) {
    result.report.timings_ms.emplace_back(stage, 0.0);
    result.report.peak_rss_mb.emplace_back(stage, 0.0);
  }
  pipeline::write(result, output_dir);
}

}  // namespace

// Points only, `build` streams its inputs; the outputs are those of reading them whole: map.bt,
// voxels.csv, obstacles.json and obstacles.obj byte for byte, the same account of every point. Two inputs (the
// second with NaNs), a crop and a z bound that drop points, several batches of 65536 points.
TEST(CliBuild, PointsOnlyStreamsTheOutputsOfReadingWhole) {
  const auto dir = freshDir("cli_streamed");
  sampleScene(dir, 200000);
  std::ifstream scene(dir / "map_points.txt");
  std::ofstream a(dir / "a.txt");
  std::ofstream b(dir / "b.txt");
  std::size_t line_no = 0;
  for (std::string line; std::getline(scene, line); ++line_no) {
    (line_no < 150000 ? a : b) << line << '\n';
    if (line_no % 5000 == 0) b << "nan 1 2\n";
  }
  a.close();
  b.close();
  hullmap::pipeline::BuildParams options;
  options.inputs = {dir / "a.txt", dir / "b.txt"};
  options.frame.up = hullmap::mapper::UpAxis::kNegY;
  options.filters.crop = hullmap::mapper::Box{{-4, -4, -1}, {4, 4, 2.5}};
  options.filters.z_min = 0.02;
  options.eps = 0.1;
  options.min_pts = 5;
  options.floor.mode = hullmap::mapper::PlaneSetting::Mode::kNone;
  options.convex_parts.reset();
  buildWholeFile(options, dir / "whole");

  const auto out = dir / "out";
  const auto r = runHullmap("build " + options.inputs[0].string() + " " + options.inputs[1].string() +
                            " --up -y --crop -4,-4,-1,4,4,2.5 --z-min 0.02 --eps 0.1 --min-pts 5 --floor none "
                            "--concavity none -o " +
                            out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(slurp(out / "map.bt"), slurp(dir / "whole" / "map.bt"));
  EXPECT_EQ(slurp(out / "voxels.csv"), slurp(dir / "whole" / "voxels.csv"));
  EXPECT_EQ(slurp(out / "obstacles.json"), slurp(dir / "whole" / "obstacles.json"));
  EXPECT_EQ(slurp(out / "obstacles.obj"), slurp(dir / "whole" / "obstacles.obj"));

  const auto report = readJson(out / "report.json");
  const auto whole = readJson(dir / "whole" / "report.json");
  for (const char* key : {"inputs", "points", "octree", "clusters", "obstacles", "parameters", "frame", "keyframes"})
    EXPECT_EQ(report[key], whole[key]) << key;
  for (const char* reason : {"non_finite", "outside_crop", "below_z_min"})
    EXPECT_GT(report["points"]["dropped"].value(reason, 0), 0) << reason;
  EXPECT_EQ(report["points"]["read"].get<std::size_t>(), 200000u + 40u);
  for (const char* stage : {"read", "frame_and_filters", "octree", "dbscan", "obstacles"})
    EXPECT_GT(report["peak_rss_mb"].value(stage, 0.0), 1.0) << stage;
  double sum = 0;
  for (const auto& [stage, ms] : report["timings_ms"].items()) {
    if (stage != "total") sum += ms.get<double>();
  }
  EXPECT_NEAR(report["timings_ms"]["total"].get<double>(), sum, 1e-6);
}

// A FIFO (not a regular file: read in chunks, never mapped) streams to the same map.
TEST(CliBuild, FifoInputStreamsToTheSameMap) {
  const auto dir = freshDir("cli_fifo");
  sampleScene(dir, 100000);
  const auto fifo = dir / "points.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string file = (dir / "map_points.txt").string();
  ASSERT_EQ(runHullmap("build " + file + " --up -y -o " + (dir / "file").string()).status, 0);
  // The writer gives up after 60 s should hullmap never open the FIFO.
  const std::string command = "(timeout 60 sh -c 'cat \"" + file + "\" > \"" + fifo.string() + "\"' &) ; '" +
                              HULLMAP_BINARY + "' build '" + fifo.string() + "' --up -y -o '" +
                              (dir / "fifo").string() + "' >/dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(slurp(dir / "fifo" / "map.bt"), slurp(dir / "file" / "map.bt"));
  EXPECT_EQ(slurp(dir / "fifo" / "voxels.csv"), slurp(dir / "file" / "voxels.csv"));
  EXPECT_EQ(readJson(dir / "fifo" / "report.json")["points"], readJson(dir / "file" / "report.json")["points"]);
}

// Errors of a streamed build are those of a build that reads its inputs whole (--origin does),
// in the same order: an input error (even after batches went into the octree), then "no points",
// then the filters', then a bad octree parameter. Exit 2, nothing written.
TEST(CliBadInput, StreamedBuildFailsAsTheWholeFileBuild) {
  const auto dir = freshDir("cli_streamed_errors");
  std::string big;
  for (int i = 0; i < 100000; ++i) big += "0." + std::to_string(i % 1000) + " 1 2\n";
  writeText(dir / "big_bad.txt", big + "1 2 3 4\n");
  writeText(dir / "good.txt", big);
  writeText(dir / "nan1.txt", "nan 1 2\n");
  writeText(dir / "nan2.txt", "1 inf 2\n");
  const std::string out = " -o " + (dir / "out").string();
  const std::string bad_params = " --clamp-min 0.9 --clamp-max 0.5";
  const std::string outside = " --crop 5,5,5,6,6,6";
  const struct {
    std::string args;
    std::string message;
  } cases[] = {
      {(dir / "big_bad.txt").string(),
       (dir / "big_bad.txt").string() + ":100001: expected 3 numbers like the first data line, got 4"},
      {(dir / "big_bad.txt").string() + bad_params + outside, (dir / "big_bad.txt").string() + ":100001: "},
      {(dir / "nan1.txt").string() + " " + (dir / "nan2.txt").string() + bad_params,
       (dir / "nan1.txt").string() + ", " + (dir / "nan2.txt").string() + ": no points"},
      {(dir / "good.txt").string() + outside + bad_params, "--crop/--z-min/--z-max: no points left inside the bounds"},
      {(dir / "good.txt").string() + " --z-min 3", "--crop/--z-min/--z-max: no points left inside the bounds"},
      {(dir / "good.txt").string() + bad_params,
       "--clamp-min/--clamp-max: the lower clamp must be below the upper one"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    const auto streamed = runHullmap("build " + c.args + out);
    expectOneLineError(streamed, c.message);
    EXPECT_FALSE(fs::exists(dir / "out"));
    const auto whole = runHullmap("build " + c.args + " --origin 0,0,0" + out);
    EXPECT_EQ(streamed.err, whole.err);
    EXPECT_EQ(whole.status, 2);
    EXPECT_FALSE(fs::exists(dir / "out"));
  }
}

// A live node has no file: buildFromPoints on the points a file holds makes the map, voxel labels and
// obstacles that build makes of the file (with and without a sensor origin), and write()s the same
// obstacles.json apart from the inputs it names.
TEST(PipelineLibrary, BuildFromPointsInMemoryIsBuildOfTheFile) {
  using namespace hullmap;
  const fs::path file = fs::path(HULLMAP_SOURCE_DIR) / "maps" / "simple" / "map_points.txt";
  for (const bool with_origin : {false, true}) {
    SCOPED_TRACE(with_origin ? "one scan from an origin" : "points only");
    pipeline::BuildParams params;
    params.inputs = {file};
    params.frame.up = mapper::UpAxis::kNegY;
    if (with_origin) params.origin = Eigen::Vector3d(0, -1, 0);
    const pipeline::BuildResult from_file = pipeline::build(params);
    io::Points points = io::readPointFile(file.string()).points;
    points.push_back(Eigen::Vector3d(std::nan(""), 0, 0));
    const pipeline::BuildResult from_memory = pipeline::buildFromPoints(points, params, "live");
    ASSERT_EQ(from_memory.voxels.size(), from_file.voxels.size());
    for (std::size_t i = 0; i < from_file.voxels.size(); ++i) {
      ASSERT_EQ(from_memory.voxels[i].center, from_file.voxels[i].center) << i;
      ASSERT_EQ(from_memory.voxels[i].weight, from_file.voxels[i].weight) << i;
    }
    EXPECT_EQ(from_memory.clusters.labels, from_file.clusters.labels);
    ASSERT_EQ(from_memory.obstacles.size(), from_file.obstacles.size());
    EXPECT_GT(from_file.obstacles.size(), 5u);
    EXPECT_EQ(from_memory.report.points.used, from_file.report.points.used);
    EXPECT_EQ(from_memory.report.points.read, from_file.report.points.read + 1);
    EXPECT_EQ(from_memory.report.points.dropped.at("non_finite"), 1u);
    EXPECT_EQ(from_memory.report.inputs.at(0).format, "memory");
    const auto dir = freshDir(with_origin ? "memory_origin" : "memory_points");
    pipeline::write(from_memory, dir / "memory");
    pipeline::write(from_file, dir / "file");
    const auto back = pipeline::readObstacles(dir / "memory" / "obstacles.json");
    ASSERT_EQ(back.size(), from_file.obstacles.size());
    for (std::size_t i = 0; i < back.size(); ++i) {
      EXPECT_EQ(back[i].id, from_file.obstacles[i].id);
      EXPECT_EQ(back[i].hull.vertices, from_file.obstacles[i].hull.vertices);
    }
    EXPECT_EQ(slurp(dir / "memory" / "voxels.csv"), slurp(dir / "file" / "voxels.csv"));
    EXPECT_EQ(slurp(dir / "memory" / "obstacles.obj"), slurp(dir / "file" / "obstacles.obj"));
  }
}
