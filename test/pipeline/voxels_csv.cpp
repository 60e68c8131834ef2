// voxels.csv, byte for byte: every coordinate as printf's %.9g writes it (what the file held when an
// ostream at setprecision(9) wrote it), weights, labels and core flags as integers.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/pipeline/voxels_csv.hpp"
#include "test_support.hpp"

namespace {

namespace pipeline = hullmap::pipeline;

TEST(VoxelsCsv, RowsAreThePrintfNineDigitTextOfEachVoxel) {
  std::vector<double> values{0.0,       -0.0,         0.05,        -4.85,
                             0.1 + 0.2, 1.0 / 3.0,    123456789.5, 1e-5,
                             -2.5e-7,   9.99999999e8, 1e21,        1234567890123.0,
                             0.45,      -1e300,       5e-324,      std::numeric_limits<double>::max()};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> spread(-1e4, 1e4);
  for (int k = 0; k < 300; ++k) values.push_back(spread(rng) / double(1 + k % 7));
  std::vector<hullmap::mapper::OccupiedVoxel> voxels;
  hullmap::clustering::DbscanResult clusters;
  for (std::size_t i = 0; i + 2 < values.size(); ++i) {
    hullmap::mapper::OccupiedVoxel v;
    v.center = {values[i], values[i + 1], values[i + 2]};
    v.weight = i == 0 ? std::numeric_limits<std::uint32_t>::max() : std::uint32_t(i * 7919);
    voxels.push_back(v);
    clusters.labels.push_back(i % 5 == 0 ? hullmap::clustering::kNoise : std::int32_t(i) * (i % 2 ? 1 : -1));
    clusters.core.push_back(std::uint8_t(i % 3 == 0));
  }
  const auto file = hullmap::test::freshDir("voxels_csv_text") / "voxels.csv";
  pipeline::writeVoxelsCsv(file, voxels, clusters);
  std::ostringstream expected;
  expected << "x,y,z,weight,label,core\n";
  char line[256];
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    const auto& c = voxels[i].center;
    std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g,%u,%d,%d\n", c.x(), c.y(), c.z(), unsigned(voxels[i].weight),
                  int(clusters.labels[i]), int(clusters.core[i]));
    expected << line;
  }
  std::ifstream in(file, std::ios::binary);
  std::stringstream written;
  written << in.rdbuf();
  EXPECT_EQ(written.str(), expected.str());
}

}  // namespace
