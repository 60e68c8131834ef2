#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "hullmap/clustering/cluster_extension.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "metric_distance.hpp"

namespace hullmap::clustering {
namespace {

using Points = std::vector<Eigen::Vector3d>;
using Weights = std::vector<std::uint32_t>;

using hullmap::test::squaredDistance;

/// The documented rounds by brute force, O(n^2) a round: density of every point against all
/// points, then each round every dense noise point looks at every point labelled before the round.
DbscanResult oracleExtension(const Points& points, const Weights& weights, DbscanResult r,
                             const ClusterExtensionParams& params, ClusterExtension& out) {
  const std::size_t n = points.size();
  std::vector<bool> dense(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t w = 0;
    for (std::size_t j = 0; j < n; ++j)
      if (squaredDistance(points[i], points[j], params.metric) <= params.eps * params.eps)
        w += weights.empty() ? 1 : weights[j];
    dense[i] = w >= std::uint64_t(params.min_pts);
  }
  out = {};
  for (;;) {
    const std::vector<std::int32_t> before = r.labels;
    std::size_t joined = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (before[i] != kNoise || !dense[i]) continue;
      double best = params.reach * params.reach;
      int best_j = -1;
      for (std::size_t j = 0; j < n; ++j) {
        if (before[j] == kNoise || !dense[j]) continue;
        const double d = squaredDistance(points[i], points[j], params.metric);
        if (d < best || (d == best && best_j < 0)) {
          best = d;
          best_j = int(j);
        }
      }
      if (best_j < 0) continue;
      r.labels[i] = before[std::size_t(best_j)];
      ++r.cluster_sizes[std::size_t(r.labels[i])];
      --r.noise;
      ++joined;
    }
    if (joined == 0) break;
    out.joined += joined;
    ++out.rounds;
  }
  return r;
}

/// Checks extendClusters against the oracle; returns what the oracle did (so that a test can tell
/// that its inputs exercise joins and chains, not only the empty case).
ClusterExtension expectSameAsOracle(const Points& points, const Weights& weights, const DbscanParams& dbscan_params,
                                    const ClusterExtensionParams& params) {
  SCOPED_TRACE(::testing::Message() << points.size() << " points, eps " << params.eps << ", min_pts " << params.min_pts
                                    << ", reach " << params.reach << ", " << toString(params.metric));
  const DbscanResult first = dbscan(points, weights, dbscan_params);
  ClusterExtension expected_out;
  const DbscanResult expected = oracleExtension(points, weights, first, params, expected_out);
  DbscanResult got = first;
  const ClusterExtension out = extendClusters(points, weights, got, params);
  EXPECT_EQ(got.labels, expected.labels);
  EXPECT_EQ(got.cluster_sizes, expected.cluster_sizes);
  EXPECT_EQ(got.noise, expected.noise);
  EXPECT_EQ(got.core, first.core);
  EXPECT_EQ(out.joined, expected_out.joined);
  EXPECT_EQ(out.rounds, expected_out.rounds);
  return expected_out;
}

/// Dense blobs, sparse chains hanging off them (a table's legs) and uniform outliers.
Points blobsChainsAndOutliers(std::uint32_t seed, std::size_t outliers) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> g(0.0, 0.03);
  Points points;
  for (int b = 0; b < 3; ++b) {
    const Eigen::Vector3d c(u(rng), u(rng), u(rng));
    for (int i = 0; i < 60; ++i) points.push_back(c + Eigen::Vector3d(g(rng), g(rng), g(rng)));
    Eigen::Vector3d step(u(rng), u(rng), u(rng));
    step *= 0.12 / step.norm();
    for (int k = 1; k <= 6; ++k) {
      const Eigen::Vector3d at = c + 1.2 * double(k) * step;
      for (int i = 0; i < 1 + int(rng() % 3); ++i) points.push_back(at + 0.2 * Eigen::Vector3d(g(rng), g(rng), g(rng)));
    }
  }
  for (std::size_t i = 0; i < outliers; ++i) points.emplace_back(2 * u(rng), 2 * u(rng), 2 * u(rng));
  std::shuffle(points.begin(), points.end(), rng);
  return points;
}

TEST(ClusterExtension, MatchesOracleOnBlobsChainsAndOutliers) {
  std::size_t joined = 0, longest = 0;
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const Points points = blobsChainsAndOutliers(seed, 80);
    for (int min_pts : {1, 2, 3}) {
      for (double reach : {0.1, 0.15, 0.3}) {
        for (const auto& o : {expectSameAsOracle(points, {}, DbscanParams{0.1, 12, Metric::kXyz},
                                                 ClusterExtensionParams{0.1, min_pts, reach, Metric::kXyz}),
                              expectSameAsOracle(points, {}, DbscanParams{0.1, 20, Metric::kXy},
                                                 ClusterExtensionParams{0.1, min_pts, reach, Metric::kXy})}) {
          joined += o.joined;
          longest = std::max(longest, o.rounds);
        }
      }
    }
  }
  EXPECT_GT(joined, 100u);
  EXPECT_GE(longest, 3u);
}

TEST(ClusterExtension, MatchesOracleWithWeights) {
  for (std::uint32_t seed = 7; seed <= 10; ++seed) {
    const Points points = blobsChainsAndOutliers(seed, 60);
    std::mt19937 rng(seed);
    Weights weights(points.size());
    for (auto& w : weights) w = 1 + rng() % 4;
    expectSameAsOracle(points, weights, DbscanParams{0.1, 30, Metric::kXyz},
                       ClusterExtensionParams{0.1, 4, 0.15, Metric::kXyz});
    expectSameAsOracle(points, weights, DbscanParams{0.1, 30, Metric::kXy},
                       ClusterExtensionParams{0.12, 3, 0.2, Metric::kXy});
  }
}

TEST(ClusterExtension, MatchesOracleOnALatticeWithExactTies) {
  // Integer lattice coordinates: many points at exactly eps and exactly reach, and equally near
  // clustered points of two clusters (the lower index wins).
  std::mt19937 rng(3);
  Points points;
  for (int x = 0; x < 12; ++x)
    for (int y = 0; y < 5; ++y)
      if (rng() % 3 != 0) points.emplace_back(x, y, rng() % 2);
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 3; ++y)
      for (int z = 0; z < 2; ++z) {
        points.emplace_back(x, y, z);
        points.emplace_back(x + 9, y, z);
      }
  for (double reach : {1.0, 2.0, 3.0}) {
    for (int min_pts : {2, 3, 4}) {
      expectSameAsOracle(points, {}, DbscanParams{1.0, 8, Metric::kXyz},
                         ClusterExtensionParams{1.0, min_pts, reach, Metric::kXyz});
      expectSameAsOracle(points, {}, DbscanParams{1.0, 12, Metric::kXy},
                         ClusterExtensionParams{1.0, min_pts, reach, Metric::kXy});
    }
  }
}

// A cluster with a sparse chain leading off it (a table leg: pairs of points 0.3 apart, 0.12
// between pairs), a lone point beside the cluster, and a dense group that no cluster reaches.
TEST(ClusterExtension, ChainsJoinLonePointsAndUnreachedGroupsDoNot) {
  Points points;
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y) points.emplace_back(0.05 * x, 0.05 * y, 1.0);  // core blob at z = 1
  const std::size_t chain_begin = points.size();
  for (int k = 1; k <= 4; ++k) {  // pairs going down from the blob, 0.12 apart
    points.emplace_back(0.0, 0.0, 1.0 - 0.12 * k);
    points.emplace_back(0.03, 0.0, 1.0 - 0.12 * k);
  }
  const std::size_t lone = points.size();
  points.emplace_back(0.5, 0.0, 1.0);  // 0.35 beside the blob's corner at (0.15, 0, 1)
  const std::size_t group = points.size();
  for (int k = 0; k < 3; ++k) points.emplace_back(3.0 + 0.02 * k, 0.0, 0.0);  // far, dense
  const DbscanResult first = dbscan(points, {}, DbscanParams{0.1, 9, Metric::kXyz});
  ASSERT_EQ(first.cluster_sizes.size(), 1u);
  for (std::size_t i = chain_begin; i < points.size(); ++i) ASSERT_EQ(first.labels[i], kNoise) << i;

  DbscanResult r = first;
  const ClusterExtension out = extendClusters(points, {}, r, ClusterExtensionParams{0.1, 2, 0.4, Metric::kXyz});
  for (std::size_t i = chain_begin; i < lone; ++i) EXPECT_EQ(r.labels[i], 0) << i;
  EXPECT_EQ(r.labels[lone], kNoise);  // alone within eps: never dense at min_pts 2
  for (std::size_t i = group; i < points.size(); ++i) EXPECT_EQ(r.labels[i], kNoise) << i;  // no new cluster
  EXPECT_EQ(out.joined, lone - chain_begin);
  EXPECT_EQ(out.rounds, 2u);  // pairs 1 to 3 lie within 0.4 of the blob, pair 4 of pair 3
  EXPECT_EQ(r.cluster_sizes[0], 16 + (lone - chain_begin));
  EXPECT_EQ(r.noise, first.noise - out.joined);

  // reach just above the pairs' spacing: one pair a round, down the chain.
  DbscanResult step = first;
  const ClusterExtension steps = extendClusters(points, {}, step, ClusterExtensionParams{0.1, 2, 0.125, Metric::kXyz});
  EXPECT_EQ(steps.rounds, 4u);
  EXPECT_EQ(steps.joined, lone - chain_begin);
  // min_pts 3: the pairs are not dense, nothing joins.
  DbscanResult none = first;
  EXPECT_EQ(extendClusters(points, {}, none, ClusterExtensionParams{0.1, 3, 0.4, Metric::kXyz}).joined, 0u);
  EXPECT_EQ(none.labels, first.labels);
}

TEST(ClusterExtension, NeverMergesOrRelabelsClusters) {
  // Two dense blobs 1.0 apart, joined by dense noise: every noise point joins its nearer blob.
  Points points;
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 3; ++y) {
      points.emplace_back(0.02 * x, 0.02 * y, 0.0);
      points.emplace_back(1.0 + 0.02 * x, 0.02 * y, 0.0);
    }
  for (int k = 1; k < 10; ++k) {
    points.emplace_back(0.02 + 0.1 * k, 0.02, 0.0);
    points.emplace_back(0.02 + 0.1 * k, 0.03, 0.0);
  }
  const DbscanResult first = dbscan(points, {}, DbscanParams{0.05, 9, Metric::kXyz});
  ASSERT_EQ(first.cluster_sizes.size(), 2u);
  DbscanResult r = first;
  extendClusters(points, {}, r, ClusterExtensionParams{0.12, 2, 0.12, Metric::kXyz});
  EXPECT_EQ(r.cluster_sizes.size(), 2u);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (first.labels[i] != kNoise) {
      EXPECT_EQ(r.labels[i], first.labels[i]) << i;
    }
    ASSERT_NE(r.labels[i], kNoise) << i;
    // Point 0 is the first blob's, point 1 the second's; the middle pair (x 0.52) may go either way.
    if (points[i].x() < 0.5) {
      EXPECT_EQ(r.labels[i], first.labels[0]) << i << " at x " << points[i].x();
    } else if (points[i].x() > 0.55) {
      EXPECT_EQ(r.labels[i], first.labels[1]) << i << " at x " << points[i].x();
    }
  }
}

TEST(ClusterExtension, SameResultWithOneAndTwoThreadsAndGrossOutliers) {
  Points points;
  for (std::uint32_t seed = 20; seed < 40; ++seed) {
    Points part = blobsChainsAndOutliers(seed, 200);
    for (auto& p : part) p += Eigen::Vector3d(5.0 * (seed % 5), 5.0 * (seed / 5 % 4), 0.0);
    points.insert(points.end(), part.begin(), part.end());
  }
  for (int k = 0; k < 5; ++k)
    points.emplace_back(1e6 * (k + 1), 0.0, -1e15 * k);  // beyond the clamped cells (2^50 x 0.15)
  const DbscanResult first = dbscan(points, {}, DbscanParams{0.1, 12, Metric::kXyz});
  const ClusterExtensionParams params{0.1, 2, 0.15, Metric::kXyz};
  DbscanResult one = first, two = first;
  ClusterExtension by_one, by_two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    by_one = extendClusters(points, {}, one, params);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    by_two = extendClusters(points, {}, two, params);
  }
  EXPECT_GT(by_one.joined, 50u);
  EXPECT_EQ(by_one.joined, by_two.joined);
  EXPECT_EQ(by_one.rounds, by_two.rounds);
  EXPECT_EQ(one.labels, two.labels);
  EXPECT_EQ(one.cluster_sizes, two.cluster_sizes);
}

TEST(ClusterExtension, NoClusterNoNoiseAndEmpty) {
  Points points{{0, 0, 0}, {0.01, 0, 0}, {0.02, 0, 0}};
  DbscanResult none = dbscan(points, {}, DbscanParams{0.05, 10, Metric::kXyz});
  ASSERT_TRUE(none.cluster_sizes.empty());
  const DbscanResult before = none;
  EXPECT_EQ(extendClusters(points, {}, none, ClusterExtensionParams{0.05, 2, 1.0, Metric::kXyz}).joined, 0u);
  EXPECT_EQ(none.labels, before.labels);  // dense, but no cluster to join: stays noise
  DbscanResult all = dbscan(points, {}, DbscanParams{0.05, 2, Metric::kXyz});
  EXPECT_EQ(extendClusters(points, {}, all, ClusterExtensionParams{0.05, 2, 1.0, Metric::kXyz}).rounds, 0u);
  DbscanResult empty = dbscan({}, {}, DbscanParams{});
  EXPECT_EQ(extendClusters({}, {}, empty, ClusterExtensionParams{}).joined, 0u);
}

TEST(ClusterExtension, RejectsBadInput) {
  const Points points{{0, 0, 0}, {1, 0, 0}};
  const DbscanResult good = dbscan(points, {}, DbscanParams{0.5, 1, Metric::kXyz});
  auto parameterOf = [&](const Points& p, const Weights& w, DbscanResult r, const ClusterExtensionParams& params) {
    try {
      extendClusters(p, w, r, params);
    } catch (const Error& e) {
      return e.parameter();
    }
    return std::string("no error");
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(parameterOf(points, {}, good, {0.0, 2, 1.0, Metric::kXyz}), "eps");
  EXPECT_EQ(parameterOf(points, {}, good, {nan, 2, 1.0, Metric::kXyz}), "eps");
  EXPECT_EQ(parameterOf(points, {}, good, {0.5, 0, 1.0, Metric::kXyz}), "min_pts");
  EXPECT_EQ(parameterOf(points, {}, good, {0.5, 2, 0.4, Metric::kXyz}), "reach");
  EXPECT_EQ(parameterOf(points, {}, good, {0.5, 2, nan, Metric::kXyz}), "reach");
  EXPECT_EQ(parameterOf(points, {1}, good, {0.5, 2, 1.0, Metric::kXyz}), "weights");
  EXPECT_EQ(parameterOf(points, {1, 0}, good, {0.5, 2, 1.0, Metric::kXyz}), "weights");
  EXPECT_EQ(parameterOf({{0, 0, 0}, {nan, 0, 0}}, {}, good, {0.5, 2, 1.0, Metric::kXyz}), "points");
  DbscanResult short_labels = good;
  short_labels.labels.pop_back();
  EXPECT_EQ(parameterOf(points, {}, short_labels, {0.5, 2, 1.0, Metric::kXyz}), "labels");
  DbscanResult bad_label = good;
  bad_label.labels[0] = std::int32_t(good.cluster_sizes.size());
  EXPECT_EQ(parameterOf(points, {}, bad_label, {0.5, 2, 1.0, Metric::kXyz}), "labels");
  bad_label.labels[0] = -2;
  EXPECT_EQ(parameterOf(points, {}, bad_label, {0.5, 2, 1.0, Metric::kXyz}), "labels");
}

TEST(ClusterExtension, PipelineRuleFromTheDbscanParameters) {
  const ClusterExtensionRule rule;
  auto made = [&](double eps, int min_pts) { return extensionParams(DbscanParams{eps, min_pts, Metric::kXy}, rule); };
  EXPECT_EQ(made(0.4, 7).min_pts, 2);   // floor(2.1)
  EXPECT_EQ(made(0.4, 6).min_pts, 2);   // floor(1.8) = 1, raised to min_min_pts
  EXPECT_EQ(made(0.3, 16).min_pts, 4);  // floor(4.8)
  EXPECT_EQ(made(0.3, 10).min_pts, 3);  // 0.3 * 10 is 3 within rounding
  EXPECT_EQ(made(0.3, 1).min_pts, 2);
  EXPECT_DOUBLE_EQ(made(0.4, 7).reach, 0.6);
  EXPECT_DOUBLE_EQ(made(0.4, 7).eps, 0.4);
  EXPECT_EQ(made(0.4, 7).metric, Metric::kXy);
  auto parameterOf = [](const ClusterExtensionRule& r, double eps = 0.1) {
    try {
      extensionParams(DbscanParams{eps, 5, Metric::kXyz}, r);
    } catch (const Error& e) {
      return e.parameter();
    }
    return std::string("no error");
  };
  EXPECT_EQ(parameterOf(ClusterExtensionRule{0.0, 1.5, 2}), "min_pts_factor");
  EXPECT_EQ(parameterOf(ClusterExtensionRule{1.5, 1.5, 2}), "min_pts_factor");
  EXPECT_EQ(parameterOf(ClusterExtensionRule{0.3, 0.9, 2}), "reach_factor");
  EXPECT_EQ(parameterOf(ClusterExtensionRule{0.3, 1.5, 0}), "min_min_pts");
  EXPECT_EQ(parameterOf(ClusterExtensionRule{}, 0.0), "eps");
  EXPECT_EQ(parameterOf(ClusterExtensionRule{}), "no error");
}

}  // namespace
}  // namespace hullmap::clustering
