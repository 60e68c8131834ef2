// hullmap plot: SVG renderer (palette, cell merging, footprints, path marks), PNG output via
// rsvg-convert, the sweep's small multiples, and the `plot` subcommand on a build directory.
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/plot/svg_plot.hpp"
#include "plot_fixtures.hpp"
#include "run_hullmap.hpp"

namespace {

// ---------------------------------------------------------------- helpers

// ---------------------------------------------------------------- palette

// ---------------------------------------------------------------- map rendering

// ---------------------------------------------------------------- sweep

// ---------------------------------------------------------------- output files

// ---------------------------------------------------------------- the subcommand

// A build directory as `hullmap build` writes it, from the in-memory scene.
fs::path writeBuildDir(const Scene& s, const std::string& name) {
  const auto dir = hullmap::test::freshDir(name);
  std::ofstream csv(dir / "voxels.csv");
  csv << "x,y,z,weight,label,core\n";
  for (std::size_t i = 0; i < s.plot.centers.size(); ++i) {
    const auto& c = s.plot.centers[i];
    csv << c.x() << ',' << c.y() << ',' << c.z() << ",1," << s.plot.labels[i] << ",1\n";
  }
  std::ofstream(dir / "report.json") << R"({"parameters": {"eps": 0.1, "min_pts": 10, "metric": "xyz", "resolution": )"
                                     << s.plot.voxel_size << R"(}, "frame": "z-up map, up=-y of input"})";
  hullmap::pipeline::writeObstaclesJson((dir / "obstacles.json").string(), s.plot.obstacles, {});
  return dir;
}

TEST(PlotCommand, DrawsABuildDirectory) {
  Scene s = makeScene(5, 0.05, 4);
  const auto dir = writeBuildDir(s, "plot_cmd");
  const auto out = dir / "map.svg";
  const auto r = hullmap::test::runHullmap("plot '" + dir.string() + "' -o '" + out.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("5 obstacles"), std::string::npos) << r.out;
  const std::string svg = hullmap::test::slurp(out);
  EXPECT_NE(svg.find("eps = 0.1, minPts = 10, metric = xyz"), std::string::npos);
  EXPECT_NE(svg.find("frame: z-up map, up=-y of input"), std::string::npos);
  std::size_t footprints = 0;
  for (std::size_t p = svg.find("class=\"footprint\""); p != std::string::npos;
       p = svg.find("class=\"footprint\"", p + 1)) {
    ++footprints;
  }
  EXPECT_EQ(footprints, 5u);

  const auto side =
      hullmap::test::runHullmap("plot '" + dir.string() + "' --side -o '" + (dir / "side.svg").string() + "'");
  ASSERT_EQ(side.status, 0) << side.err;
  EXPECT_NE(hullmap::test::slurp(dir / "side.svg").find("side view (x-z)"), std::string::npos);

  if (hullmap::plot::findPngConverter()) {
    const auto png = hullmap::test::runHullmap("plot '" + dir.string() + "' -o '" + (dir / "map.png").string() + "'");
    ASSERT_EQ(png.status, 0) << png.err;
    EXPECT_NE(png.out.find("rsvg-convert"), std::string::npos) << png.out;
    EXPECT_EQ(hullmap::test::slurp(dir / "map.png").substr(1, 3), "PNG");
  }
}

TEST(PlotCommand, PathThroughAnObstacleIsMarkedRed) {
  Scene s = makeScene(3, 0.05, 4);
  // Obstacle 0 covers x 0.2..0.4, y 0.2..0.35, z 0..0.1: the first segment crosses it at mid-height,
  // the second climbs at x = 0.6, 0.2 from obstacle 0 and 0.3 from obstacle 1 (x >= 0.9).
  ASSERT_NEAR(s.plot.obstacles[0].aabb_max.x(), 0.4, 1e-9);
  ASSERT_NEAR(s.plot.obstacles[1].aabb_min.x(), 0.9, 1e-9);
  const auto dir = writeBuildDir(s, "plot_cmd_path");
  std::ofstream(dir / "path.txt") << "# x y z\n0 0.275 0.05\n0.6 0.275 0.05\n\n0.6 2 2\n";
  const auto r = hullmap::test::runHullmap("plot '" + dir.string() + "' --path '" + (dir / "path.txt").string() +
                                           "' --radius 0.05 -o '" + (dir / "map.svg").string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("first contact on segment 0"), std::string::npos) << r.out;
  const std::string svg = hullmap::test::slurp(dir / "map.svg");
  EXPECT_NE(svg.find("class=\"colliding-segment\" data-segment=\"0\""), std::string::npos);
  EXPECT_EQ(svg.find("data-segment=\"1\""), std::string::npos);
  EXPECT_NE(svg.find("class=\"first-contact\""), std::string::npos);
  // The first contact lies on segment 0 before the obstacle's near face (x = 0.2) less the radius.
  const std::size_t contact = svg.find("first contact at (");
  ASSERT_NE(contact, std::string::npos) << "caption names the first contact";
  double cx = 0, cy = 0, cz = 0;
  ASSERT_EQ(std::sscanf(svg.c_str() + contact, "first contact at (%lf, %lf, %lf)", &cx, &cy, &cz), 3);
  EXPECT_NEAR(cx, 0.15, 0.01);
  EXPECT_NEAR(cy, 0.275, 1e-6);

  std::ofstream(dir / "clear.txt") << "0 2 2\n2 2 2\n";
  const auto clear = hullmap::test::runHullmap("plot '" + dir.string() + "' --path '" + (dir / "clear.txt").string() +
                                               "' --radius 0.05 -o '" + (dir / "clear.svg").string() + "'");
  ASSERT_EQ(clear.status, 0) << clear.err;
  const std::string clear_svg = hullmap::test::slurp(dir / "clear.svg");
  EXPECT_EQ(clear_svg.find("colliding-segment"), std::string::npos);
  EXPECT_NE(clear_svg.find("radius 0.05, clear"), std::string::npos);

  std::ofstream(dir / "bad.txt") << "0 0 0\n1 1\n";
  const auto bad = hullmap::test::runHullmap("plot '" + dir.string() + "' --path '" + (dir / "bad.txt").string() +
                                             "' --radius 0.05 -o '" + (dir / "bad.svg").string() + "'");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("bad.txt:2"), std::string::npos) << bad.err;
}

TEST(PlotCommand, GenerateBuildPlotEndToEnd) {
  const auto dir = hullmap::test::freshDir("plot_e2e");
  const auto scene = dir / "scene";
  const auto out = dir / "out";
  auto r = hullmap::test::runHullmap("generate --points 6000 --obstacles 5 -o '" + scene.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  r = hullmap::test::runHullmap("build '" + (scene / "map_points.txt").string() + "' --trajectory '" +
                                (scene / "KeyFrameTrajectory.txt").string() + "' --up -y --eps 0.15 --min-pts 5 -o '" +
                                out.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  r = hullmap::test::runHullmap("plot '" + out.string() + "' -o '" + (dir / "top.svg").string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  // The build's keyframes (trajectory.txt) and its floor are drawn.
  EXPECT_NE(r.out.find(", 60 keyframes"), std::string::npos) << r.out;
  {
    const std::string top = hullmap::test::slurp(dir / "top.svg");
    EXPECT_NE(top.find("<g class=\"trajectory\""), std::string::npos);
    EXPECT_NE(top.find("<polygon class=\"floor-outline\""), std::string::npos);
  }
  const auto obstacles = hullmap::pipeline::readObstaclesJson((out / "obstacles.json").string());
  ASSERT_FALSE(obstacles.empty());
  const std::string svg = hullmap::test::slurp(dir / "top.svg");
  for (const auto& o : obstacles) {
    EXPECT_NE(svg.find("class=\"footprint\" id=\"obstacle-" + std::to_string(o.id) + "\""), std::string::npos) << o.id;
  }
  if (havePython()) {
    const auto elements = parseSvg(svg, "e2e");
    std::size_t outlines = 0;  // one per convex part (one for an obstacle without parts)
    for (const auto& o : obstacles) outlines += std::max<std::size_t>(o.parts.size(), 1);
    EXPECT_EQ(countClass(elements, "footprint"), outlines);
    EXPECT_EQ(countClass(elements, "obstacle-id"), obstacles.size());
    for (const auto& e : elements) {
      if (e.cls == "cells") {
        EXPECT_EQ(e.fill, e.label == "-2" ? "#ddd3bb" : toHex(clusterColour(std::stoi(e.label))));
      }
    }
  }
}

TEST(PlotCommand, SweepPlotHasOnePanelPerPairMatchingTheTable) {
  const auto dir = hullmap::test::freshDir("plot_sweep_cmd");
  {
    std::ofstream points(dir / "points.txt");
    std::mt19937_64 rng(8);
    std::normal_distribution<double> blob(0.0, 0.05);
    std::uniform_real_distribution<double> room(-2.0, 2.0);
    for (int i = 0; i < 300; ++i) points << 1 + blob(rng) << ' ' << blob(rng) << ' ' << blob(rng) << '\n';
    for (int i = 0; i < 200; ++i) points << -1 + blob(rng) << ' ' << 1 + blob(rng) << ' ' << blob(rng) << '\n';
    for (int i = 0; i < 40; ++i) points << room(rng) << ' ' << room(rng) << ' ' << room(rng) << '\n';
  }
  const auto r =
      hullmap::test::runHullmap("sweep '" + (dir / "points.txt").string() + "' --eps 0.05,0.2,0.5 --min-pts 3,20 -o '" +
                                (dir / "sweep.csv").string() + "' --plot '" + (dir / "sweep.svg").string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string svg = hullmap::test::slurp(dir / "sweep.svg");
  // Every CSV row has its panel with the same cluster count.
  std::istringstream csv(hullmap::test::slurp(dir / "sweep.csv"));
  std::string line;
  std::getline(csv, line);
  int rows = 0;
  while (std::getline(csv, line)) {
    std::istringstream f(line);
    std::string eps, min_pts, clusters;
    std::getline(f, eps, ',');
    std::getline(f, min_pts, ',');
    std::getline(f, clusters, ',');
    ++rows;
    EXPECT_NE(svg.find("data-eps=\"" + eps + "\" data-min-pts=\"" + min_pts + "\" data-clusters=\"" + clusters + "\""),
              std::string::npos)
        << line;
  }
  EXPECT_EQ(rows, 6);
  if (havePython()) {
    EXPECT_EQ(countClass(parseSvg(svg, "sweep_cmd"), "panel"), 6u);
  }
  const auto bad = hullmap::test::runHullmap("sweep '" + (dir / "points.txt").string() + "' --plot '" +
                                             (dir / "nodir/s.svg").string() + "'");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--plot"), std::string::npos) << bad.err;
  EXPECT_EQ(bad.out.find("clusters"), std::string::npos) << "fails before the runs";
}

TEST(PlotCommand, ErrorsNameTheFileOrOption) {
  Scene s = makeScene(2, 0.05, 4);
  const auto dir = writeBuildDir(s, "plot_cmd_err");
  auto r = hullmap::test::runHullmap("plot '" + (dir / "missing").string() + "' -o x.svg");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("hullmap: error:"), std::string::npos);
  EXPECT_NE(r.err.find("missing"), std::string::npos) << r.err;

  r = hullmap::test::runHullmap("plot '" + dir.string() + "' -o '" + (dir / "no/such/dir/map.svg").string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("-o"), std::string::npos) << r.err;

  // An SVG under another picture format's name would be a lie the next program trips on.
  r = hullmap::test::runHullmap("plot '" + dir.string() + "' -o '" + (dir / "map.gif").string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("-o " + (dir / "map.gif").string() + ": expected a .svg or .png file name"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "map.gif"));

  std::ofstream(dir / "voxels.csv", std::ios::app) << "1,2,oops\n";
  r = hullmap::test::runHullmap("plot '" + dir.string() + "' -o '" + (dir / "m.svg").string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("voxels.csv:" + std::to_string(s.plot.centers.size() + 2)), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "m.svg"));

  r = hullmap::test::runHullmap("plot '" + dir.string() + "' --path p.txt -o '" + (dir / "m.svg").string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--radius"), std::string::npos) << r.err;
}

}  // namespace

TEST(PlotCommand, RoadmapAndSeveralPathsOneColourEach) {
  Scene s = makeScene(3, 0.05, 4);
  const auto dir = writeBuildDir(s, "plot_cmd_roadmap");
  const auto roadmap = dir / "roadmap.json";
  auto r = hullmap::test::runHullmap("roadmap '" + dir.string() + "' --radius 0.02 -o '" + roadmap.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string json = hullmap::test::slurp(roadmap);
  std::size_t edges = 0;
  for (auto at = json.find("\"polyline\""); at != std::string::npos; at = json.find("\"polyline\"", at + 1)) ++edges;
  ASSERT_GT(edges, 0u);
  std::ofstream(dir / "a.txt") << "0 0 0.05\n0.6 0.9 0.05\n";
  std::ofstream(dir / "b.txt") << "# t x y z: a timed path of plan --robots\n0 1 1 0.05\n1 1.5 1.2 0.05\n2 2 0 0.05\n";
  r = hullmap::test::runHullmap("plot '" + dir.string() + "' --roadmap '" + roadmap.string() + "' --path '" +
                                (dir / "a.txt").string() + "' --path '" + (dir / "b.txt").string() + "' -r 0.02 -o '" +
                                (dir / "map.svg").string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("roadmap of " + std::to_string(edges) + " edges, 2 paths"), std::string::npos) << r.out;
  const std::string svg = hullmap::test::slurp(dir / "map.svg");
  const auto count = [&](const std::string& needle) {
    std::size_t n = 0;
    for (auto at = svg.find(needle); at != std::string::npos; at = svg.find(needle, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("class=\"roadmap-edge\""), edges);
  EXPECT_GT(count("class=\"roadmap-node\""), 0u);
  EXPECT_EQ(count("<g class=\"path\""), 2u);
  // One colour per path: the first blue, the second orange; b.txt's three timed waypoints drawn.
  std::vector<std::string> colours;
  const std::string band = "<polyline class=\"path-band\" points=\"";
  for (std::size_t at = svg.find("<g class=\"path\" data-index=\""); at != std::string::npos;
       at = svg.find("<g class=\"path\" data-index=\"", at + 1)) {
    const std::size_t line = svg.find('\n', at);
    ASSERT_EQ(svg.compare(line + 1, band.size(), band), 0) << svg.substr(at, 120);
    const std::size_t stroke = svg.find("\" fill=\"none\" stroke=\"", line + 1 + band.size());
    ASSERT_NE(stroke, std::string::npos);
    colours.push_back(svg.substr(stroke + 22, 7));
  }
  ASSERT_EQ(colours.size(), 2u);
  EXPECT_EQ(colours[0], hullmap::plot::toHex(hullmap::plot::pathColour(0)));
  EXPECT_EQ(colours[1], hullmap::plot::toHex(hullmap::plot::pathColour(1)));
  EXPECT_NE(colours[0], colours[1]);
  EXPECT_EQ(count("class=\"waypoint\""), 5u);
  EXPECT_NE(svg.find("path b.txt (" + colours[1] + "): 2 segments"), std::string::npos);

  std::ofstream(dir / "bad.json") << "{\"format\": \"hullmap-roadmap/1\", \"bounds\": [0, 0, 1]}";
  r = hullmap::test::runHullmap("plot '" + dir.string() + "' --roadmap '" + (dir / "bad.json").string() + "' -o '" +
                                (dir / "bad.svg").string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("bad.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "bad.svg"));
}
