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
#include "hullmap/clustering/obstacles.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/plot/svg_plot.hpp"
#include "test_support.hpp"

namespace {

using hullmap::plot::clusterColour;
using hullmap::plot::MapPlot;
using hullmap::plot::PlotView;
using hullmap::plot::toHex;
namespace fs = std::filesystem;

// ---------------------------------------------------------------- helpers

bool havePython() { return fs::exists(HULLMAP_PYTHON3); }

// Runs `python3 script args`, returns stdout; status in `status`.
std::string runPython(const std::string& script, const std::string& args, int& status) {
  const auto dir = hullmap::test::freshDir("plot_py_" + std::to_string(std::hash<std::string>{}(script)));
  const auto file = dir / "script.py";
  std::ofstream(file) << script;
  const std::string command = std::string("'") + HULLMAP_PYTHON3 + "' '" + file.string() + "' " + args + " 2>&1";
  std::string out;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) {
    status = -1;
    return out;
  }
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  const int raw = ::pclose(pipe);
  status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return out;
}

// Parses the SVG with a real XML parser (Python's ElementTree); one line per element that has a
// class: "class<TAB>id<TAB>data-label<TAB>fill".
constexpr const char* kXmlSummary = R"PY(
import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
assert root.tag == '{http://www.w3.org/2000/svg}svg', root.tag
for e in root.iter():
    c = e.get('class')
    if c:
        print('\t'.join([c, e.get('id', ''), e.get('data-label', ''), e.get('fill', '')]))
)PY";

struct XmlElement {
  std::string cls, id, label, fill;
};

// Writes `svg` to a file and parses it; fails the test when the XML is malformed.
std::vector<XmlElement> parseSvg(const std::string& svg, const std::string& name) {
  const auto file = hullmap::test::freshDir("plot_xml_" + name) / "picture.svg";
  std::ofstream(file) << svg;
  int status = 0;
  const std::string out = runPython(kXmlSummary, "'" + file.string() + "'", status);
  EXPECT_EQ(status, 0) << "XML parser rejected the SVG:\n" << out.substr(0, 2000);
  std::vector<XmlElement> elements;
  std::istringstream lines(out);
  std::string line;
  while (std::getline(lines, line)) {
    XmlElement e;
    std::istringstream fields(line);
    std::getline(fields, e.cls, '\t');
    std::getline(fields, e.id, '\t');
    std::getline(fields, e.label, '\t');
    std::getline(fields, e.fill, '\t');
    elements.push_back(e);
  }
  return elements;
}

std::size_t countClass(const std::vector<XmlElement>& elements, const std::string& cls) {
  std::size_t n = 0;
  for (const auto& e : elements) n += e.cls == cls;
  return n;
}

// Decodes a PNG with the Python standard library only (zlib + the five PNG filters) and prints
// "width height non_white count_of_each_colour..." for the colours given as rrggbb arguments.
constexpr const char* kPngCount = R"PY(
import sys, zlib, struct
data = open(sys.argv[1], 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n'
pos, idat = 8, b''
while pos < len(data):
    n, kind = struct.unpack('>I4s', data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b'IHDR':
        w, h, depth, ctype = struct.unpack('>IIBB', body[:10])
    elif kind == b'IDAT':
        idat += body
    pos += 12 + n
assert depth == 8 and ctype in (2, 6), (depth, ctype)
bpp = 3 if ctype == 2 else 4
raw = zlib.decompress(idat)
stride = w * bpp
prev = bytearray(stride)
rows = []
for y in range(h):
    f = raw[y * (stride + 1)]
    line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for i in range(stride):
        a = line[i - bpp] if i >= bpp else 0
        b = prev[i]
        c = prev[i - bpp] if i >= bpp else 0
        if f == 1: line[i] = (line[i] + a) & 255
        elif f == 2: line[i] = (line[i] + b) & 255
        elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
        elif f == 4:
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    rows.append(line)
    prev = line
targets = [tuple(int(t[i:i + 2], 16) for i in (0, 2, 4)) for t in sys.argv[2:]]
counts = [0] * len(targets)
non_white = 0
for line in rows:
    for x in range(w):
        px = tuple(line[x * bpp:x * bpp + 3])
        if bpp == 4 and line[x * bpp + 3] == 0:
            continue
        if px != (255, 255, 255):
            non_white += 1
        for k, t in enumerate(targets):
            if px == t:
                counts[k] += 1
print(w, h, non_white, *counts)
)PY";

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

// A room of voxels: `k` box-shaped clusters of stacked voxels plus scattered noise voxels and two
// far outliers. Labels as DBSCAN would give them.
struct Scene {
  MapPlot plot;
  std::vector<std::uint32_t> weights;
};

Scene makeScene(int clusters, double vs, std::uint64_t seed) {
  Scene s;
  s.plot.voxel_size = vs;
  std::mt19937_64 rng(seed);
  const auto centre = [vs](int i) { return (i + 0.5) * vs; };
  for (int c = 0; c < clusters; ++c) {
    const int x0 = 4 + (c % 8) * 14, y0 = 4 + (c / 8) * 14;
    const int w = 4 + c % 5, d = 3 + c % 4, h = 2 + c % 3;
    for (int i = 0; i < w; ++i)
      for (int j = 0; j < d; ++j)
        for (int k = 0; k < h; ++k) {
          s.plot.centers.emplace_back(centre(x0 + i), centre(y0 + j), centre(k));
          s.plot.labels.push_back(c);
        }
  }
  std::uniform_int_distribution<int> cell(0, 8 * 14 + 4);
  std::uniform_int_distribution<int> level(0, 10);
  for (int n = 0; n < 60; ++n) {
    s.plot.centers.emplace_back(centre(cell(rng)), centre(cell(rng) % (((clusters + 7) / 8) * 14 + 4)),
                                centre(level(rng)));
    s.plot.labels.push_back(hullmap::clustering::kNoise);
  }
  s.plot.centers.emplace_back(centre(40000), centre(3), centre(1));  // gross outliers
  s.plot.labels.push_back(hullmap::clustering::kNoise);
  s.plot.centers.emplace_back(centre(-30000), centre(-30000), centre(1));
  s.plot.labels.push_back(hullmap::clustering::kNoise);
  s.weights.assign(s.plot.centers.size(), 1);
  s.plot.obstacles = hullmap::clustering::buildObstacles(s.plot.centers, s.weights, s.plot.labels, vs);
  s.plot.caption = {"eps = 0.1, minPts = 10, resolution = " + std::to_string(vs)};
  return s;
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

TEST(PlotOutput, PngIsRenderedAndNotBlank) {
  const auto converter = hullmap::plot::findPngConverter();
  if (!converter) GTEST_SKIP() << "rsvg-convert not on PATH (Debian package librsvg2-bin)";
  if (!havePython()) GTEST_SKIP() << "no PNG decoder: " << HULLMAP_PYTHON3 << " not found";
  Scene s = makeScene(4, 0.05, 9);
  const auto dir = hullmap::test::freshDir("plot_png");
  const auto svg = hullmap::plot::renderMapSvg(s.plot).svg;
  const auto written = hullmap::plot::writePicture(svg, {(dir / "map.svg").string(), true, "-o"}, converter);
  ASSERT_EQ(written.size(), 2u);
  EXPECT_TRUE(fs::exists(dir / "map.svg"));
  ASSERT_TRUE(fs::exists(dir / "map.png"));
  int status = 0;
  const std::string out = runPython(kPngCount, "'" + (dir / "map.png").string() + "' 000000 f3c300 875692", status);
  ASSERT_EQ(status, 0) << out;
  std::istringstream fields(out);
  long w = 0, h = 0, non_white = 0, black = 0, first = 0, second = 0;
  fields >> w >> h >> non_white >> black >> first >> second;
  EXPECT_GT(w, 300);
  EXPECT_GT(h, 300);
  EXPECT_GT(non_white, w * h / 50) << out;
  EXPECT_GT(black, 0) << "noise and outlines";
  EXPECT_GT(first, 20) << "cluster 0 in #f3c300";
  EXPECT_GT(second, 20) << "cluster 1 in #875692";

  // PNG only, by extension; nothing else left in the directory.
  const auto only = hullmap::test::freshDir("plot_png_only");
  hullmap::plot::writePicture(svg, {(only / "map.png").string(), false, "-o"}, converter);
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(only)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);
  EXPECT_EQ(hullmap::test::slurp(only / "map.png").substr(1, 3), "PNG");
}

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
