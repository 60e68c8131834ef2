// End-to-end tests of `hullmap roadmap` and `hullmap plan`: paths that `check` accepts, blocked and
// unreachable goals (exit 1, one line saying where), bad inputs (exit 2, one line naming them).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "planning_support.hpp"
#include "run_hullmap.hpp"

namespace fs = std::filesystem;
using hullmap::test::freshDir;
using hullmap::test::lineCount;
using hullmap::test::runHullmap;
using hullmap::test::slurp;

namespace {

/// A generated scene (z-up) and `hullmap build` of it in dir/out; returns the scene.
hullmap::sim::Scene builtScene(const fs::path& dir) {
  hullmap::sim::SceneParams params;
  params.seed = 7;
  params.orbslam_frame = false;
  const auto scene = hullmap::sim::generateScene(params);
  hullmap::sim::writeScene(scene, params, dir.string());
  const auto r = runHullmap("build " + (dir / "map_points.txt").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(r.status, 0) << r.err;
  return scene;
}

std::vector<std::vector<double>> readRows(const fs::path& path) {
  std::vector<std::vector<double>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::vector<double> row;
    for (double v; s >> v;) row.push_back(v);
    rows.push_back(row);
  }
  return rows;
}

void expectOneLine(const hullmap::test::CommandResult& r, int status, const std::string& text,
                   const std::string& needle) {
  EXPECT_EQ(r.status, status) << r.out << r.err;
  EXPECT_EQ(lineCount(text), 1) << text;
  EXPECT_NE(text.find(needle), std::string::npos) << "expected '" << needle << "' in: " << text;
}

/// Four walls round the origin (1 m inside), the gaps between them 0.4 m wide at the corners.
fs::path walledRoom(const fs::path& dir) {
  using hullmap::test::prism;
  const std::vector<hullmap::hulls::Obstacle> walls{
      prism(0, {{-1.2, -1.2}, {1.2, -1.2}, {1.2, -1.0}, {-1.2, -1.0}}, 0, 2),  // south
      prism(1, {{-1.2, 1.0}, {1.2, 1.0}, {1.2, 1.2}, {-1.2, 1.2}}, 0, 2),      // north
      prism(2, {{-1.2, -0.6}, {-1.0, -0.6}, {-1.0, 0.6}, {-1.2, 0.6}}, 0, 2),  // west: 0.4 m gaps
      prism(3, {{1.0, -0.6}, {1.2, -0.6}, {1.2, 0.6}, {1.0, 0.6}}, 0, 2),      // east
  };
  const fs::path path = dir / "obstacles.json";
  hullmap::pipeline::writeObstaclesJson(path.string(), walls, {});
  return path;
}

}  // namespace

TEST(CliPlan, PathKeepsTheRadiusFromTheTruthAndCheckAcceptsIt) {
  const auto dir = freshDir("cli_plan_path");
  const auto scene = builtScene(dir);
  const auto out = (dir / "out").string();
  const auto path = dir / "path.txt";
  const auto r = runHullmap("plan " + out + " --from -4,-4,1 --to 4,4,1 --radius 0.3 -o " + path.string());
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  expectOneLine(r, 0, r.out, "-> " + path.string());
  const auto check = runHullmap("check " + out + " --radius 0.3 --path " + path.string());
  EXPECT_EQ(check.status, 0) << check.out;
  EXPECT_NE(check.out.find("path: clear"), std::string::npos);
  const auto rows = readRows(path);
  ASSERT_GE(rows.size(), 2u);
  EXPECT_EQ(rows.front(), (std::vector<double>{-4, -4, 1}));
  EXPECT_EQ(rows.back(), (std::vector<double>{4, 4, 1}));
  const auto truth = scene.truth.primitives();
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const Eigen::Vector3d a(rows[k - 1][0], rows[k - 1][1], rows[k - 1][2]), b(rows[k][0], rows[k][1], rows[k][2]);
    for (int s = 0; s <= 200; ++s)
      for (const auto& o : truth) ASSERT_GE(hullmap::test::distanceToSolid(o, a + (b - a) * (s / 200.0)), 0.3);
  }
  // Without -o the waypoints go to stdout.
  const auto printed = runHullmap("plan " + out + " --from -4,-4,1 --to 4,4,1 --radius 0.3");
  EXPECT_EQ(printed.status, 0);
  EXPECT_EQ(printed.out, slurp(path));
}

TEST(CliPlan, RoadmapWritesTheDocumentedGraph) {
  const auto dir = freshDir("cli_plan_roadmap");
  builtScene(dir);
  const auto file = dir / "rm.json";
  const auto r = runHullmap("roadmap " + (dir / "out").string() + " --radius 0.25 --band 0.5,1.5 -o " + file.string());
  expectOneLine(r, 0, r.out, "roadmap: ");
  const auto j = nlohmann::json::parse(slurp(file));
  EXPECT_EQ(j["format"], "hullmap-roadmap/1");
  EXPECT_EQ(j["band"], (std::vector<double>{0.5, 1.5}));
  ASSERT_FALSE(j["edges"].empty());
  for (const auto& e : j["edges"]) EXPECT_GE(e["clearance"].get<double>(), 0.25);
  // Without -o: roadmap.json in the build directory.
  EXPECT_EQ(runHullmap("roadmap " + (dir / "out").string() + " --radius 0.25").status, 0);
  EXPECT_TRUE(fs::exists(dir / "out" / "roadmap.json"));
}

// Every roadmap edge keeps R from the exact hulls along its whole polyline at a height inside the
// band. The union of touching footprints once left vertices a rounding error apart, and the Voronoi
// vertices around that tiny site went astray: an edge claiming 0.5 m of clearance was drawn straight
// through a footprint. And an edge whose clearance was R itself (0.30000000000000004 on this scene,
// a Voronoi vertex 0.3 from two sites) was kept, though its polyline's last chord, within the
// tolerance of the parabola, came 0.2999999 m near a hull: the exact check at R called it a
// collision (plan, which takes edges of clearance R + tolerance only, never used it). Edges below R +
// tolerance are dropped now.
TEST(CliPlan, RoadmapEdgesKeepTheirClearanceFromTheHulls) {
  const auto dir = freshDir("cli_plan_roadmap_hulls");
  builtScene(dir);
  const auto file = dir / "rm.json";
  const double radius = 0.3;
  const auto r = runHullmap("roadmap " + (dir / "out").string() + " --radius 0.3 --band 0.5,1.5 -o " + file.string());
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(slurp(file));
  const hullmap::collision::HullChecker hulls(hullmap::pipeline::readObstacles(dir / "out" / "obstacles.json"));
  int checked = 0;
  for (const auto& e : j["edges"]) {
    EXPECT_GE(e["clearance"].get<double>(), radius + j["tolerance"].get<double>());
    std::vector<Eigen::Vector3d> polyline;
    for (const auto& p : e["polyline"]) polyline.emplace_back(p[0].get<double>(), p[1].get<double>(), 1.0);
    const auto check = hulls.checkPath(polyline, radius);
    EXPECT_FALSE(check.first_colliding_segment.has_value())
        << "edge " << e["from"] << "-" << e["to"] << " (clearance " << e["clearance"] << ") hits the hulls at "
        << check.first_contact->transpose();
    ++checked;
  }
  EXPECT_GT(checked, 50);
}

TEST(CliPlan, BlockedUnreachableAndInsideSayWhereInOneLine) {
  const auto dir = freshDir("cli_plan_blocked");
  const auto room = walledRoom(dir).string();
  // Through a 0.4 m gap: 0.15 passes, 0.3 does not and is told the narrowest passage.
  EXPECT_EQ(runHullmap("plan " + room + " --from 0,0,1 --to 3,0,1 --radius 0.15").status, 0);
  const auto blocked = runHullmap("plan " + room + " --from 0,0,1 --to 3,0,1 --radius 0.3");
  expectOneLine(blocked, 1, blocked.out, "narrows to clearance 0.2");
  EXPECT_TRUE(blocked.err.empty()) << blocked.err;
  const auto inside = runHullmap("plan " + room + " --from 0,-1.1,1 --to 3,0,1 --radius 0.1");
  expectOneLine(inside, 1, inside.out, "start (0, -1.1, 1) is inside obstacle 0");
  const auto goal_inside =
      runHullmap("plan " + room + " --from 3,0,1 --to 0,1.05,1 --radius 0.1 -o " + (dir / "p.txt").string());
  expectOneLine(goal_inside, 1, goal_inside.out, "goal (0, 1.05, 1) is inside obstacle 1");
  EXPECT_FALSE(fs::exists(dir / "p.txt"));
}

TEST(CliPlan, BadInputsExitTwoWithOneLine) {
  const auto dir = freshDir("cli_plan_bad");
  const auto room = walledRoom(dir).string();
  struct Case {
    std::string args, needle;
  };
  std::ofstream(dir / "bad_robots.txt") << "0 0 1 3 0 1\n1 2 3\n";
  std::ofstream(dir / "word_robots.txt") << "0 0 1 3 0 x1\n";
  std::ofstream(dir / "not.json") << "{ nope";
  fs::create_directories(dir / "empty");
  const std::vector<Case> cases{
      {"plan " + (dir / "missing").string() + " --from 0,0,1 --to 1,1,1 -r 0.1", "no such file or directory"},
      {"plan " + (dir / "empty").string() + " --from 0,0,1 --to 1,1,1 -r 0.1", "no obstacles.json in this directory"},
      {"plan " + (dir / "not.json").string() + " --from 0,0,1 --to 1,1,1 -r 0.1", "not.json"},
      {"plan " + room + " --from 0,0 --to 1,1,1 -r 0.1", "--from: expected 3 comma-separated numbers, got 2"},
      {"plan " + room + " --from 0,a,1 --to 1,1,1 -r 0.1", "--from: not a number: \"a\""},
      {"plan " + room + " --from 0,0,1 -r 0.1", "--to is required with --from"},
      {"plan " + room + " --from 0,0,1 --to 1,1,1 -r -1", "--radius: must be >= 0"},
      {"plan " + room + " --robots " + (dir / "bad_robots.txt").string() + " -r 0.1 --speed 1 -o " +
           (dir / "p").string(),
       "bad_robots.txt:2: expected 6 numbers"},
      {"plan " + room + " --robots " + (dir / "word_robots.txt").string() + " -r 0.1 --speed 1 -o " +
           (dir / "p").string(),
       "word_robots.txt:1: not a number: \"x1\""},
      {"plan " + room + " --robots " + (dir / "none.txt").string() + " -r 0.1 --speed 1 -o " + (dir / "p").string(),
       "none.txt: cannot open"},
      {"plan " + room + " --robots " + (dir / "bad_robots.txt").string() + " -r 0.1 -o " + (dir / "p").string(),
       "--speed: must be > 0"},
      {"roadmap " + room + " -r 0.1 --band 2,1", "--band: need z0 <= z1"},
      {"roadmap " + room + " -r 0.1 --bounds 0,0,1", "--bounds: expected 4 comma-separated numbers, got 3"},
  };
  for (const auto& c : cases) {
    const auto r = runHullmap(c.args);
    SCOPED_TRACE(c.args);
    expectOneLine(r, 2, r.err, c.needle);
  }
}

TEST(CliPlan, FleetWritesTimedPathsApartAndNamesTheUnrouted) {
  const auto dir = freshDir("cli_plan_fleet");
  const auto scene = builtScene(dir);
  std::ofstream(dir / "robots.txt")
      << "# sx sy sz gx gy gz\n-4 -4 1 4 4 1\n4 4 1 -4 -4 1\n-4 4 1 4 -4 1\n4 -4 1 -4 4 1\n";
  const auto paths = dir / "paths";
  const auto r = runHullmap("plan " + (dir / "out").string() + " --robots " + (dir / "robots.txt").string() +
                            " --radius 0.3 --speed 1.5 -o " + paths.string());
  expectOneLine(r, 0, r.out, "4 of 4 drones routed");
  std::vector<std::vector<std::vector<double>>> timed;
  for (int i = 0; i < 4; ++i) timed.push_back(readRows(paths / ("robot_" + std::to_string(i) + ".txt")));
  auto at = [](const std::vector<std::vector<double>>& rows, double t) {
    if (t <= rows.front()[0]) return Eigen::Vector3d(rows.front()[1], rows.front()[2], rows.front()[3]);
    for (std::size_t k = 1; k < rows.size(); ++k)
      if (t <= rows[k][0]) {
        const double s = (t - rows[k - 1][0]) / (rows[k][0] - rows[k - 1][0]);
        const Eigen::Vector3d a(rows[k - 1][1], rows[k - 1][2], rows[k - 1][3]), b(rows[k][1], rows[k][2], rows[k][3]);
        return Eigen::Vector3d(a + s * (b - a));
      }
    return Eigen::Vector3d(rows.back()[1], rows.back()[2], rows.back()[3]);
  };
  double end = 0;
  for (const auto& rows : timed) {
    ASSERT_FALSE(rows.empty());
    for (const auto& row : rows) ASSERT_EQ(row.size(), 4u);
    end = std::max(end, rows.back()[0]);
  }
  const auto truth = scene.truth.primitives();
  for (double t = 0; t <= end; t += 0.002)
    for (std::size_t i = 0; i < timed.size(); ++i) {
      for (const auto& o : truth) ASSERT_GE(hullmap::test::distanceToSolid(o, at(timed[i], t)), 0.3 - 1e-9);
      for (std::size_t j = i + 1; j < timed.size(); ++j)
        ASSERT_GE((at(timed[i], t) - at(timed[j], t)).norm(), 0.6 - 1e-9);
    }

  // A drone starting 0.3 m from another cannot be routed: exit 1, named; the others still are.
  std::ofstream(dir / "crowded.txt") << "-4 -4 1 4 4 1\n-4 -3.7 1 4 -4 1\n";
  const auto crowded = runHullmap("plan " + (dir / "out").string() + " --robots " + (dir / "crowded.txt").string() +
                                  " --radius 0.3 --speed 1.5 -o " + (dir / "crowded").string());
  EXPECT_EQ(crowded.status, 1) << crowded.out << crowded.err;
  EXPECT_NE(crowded.out.find("not routed: drone 1\n"), std::string::npos) << crowded.out;
  EXPECT_TRUE(fs::exists(dir / "crowded" / "robot_0.txt"));
  EXPECT_FALSE(fs::exists(dir / "crowded" / "robot_1.txt"));
}

TEST(CliPlan, OmplMethodPlansRoundAThinPlateAndCheckAcceptsIt) {
  const auto dir = freshDir("cli_plan_ompl");
  using hullmap::test::prism;
  // A 1 cm plate, 4 m wide and 3 m tall, across the straight line.
  const std::vector<hullmap::hulls::Obstacle> plate{
      prism(0, {{-0.005, -2}, {0.005, -2}, {0.005, 2}, {-0.005, 2}}, 0, 3)};
  const auto json = (dir / "obstacles.json").string();
  hullmap::pipeline::writeObstaclesJson(json, plate, {});
  const auto path = dir / "path.txt";
  const auto r = runHullmap(
      "plan " + json + " --method ompl --time-limit 0.5 --from -2,0,1 --to 2,0,1 --radius 0.1 -o " + path.string());
  expectOneLine(r, 0, r.out, "clear by 0.1 (exact hull check) -> " + path.string());
  const auto rows = readRows(path);
  ASSERT_GE(rows.size(), 3u);
  EXPECT_EQ(rows.front(), (std::vector<double>{-2, 0, 1}));
  EXPECT_EQ(rows.back(), (std::vector<double>{2, 0, 1}));
  const auto check = runHullmap("check " + json + " --radius 0.1 --path " + path.string());
  EXPECT_EQ(check.status, 0) << check.out << check.err;
  EXPECT_NE(check.out.find("path: clear"), std::string::npos) << check.out;

  const auto inside =
      runHullmap("plan " + json + " --method ompl --time-limit 0.1 --from 0,0,1 --to 2,0,1 --radius 0.1");
  expectOneLine(inside, 1, inside.out, "start (0, 0, 1) is inside obstacle 0");
}

TEST(CliPlan, OmplOptionsAreChecked) {
  const auto dir = freshDir("cli_plan_ompl_bad");
  const auto room = walledRoom(dir).string();
  struct Case {
    std::string args, needle;
  };
  const std::string trip = "plan " + room + " --from 0,0,1 --to 3,0,1 -r 0.1 ";
  const std::vector<Case> cases{
      {trip + "--method ompl --time-limit 0", "--time-limit: must be > 0"},
      {trip + "--method ompl --time-limit -2", "--time-limit: must be > 0"},
      {trip + "--method ompl --time-limit nan", "--time-limit"},
      {trip + "--method ompl --time-limit 1e9", "--time-limit: must be > 0 and at most 86400"},
      {trip + "--method ompl --time-limit soon", "--time-limit"},
      {trip + "--time-limit 1", "--time-limit: only with --method ompl"},
      {trip + "--method prm", "--method: unknown method \"prm\" (roadmap or ompl)"},
      {"plan " + room + " --robots r.txt -r 0.1 --speed 1 -o p --method ompl", "--method ompl: plans one drone"},
  };
  for (const auto& c : cases) {
    const auto r = runHullmap(c.args);
    SCOPED_TRACE(c.args);
    expectOneLine(r, 2, r.err, c.needle);
  }
}
