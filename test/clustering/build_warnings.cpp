// clustering::buildWarnings and hullCheckWarnings: which outcomes speak, at the limits, with which
// codes and numbers.
#include <gtest/gtest.h>

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
