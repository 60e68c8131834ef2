#include <algorithm>
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
#include <tbb/global_control.h>

#include "dbscan_fixtures.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "metric_distance.hpp"
#include "test_support.hpp"

namespace hullmap::clustering {
namespace {

// ---- scikit-learn on real SLAM maps ----

/// Reads `x y z` (or `x, y, z`) lines; lines that do not start with a number (headers) are skipped.
Points readXyz(const std::string& path) {
  std::ifstream in(path);
  Points points;
  std::string line;
  while (std::getline(in, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream s(line);
    double x, y, z;
    if (s >> x >> y >> z) points.emplace_back(x, y, z);
  }
  return points;
}

/// Runs test/clustering/sklearn_dbscan.py; false (with `why`) when scikit-learn cannot be run.
bool sklearnDbscan(const Points& points, const DbscanParams& params, std::vector<std::int32_t>& labels,
                   std::vector<std::uint8_t>& core, std::string& why) {
  const auto dir = test::freshDir("sklearn_dbscan");
  const std::string file = (dir / "points.xyz").string();
  {
    std::ofstream out(file);
    out.precision(17);
    for (const auto& p : points) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  }
  const std::string python = HULLMAP_PYTHON3;
  if (python.empty()) {
    why = "no /usr/bin/python3";
    return false;
  }
  std::ostringstream command;
  command.precision(17);
  command << "'" << python << "' '" << HULLMAP_SOURCE_DIR << "/test/clustering/sklearn_dbscan.py' '" << file << "' "
          << params.eps << ' ' << params.min_pts << ' ' << toString(params.metric) << " 2>&1";
  FILE* pipe = popen(command.str().c_str(), "r");
  if (!pipe) {
    why = "popen failed";
    return false;
  }
  std::string output;
  char buffer[4096];
  while (std::size_t got = fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, got);
  const int status = pclose(pipe);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 3) {
    why = output;
    return false;
  }
  EXPECT_EQ(status, 0) << output;
  std::istringstream s(output);
  int label, c;
  while (s >> label >> c) {
    labels.push_back(label);
    core.push_back(std::uint8_t(c));
  }
  return true;
}

void expectSameAsSklearn(const Points& points, const DbscanParams& params) {
  SCOPED_TRACE("eps " + std::to_string(params.eps) + " minPts " + std::to_string(params.min_pts) + " " +
               toString(params.metric));
  std::vector<std::int32_t> labels;
  std::vector<std::uint8_t> core;
  std::string why;
  if (!sklearnDbscan(points, params, labels, core, why)) GTEST_SKIP() << "scikit-learn: " << why;
  ASSERT_EQ(labels.size(), points.size());
  const DbscanResult got = dbscan(points, {}, params);
  expectWellFormed(got);
  expectDbscanAgrees(points, params, got, labels, core);
  EXPECT_EQ(got.cluster_sizes.size(), std::size_t(*std::max_element(labels.begin(), labels.end()) + 1));
}

TEST(DbscanRealData, MatchesSklearnOnOrbSlam2V101) {
  HULLMAP_REQUIRE_REAL_DATA(path, "orbslam2_euroc_V1_01_MapPoints.txt");
  const Points points = readXyz(path);
  ASSERT_EQ(points.size(), 8704u);
  expectSameAsSklearn(points, DbscanParams{0.1, 10, Metric::kXyz});
  expectSameAsSklearn(points, DbscanParams{0.05, 5, Metric::kXyz});
  expectSameAsSklearn(points, DbscanParams{0.3, 35, Metric::kXyz});
  expectSameAsSklearn(points, DbscanParams{0.13, 15, Metric::kXy});
}

TEST(DbscanRealData, MatchesSklearnOnOrbSlam3Mh01Union) {
  HULLMAP_REQUIRE_REAL_DATA(a, "orbslam3_euroc_MH_01_mono_pointcloud.txt");
  HULLMAP_REQUIRE_REAL_DATA(b, "orbslam3_euroc_MH_01_mono_ref_pointcloud.txt");
  Points points = readXyz(a);
  const Points ref = readXyz(b);
  points.insert(points.end(), ref.begin(), ref.end());
  ASSERT_EQ(points.size(), 12292u);
  expectSameAsSklearn(points, DbscanParams{0.1, 10, Metric::kXyz});
  expectSameAsSklearn(points, DbscanParams{0.2, 5, Metric::kXyz});
  expectSameAsSklearn(points, DbscanParams{0.1, 10, Metric::kXy});
}

// ---- hullmap cluster / hullmap sweep ----

}  // namespace
}  // namespace hullmap::clustering
