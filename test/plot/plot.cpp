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
#include "test_support.hpp"

namespace {

// ---------------------------------------------------------------- helpers

// sRGB -> CIE Lab (D65), written independently of the renderer's LCh -> sRGB.
std::array<double, 3> toLab(hullmap::plot::Rgb c) {
  const auto lin = [](std::uint8_t v) {
    const double s = v / 255.0;
    return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
  };
  const double r = lin(c.r), g = lin(c.g), b = lin(c.b);
  const double x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047;
  const double y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  const double z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883;
  const auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; };
  return {116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z))};
}

double deltaE(hullmap::plot::Rgb a, hullmap::plot::Rgb b) {
  const auto la = toLab(a), lb = toLab(b);
  return std::sqrt((la[0] - lb[0]) * (la[0] - lb[0]) + (la[1] - lb[1]) * (la[1] - lb[1]) +
                   (la[2] - lb[2]) * (la[2] - lb[2]));
}

// Brute-force oracle of the merged top view: per x-y cell the label of the topmost clustered voxel,
// else -1; far outliers (|coordinate| > 100) excluded.
std::map<std::pair<long, long>, int> expectedTopCells(const MapPlot& plot) {
  std::map<std::pair<long, long>, std::pair<int, double>> best;
  for (std::size_t i = 0; i < plot.centers.size(); ++i) {
    const auto& c = plot.centers[i];
    if (std::abs(c.x()) > 100 || std::abs(c.y()) > 100) continue;
    const auto key =
        std::make_pair(std::lround(c.y() / plot.voxel_size - 0.5), std::lround(c.x() / plot.voxel_size - 0.5));
    const int label = plot.labels[i] < 0 ? -1 : plot.labels[i];
    auto it = best.find(key);
    if (it == best.end()) {
      best[key] = {label, c.z()};
      continue;
    }
    const bool better =
        (label >= 0 && it->second.first < 0) || ((label >= 0) == (it->second.first >= 0) && c.z() > it->second.second);
    if (better) it->second = {label, c.z()};
  }
  std::map<std::pair<long, long>, int> out;
  for (const auto& [k, v] : best) out[k] = v.first;
  return out;
}

// Expands the renderer's cell paths ("M col row h n v1h-n z" in cell units) back into cells.
std::map<std::pair<long, long>, int> drawnCells(const std::string& svg, std::size_t& rectangles) {
  std::map<std::pair<long, long>, int> cells;
  rectangles = 0;
  // Parsed by hand: <regex> makes GCC 12 at -O1 (the sanitized build) warn -Wmaybe-uninitialized.
  const std::string path_tag = "<path class=\"cells\" data-label=\"";
  for (std::size_t at = svg.find(path_tag); at != std::string::npos; at = svg.find(path_tag, at + 1)) {
    const int label = std::stoi(svg.substr(at + path_tag.size()));
    const std::size_t d_at = svg.find(" d=\"", at);
    const std::size_t tag_end = svg.find('>', at);
    if (d_at == std::string::npos || d_at > tag_end) {
      ADD_FAILURE() << "cell path without d: " << svg.substr(at, 80);
      continue;
    }
    const std::string d = svg.substr(d_at + 4, svg.find('"', d_at + 4) - (d_at + 4));
    const char* p = d.c_str();
    long col = 0, row = 0, n = 0, back = 0;
    int used = 0;
    while (std::sscanf(p, "M%ld %ldh%ldv1h-%ldz%n", &col, &row, &n, &back, &used) == 4) {
      p += used;
      ++rectangles;
      EXPECT_EQ(n, back);
      for (long k = 0; k < n; ++k) {
        EXPECT_TRUE(cells.emplace(std::make_pair(row, col + k), label).second) << "cell drawn twice";
      }
    }
    EXPECT_EQ(*p, '\0') << "unparsed cell path: " << p;
  }
  return cells;
}

// ---------------------------------------------------------------- palette

TEST(PlotPalette, NoiseIsBlackAndFiftyClustersStayApart) {
  EXPECT_EQ(toHex(clusterColour(hullmap::clustering::kNoise)), "#000000");
  EXPECT_EQ(toHex(clusterColour(0)), "#f3c300");  // Kelly's first colour
  const hullmap::plot::Rgb black{0, 0, 0}, white{255, 255, 255};
  std::set<std::string> seen;
  for (int i = 0; i < 50; ++i) {
    const auto c = clusterColour(i);
    EXPECT_TRUE(seen.insert(toHex(c)).second) << "label " << i << " repeats " << toHex(c);
    EXPECT_GT(deltaE(c, black), 35.0) << "label " << i << " " << toHex(c) << " looks like noise";
    EXPECT_GT(deltaE(c, white), 25.0) << "label " << i << " " << toHex(c) << " vanishes on white";
    for (int j = i + 1; j < std::min(50, i + 6); ++j) {
      EXPECT_GT(deltaE(c, clusterColour(j)), i + 1 == j ? 20.0 : 15.0)
          << "labels " << i << " and " << j << ": " << toHex(c) << " " << toHex(clusterColour(j));
    }
  }
  // From label 18 on, lightness cycles through 55, 72, 45 (CIE L*, measured by the test's own
  // sRGB -> Lab; sRGB rounding moves it by well under 1).
  const double lightness[3] = {55.0, 72.0, 45.0};
  for (int label = 18; label < 200; ++label)
    EXPECT_NEAR(toLab(clusterColour(label))[0], lightness[(label - 18) % 3], 1.0) << "label " << label;
}

// ---------------------------------------------------------------- map rendering

TEST(PlotMap, TopViewIsValidXmlWithOneFootprintPerObstacleAndPaletteColours) {
  if (!havePython())
    GTEST_SKIP() << "no XML parser: " << HULLMAP_PYTHON3 << " not found and libxml2 is not a dependency";
  Scene s = makeScene(12, 0.05, 7);
  ASSERT_EQ(s.plot.obstacles.size(), 12u);
  const auto picture = hullmap::plot::renderMapSvg(s.plot);
  const auto elements = parseSvg(picture.svg, "top");
  EXPECT_EQ(countClass(elements, "footprint"), s.plot.obstacles.size());
  EXPECT_EQ(countClass(elements, "obstacle-id"), s.plot.obstacles.size());
  std::set<std::string> ids;
  for (const auto& e : elements) {
    if (e.cls == "footprint") ids.insert(e.id);
    if (e.cls != "cells") continue;
    const int label = std::stoi(e.label);
    EXPECT_EQ(e.fill, label < 0 ? "#000000" : toHex(clusterColour(label))) << "label " << label;
  }
  for (const auto& o : s.plot.obstacles) EXPECT_TRUE(ids.count("obstacle-" + std::to_string(o.id))) << o.id;
  // One cell path per label present: 12 clusters and the noise.
  EXPECT_EQ(countClass(elements, "cells"), 13u);
  EXPECT_EQ(picture.hidden_voxels, 2u);  // the gross outliers do not squash the picture
  EXPECT_NE(picture.svg.find("eps = 0.1, minPts = 10"), std::string::npos);
  EXPECT_NE(picture.svg.find("map units"), std::string::npos);
  EXPECT_EQ(countClass(elements, "scale-bar"), 1u);
}

TEST(PlotMap, KeyframesAndTheFloorsOutlineAreDrawn) {
  Scene s = makeScene(3, 0.05, 9);
  // A floor of 20 x 12 voxels under the scene, at its own label (pipeline's kFloorLabel, -2).
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 12; ++j) {
      s.plot.centers.emplace_back((10 + i + 0.5) * 0.05, (2 + j + 0.5) * 0.05, -0.025);
      s.plot.labels.push_back(-2);
    }
  for (int k = 0; k < 7; ++k) s.plot.keyframes.emplace_back(0.3 + 0.2 * k, 0.9, 1.2);
  const std::string without = hullmap::plot::renderMapSvg(s.plot).svg;
  EXPECT_EQ(without.find("floor-outline"), std::string::npos) << "no outline without floor_label";
  s.plot.floor_label = -2;
  const std::string svg = hullmap::plot::renderMapSvg(s.plot).svg;
  std::size_t keyframes = 0;
  for (auto at = svg.find("class=\"keyframe\""); at != std::string::npos; at = svg.find("class=\"keyframe\"", at + 1))
    ++keyframes;
  EXPECT_EQ(keyframes, 7u);
  EXPECT_NE(svg.find("<g class=\"trajectory\""), std::string::npos);
  EXPECT_NE(svg.find("keyframe trajectory (dashed purple): 7 keyframes"), std::string::npos);
  EXPECT_NE(svg.find("floor (light brown cells, dashed outline): 240 voxels"), std::string::npos);
  EXPECT_NE(svg.find("data-label=\"-2\" fill=\"#ddd3bb\""), std::string::npos) << "floor cells, not black";
  // The outline is the rectangle around the floor's cells: 4 corners, 20 x 12 voxels.
  const auto at = svg.find("<polygon class=\"floor-outline\" points=\"");
  ASSERT_NE(at, std::string::npos);
  const auto start = svg.find("points=\"", at) + 8;
  std::istringstream points(svg.substr(start, svg.find('"', start) - start));
  std::vector<std::pair<double, double>> corners;
  std::string pair;
  while (points >> pair) {
    const auto comma = pair.find(',');
    corners.emplace_back(std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1)));
  }
  ASSERT_EQ(corners.size(), 4u);
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const auto& [x, y] : corners) {
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  EXPECT_NEAR((x1 - x0) / (y1 - y0), 20.0 / 12.0, 0.05);
}

TEST(PlotMap, EachTopCellDrawnOnceWithItsTopmostClusteredVoxel) {
  Scene s = makeScene(10, 0.1, 3);
  // A noise voxel above a cluster must not hide it; a higher cluster voxel hides a lower one.
  s.plot.centers.emplace_back(0.45, 0.45, 5.05);
  s.plot.labels.push_back(-1);
  s.plot.centers.emplace_back(0.45, 0.45, 0.05);
  s.plot.labels.push_back(9);
  s.plot.centers.emplace_back(0.45, 0.45, 0.25);
  s.plot.labels.push_back(3);
  const auto picture = hullmap::plot::renderMapSvg(s.plot);
  const auto expected = expectedTopCells(s.plot);
  std::size_t rectangles = 0;
  const auto drawn = drawnCells(picture.svg, rectangles);
  EXPECT_EQ(drawn, expected);
  EXPECT_EQ(drawn.at({4, 4}), 3);
  EXPECT_EQ(picture.cells, expected.size());
  EXPECT_LT(rectangles, expected.size());  // runs merged
}

TEST(PlotMap, HundredThousandVoxelsGiveASmallFile) {
  // 100k voxels on the walls and boxes of a 20 m room at 5 cm, as a SLAM map looks.
  MapPlot plot;
  plot.voxel_size = 0.05;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 20.0), h(0.0, 3.0);
  const auto snap = [](double v) { return (std::floor(v / 0.05) + 0.5) * 0.05; };
  while (plot.centers.size() < 100000) {
    const int wall = static_cast<int>(plot.centers.size() % 5);
    const double a = u(rng);
    Eigen::Vector3d p = wall == 0   ? Eigen::Vector3d(a, 0.0, h(rng))
                        : wall == 1 ? Eigen::Vector3d(a, 20.0, h(rng))
                        : wall == 2 ? Eigen::Vector3d(0.0, a, h(rng))
                        : wall == 3 ? Eigen::Vector3d(20.0, a, h(rng))
                                    : Eigen::Vector3d(std::fmod(a, 4.0) + 8.0, std::fmod(u(rng), 4.0) + 8.0, h(rng));
    plot.centers.emplace_back(snap(p.x()), snap(p.y()), snap(p.z()));
    plot.labels.push_back(wall == 4 && p.x() > 9.0 ? -1 : wall);
  }
  const auto picture = hullmap::plot::renderMapSvg(plot);
  EXPECT_EQ(picture.cells, expectedTopCells(plot).size());
  EXPECT_LT(picture.svg.size(), 300u * 1024u) << picture.cells << " cells";
}

TEST(PlotMap, SideViewShowsHeightsAndOutlinesEachHull) {
  if (!havePython()) GTEST_SKIP() << "no XML parser: " << HULLMAP_PYTHON3 << " not found";
  Scene s = makeScene(5, 0.05, 11);
  s.plot.view = PlotView::kSide;
  const auto picture = hullmap::plot::renderMapSvg(s.plot);
  const auto elements = parseSvg(picture.svg, "side");
  EXPECT_EQ(countClass(elements, "footprint"), s.plot.obstacles.size());
  EXPECT_NE(picture.svg.find("z (map units)"), std::string::npos);
  EXPECT_NE(picture.svg.find("side view (x-z)"), std::string::npos);
  // Side cells are keyed by (z, x): cluster 0 spans 2 voxel layers, so 2 rows of cells exist at x0.
  std::size_t rectangles = 0;
  const auto drawn = drawnCells(picture.svg, rectangles);
  EXPECT_TRUE(drawn.count({0, 4}) && drawn.count({1, 4}));
}

TEST(PlotMap, PathMarksCollidingSegmentsAndFirstContact) {
  if (!havePython()) GTEST_SKIP() << "no XML parser: " << HULLMAP_PYTHON3 << " not found";
  Scene s = makeScene(3, 0.05, 5);
  hullmap::plot::PlotPath path;
  path.waypoints = {{0.0, 0.0, 0.1}, {1.0, 0.3, 0.1}, {2.0, 0.3, 0.1}, {2.0, 2.0, 0.1}};
  path.radius = 0.1;
  path.check.segments.resize(3);
  path.check.segments[1].collides = true;
  path.check.segments[1].obstacle = 1;
  path.check.segments[1].t = 0.2;
  path.check.segments[2].collides = true;
  path.check.first_colliding_segment = 1;
  path.check.first_contact = Eigen::Vector3d(1.2, 0.3, 0.1);
  s.plot.paths = {path};
  const auto picture = hullmap::plot::renderMapSvg(s.plot);
  const auto elements = parseSvg(picture.svg, "path");
  EXPECT_EQ(countClass(elements, "colliding-segment"), 2u);
  EXPECT_EQ(countClass(elements, "first-contact"), 1u);
  EXPECT_EQ(countClass(elements, "waypoint"), 4u);
  EXPECT_NE(picture.svg.find("first contact at (1.2, 0.3, 0.1) on segment 1"), std::string::npos);

  path.check.segments.pop_back();  // inconsistent with the waypoints
  s.plot.paths = {path};
  EXPECT_THROW(hullmap::plot::renderMapSvg(s.plot), hullmap::Error);
}

TEST(PlotMap, BadInputIsAnError) {
  MapPlot plot;
  plot.voxel_size = 0.0;
  EXPECT_THROW(hullmap::plot::renderMapSvg(plot), hullmap::Error);
  plot.voxel_size = 0.1;
  plot.centers.emplace_back(0, 0, 0);
  EXPECT_THROW(hullmap::plot::renderMapSvg(plot), hullmap::Error);
  plot.labels.push_back(0);
  EXPECT_NO_THROW(hullmap::plot::renderMapSvg(plot));
}

// ---------------------------------------------------------------- sweep

TEST(PlotSweep, OnePanelPerRunInAnEpsByMinPtsGrid) {
  if (!havePython()) GTEST_SKIP() << "no XML parser: " << HULLMAP_PYTHON3 << " not found";
  Scene s = makeScene(6, 0.05, 2);
  std::vector<hullmap::plot::SweepPanel> panels;
  for (int min_pts : {5, 10}) {
    for (double eps : {0.05, 0.1, 0.3}) {
      hullmap::plot::SweepPanel p{eps, min_pts, s.plot.labels};
      if (eps > 0.2) std::fill(p.labels.begin(), p.labels.end(), 0);  // one big cluster
      panels.push_back(p);
    }
  }
  const std::string svg = hullmap::plot::renderSweepSvg(s.plot.centers, panels, 0.0, "sweep");
  const auto elements = parseSvg(svg, "sweep");
  EXPECT_EQ(countClass(elements, "panel"), 6u);
  EXPECT_NE(svg.find("data-eps=\"0.3\" data-min-pts=\"10\" data-clusters=\"1\""), std::string::npos);
  EXPECT_NE(svg.find("data-eps=\"0.05\" data-min-pts=\"5\" data-clusters=\"6\""), std::string::npos);
  for (const auto& e : elements) {
    if (e.cls == "cells") {
      EXPECT_EQ(e.fill, toHex(clusterColour(std::stoi(e.label))));
    }
  }
  panels[2].labels.pop_back();
  EXPECT_THROW(hullmap::plot::renderSweepSvg(s.plot.centers, panels, 0.0, "sweep"), hullmap::Error);
}

// ---------------------------------------------------------------- output files

TEST(PlotOutput, MissingConverterNamesThePackageAndWritesNothing) {
  const auto dir = hullmap::test::freshDir("plot_noconv");
  EXPECT_FALSE(hullmap::plot::findProgram("rsvg-convert", dir.string()));
  try {
    hullmap::plot::writePicture("<svg/>", {(dir / "map.png").string(), false, "-o"}, std::nullopt);
    FAIL() << "expected hullmap::Error";
  } catch (const hullmap::Error& e) {
    EXPECT_NE(std::string(e.what()).find("librsvg2-bin"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("map.png"), std::string::npos) << e.what();
  }
  EXPECT_THROW(hullmap::plot::writePicture("<svg/>", {(dir / "map.svg").string(), true, "-o"}, std::nullopt),
               hullmap::Error);
  EXPECT_TRUE(fs::is_empty(dir));
  // findProgram takes the first executable match in PATH order.
  const auto bin = dir / "bin";
  fs::create_directories(bin);
  std::ofstream(bin / "rsvg-convert") << "#!/bin/sh\n";
  fs::permissions(bin / "rsvg-convert", fs::perms::owner_all);
  EXPECT_EQ(hullmap::plot::findProgram("rsvg-convert", "/nonexistent::" + bin.string()),
            (bin / "rsvg-convert").string());
}

// ---------------------------------------------------------------- the subcommand

}  // namespace
