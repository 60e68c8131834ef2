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

TEST(CliFrames, CheckInTheInputFrameAnswersForTheSamePlaces) {
  // maps/simple in ORB-SLAM's camera frame, levelled: input and map frames differ by a rotation
  // about x (-y up) and the floor's levelling.
  const auto dir = freshDir("simple");
  const fs::path out = dir / "out";
  auto r = runHullmap("build " + sample("simple/map_points.txt") + " --trajectory " +
                      sample("simple/KeyFrameTrajectory.txt") + " --up -y --eps 0.12 --min-pts 5 -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  ASSERT_TRUE(readJson(out / "report.json")["floor"]["levelled"].get<bool>());
  const hullmap::mapper::Similarity to_map = inputToOutput(out);
  const hullmap::mapper::Similarity to_input = hullmap::mapper::inverse(to_map);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> xy(-3.5, 3.5), z(-0.5, 2.5);
  std::ostringstream in_map, in_input;
  in_map.precision(17);
  in_input.precision(17);
  std::vector<std::pair<V3, V3>> segments;
  for (int i = 0; i < 200; ++i) {
    const V3 a(xy(rng), xy(rng), z(rng)), b(xy(rng), xy(rng), z(rng));
    segments.emplace_back(a, b);
    in_map << a.x() << ' ' << a.y() << ' ' << a.z() << ' ' << b.x() << ' ' << b.y() << ' ' << b.z() << '\n';
    const V3 ia = to_input(a), ib = to_input(b);
    in_input << ia.x() << ' ' << ia.y() << ' ' << ia.z() << ' ' << ib.x() << ' ' << ib.y() << ' ' << ib.z() << '\n';
  }
  writeText(dir / "map.txt", in_map.str());
  writeText(dir / "input.txt", in_input.str());
  const auto map_run = runHullmap("check " + out.string() + " -r 0.2 --json --segments " + (dir / "map.txt").string());
  const auto input_run =
      runHullmap("check " + out.string() + " -r 0.2 --json --frame input --segments " + (dir / "input.txt").string());
  ASSERT_EQ(map_run.status, input_run.status) << map_run.err << input_run.err;
  const auto a = jsonLines(map_run.out), b = jsonLines(input_run.out);
  ASSERT_EQ(a.size(), 200u);
  ASSERT_EQ(b.size(), 200u);
  int collisions = 0, floor_hits = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i]["collides"], b[i]["collides"]) << i;
    EXPECT_EQ(a[i]["obstacle"], b[i]["obstacle"]) << i;
    EXPECT_EQ(a[i]["surface"], b[i]["surface"]) << i;
    EXPECT_NEAR(a[i]["clearance"].get<double>(), b[i]["clearance"].get<double>(), 1e-9) << i;
    if (a[i]["collides"].get<bool>()) {
      ++collisions;
      floor_hits += a[i]["surface"] == "floor";
      EXPECT_NEAR(a[i]["t"].get<double>(), b[i]["t"].get<double>(), 1e-6) << i;
    }
  }
  EXPECT_GT(collisions, 20);
  EXPECT_GT(floor_hits, 5);
  EXPECT_LT(collisions, 190);

  // The contact point printed is on the segment as given, in its frame: for a floor hit, taken back
  // to the map frame it is the map run's contact point.
  std::size_t hit = 0;
  while (hit < a.size() && (a[hit]["surface"] != "floor" || !(a[hit]["t"].get<double>() > 0))) ++hit;
  ASSERT_LT(hit, a.size());
  const auto [ma, mb] = segments[hit];
  const V3 map_contact = ma + a[hit]["t"].get<double>() * (mb - ma);
  std::ostringstream one;
  one.precision(17);
  const V3 ia = to_input(ma), ib = to_input(mb);
  one << ia.x() << ',' << ia.y() << ',' << ia.z() << ',' << ib.x() << ',' << ib.y() << ',' << ib.z();
  r = runHullmap("check " + out.string() + " -r 0.2 --frame input --segment=" + one.str());
  ASSERT_EQ(r.status, 1) << r.out << r.err;
  const auto open = r.out.find(" ("), close = r.out.find(')', open);
  ASSERT_NE(open, std::string::npos) << r.out;
  std::istringstream contact(r.out.substr(open + 2, close - open - 2));
  V3 p;
  contact >> p.x() >> p.y() >> p.z();
  EXPECT_LT((to_map(p) - map_contact).norm(), 1e-6) << r.out;
  EXPECT_NEAR(map_contact.z(), readJson(out / "obstacles.json")["surfaces"][0]["offset"].get<double>() + 0.2, 1e-6);
}

TEST(CliFrames, LevelOption) {
  const auto dir = freshDir("level");
  // A metric z-up cloud with a tilted floor: kept in its frame, with a warning naming --level.
  std::ostringstream cloud;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  const double slope = std::tan(5.0 * M_PI / 180);
  for (int i = 0; i < 20000; ++i) {
    const double x = u(rng), y = u(rng);
    cloud << x << ' ' << y << ' ' << slope * x << '\n';
    if (i % 4 == 0) cloud << x * 0.1 << ' ' << y * 0.1 + 1 << ' ' << 0.3 + 0.2 * (u(rng) + 3) << '\n';
  }
  writeText(dir / "cloud.xyz", cloud.str());
  auto r = runHullmap("build " + (dir / "cloud.xyz").string() + " -o " + (dir / "kept").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("map kept in its frame"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("--level on levels it"), std::string::npos) << r.err;
  EXPECT_EQ(readJson(dir / "kept" / "report.json")["input_to_output"]["matrix"],
            nlohmann::json::parse("[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]"));
  r = runHullmap("build " + (dir / "cloud.xyz").string() + " --level on -o " + (dir / "on").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("levelled to z = 0"), std::string::npos) << r.out;
  EXPECT_EQ(readJson(dir / "on" / "report.json")["parameters"]["level"], "on");
  // ORB-SLAM's frame (--up -y) is levelled unless told not to.
  r = runHullmap("build " + sample("simple/map_points.txt") + " --up -y --level off -o " + (dir / "off").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("map kept in its frame"), std::string::npos) << r.out;
  r = runHullmap("build " + (dir / "cloud.xyz").string() + " --level sometimes -o " + (dir / "bad").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--level"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));
  r = runHullmap("build " + (dir / "cloud.xyz").string() + " --level on --floor none -o " + (dir / "bad").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--level"), std::string::npos) << r.err;
}

}  // namespace
