// clustering::buildWarnings and hullCheckWarnings: which outcomes speak, at the limits, with which
// codes and numbers.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "hullmap/clustering/auto_params.hpp"
#include "hullmap/clustering/build_warnings.hpp"

using hullmap::Warning;
using hullmap::warningText;
using hullmap::clustering::buildWarnings;
using hullmap::clustering::ClusteringOutcome;
using hullmap::clustering::hullCheckWarnings;

TEST(BuildWarnings, NoiseShareNoObstacleAndEpsBelowResolution) {
  ClusteringOutcome ok{100, 50, 3, 0.1, 10, hullmap::clustering::Metric::kXyz, 0.05};
  EXPECT_TRUE(buildWarnings(ok).empty()) << "exactly half is not most";
  EXPECT_TRUE(hullCheckWarnings(ok).empty());
  ClusteringOutcome noisy = ok;
  noisy.noise_voxels = 51;
  ASSERT_EQ(buildWarnings(noisy).size(), 1u);
  EXPECT_EQ(buildWarnings(noisy)[0].code, Warning::Code::kMostlyNoise);
  EXPECT_EQ(buildWarnings(noisy)[0].number("noise_voxels"), 51.0);
  EXPECT_EQ(buildWarnings(noisy)[0].number("occupied_voxels"), 100.0);
  EXPECT_EQ(warningText(buildWarnings(noisy)[0]).rfind("51% of the occupied voxels (51 of 100)", 0), 0u);
  ASSERT_EQ(hullCheckWarnings(noisy).size(), 1u);
  EXPECT_EQ(hullCheckWarnings(noisy)[0].code, Warning::Code::kCheckMostlyNoise);
  ClusteringOutcome none = ok;
  none.noise_voxels = 100;
  none.obstacles = 0;
  ASSERT_EQ(buildWarnings(none).size(), 1u) << "no obstacle says it all";
  EXPECT_EQ(buildWarnings(none)[0].code, Warning::Code::kNoObstacle);
  EXPECT_EQ(warningText(buildWarnings(none)[0])
                .rfind("no obstacle: all 100 occupied voxels are noise to DBSCAN "
                       "(eps=0.1, min_pts=10)",
                       0),
            0u);
  ClusteringOutcome small_eps = ok;
  small_eps.eps = 0.04;
  ASSERT_EQ(buildWarnings(small_eps).size(), 1u);
  EXPECT_EQ(buildWarnings(small_eps)[0].code, Warning::Code::kEpsBelowResolution);
  EXPECT_EQ(
      warningText(buildWarnings(small_eps)[0]).rfind("eps=0.04 is below the octree resolution 0.05: no two voxels", 0),
      0u);
  small_eps.metric = hullmap::clustering::Metric::kXy;
  EXPECT_EQ(buildWarnings(small_eps)[0].code, Warning::Code::kEpsBelowResolutionInColumns);
  EXPECT_NE(warningText(buildWarnings(small_eps)[0]).find("only voxels in one vertical column"), std::string::npos);
  ClusteringOutcome equal = ok;
  equal.eps = 0.05;
  EXPECT_TRUE(buildWarnings(equal).empty()) << "eps = resolution: face neighbours join";
  ClusteringOutcome empty_map{};
  EXPECT_TRUE(buildWarnings(empty_map).empty());
  ASSERT_EQ(hullCheckWarnings(empty_map).size(), 1u) << "no obstacle, voxels unknown";
  EXPECT_EQ(hullCheckWarnings(empty_map)[0].code, Warning::Code::kCheckNoObstacle);
  EXPECT_EQ(warningText(hullCheckWarnings(empty_map)[0]).rfind("the build has no obstacle: every path is clear", 0),
            0u);
}

// The resolution suggested for a sparse map: rounded down to 1, 2 or 5 x 10^n.
TEST(BuildWarnings, SuggestedResolutionsAreOneTwoOrFiveTimesAPowerOfTen) {
  using hullmap::clustering::roundResolution;
  EXPECT_DOUBLE_EQ(roundResolution(0.344), 0.2);
  EXPECT_DOUBLE_EQ(roundResolution(0.3), 0.2);
  EXPECT_DOUBLE_EQ(roundResolution(0.05), 0.05);
  EXPECT_DOUBLE_EQ(roundResolution(0.1), 0.1);
  EXPECT_DOUBLE_EQ(roundResolution(0.14), 0.1);
  EXPECT_DOUBLE_EQ(roundResolution(0.19), 0.1);
  EXPECT_DOUBLE_EQ(roundResolution(0.2), 0.2);
  EXPECT_DOUBLE_EQ(roundResolution(0.5), 0.5);
  EXPECT_DOUBLE_EQ(roundResolution(7.5), 5.0);
  EXPECT_DOUBLE_EQ(roundResolution(9.99), 5.0);
  EXPECT_DOUBLE_EQ(roundResolution(10.0), 10.0);
  EXPECT_DOUBLE_EQ(roundResolution(3.2), 2.0);
}

// kSparseForResolution on voxel centres whose 4th nearest neighbour lies beyond the auto rule's
// reach, against the brute-force spacing; none on a dense surface or when the rule found the spacing.
TEST(BuildWarnings, SparseMapsAreToldACoarserResolution) {
  using hullmap::clustering::AutoParamsRule;
  using hullmap::clustering::chooseDbscanParams;
  using hullmap::clustering::sparseMapWarning;
  const double resolution = 0.05;
  const AutoParamsRule rule;
  // A plane sampled every 0.8 m (16 voxels), with centres on the voxel lattice.
  std::vector<Eigen::Vector3d> sparse;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) sparse.emplace_back(0.025 + 0.8 * i, 0.025 + 0.8 * j, 0.025);
  const auto chosen = chooseDbscanParams(sparse, {}, resolution, hullmap::clustering::Metric::kXyz, rule);
  ASSERT_FALSE(std::isfinite(chosen.knn)) << "beyond the rule's reach of " << rule.max_eps_voxels << " voxels";
  const auto w = sparseMapWarning(sparse, resolution, chosen, rule, hullmap::clustering::Metric::kXyz);
  ASSERT_TRUE(w.has_value());
  EXPECT_EQ(w->code, Warning::Code::kSparseForResolution);
  // The 4th nearest: two at 0.8, two at 0.8 (a lattice point's four axis neighbours), at the border
  // the diagonal 0.8 sqrt(2); three in four of the sampled points are inside: 0.8.
  EXPECT_NEAR(w->number("spacing"), 0.8, 1e-9);
  EXPECT_DOUBLE_EQ(w->number("resolution"), resolution);
  EXPECT_DOUBLE_EQ(w->number("suggested"), 0.2);  // 0.8 / 2.5 = 0.32, rounded down
  // The same plane every 0.1 m (2 voxels): the rule finds the spacing, nothing to say.
  std::vector<Eigen::Vector3d> dense;
  for (int i = 0; i < 80; ++i)
    for (int j = 0; j < 80; ++j) dense.emplace_back(0.025 + 0.1 * i, 0.025 + 0.1 * j, 0.025);
  const auto dense_chosen = chooseDbscanParams(dense, {}, resolution, hullmap::clustering::Metric::kXyz, rule);
  EXPECT_TRUE(std::isfinite(dense_chosen.knn));
  EXPECT_FALSE(sparseMapWarning(dense, resolution, dense_chosen, rule, hullmap::clustering::Metric::kXyz));
  // A plane every 1 m in voxels of 0.5 m (2 voxels apart): found, no warning.
  std::vector<Eigen::Vector3d> coarse;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) coarse.emplace_back(0.25 + 1.0 * i, 0.25 + 1.0 * j, 0.25);
  const auto coarse_chosen = chooseDbscanParams(coarse, {}, 0.5, hullmap::clustering::Metric::kXyz, rule);
  EXPECT_FALSE(sparseMapWarning(coarse, 0.5, coarse_chosen, rule, hullmap::clustering::Metric::kXyz));
}
