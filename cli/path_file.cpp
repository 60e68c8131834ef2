#include "path_file.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "hullmap/core/error.hpp"
#include "hullmap/io/number_table.hpp"

namespace hullmap::cli {

std::vector<Eigen::Vector3d> readPathFile(const std::string& path) {
  std::vector<Eigen::Vector3d> waypoints;
  for (const auto& r : io::readNumberTable(path, 3, "x y z")) waypoints.emplace_back(r[0], r[1], r[2]);
  if (waypoints.size() < 2) {
    throw Error("--path " + path + ": a path needs at least two waypoints, got " + std::to_string(waypoints.size()) +
                " (one position is the segment x,y,z,x,y,z)");
  }
  return waypoints;
}

std::vector<Eigen::Vector3d> readPlainOrTimedPathFile(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::size_t fields = 0;
  while (fields == 0 && std::getline(in, line)) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    for (char& c : line)
      if (c == ',' || c == '\t') c = ' ';
    std::istringstream words(line);
    for (std::string w; words >> w;) ++fields;
  }
  if (fields != 4) return readPathFile(path);  // readPathFile says what is wrong, if anything
  std::vector<Eigen::Vector3d> waypoints;
  for (const auto& r : io::readNumberTable(path, 4, "t x y z")) waypoints.emplace_back(r[1], r[2], r[3]);
  if (waypoints.size() < 2) {
    throw Error("--path " + path + ": a path needs at least two waypoints, got " + std::to_string(waypoints.size()));
  }
  return waypoints;
}

std::vector<collision::Segment> readSegmentsFile(const std::string& path) {
  std::vector<collision::Segment> segments;
  for (const auto& r : io::readNumberTable(path, 6, "x0 y0 z0 x1 y1 z1"))
    segments.push_back({{r[0], r[1], r[2]}, {r[3], r[4], r[5]}});
  return segments;
}

void checkRadius(double radius) {
  if (radius >= 0 && std::isfinite(radius)) return;
  char buffer[32];
  throw Error("--radius: must be >= 0, got " +
              std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, radius).ptr));
}

}  // namespace hullmap::cli
