// The command line in the user's frame: paths through the floor collide and say so, `check` and
// `plan` in the input frame answer for the same places as in the map frame, `--level`, and GPS logs
// as receivers write them.
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "frames_fixtures.hpp"
#include "hullmap/mapper/align.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "run_hullmap.hpp"

namespace {

/// maps/room built at the defaults (aligned, floor found at z = 0), once for the tests here.
const fs::path& roomBuild() {
  static const fs::path out = [] {
    const fs::path dir = fs::path(HULLMAP_TEST_TMP) / "cli_frames_room";
    fs::remove_all(dir);
    const auto r =
        runHullmap("build " + sample("room/map_points.txt") + " --trajectory " + sample("room/KeyFrameTrajectory.txt") +
                   " --align " + sample("room/reference_trajectory.txt") + " -p -o " + dir.string());
    EXPECT_EQ(r.status, 0) << r.err;
    return dir;
  }();
  return out;
}

TEST(CliFrames, APathThroughTheFloorCollidesWithTheFloorNamed) {
  const fs::path& room = roomBuild();
  auto r = runHullmap("check " + room.string() + " --radius 0.3 --segment 0,0,1,0,0,-1");
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("COLLIDES with the floor at t="), std::string::npos) << r.out;
  r = runHullmap("check " + room.string() + " --radius 0.3 --segment 0,0,1,0,0,-1 --json");
  ASSERT_EQ(r.status, 1) << r.err;
  const auto lines = jsonLines(r.out);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0]["surface"], "floor");
  EXPECT_TRUE(lines[0]["obstacle"].is_null());
  // Against the octree too (here a voxel of the dense floor is met first), and a clear segment says null.
  r = runHullmap("check " + room.string() + " --radius 0.3 --segment 0,0,1,0,0,-1 --against octree");
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  r = runHullmap("check " + room.string() + " --radius 0.1 --segment 4,3,1.2,4.2,3,1.2 --json");
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_TRUE(jsonLines(r.out).at(0)["surface"].is_null()) << r.out;
}

TEST(CliFrames, ThroughTheRealV1_01FloorInBothModes) {
  HULLMAP_REQUIRE_REAL_DATA(map, "orbslam2_euroc_V1_01_MapPoints.txt");
  const auto dir = freshDir("v101");
  auto r = runHullmap("build " + map + " --up -y -o " + (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* against : {"hulls", "octree"}) {
    r = runHullmap("check " + (dir / "out").string() + " -r 0.1 --segment 0,-3,1,0,-3,-2 --against " + against);
    EXPECT_EQ(r.status, 1) << against << ": " << r.out << r.err;
    EXPECT_NE(r.out.find("COLLIDES with the floor"), std::string::npos) << against << ": " << r.out;
  }
}

TEST(CliFrames, PlanInTheInputFrameAndAroundTheFloor) {
  const auto dir = freshDir("plan");
  const fs::path out = dir / "out";
  auto r =
      runHullmap("build " + sample("simple/map_points.txt") + " --up -y --eps 0.12 --min-pts 5 -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const hullmap::mapper::Similarity to_input = hullmap::mapper::inverse(inputToOutput(out));
  const auto text = [](const V3& p) {
    std::ostringstream s;
    s.precision(17);
    s << p.x() << ',' << p.y() << ',' << p.z();
    return s.str();
  };
  const V3 from(-3, -3, 1), to(3, 3, 1);
  r = runHullmap("plan " + out.string() + " -r 0.2 --frame input --from=" + text(to_input(from)) +
                 " --to=" + text(to_input(to)) + " -o " + (dir / "path.txt").string());
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  // Written in the input frame: checked there, it is clear, and it ends where it was asked to.
  r = runHullmap("check " + out.string() + " -r 0.2 --frame input --path " + (dir / "path.txt").string());
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("path: clear"), std::string::npos) << r.out;
  r = runHullmap("check " + out.string() + " -r 0.2 --path " + (dir / "path.txt").string());
  EXPECT_NE(r.out.find("path: first collision"), std::string::npos)
      << "an input-frame path is not a map-frame one: " << r.out;
  // A start within the radius of the floor (its voxels reach 0.05 up) is refused, naming it.
  r = runHullmap("plan " + out.string() + " -r 0.2 --from -3,-3,0.2 --to 3,3,1");
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("inside the floor"), std::string::npos) << r.out;
  // A roadmap band under the floor is refused; one across it is cut to what lies above it.
  r = runHullmap("roadmap " + out.string() + " -r 0.2 --band -1,0 -o " + (dir / "r.json").string());
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.err.find("inside the floor"), std::string::npos) << r.err;
  r = runHullmap("roadmap " + out.string() + " -r 0.2 --band -1,1 -o " + (dir / "r.json").string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("between the floor and ceiling"), std::string::npos) << r.out;
  EXPECT_GT(readJson(dir / "r.json")["band"][0].get<double>(), 0.0);
}

TEST(CliFrames, AGpsLogStartingWithoutAFixAligns) {
  const auto dir = freshDir("gps");
  // The room's metric reference as a receiver would log it (small-angle ENU -> WGS84), after a
  // `t 0 0 0` line written before the first fix.
  std::ifstream in(sample("room/reference_trajectory.txt"));
  std::ostringstream log;
  log.precision(12);
  log << "0 0 0 0\n";
  const double lat0 = 47.3769, lon0 = 8.5417, r = 6378137.0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream f(line);
    double t, x, y, z;
    f >> t >> x >> y >> z;
    log << t << ' ' << lat0 + y / r * 180 / M_PI << ' ' << lon0 + x / (r * std::cos(lat0 * M_PI / 180)) * 180 / M_PI
        << ' ' << 408 + z << '\n';
  }
  writeText(dir / "gps.txt", log.str());
  const auto b =
      runHullmap("build " + sample("room/map_points.txt") + " --trajectory " + sample("room/KeyFrameTrajectory.txt") +
                 " --align " + (dir / "gps.txt").string() + " --align-format gps -o " + (dir / "out").string());
  ASSERT_EQ(b.status, 0) << b.err;
  const auto report = readJson(dir / "out" / "report.json");
  EXPECT_EQ(report["alignment"]["reference_dropped"]["no_fix"], 1);
  EXPECT_EQ(report["alignment"]["matched"], 60);
  EXPECT_LT(report["alignment"]["rmse"].get<double>(), 0.01);
}

}  // namespace
