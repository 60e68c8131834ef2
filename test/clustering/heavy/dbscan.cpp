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

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "test_support.hpp"
#include "metric_distance.hpp"

namespace hullmap::clustering {
namespace {

using Points = std::vector<Eigen::Vector3d>;
using Weights = std::vector<std::uint32_t>;

using hullmap::test::squaredDistance;

/// The checks that hold for any correct DBSCAN, whatever its border rule: same core flags, same noise
/// set, same partition of the core points, every border point in a cluster with a core point within eps.
void expectDbscanAgrees(const Points& points, const DbscanParams& params, const DbscanResult& got,
                        const std::vector<std::int32_t>& ref_labels, const std::vector<std::uint8_t>& ref_core) {
  const std::size_t n = points.size();
  ASSERT_EQ(got.labels.size(), n);
  ASSERT_EQ(got.core.size(), n);
  std::size_t core_mismatch = 0, noise_mismatch = 0;
  for (std::size_t i = 0; i < n; ++i) {
    core_mismatch += got.core[i] != ref_core[i];
    noise_mismatch += (got.labels[i] == kNoise) != (ref_labels[i] == kNoise);
  }
  EXPECT_EQ(core_mismatch, 0u) << "core flags differ";
  EXPECT_EQ(noise_mismatch, 0u) << "noise sets differ";
  std::map<std::int32_t, std::int32_t> to_ref, from_ref;
  std::size_t partition_mismatch = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!got.core[i] || !ref_core[i]) continue;
    const auto [a, inserted_a] = to_ref.emplace(got.labels[i], ref_labels[i]);
    const auto [b, inserted_b] = from_ref.emplace(ref_labels[i], got.labels[i]);
    partition_mismatch += a->second != ref_labels[i] || b->second != got.labels[i];
  }
  EXPECT_EQ(partition_mismatch, 0u) << "core partitions differ";
  const double eps2 = params.eps * params.eps;
  std::size_t bad_border = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (got.core[i] || got.labels[i] == kNoise) continue;
    bool reachable = false;
    for (std::size_t j = 0; j < n && !reachable; ++j) {
      reachable =
          got.core[j] && got.labels[j] == got.labels[i] && squaredDistance(points[i], points[j], params.metric) <= eps2;
    }
    bad_border += !reachable;
  }
  EXPECT_EQ(bad_border, 0u) << "border points without a core point of their cluster within eps";
}

/// Labels 0..k-1 numbered by first appearance, sizes and noise consistent.
void expectWellFormed(const DbscanResult& r) {
  std::int32_t next = 0;
  std::vector<std::size_t> sizes;
  std::size_t noise = 0;
  for (std::int32_t label : r.labels) {
    if (label == kNoise) {
      ++noise;
      continue;
    }
    ASSERT_GE(label, 0);
    ASSERT_LE(label, next) << "cluster numbered before an earlier one appeared";
    if (label == next) {
      ++next;
      sizes.push_back(0);
    }
    ++sizes[label];
  }
  EXPECT_EQ(r.cluster_sizes, sizes);
  EXPECT_EQ(r.noise, noise);
}

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

/// Runs test/clustering_sklearn_dbscan.py; false (with `why`) when scikit-learn cannot be run.
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
  command << "'" << python << "' '" << HULLMAP_SOURCE_DIR << "/test/clustering_sklearn_dbscan.py' '" << file << "' "
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
