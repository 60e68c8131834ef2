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

/// Ester et al.'s DBSCAN by brute force, O(n^2), with the documented border and numbering rules:
/// a border point joins the cluster of its nearest core point (ties: the first in the input), and
/// clusters are numbered by their first point in the input.
DbscanResult oracleDbscan(const Points& points, const Weights& weights, const DbscanParams& params) {
  const std::size_t n = points.size();
  const double eps2 = params.eps * params.eps;
  const auto weight = [&](std::size_t i) -> std::uint64_t { return weights.empty() ? 1 : weights[i]; };
  const auto near = [&](std::size_t i, std::size_t j) {
    return squaredDistance(points[i], points[j], params.metric) <= eps2;
  };
  DbscanResult r;
  r.core.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t w = 0;
    for (std::size_t j = 0; j < n; ++j) w += near(i, j) ? weight(j) : 0;
    r.core[i] = w >= std::uint64_t(params.min_pts);
  }
  std::vector<int> component(n, -1);
  int components = 0;
  for (std::size_t s = 0; s < n; ++s) {
    if (!r.core[s] || component[s] >= 0) continue;
    std::vector<std::size_t> stack{s};
    component[s] = components;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      for (std::size_t j = 0; j < n; ++j) {
        if (r.core[j] && component[j] < 0 && near(i, j)) {
          component[j] = components;
          stack.push_back(j);
        }
      }
    }
    ++components;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (r.core[i]) continue;
    double best = eps2;
    int best_j = -1;
    for (std::size_t j = 0; j < n; ++j) {
      if (!r.core[j]) continue;
      const double d = squaredDistance(points[i], points[j], params.metric);
      if (d < best || (d == best && best_j < 0)) {
        best = d;
        best_j = int(j);
      }
    }
    component[i] = best_j < 0 ? -1 : component[best_j];
  }
  std::vector<int> number(components, -1);
  r.labels.assign(n, kNoise);
  for (std::size_t i = 0; i < n; ++i) {
    if (component[i] < 0) {
      ++r.noise;
      continue;
    }
    if (number[component[i]] < 0) {
      number[component[i]] = int(r.cluster_sizes.size());
      r.cluster_sizes.push_back(0);
    }
    r.labels[i] = number[component[i]];
    ++r.cluster_sizes[r.labels[i]];
  }
  return r;
}

void expectSameAsOracle(const Points& points, const Weights& weights, const DbscanParams& params) {
  const DbscanResult got = dbscan(points, weights, params);
  const DbscanResult ref = oracleDbscan(points, weights, params);
  expectWellFormed(got);
  expectDbscanAgrees(points, params, got, ref.labels, ref.core);
  // The documented border and numbering rules make the whole result unique.
  EXPECT_EQ(got.labels, ref.labels);
  EXPECT_EQ(got.core, ref.core);
  EXPECT_EQ(got.cluster_sizes, ref.cluster_sizes);
  EXPECT_EQ(got.noise, ref.noise);
}

TEST(Dbscan, MatchesOracleOnRandomBlobs) {
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const Points points = blobs(seed, 1500, 2.0, 4 + int(seed), 0.08);
    for (const auto& [eps, min_pts] : {std::pair{0.05, 4}, {0.1, 10}, {0.13, 15}, {0.3, 35}, {0.07, 2}}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + " eps " + std::to_string(eps) + " minPts " +
                   std::to_string(min_pts));
      expectSameAsOracle(points, {}, DbscanParams{eps, min_pts, Metric::kXyz});
    }
  }
}

TEST(Dbscan, MatchesOracleWithGroundPlaneMetric) {
  for (std::uint32_t seed = 11; seed <= 14; ++seed) {
    Points points = blobs(seed, 1200, 2.0, 5, 0.06);
    // Spread z: in the ground plane these points are still close.
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> z(-50.0, 50.0);
    for (std::size_t i = 0; i < points.size(); i += 3) points[i].z() = z(rng);
    SCOPED_TRACE("seed " + std::to_string(seed));
    expectSameAsOracle(points, {}, DbscanParams{0.08, 6, Metric::kXy});
    expectSameAsOracle(points, {}, DbscanParams{0.15, 20, Metric::kXy});
  }
}

TEST(Dbscan, MatchesOracleWithWeights) {
  for (std::uint32_t seed = 21; seed <= 24; ++seed) {
    const Points points = blobs(seed, 1000, 2.0, 6, 0.1);
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<std::uint32_t> w(1, 9);
    Weights weights(points.size());
    for (auto& x : weights) x = w(rng);
    SCOPED_TRACE("seed " + std::to_string(seed));
    expectSameAsOracle(points, weights, DbscanParams{0.08, 25, Metric::kXyz});
    expectSameAsOracle(points, weights, DbscanParams{0.1, 12, Metric::kXy});
  }
}

TEST(Dbscan, MatchesOracleWithDuplicates) {
  Points points = blobs(31, 400, 1.0, 3, 0.05);
  const Points copy = points;
  for (std::size_t i = 0; i < copy.size(); i += 2) points.push_back(copy[i]);
  for (int k = 0; k < 30; ++k) points.push_back(copy[7]);  // one heavy duplicate stack
  std::shuffle(points.begin(), points.end(), std::mt19937_64(31));
  expectSameAsOracle(points, {}, DbscanParams{0.05, 5, Metric::kXyz});
  expectSameAsOracle(points, {}, DbscanParams{0.02, 3, Metric::kXyz});
  // Only duplicates of one point: one cluster when there are enough of them.
  const Points stack(12, Eigen::Vector3d(0.3, -2.0, 7.0));
  expectSameAsOracle(stack, {}, DbscanParams{0.1, 12, Metric::kXyz});
  expectSameAsOracle(stack, {}, DbscanParams{0.1, 13, Metric::kXyz});
}

TEST(Dbscan, PointsAtExactlyEpsAreNeighbours) {
  // A lattice of spacing 0.5 with eps 0.5: every axis neighbour is at exactly eps (exact in binary).
  Points lattice;
  for (int x = 0; x < 6; ++x)
    for (int y = 0; y < 5; ++y)
      for (int z = 0; z < 4; ++z) lattice.emplace_back(0.5 * x - 1.0, 0.5 * y + 3.0, 0.5 * z);
  for (int min_pts = 2; min_pts <= 8; ++min_pts) {
    SCOPED_TRACE("minPts " + std::to_string(min_pts));
    expectSameAsOracle(lattice, {}, DbscanParams{0.5, min_pts, Metric::kXyz});
    expectSameAsOracle(lattice, {}, DbscanParams{0.5, min_pts, Metric::kXy});
  }
  // Interior points have 7 neighbours (self + 6 at exactly eps), corners 4: with 7, only interior is core.
  const DbscanResult r = dbscan(lattice, {}, DbscanParams{0.5, 7, Metric::kXyz});
  std::size_t cores = std::count(r.core.begin(), r.core.end(), 1);
  EXPECT_EQ(cores, std::size_t(4 * 3 * 2));
  // A chain of points 0.25 apart with eps 0.25: one cluster; eps just below 0.25: all noise.
  Points chain;
  for (int i = 0; i < 40; ++i) chain.emplace_back(0.25 * i, 0.0, 0.0);
  EXPECT_EQ(dbscan(chain, {}, DbscanParams{0.25, 3, Metric::kXyz}).cluster_sizes, std::vector<std::size_t>{40});
  EXPECT_EQ(dbscan(chain, {}, DbscanParams{std::nextafter(0.25, 0.0), 2, Metric::kXyz}).noise, 40u);
  expectSameAsOracle(chain, {}, DbscanParams{0.25, 3, Metric::kXyz});
}

TEST(Dbscan, AllNoiseAndOneCluster) {
  Points sparse;
  for (int i = 0; i < 300; ++i) sparse.emplace_back(i * 1.0, (i * 7) % 13 * 1.0, 0.0);
  const DbscanResult noise = dbscan(sparse, {}, DbscanParams{0.5, 2, Metric::kXyz});
  EXPECT_EQ(noise.noise, sparse.size());
  EXPECT_TRUE(noise.cluster_sizes.empty());
  expectSameAsOracle(sparse, {}, DbscanParams{0.5, 2, Metric::kXyz});

  const Points blob = blobs(41, 800, 1.0, 1, 0.02);
  Points dense(blob.begin(), blob.end());
  dense.erase(
      std::remove_if(dense.begin(), dense.end(), [&](const Eigen::Vector3d& p) { return (p - blob[0]).norm() > 0.1; }),
      dense.end());
  const DbscanResult one = dbscan(dense, {}, DbscanParams{0.3, 5, Metric::kXyz});
  EXPECT_EQ(one.cluster_sizes, std::vector<std::size_t>{dense.size()});
  EXPECT_EQ(one.noise, 0u);
  expectSameAsOracle(dense, {}, DbscanParams{0.3, 5, Metric::kXyz});
}

TEST(Dbscan, BorderPointReachableFromTwoClusters) {
  // p at the origin is within eps (0.5) of core a (cluster A, left) and core b (cluster B, right),
  // has 3 neighbours (< minPts 4) and so is a border point. A and B are 1.0 apart: two clusters.
  const auto scene = [](double ax, double bx) {
    Points pts;
    pts.emplace_back(bx, 0.0, 0.0);                                        // b: first in the input
    pts.emplace_back(ax, 0.0, 0.0);                                        // a
    pts.emplace_back(0.0, 0.0, 0.0);                                       // p
    for (double y : {-0.1, 0.0, 0.1}) pts.emplace_back(ax - 0.4, y, 0.0);  // a's other neighbours
    for (double y : {-0.1, 0.0, 0.1}) pts.emplace_back(bx + 0.4, y, 0.0);  // b's other neighbours
    return pts;
  };
  for (Metric metric : {Metric::kXyz, Metric::kXy}) {
    const DbscanParams params{0.5, 4, metric};
    // Equally near: the core point first in the input (b) decides.
    const Points tie = scene(-0.5, 0.5);
    const DbscanResult r = dbscan(tie, {}, params);
    ASSERT_EQ(r.cluster_sizes.size(), 2u);
    EXPECT_EQ(r.core[2], 0);
    EXPECT_EQ(r.labels[2], r.labels[0]);
    EXPECT_EQ(r.labels[0], 0);
    EXPECT_EQ(r.labels[1], 1);
    expectSameAsOracle(tie, {}, params);
    // b nearer: b's cluster; then a nearer: a's cluster.
    const Points nearer_b = scene(-0.5, 0.25);
    EXPECT_EQ(dbscan(nearer_b, {}, params).labels[2], 0);
    expectSameAsOracle(nearer_b, {}, params);
    const Points nearer_a = scene(-0.375, 0.5);
    EXPECT_EQ(dbscan(nearer_a, {}, params).labels[2], 1);
    expectSameAsOracle(nearer_a, {}, params);
  }
}

TEST(Dbscan, FarApartClustersWithGrossOutliers) {
  Points points = blobs(51, 900, 1.0, 3, 0.03);
  const Points second = blobs(52, 900, 1.0, 3, 0.03);
  for (const auto& p : second) points.push_back(p + Eigen::Vector3d(5000.0, -3000.0, 20.0));
  for (double s : {1e6, -1e6, 7.5e5}) {
    points.emplace_back(s, 0.0, 0.0);
    points.emplace_back(0.0, s, -s);
    points.emplace_back(s, s, s);
  }
  std::shuffle(points.begin(), points.end(), std::mt19937_64(53));
  expectSameAsOracle(points, {}, DbscanParams{0.05, 5, Metric::kXyz});
  expectSameAsOracle(points, {}, DbscanParams{0.05, 5, Metric::kXy});
  // Tiny eps against a huge extent: 64-bit keys, no dense grid.
  expectSameAsOracle(points, {}, DbscanParams{1e-4, 2, Metric::kXyz});
}

TEST(Dbscan, NegativeCoordinatesAndCellBoundaries) {
  // Points straddling zero and cell edges, on a lattice of 1/8 with eps 0.25.
  Points points;
  std::mt19937_64 rng(61);
  std::uniform_int_distribution<int> cell(-12, 12);
  for (int i = 0; i < 900; ++i) points.emplace_back(cell(rng) * 0.125, cell(rng) * 0.125, cell(rng) * 0.125);
  for (int min_pts : {2, 5, 9}) {
    expectSameAsOracle(points, {}, DbscanParams{0.25, min_pts, Metric::kXyz});
    expectSameAsOracle(points, {}, DbscanParams{0.25, min_pts, Metric::kXy});
  }
}

TEST(Dbscan, EmptyAndSinglePoint) {
  const DbscanResult empty = dbscan({}, {}, DbscanParams{});
  EXPECT_TRUE(empty.labels.empty());
  EXPECT_TRUE(empty.cluster_sizes.empty());
  EXPECT_EQ(empty.noise, 0u);
  const Points one{Eigen::Vector3d(1.0, 2.0, 3.0)};
  const DbscanResult alone = dbscan(one, {}, DbscanParams{0.1, 1, Metric::kXyz});
  EXPECT_EQ(alone.labels, std::vector<std::int32_t>{0});
  EXPECT_EQ(alone.core, std::vector<std::uint8_t>{1});
  const DbscanResult noise = dbscan(one, {}, DbscanParams{0.1, 2, Metric::kXyz});
  EXPECT_EQ(noise.labels, std::vector<std::int32_t>{kNoise});
  EXPECT_EQ(noise.noise, 1u);
  // Its weight alone can make it core.
  EXPECT_EQ(dbscan(one, {5}, DbscanParams{0.1, 5, Metric::kXyz}).labels, std::vector<std::int32_t>{0});
  expectSameAsOracle(one, {}, DbscanParams{0.1, 2, Metric::kXyz});
}

TEST(Dbscan, SameResultWithOneAndTwoThreads) {
  Points points = blobs(71, 60000, 4.0, 40, 0.1);
  for (int k = 0; k < 5; ++k) points.emplace_back(1e6 * (k + 1), 0.0, 0.0);
  const DbscanParams params{0.1, 10, Metric::kXyz};
  DbscanResult one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = dbscan(points, {}, params);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = dbscan(points, {}, params);
  }
  EXPECT_GT(one.cluster_sizes.size(), 1u);
  EXPECT_EQ(one.labels, two.labels);
  EXPECT_EQ(one.core, two.core);
  EXPECT_EQ(one.cluster_sizes, two.cluster_sizes);
}

TEST(Dbscan, RejectsBadParameters) {
  const Points points{Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()};
  EXPECT_THROW(dbscan(points, {}, DbscanParams{0.0, 10, Metric::kXyz}), Error);
  EXPECT_THROW(dbscan(points, {}, DbscanParams{-1.0, 10, Metric::kXyz}), Error);
  EXPECT_THROW(dbscan(points, {}, DbscanParams{0.1, 0, Metric::kXyz}), Error);
  EXPECT_THROW(dbscan(points, {1}, DbscanParams{}), Error);
  EXPECT_THROW(dbscan(points, {1, 0}, DbscanParams{}), Error);
  const Points nan{Eigen::Vector3d(0.0, std::nan(""), 0.0)};
  EXPECT_THROW(dbscan(nan, {}, DbscanParams{}), Error);
  EXPECT_THROW(parseMetric("xz"), Error);
  EXPECT_EQ(parseMetric("xy"), Metric::kXy);
  EXPECT_EQ(parseMetric(toString(Metric::kXyz)), Metric::kXyz);
  try {
    dbscan(points, {}, DbscanParams{0.0, 10, Metric::kXyz});
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("eps"), std::string::npos) << e.what();
  }
}

TEST(KDistance, MatchesBruteForce) {
  const Points points = blobs(81, 700, 1.0, 4, 0.05);
  for (Metric metric : {Metric::kXyz, Metric::kXy}) {
    for (int min_pts : {1, 2, 5, 11}) {
      std::vector<double> ref;
      for (std::size_t i = 0; i < points.size(); ++i) {
        std::vector<double> d;
        for (std::size_t j = 0; j < points.size(); ++j) {
          if (j != i) d.push_back(std::sqrt(squaredDistance(points[i], points[j], metric)));
        }
        std::sort(d.begin(), d.end());
        ref.push_back(min_pts == 1 ? 0.0 : d[min_pts - 2]);
      }
      std::sort(ref.rbegin(), ref.rend());
      EXPECT_EQ(kDistanceCurve(points, min_pts, metric), ref) << "minPts " << min_pts;
    }
  }
  EXPECT_TRUE(kDistanceCurve(Points(3, Eigen::Vector3d::Zero()), 4, Metric::kXyz).empty());
  EXPECT_TRUE(kDistanceCurve(Points(3, Eigen::Vector3d::Zero()), 4, Metric::kXyz, 2).empty());
  EXPECT_EQ(kDistanceCurve(Points(4, Eigen::Vector3d::Zero()), 4, Metric::kXyz), std::vector<double>(4, 0.0));
  EXPECT_THROW(kDistanceCurve(points, 0, Metric::kXyz), Error);
}

// A sampled curve holds the exact k-distances (against every point, duplicates counting) of the points
// kDistanceSample picks, evenly spread over the input.
TEST(KDistance, SampledCurveMatchesBruteForceOnTheSample) {
  Points points = blobs(82, 600, 1.0, 3, 0.05);
  for (std::size_t i = 0; i < 40; ++i) points.push_back(points[i * 7]);  // duplicates
  const std::vector<std::uint32_t> sample = kDistanceSample(points.size(), 97);
  ASSERT_EQ(sample.size(), 97u);
  EXPECT_EQ(sample.front(), 0u);
  EXPECT_LT(sample.back(), points.size());
  EXPECT_TRUE(std::is_sorted(sample.begin(), sample.end()));
  EXPECT_GE(sample.back(), points.size() - points.size() / 97 - 1);  // spread to the end
  EXPECT_EQ(kDistanceSample(50, 97).size(), 50u);
  EXPECT_EQ(kDistanceSample(50, 0).size(), 50u);
  for (Metric metric : {Metric::kXyz, Metric::kXy}) {
    for (int min_pts : {2, 6, 10}) {
      std::vector<double> ref;
      for (const std::uint32_t i : sample) {
        std::vector<double> d;
        for (std::size_t j = 0; j < points.size(); ++j) {
          if (j != i) d.push_back(std::sqrt(squaredDistance(points[i], points[j], metric)));
        }
        std::sort(d.begin(), d.end());
        ref.push_back(d[min_pts - 2]);
      }
      std::sort(ref.rbegin(), ref.rend());
      EXPECT_EQ(kDistanceCurve(points, min_pts, metric, 97), ref) << "minPts " << min_pts;
    }
  }
}

/// Core distances of `sample` by brute force, sorted descending: for each sampled point, the smallest
/// r such that the points within r (itself included) weigh at least min_pts. Empty when all points
/// together weigh less than min_pts.
std::vector<double> oracleCoreDistances(const Points& points, const Weights& weights, int min_pts, Metric metric,
                                        const std::vector<std::uint32_t>& sample) {
  const auto weight = [&](std::size_t i) -> std::uint64_t { return weights.empty() ? 1 : weights[i]; };
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < points.size(); ++i) total += weight(i);
  if (total < std::uint64_t(min_pts)) return {};
  std::vector<double> curve;
  for (const std::uint32_t i : sample) {
    std::vector<std::pair<double, std::uint64_t>> by_distance;
    for (std::size_t j = 0; j < points.size(); ++j) {
      by_distance.emplace_back(squaredDistance(points[i], points[j], metric), weight(j));
    }
    std::sort(by_distance.begin(), by_distance.end());
    std::uint64_t held = 0;
    for (const auto& [d2, w] : by_distance) {
      held += w;
      if (held >= std::uint64_t(min_pts)) {
        curve.push_back(std::sqrt(d2));
        break;
      }
    }
  }
  std::sort(curve.rbegin(), curve.rend());
  return curve;
}

// dbscan() with a KDistanceRequest answers the sample's core distances on its own grid. Against brute
// force, to the bit: eps far below the spacing (most queries leave the 3^d cells around their own, the
// search over groups of cells decides), eps near it and far above it; gross outliers (isolated
// points, every group a candidate), duplicates, weights, both metrics. The labels are plain dbscan()'s.
TEST(KDistance, DbscanGridCurveMatchesBruteForce) {
  Points points = blobs(83, 500, 3.0, 4, 0.06);
  for (std::size_t i = 0; i < 30; ++i) points.push_back(points[i * 11]);  // duplicates
  points.emplace_back(5e4, -3e4, 1e3);                                    // gross outliers
  points.emplace_back(-7e5, 2e5, 9e4);
  points.emplace_back(40.0, 40.0, 40.0);
  Weights weights(points.size());
  for (std::size_t i = 0; i < weights.size(); ++i) weights[i] = 1 + std::uint32_t(i % 4);
  for (Metric metric : {Metric::kXyz, Metric::kXy}) {
    for (const double eps : {0.004, 0.05, 0.4}) {
      for (const int min_pts : {1, 2, 6, 11}) {
        for (const std::size_t samples : {std::size_t{0}, std::size_t{97}}) {
          SCOPED_TRACE("metric " + toString(metric) + " eps " + std::to_string(eps) + " minPts " +
                       std::to_string(min_pts) + " samples " + std::to_string(samples));
          const std::vector<std::uint32_t> sample = kDistanceSample(points.size(), samples);
          const DbscanParams params{eps, min_pts, metric};
          const DbscanResult got = dbscan(points, {}, params, KDistanceRequest{samples});
          EXPECT_EQ(got.k_distance_curve, oracleCoreDistances(points, {}, min_pts, metric, sample));
          EXPECT_EQ(got.k_distance_curve, kDistanceCurve(points, min_pts, metric, samples));
          const DbscanResult plain = dbscan(points, {}, params);
          EXPECT_EQ(got.labels, plain.labels);
          EXPECT_EQ(got.core, plain.core);
          EXPECT_TRUE(plain.k_distance_curve.empty());
          const DbscanResult weighted = dbscan(points, weights, params, KDistanceRequest{samples});
          EXPECT_EQ(weighted.k_distance_curve, oracleCoreDistances(points, weights, min_pts, metric, sample));
          EXPECT_EQ(weighted.labels, dbscan(points, weights, params).labels);
        }
      }
    }
  }
  // Fewer than min_pts in weight: no curve; exactly min_pts: zeros when all coincide.
  const Points three(3, Eigen::Vector3d::Zero());
  EXPECT_TRUE(dbscan(three, {}, DbscanParams{0.1, 4}, KDistanceRequest{}).k_distance_curve.empty());
  EXPECT_EQ(dbscan(three, {1, 1, 2}, DbscanParams{0.1, 4}, KDistanceRequest{}).k_distance_curve,
            std::vector<double>(3, 0.0));
  EXPECT_TRUE(dbscan(Points{}, {}, DbscanParams{0.1, 4}, KDistanceRequest{}).k_distance_curve.empty());
}

TEST(KDistance, SuggestsTheKnee) {
  EXPECT_EQ(suggestEps({}), 0.0);
  EXPECT_EQ(suggestEps({0.3}), 0.3);
  // 1000 values: 5 gross outliers, a steep drop over 95 values, then a flat tail at ~0.1.
  std::vector<double> curve;
  for (int i = 0; i < 5; ++i) curve.push_back(1e6);
  for (int i = 0; i < 95; ++i) curve.push_back(2.0 - 1.9 * i / 94.0);
  for (int i = 0; i < 900; ++i) curve.push_back(0.1 - 0.05 * i / 899.0);
  const double eps = suggestEps(curve);
  EXPECT_GT(eps, 0.09);
  EXPECT_LT(eps, 0.2);
}

// ---- scikit-learn on real SLAM maps ----

// ---- hullmap cluster / hullmap sweep ----

}  // namespace
}  // namespace hullmap::clustering
