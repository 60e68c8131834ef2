// hullmap view: the subcommand on a build directory (what it prints and writes, its errors), and its
// path checks against `hullmap check --json`. The page itself is tested in Chromium by
// test/view/browser_test.py, its data by test/view/page.cpp.
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hullmap/sim/sample_scene.hpp"
#include "hullmap/view/html_view.hpp"
#include "run_hullmap.hpp"

namespace {

namespace fs = std::filesystem;
using hullmap::test::expectOneLineError;
using hullmap::test::quoted;
using hullmap::test::runHullmap;
using hullmap::test::slurp;
using nlohmann::json;

bool haveThree() { return fs::exists(fs::path(hullmap::view::kThreeDir) / "three.min.js"); }

#define HULLMAP_REQUIRE_THREE()                                                                                      \
  if (!haveThree()) {                                                                                                \
    GTEST_SKIP() << hullmap::view::kThreeDir << "/three.min.js not found: install Debian's libjs-three (./setup.sh " \
                 << "test does)";                                                                                    \
  }

// A build of a small generated scene, with its keyframes, by the CLI.
fs::path builtScene(const std::string& name) {
  const fs::path dir = hullmap::test::freshDir(name);
  hullmap::sim::SceneParams params;
  params.points = 6000;
  params.obstacles = 4;
  params.seed = 3;
  hullmap::sim::writeScene(hullmap::sim::generateScene(params), params, dir.string());
  const auto r =
      runHullmap("build " + quoted(dir / "map_points.txt") + " --trajectory " + quoted(dir / "KeyFrameTrajectory.txt") +
                 " --up -y --eps 0.12 --min-pts 5 -o " + quoted(dir / "out"));
  EXPECT_EQ(r.status, 0) << r.err;
  return dir;
}

json pageData(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"hullmap-data\">";
  const auto start = html.find(open);
  EXPECT_NE(start, std::string::npos);
  const auto end = html.find("</script>", start);
  return json::parse(html.substr(start + open.size(), end - start - open.size()));
}

// A path from one side of the scene to the other through its middle at 0.5 m: through obstacles.
void writeCrossingPath(const fs::path& file) {
  hullmap::test::writeText(file, "# x y z\n-4.5 -0.3 0.5\n0 0.2 0.5\n4.5 0.4 0.5\n");
}

}  // namespace

TEST(ViewCommand, WritesDirHtmlBesideTheBuildAndSaysWhatItDrew) {
  HULLMAP_REQUIRE_THREE();
  const fs::path dir = builtScene("view_default");
  const auto r = runHullmap("view " + quoted(dir / "out/"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "out.html")) << "beside the directory, not in it";
  EXPECT_FALSE(fs::exists(dir / "out" / "out.html"));
  const json data = pageData(slurp(dir / "out.html"));
  std::ostringstream first;
  first << "view: " << data["voxels"]["total"].get<std::size_t>() << " voxels, "
        << data["voxels"]["total"].get<std::size_t>() << " cubes at the finest level, " << data["obstacles"].size()
        << " obstacles in " << data["hulls"]["items"].size() << " hulls, 60 keyframes\n";
  EXPECT_EQ(r.out.rfind(first.str(), 0), 0u) << r.out;
  EXPECT_NE(r.out.find("wrote " + (dir / "out").string() + ".html"), std::string::npos) << r.out;
  // The build directory may still be replaced by the next build: view wrote nothing into it.
  const auto again = runHullmap("build " + quoted(dir / "map_points.txt") + " --up -y --eps 0.12 --min-pts 5 -o " +
                                quoted(dir / "out"));
  EXPECT_EQ(again.status, 0) << again.err;
}

TEST(ViewCommand, PathsAreCheckedAsHullmapCheckChecksThem) {
  HULLMAP_REQUIRE_THREE();
  const fs::path dir = builtScene("view_paths");
  writeCrossingPath(dir / "cross.txt");
  // A timed path as `plan --robots` writes it: its positions are the path.
  hullmap::test::writeText(dir / "timed.txt", "# t x y z\n0 -4.5 -4.5 2.9\n3 4.5 -4.5 2.9\n6 4.5 4.5 2.9\n");
  hullmap::test::writeText(dir / "timed_xyz.txt", "-4.5 -4.5 2.9\n4.5 -4.5 2.9\n4.5 4.5 2.9\n");
  const auto r = runHullmap("view " + quoted(dir / "out") + " -o " + quoted(dir / "page.html") + " --path " +
                            quoted(dir / "cross.txt") + " --path " + quoted(dir / "timed.txt") + " -r 0.2");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("2 paths (1 colliding)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cross.txt: path collides: first contact on segment "), std::string::npos) << r.out;
  const json data = pageData(slurp(dir / "page.html"));
  ASSERT_EQ(data["paths"].size(), 2u);
  const char* files[] = {"cross.txt", "timed_xyz.txt"};
  for (int p = 0; p < 2; ++p) {
    const auto check = runHullmap("check " + quoted(dir / "out") + " -r 0.2 --json --path " + quoted(dir / files[p]));
    ASSERT_EQ(check.status, p == 0 ? 1 : 0) << check.err;
    std::istringstream lines(check.out);
    std::size_t s = 0;
    const json& segments = data["paths"][p]["segments"];
    for (std::string line; std::getline(lines, line); ++s) {
      const json expected = json::parse(line);
      ASSERT_LT(s, segments.size());
      EXPECT_EQ(segments[s]["collides"], expected["collides"]) << files[p] << " segment " << s;
      EXPECT_EQ(segments[s]["obstacle"], expected["obstacle"]) << files[p] << " segment " << s;
      EXPECT_EQ(segments[s]["t"], expected["t"]) << files[p] << " segment " << s;
      EXPECT_EQ(segments[s]["surface"], expected["surface"]) << files[p] << " segment " << s;
      EXPECT_EQ(segments[s]["clearance"], expected["clearance"]) << files[p] << " segment " << s;
      EXPECT_EQ(segments[s]["part"], expected.value("part", -1)) << files[p] << " segment " << s;
    }
    EXPECT_EQ(s, segments.size());
  }
  EXPECT_EQ(data["paths"][0]["name"], "cross.txt");
  EXPECT_EQ(data["paths"][1]["waypoints"][2], json::array({4.5, 4.5, 2.9}));
}

TEST(ViewCommand, MoreVoxelsThanMaxInstancesAreMergedAndSaid) {
  HULLMAP_REQUIRE_THREE();
  const fs::path dir = builtScene("view_merge");
  const auto r =
      runHullmap("view " + quoted(dir / "out") + " -o " + quoted(dir / "page.html") + " --max-instances 300");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("voxels a side: more than --max-instances 300) at the finest level"), std::string::npos)
      << r.out;
  const json data = pageData(slurp(dir / "page.html"));
  EXPECT_GT(data["voxels"]["levels"][0]["factor"].get<int>(), 1);
  EXPECT_LE(data["voxels"]["levels"][0]["instances"].get<std::size_t>(), 300u);
}

TEST(ViewCommand, ErrorsNameTheFileOrOptionAndWriteNothing) {
  const fs::path dir = builtScene("view_errors");
  const fs::path page = dir / "page.html";
  const std::string out = quoted(dir / "out");
  expectOneLineError(runHullmap("view " + quoted(dir / "missing") + " -o " + quoted(page)),
                     "missing is not a directory");
  expectOneLineError(runHullmap("view " + out + " -o " + quoted(dir / "page.txt")),
                     "-o " + (dir / "page.txt").string() + ": the page is HTML");
  expectOneLineError(runHullmap("view " + out + " -o " + quoted(dir / "no/such/page.html")), "does not exist");
  expectOneLineError(runHullmap("view " + out + " -o " + quoted(page) + " --three-dir " + quoted(dir / "nothing")),
                     "--three-dir: " + (dir / "nothing").string() + "/three.min.js not found");
  expectOneLineError(runHullmap("view " + out + " -o " + quoted(page) + " --three-dir " + quoted(dir / "nothing")),
                     "libjs-three");
  expectOneLineError(runHullmap("view " + out + " -o " + quoted(page) + " --max-instances 0"), "--max-instances");
  writeCrossingPath(dir / "cross.txt");
  expectOneLineError(runHullmap("view " + out + " -o " + quoted(page) + " --path " + quoted(dir / "cross.txt")),
                     "--radius");
  hullmap::test::writeText(dir / "bad.txt", "0 0 1\n1 1\n");
  expectOneLineError(runHullmap("view " + out + " -o " + quoted(page) + " -r 0.2 --path " + quoted(dir / "bad.txt")),
                     (dir / "bad.txt").string() + ":2:");
  hullmap::test::writeText(dir / "one.txt", "0 0 1\n");
  expectOneLineError(runHullmap("view " + out + " -o " + quoted(page) + " -r 0.2 --path " + quoted(dir / "one.txt")),
                     "a path needs at least two waypoints");
  expectOneLineError(runHullmap("view " + out + " -o " + quoted(page) + " -r -1 --path " + quoted(dir / "cross.txt")),
                     "--radius");
  hullmap::test::writeText(dir / "roadmap.json", "{\"format\": \"hullmap-roadmap/1\"");
  expectOneLineError(runHullmap("view " + out + " -o " + quoted(page) + " --roadmap " + quoted(dir / "roadmap.json")),
                     (dir / "roadmap.json").string());
  hullmap::test::writeText(dir / "truth.json", "{\"obstacles\": [{\"shape\": \"cone\"}]}");
  expectOneLineError(runHullmap("view " + out + " -o " + quoted(page) + " --truth " + quoted(dir / "truth.json")),
                     (dir / "truth.json").string());
  EXPECT_FALSE(fs::exists(page));
  EXPECT_FALSE(fs::exists(dir / "page.txt"));
}
