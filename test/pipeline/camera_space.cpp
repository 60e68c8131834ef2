// A camera was where each keyframe is: no hull of a build holds one, on a real ORB-SLAM3 map with
// its keyframes and on generated scenes, and a map point beside the camera takes no obstacle there.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/io/readers.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace {

namespace pipeline = hullmap::pipeline;
namespace sim = hullmap::sim;
using V3 = Eigen::Vector3d;

/// Inside the closed hull (outward triangles), brute force, independent of the library's test.
bool hullHoldsPoint(const hullmap::hulls::ConvexHull& hull, const V3& p) {
  if (hull.triangles.empty()) return false;
  for (const auto& t : hull.triangles) {
    const V3& a = hull.vertices[std::size_t(t[0])];
    const V3 n = (hull.vertices[std::size_t(t[1])] - a).cross(hull.vertices[std::size_t(t[2])] - a);
    if (n.dot(p - a) > 1e-12 * n.norm()) return false;
  }
  return true;
}

/// Keyframes inside some part's hull (or an obstacle's whole hull when it has no part).
std::size_t keyframesInsideAnyHull(const pipeline::BuildResult& r) {
  std::size_t inside = 0;
  for (const auto& k : r.keyframes) {
    bool in = false;
    for (const auto& o : r.obstacles) {
      if (o.parts.empty()) in = in || hullHoldsPoint(o.hull, k.position);
      for (const auto& part : o.parts) in = in || hullHoldsPoint(part.hull, k.position);
    }
    inside += in;
  }
  return inside;
}

void expectNoKeyframeInside(const pipeline::BuildResult& r) {
  ASSERT_FALSE(r.keyframes.empty());
  ASSERT_TRUE(r.report.parts);
  EXPECT_EQ(keyframesInsideAnyHull(r), 0u);
  EXPECT_EQ(r.report.keyframes_inside_hulls, 0u);
  // The voxels around a camera are in no obstacle.
  const double half = 0.5 * r.map.resolution();
  for (std::size_t i = 0; i < r.voxels.size(); ++i) {
    if (r.clusters.labels[i] < 0) continue;
    for (const auto& k : r.keyframes)
      ASSERT_GT((k.position - r.voxels[i].center).cwiseAbs().maxCoeff(), half) << "voxel " << i;
  }
}

TEST(PipelineCameraSpace, NoHullHoldsAKeyframeOfTheRealMh01Map) {
  HULLMAP_REQUIRE_REAL_DATA(points, "orbslam3_euroc_MH_01_mono_pointcloud.txt");
  HULLMAP_REQUIRE_REAL_DATA(reference, "orbslam3_euroc_MH_01_mono_ref_pointcloud.txt");
  HULLMAP_REQUIRE_REAL_DATA(keyframes, "orbslam3_euroc_MH_01_mono_KeyFrameTrajectory.txt");
  pipeline::BuildParams params;
  params.inputs = {points, reference};
  params.trajectory = keyframes;
  const pipeline::BuildResult r = pipeline::build(params);
  expectNoKeyframeInside(r);
  // Its first keyframes sit in voxels that SLAM put map points into (9 of them inside hulls before).
  EXPECT_GT(r.report.camera_voxels, 0u);
}

TEST(PipelineCameraSpace, NoHullHoldsAKeyframeOfGeneratedRoomsAndStreets) {
  for (const sim::SceneLayout layout : {sim::SceneLayout::kRoom, sim::SceneLayout::kOutdoor}) {
    for (const std::uint64_t seed : {7u, 8u}) {
      sim::SceneParams p = layout == sim::SceneLayout::kOutdoor ? sim::outdoorSceneParams() : sim::SceneParams{};
      p.layout = layout;
      p.seed = seed;
      if (layout == sim::SceneLayout::kOutdoor) {
        p.track_length = 80.0;
        p.buildings = 6;
        p.trees = 6;
        p.cars = 4;
        p.posts = 4;
      }
      const sim::Scene scene = sim::generateScene(p);
      const auto dir = hullmap::test::freshDir("scene");
      sim::writeScene(scene, p, dir.string());
      pipeline::BuildParams params;
      params.inputs = {dir / "map_points.txt"};
      params.trajectory = dir / "KeyFrameTrajectory.txt";
      params.align = pipeline::AlignSettings{dir / "reference_trajectory.txt", {}, {}};
      SCOPED_TRACE(std::string(layout == sim::SceneLayout::kRoom ? "room " : "street ") + std::to_string(seed));
      expectNoKeyframeInside(pipeline::build(params));
    }
  }
}

TEST(PipelineCameraSpace, MapPointsBesideACameraMakeNoObstacleAroundIt) {
  // A dense wall at x = 1.01, and a keyframe 2 m in front of it with a tight clump of SLAM's stray
  // points around the camera itself: the clump is a cluster, but the camera's voxel holds no hull.
  hullmap::io::Points points;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 30; ++j) points.push_back({1.01, -1.0 + 0.05 * i, 0.05 * j});
  const V3 camera(-1.0, 0.02, 0.76);
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j)
      for (int k = -2; k <= 2; ++k) points.push_back(camera + 0.02 * V3(i, j, k));
  hullmap::io::Keyframe kf;
  kf.position = camera;
  kf.stamp = 0.0;
  pipeline::BuildParams params;
  params.floor.mode = hullmap::mapper::PlaneSetting::Mode::kNone;
  const pipeline::BuildResult r =
      pipeline::buildFromPoints(points, std::vector<hullmap::io::Keyframe>{kf}, params, "points");
  expectNoKeyframeInside(r);
  EXPECT_GT(r.report.camera_voxels, 0u);
  // The wall is still an obstacle.
  bool wall = false;
  for (const auto& o : r.obstacles) wall = wall || (o.aabb_min.x() < 1.01 && o.aabb_max.x() > 1.01);
  EXPECT_TRUE(wall);
}

}  // namespace
