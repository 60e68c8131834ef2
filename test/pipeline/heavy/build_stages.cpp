// The stages issue 13 adds to the build (align, floor, auto eps/minPts, convex parts with known free
// space) on a generated room in ORB-SLAM's frame at a monocular scale, and their bad inputs.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "build_stages_fixtures.hpp"
#include "hullmap/clustering/auto_params.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/pipeline/report.hpp"
#include "hullmap/sim/evaluate.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace {

namespace pipeline = hullmap::pipeline;
namespace mapper = hullmap::mapper;

TEST(PipelineStages, BuildFromPointsRunsTheSameStages) {
  const Room room = writeRoom("stages_memory", 8);
  pipeline::BuildParams params = alignedBuild(room);
  const pipeline::BuildResult file = pipeline::build(params);
  const pipeline::BuildResult memory = pipeline::buildFromPoints(room.scene.points, params);
  ASSERT_TRUE(memory.report.alignment);
  EXPECT_EQ(memory.report.alignment->transform.scale, file.report.alignment->transform.scale);
  EXPECT_EQ(memory.voxels.size(), file.voxels.size());
  EXPECT_EQ(memory.report.floor.voxels, file.report.floor.voxels);
  EXPECT_EQ(memory.report.cluster_params.used.eps, file.report.cluster_params.used.eps);
  EXPECT_EQ(memory.obstacles.size(), file.obstacles.size());
  ASSERT_TRUE(memory.report.parts);
  EXPECT_EQ(memory.report.parts->parts, file.report.parts->parts);
}

// The coplanar merge after the extension: in generated room 4 at 30 points per m^2 (the 10 m room of
// bench/quality_scan.py's seed 4, held out of QUALITY.md), a stretch of a wall's foot is a DBSCAN
// cluster of its own, and the wall's two halves around it could not merge (the wall in 3 hulls);
// joined to the wall, every wall is 2 hulls at most.
TEST(PipelineStages, CoplanarMergeJoinsAWallsFootToTheWall) {
  const Room room = writeRoom("stages_coplanar", 4, 10.0, 8, 30.0);
  const pipeline::BuildResult r = pipeline::build(alignedBuild(room));
  const auto& cp = r.report.cluster_params;
  ASSERT_TRUE(cp.coplanar_params);
  EXPECT_DOUBLE_EQ(cp.coplanar_params->reach, cp.used.eps);
  EXPECT_DOUBLE_EQ(cp.coplanar_params->thickness, 3.0 * r.map.resolution());
  EXPECT_GE(cp.coplanar.merged, 1u);
  EXPECT_EQ(r.clusters.cluster_sizes.size(), r.obstacles.size());
  const nlohmann::json report = pipeline::reportJson(r);
  EXPECT_EQ(report["clustering"]["coplanar_merge"]["merged"].get<std::size_t>(), cp.coplanar.merged);

  const hullmap::sim::Evaluation e = score(r, room, 200);
  for (const auto& t : e.truth)
    if (t.label.rfind("wall ", 0) == 0) {
      EXPECT_LE(t.parts.size(), 2u) << t.label;
    }
  EXPECT_EQ(e.missed, 0u);

  // Without the extension (minPts given) neither pass runs: DBSCAN's clusters as they are.
  pipeline::BuildParams plain = alignedBuild(room);
  plain.min_pts = cp.used.min_pts;
  const pipeline::BuildResult p = pipeline::build(plain);
  EXPECT_FALSE(p.report.cluster_params.coplanar_params);
  EXPECT_EQ(p.report.cluster_params.coplanar.merged, 0u);
}

// The extension after DBSCAN only adds noise voxels to the clusters plain DBSCAN found: same
// clusters, none new, no clustered voxel relabelled; and on a sparse room with tables it brings
// their legs' points inside the hulls.
// The extension pass: the extension grows DBSCAN's clusters, then the outlier trim takes back to
// noise only clustered voxels that are not core and have no other voxel within its radius, and the
// stray-part rule (convex parts) the voxels of the parts it drops.
TEST(PipelineStages, ExtensionOnlyGrowsClustersAndOffIsPlainDbscan) {
  const Room room = writeRoom("stages_extension", 3, 6.0, 6, 30.0);
  pipeline::BuildParams params = alignedBuild(room);
  const pipeline::BuildResult grown = pipeline::build(params);
  params.extension = false;
  const pipeline::BuildResult plain = pipeline::build(params);

  ASSERT_TRUE(grown.report.cluster_params.extension_params);
  EXPECT_FALSE(plain.report.cluster_params.extension_params);
  EXPECT_EQ(plain.report.cluster_params.extension.joined, 0u);
  const auto& used = grown.report.cluster_params.used;
  EXPECT_EQ(used.eps, plain.report.cluster_params.used.eps);
  EXPECT_EQ(used.min_pts, plain.report.cluster_params.used.min_pts);
  const auto& ext = *grown.report.cluster_params.extension_params;
  EXPECT_EQ(ext.min_pts, std::max(2, int(0.3 * used.min_pts + 1e-9)));
  EXPECT_DOUBLE_EQ(ext.reach, 1.5 * used.eps);
  const std::size_t joined = grown.report.cluster_params.extension.joined;
  EXPECT_GT(joined, 0u) << "a sparse room's table legs should join their tables";
  ASSERT_TRUE(grown.report.cluster_params.trim_params);
  EXPECT_FALSE(plain.report.cluster_params.trim_params);
  const auto& trim = *grown.report.cluster_params.trim_params;
  EXPECT_DOUBLE_EQ(trim.radius, 3.0 * grown.map.resolution());
  EXPECT_DOUBLE_EQ(trim.reach, ext.reach);
  const std::size_t dropped = grown.report.cluster_params.trim.dropped;
  EXPECT_GT(dropped, 0u) << "a sparse room's outliers in front of its walls should be dropped";
  // With the extension the stray-part rule runs too (convex parts on): its voxels are noise again.
  ASSERT_TRUE(grown.report.parts && plain.report.parts);
  const std::size_t strays = grown.report.parts->stray_voxels.size();
  EXPECT_EQ(grown.report.parts->stray_obstacles.size(), strays);
  EXPECT_TRUE(plain.report.parts->stray_voxels.empty()) << "no stray-part rule without the extension";
  for (const std::size_t i : grown.report.parts->stray_voxels) EXPECT_EQ(grown.clusters.labels[i], -1);
  EXPECT_EQ(grown.clusters.noise + joined, plain.clusters.noise + dropped + strays);
  EXPECT_EQ(grown.obstacles.size(), plain.obstacles.size());

  // Unset, the extension follows min_pts: off when it is given (the clusters are then DBSCAN's),
  // on when asked for; with min_pts given as the auto rule chose it, the result is the auto run's.
  params.extension.reset();
  params.min_pts = used.min_pts;
  const pipeline::BuildResult given = pipeline::build(params);
  EXPECT_FALSE(given.report.cluster_params.extension_params);
  EXPECT_EQ(given.clusters.labels, plain.clusters.labels);
  params.extension = true;
  const pipeline::BuildResult asked = pipeline::build(params);
  ASSERT_TRUE(asked.report.cluster_params.extension_params);
  EXPECT_EQ(asked.report.cluster_params.extension.joined, joined);
  EXPECT_EQ(asked.clusters.labels, grown.clusters.labels);

  // A rule out of range is refused before anything is read, naming the field.
  params.extension_rule.min_pts_factor = 0.0;
  try {
    pipeline::build(params);
    ADD_FAILURE() << "a min_pts_factor of 0 was accepted";
  } catch (const hullmap::Error& e) {
    EXPECT_EQ(e.parameter(), "extension_rule");
    EXPECT_NE(std::string(e.what()).find("min_pts_factor"), std::string::npos) << e.what();
  }
  params.extension_rule = {};

  // On the obstacle voxels (those DBSCAN saw: above the floor's band, where the rims rule may pick
  // another neighbour) no clustered voxel changes its label but to noise, and only a stray part's
  // (checked above) or one that is not core with no other voxel within the trim's radius; every
  // voxel that left the noise is dense at the extension's level (brute force over the obstacle
  // voxels).
  const std::set<std::size_t> stray_set(grown.report.parts->stray_voxels.begin(),
                                        grown.report.parts->stray_voxels.end());
  ASSERT_EQ(grown.voxels.size(), plain.voxels.size());
  ASSERT_TRUE(grown.report.floor.plane);
  ASSERT_FALSE(grown.report.ceiling.plane);
  const auto& floor = *grown.report.floor.plane;
  std::vector<std::size_t> obstacle_voxels;
  for (std::size_t i = 0; i < grown.voxels.size(); ++i)
    if (floor.signedDistance(grown.voxels[i].center) > 1.25 * grown.map.resolution()) obstacle_voxels.push_back(i);
  std::size_t left_noise = 0;
  for (std::size_t i : obstacle_voxels) {
    const auto before = plain.clusters.labels[i], after = grown.clusters.labels[i];
    if (before >= 0 && after != before && !stray_set.count(i)) {
      EXPECT_EQ(after, hullmap::clustering::kNoise) << i;
      EXPECT_FALSE(plain.clusters.core[i]) << i;
      for (std::size_t j = 0; j < grown.voxels.size(); ++j)
        EXPECT_TRUE(j == i || (grown.voxels[j].center - grown.voxels[i].center).norm() > trim.radius) << i << " " << j;
    }
    if (before != hullmap::clustering::kNoise || after < 0) continue;
    ++left_noise;
    double weight = 0.0;
    for (std::size_t j : obstacle_voxels)
      if ((grown.voxels[j].center - grown.voxels[i].center).squaredNorm() <= ext.eps * ext.eps)
        weight += grown.voxels[j].weight;
    EXPECT_GE(weight, ext.min_pts) << "voxel " << i << " joined without being dense";
  }
  // Every voxel the extension joined left the noise, unless the trim took it back.
  EXPECT_LE(left_noise, joined);
  EXPECT_GE(left_noise + dropped, joined);

  // Scored against the truth: every true obstacle keeps at least the share of its points inside
  // hulls, and no deep collision is missed.
  const hullmap::sim::Evaluation g = score(grown, room, 500), p = score(plain, room, 500);
  EXPECT_EQ(g.missed, 0u);
  double sum_grown = 0.0, sum_plain = 0.0;
  for (std::size_t k = 0; k < g.truth.size(); ++k) {
    sum_grown += g.truth[k].points_inside;
    sum_plain += p.truth[k].points_inside;
  }
  EXPECT_GT(sum_grown, sum_plain);
}

}  // namespace
