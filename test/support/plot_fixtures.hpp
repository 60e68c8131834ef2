#pragma once
// Helpers shared by plot/plot.cpp, plot/heavy/plot.cpp, e2e/plot.cpp.

#include <gtest/gtest.h>
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

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/plot/svg_plot.hpp"
#include "test_support.hpp"

namespace {
using hullmap::plot::clusterColour;
using hullmap::plot::MapPlot;
using hullmap::plot::PlotView;
using hullmap::plot::toHex;
namespace fs = std::filesystem;

inline bool havePython() { return fs::exists(HULLMAP_PYTHON3); }

// Runs `python3 script args`, returns stdout; status in `status`.
inline std::string runPython(const std::string& script, const std::string& args, int& status) {
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
inline std::vector<XmlElement> parseSvg(const std::string& svg, const std::string& name) {
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

inline std::size_t countClass(const std::vector<XmlElement>& elements, const std::string& cls) {
  std::size_t n = 0;
  for (const auto& e : elements) n += e.cls == cls;
  return n;
}

// A room of voxels: `k` box-shaped clusters of stacked voxels plus scattered noise voxels and two
// far outliers. Labels as DBSCAN would give them.
struct Scene {
  MapPlot plot;
  std::vector<std::uint32_t> weights;
};

inline Scene makeScene(int clusters, double vs, std::uint64_t seed) {
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
  s.plot.obstacles = hullmap::hulls::buildObstacles(s.plot.centers, s.weights, s.plot.labels, vs);
  s.plot.caption = {"eps = 0.1, minPts = 10, resolution = " + std::to_string(vs)};
  return s;
}

}  // namespace
