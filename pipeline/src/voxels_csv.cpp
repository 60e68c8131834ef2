// voxels.csv: every occupied voxel with its weight, label and core flag.
#include "hullmap/pipeline/voxels_csv.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::pipeline {

namespace fs = std::filesystem;

void writeVoxelsCsv(const fs::path& path, const std::vector<mapper::OccupiedVoxel>& voxels,
                    const clustering::DbscanResult& clusters) {
  // Formatted with std::to_chars, which writes a double at precision 9 as printf's %.9g (and so as an
  // ostream at setprecision(9)) does, about ten times faster: this file is the longest output of a build.
  std::string text = "x,y,z,weight,label,core\n";
  text.reserve(text.size() + voxels.size() * 64);
  const auto put = [&](auto value, char after, auto... format) {
    char field[32];  // a double at precision 9 takes at most 16, an int 11
    text.append(field, std::to_chars(field, field + sizeof field, value, format...).ptr);
    text.push_back(after);
  };
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    const auto& v = voxels[i];
    for (const double x : {v.center.x(), v.center.y(), v.center.z()}) put(x, ',', std::chars_format::general, 9);
    put(v.weight, ',');
    put(clusters.labels[i], ',');
    put(int(clusters.core[i]), '\n');
  }
  core::writeFileAtomically(path.string(),
                            [&](std::ostream& os) { os.write(text.data(), std::streamsize(text.size())); });
}

std::vector<VoxelRow> readVoxelsCsv(const fs::path& path) {
  const std::string name = path.string();
  std::ifstream in(path);
  if (!in) throw Error(name + ": cannot open (is this a hullmap build directory?)");
  std::string line;
  if (!std::getline(in, line) || line.rfind("x,y,z,weight,label", 0) != 0) {
    throw Error(name + ":1: expected header x,y,z,weight,label,core");
  }
  std::vector<VoxelRow> rows;
  std::size_t number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line == "\r") continue;
    std::istringstream fields(line);
    double v[6] = {0, 0, 0, 0, 0, 0};
    char comma = 0;
    bool ok = static_cast<bool>(fields >> v[0]);
    for (int i = 1; ok && i < 5; ++i) ok = (fields >> comma) && comma == ',' && (fields >> v[i]);
    if (ok && (fields >> comma)) ok = comma == ',' && (fields >> v[5]);
    if (!ok || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      throw Error(name + ":" + std::to_string(number) + ": expected x,y,z,weight,label,core numbers");
    }
    VoxelRow row;
    row.center = Eigen::Vector3d(v[0], v[1], v[2]);
    row.weight = static_cast<std::uint32_t>(v[3]);
    row.label = static_cast<std::int32_t>(v[4]);
    row.core = v[5] != 0.0;
    rows.push_back(row);
  }
  return rows;
}

}  // namespace hullmap::pipeline
