// The stages issue 13 adds to the build (align, floor, auto eps/minPts, convex parts with known free
// space) on a generated room in ORB-SLAM's frame at a monocular scale, and their bad inputs.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
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

/// True when p is inside the convex hull (outward triangles) or on it.
bool insideHull(const hullmap::hulls::ConvexHull& hull, const V3& p) {
  if (hull.triangles.empty()) return false;
  for (const auto& t : hull.triangles) {
    const V3& a = hull.vertices[t[0]];
    const V3 n = (hull.vertices[t[1]] - a).cross(hull.vertices[t[2]] - a);
    if (n.dot(p - a) > 1e-12 * n.norm()) return false;
  }
  return true;
}

TEST(PipelineStages, AlignedRoomAtTheDefaults) {
  const Room room = writeRoom("stages_room", 3);
  const pipeline::BuildResult r = pipeline::build(alignedBuild(room));
  const auto& report = r.report;

  // The fitted similarity is the generator's inverse: map units -> metres by 1 / monocular scale.
  ASSERT_TRUE(report.alignment);
  EXPECT_NEAR(report.alignment->transform.scale, 1.0 / room.scene.output_scale, 1e-6);
  EXPECT_TRUE(report.alignment->transform.rotation.isApprox(room.scene.output_rotation.transpose(), 1e-6));
  EXPECT_LT(report.alignment->rmse, 1e-6);
  EXPECT_EQ(report.alignment->matched, room.scene.keyframes.size());

  // The floor (z = 0 in the reference frame) is found and not moved (REF defines up).
  ASSERT_TRUE(report.floor.plane);
  EXPECT_FALSE(report.floor.levelled);
  EXPECT_NEAR(report.floor.plane->normal.z(), 1.0, 1e-12);
  EXPECT_NEAR(report.floor.plane->offset, 0.0, 0.03);
  EXPECT_GT(report.floor.voxels, 100u);

  // Floor voxels are in no obstacle; every voxel is floor, noise or in exactly one obstacle.
  std::size_t floor_voxels = 0, clustered = 0;
  for (std::size_t i = 0; i < r.voxels.size(); ++i) {
    floor_voxels += r.clusters.labels[i] == pipeline::kFloorLabel;
    clustered += r.clusters.labels[i] >= 0;
    if (r.clusters.labels[i] == pipeline::kFloorLabel) {
      EXPECT_GT(r.voxels[i].center.z(), -0.2);
    }
  }
  EXPECT_EQ(floor_voxels, report.floor.voxels);
  std::size_t in_obstacles = 0;
  for (const auto& o : r.obstacles) in_obstacles += o.voxel_count;
  EXPECT_EQ(in_obstacles, clustered);
  EXPECT_EQ(clustered + r.clusters.noise + floor_voxels, r.voxels.size());

  // Auto eps/minPts were chosen and recorded.
  EXPECT_TRUE(report.cluster_params.eps_auto);
  EXPECT_TRUE(report.cluster_params.min_pts_auto);
  ASSERT_TRUE(report.cluster_params.chosen);
  EXPECT_EQ(report.cluster_params.used.eps, report.cluster_params.chosen->eps);

  // No part's hull contains a keyframe (brute force over every part and keyframe).
  ASSERT_TRUE(report.parts);
  ASSERT_EQ(r.keyframes.size(), room.scene.keyframes.size());
  std::size_t inside = 0;
  for (const auto& o : r.obstacles)
    for (const auto& part : o.parts)
      for (const auto& k : r.keyframes) inside += insideHull(part.hull, k.position);
  EXPECT_EQ(inside, report.keyframes_inside_hulls);
  EXPECT_EQ(inside, 0u);

  // Scored against the truth at r = 0.3 on issue 13's five targets (docs/QUALITY.md): no deep
  // collision missed, false alarms at most 5 % of the clear segments, swallowed free space at most 5 %.
  const hullmap::sim::Evaluation e = score(r, room, 1000);
  std::cout << "room: " << e.parts << " parts for " << e.truth.size() << " true objects; deep " << e.deep << " missed "
            << e.missed << "; clear " << e.clear << " false alarms " << e.false_alarms << "; far volume "
            << e.far_volume << " of " << e.union_volume << "\n";
  // The other two targets: at least 98 % of each true obstacle's observed points inside hulls, and at
  // most 1.5 hulls representing each convex true obstacle (walls, boxes, cylinders) on average.
  std::size_t convex = 0, convex_parts = 0;
  for (const auto& t : e.truth) {
    std::cout << "  " << t.label << ": " << t.points_inside << " / " << t.points_near << ", " << t.parts.size()
              << " hulls\n";
    if (t.surface) continue;
    EXPECT_GE(t.points_inside, 0.98 * t.points_near) << t.label;
    for (const std::string kind : {"wall ", "box ", "cylinder "})
      if (t.label.rfind(kind, 0) == 0) {
        ++convex;
        convex_parts += t.parts.size();
      }
  }
  EXPECT_GT(e.deep, 0u);
  EXPECT_EQ(e.missed, 0u);
  EXPECT_LE(double(e.false_alarms), 0.05 * double(e.clear));
  EXPECT_LE(e.far_volume, 0.05 * e.union_volume);
  ASSERT_GT(convex, 0u);
  EXPECT_LE(double(convex_parts), 1.5 * double(convex));
}

TEST(PipelineStages, ExplicitEpsAndMinPtsWinOverAuto) {
  const Room room = writeRoom("stages_explicit", 5);
  pipeline::BuildParams params = alignedBuild(room);
  params.convex_parts.reset();
  const pipeline::BuildResult automatic = pipeline::build(params);
  params.eps = 0.17;
  params.min_pts = 4;
  const pipeline::BuildResult given = pipeline::build(params);
  EXPECT_EQ(given.report.cluster_params.used.eps, 0.17);
  EXPECT_EQ(given.report.cluster_params.used.min_pts, 4);
  EXPECT_FALSE(given.report.cluster_params.eps_auto);
  EXPECT_FALSE(given.report.cluster_params.min_pts_auto);
  EXPECT_FALSE(given.report.cluster_params.chosen);
  const auto json = pipeline::reportJson(given);
  EXPECT_EQ(json["parameters"]["eps"].get<double>(), 0.17);
  EXPECT_FALSE(json["parameters"]["eps_auto"].get<bool>());
  // The auto values are those of the rule on the obstacle voxels (floor left out).
  std::vector<V3> centers;
  std::vector<std::uint32_t> weights;
  for (std::size_t i = 0; i < automatic.voxels.size(); ++i) {
    if (automatic.clusters.labels[i] == pipeline::kFloorLabel) continue;
    centers.push_back(automatic.voxels[i].center);
    weights.push_back(automatic.voxels[i].weight);
  }
  // Rims of the floor joined clusters after DBSCAN; the rule saw every non-floor voxel before that.
  EXPECT_GE(centers.size(), automatic.voxels.size() - automatic.report.floor.voxels);
  EXPECT_TRUE(automatic.report.cluster_params.eps_auto);
  EXPECT_NE(automatic.report.cluster_params.used.eps, 0.17);
}

TEST(PipelineStages, UnalignedTiltedFloorIsLevelledAtZeroInBothPaths) {
  // The room in ORB-SLAM's frame read with --up -y: tilted by the camera pitch, at monocular scale.
  const Room room = writeRoom("stages_level", 11);
  pipeline::BuildParams params;
  params.inputs = {room.dir / "map_points.txt"};
  params.frame.up = mapper::UpAxis::kNegY;
  params.eps = 0.05;
  params.min_pts = 3;
  params.convex_parts.reset();
  params.stream_above_bytes = 0;  // stream, twice: the first pass finds the floor
  const pipeline::BuildResult streamed = pipeline::build(params);
  ASSERT_TRUE(streamed.report.floor.plane);
  EXPECT_TRUE(streamed.report.floor.levelled);
  EXPECT_NEAR(streamed.report.floor.fit.tilt_deg, room.params.camera_pitch_deg, 2.0);
  EXPECT_GT(streamed.report.floor.voxels, 100u);
  for (std::size_t i = 0; i < streamed.voxels.size(); ++i)
    if (streamed.clusters.labels[i] == pipeline::kFloorLabel) {
      EXPECT_LT(std::abs(streamed.voxels[i].center.z()), 0.1);
    }
  // The in-memory path (whole) samples and levels the same way (the file holds rounded numbers).
  const pipeline::BuildResult memory = pipeline::buildFromPoints(room.scene.points, params);
  EXPECT_TRUE(memory.report.levelling.isApprox(streamed.report.levelling, 1e-6));
  EXPECT_EQ(memory.voxels.size(), streamed.voxels.size());
  // A file this small is read whole at the default (one pass): the same map, voxel for voxel.
  params.stream_above_bytes = pipeline::BuildParams{}.stream_above_bytes;
  const pipeline::BuildResult whole = pipeline::build(params);
  EXPECT_TRUE(whole.report.levelling.isApprox(streamed.report.levelling, 0.0));
  ASSERT_EQ(whole.voxels.size(), streamed.voxels.size());
  for (std::size_t i = 0; i < whole.voxels.size(); ++i) {
    EXPECT_EQ(whole.voxels[i].center, streamed.voxels[i].center) << i;
    EXPECT_EQ(whole.voxels[i].weight, streamed.voxels[i].weight) << i;
  }
  EXPECT_EQ(whole.clusters.labels, streamed.clusters.labels);
}

}  // namespace

// A room sampled at 3 points per m^2 (points about 0.9 m apart) at the default 5 cm: the build says
// so and names a resolution that fits (warning 10); the same room at 60 points per m^2 does not, nor
// does the sparse one at the resolution suggested. The spacing said is the exact one the rule
// measures (checked against kDistanceCurve in BuildWarnings.SparseMapsAreToldACoarserResolution).
TEST(PipelineStages, ASparseMapIsToldAResolutionThatFitsIt) {
  const auto sparse_warning = [](const pipeline::BuildResult& r) -> const hullmap::Warning* {
    for (const auto& w : r.report.warnings)
      if (w.code == hullmap::Warning::Code::kSparseForResolution) return &w;
    return nullptr;
  };
  const Room sparse = writeRoom("stages_sparse", 21, 6.0, 4, 3.0);
  pipeline::BuildParams params = alignedBuild(sparse);
  params.convex_parts.reset();
  params.adapt_resolution = false;  // as with --resolution 0.05 given
  const pipeline::BuildResult fine = pipeline::build(params);
  const hullmap::Warning* w = sparse_warning(fine);
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->number("resolution"), 0.05);
  EXPECT_GT(w->number("spacing"), 0.4);
  EXPECT_LT(w->number("spacing"), 2.0);
  const double suggested = w->number("suggested");
  EXPECT_GE(suggested, 0.1);
  const auto json = pipeline::reportJson(fine);
  bool named = false;
  for (const auto& item : json["warnings"])
    named = named || item.get<std::string>().rfind("the map's points lie about", 0) == 0;
  EXPECT_TRUE(named) << json["warnings"].dump();
  // The default resolution adapts by the same measure on the points: about the spacing the warning
  // said, a resolution 2.5 to 6.25 times finer, no warning.
  params.adapt_resolution = true;
  const pipeline::BuildResult adapted = pipeline::build(params);
  ASSERT_TRUE(adapted.report.resolution.has_value());
  ASSERT_TRUE(adapted.report.resolution->spacing.has_value());
  EXPECT_NEAR(*adapted.report.resolution->spacing, w->number("spacing"), 0.25 * w->number("spacing"));
  EXPECT_EQ(adapted.params.octree.resolution, adapted.report.resolution->used);
  EXPECT_EQ(adapted.map.resolution(), adapted.report.resolution->used);
  EXPECT_GE(adapted.report.resolution->used, *adapted.report.resolution->spacing / 6.25);
  EXPECT_LE(adapted.report.resolution->used, *adapted.report.resolution->spacing / 2.5);
  EXPECT_EQ(sparse_warning(adapted), nullptr);
  params.adapt_resolution = false;
  params.octree.resolution = suggested;
  EXPECT_EQ(sparse_warning(pipeline::build(params)), nullptr) << "at the suggested " << suggested;
  const Room dense = writeRoom("stages_dense", 21);
  pipeline::BuildParams dense_params = alignedBuild(dense);
  dense_params.convex_parts.reset();
  const pipeline::BuildResult kept = pipeline::build(dense_params);
  EXPECT_EQ(sparse_warning(kept), nullptr);
  EXPECT_EQ(kept.map.resolution(), 0.05) << "a dense room keeps the default";
}
