#pragma once
// Helpers shared by clustering/dbscan.cpp, clustering/heavy/dbscan.cpp, e2e/cluster.cpp.

#include <gtest/gtest.h>
#include <tbb/global_control.h>
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

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "metric_distance.hpp"
#include "test_support.hpp"

namespace hullmap::clustering {

namespace {
using Points = std::vector<Eigen::Vector3d>;
using Weights = std::vector<std::uint32_t>;
using hullmap::test::squaredDistance;

/// The checks that hold for any correct DBSCAN, whatever its border rule: same core flags, same noise
/// set, same partition of the core points, every border point in a cluster with a core point within eps.
inline void expectDbscanAgrees(const Points& points, const DbscanParams& params, const DbscanResult& got,
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
inline void expectWellFormed(const DbscanResult& r) {
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

/// Gaussian blobs plus uniform background, in a box of side `extent`.
inline Points blobs(std::uint32_t seed, std::size_t n, double extent, int blob_count, double sigma) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, extent);
  std::normal_distribution<double> gauss(0.0, sigma);
  std::vector<Eigen::Vector3d> centers;
  for (int b = 0; b < blob_count; ++b) centers.emplace_back(uniform(rng), uniform(rng), uniform(rng));
  Points points;
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 5 == 4 || centers.empty()) {
      points.emplace_back(uniform(rng), uniform(rng), uniform(rng));
    } else {
      const Eigen::Vector3d& c = centers[i % centers.size()];
      points.emplace_back(c.x() + gauss(rng), c.y() + gauss(rng), c.z() + gauss(rng));
    }
  }
  return points;
}

}  // namespace
}  // namespace hullmap::clustering
