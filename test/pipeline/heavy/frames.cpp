// The user's frame: a metric z-up input keeps it (OctoMap's own tree for a real scan at the
// defaults), a camera's frame is levelled, report.input_to_output takes the input's coordinates to
// the outputs' (checked on the keyframes, which go through the same frame change as the points), GPS
// logs with lines without a fix align, and the floor's half-space holds every floor voxel.
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include "frames_fixtures.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/pipeline/map_obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/pipeline/report.hpp"
#include "octree_oracle.hpp"
#include "test_support.hpp"

namespace hullmap::pipeline {
namespace {

bool isIdentity(const mapper::Similarity& s) {
  return s.scale == 1.0 && s.rotation == Eigen::Matrix3d::Identity() && s.translation == V3::Zero();
}

TEST(PipelineFrames, MetricScanAtTheDefaultsIsOctomapsTreeInItsOwnFrame) {
  HULLMAP_REQUIRE_REAL_DATA(path, "octomap_scan.dat");
  BuildParams params;  // the defaults of `hullmap build scan.dat --origin 0,0,0 --resolution 0.1`
  params.inputs = {path};
  params.origin = V3::Zero();
  params.octree.resolution = 0.1;
  const BuildResult result = build(params);

  octomap::OcTree expected(0.1);
  expected.insertPointCloud(test::toCloud(test::readXyz(path)), octomap::point3d(0, 0, 0));
  EXPECT_TRUE(test::sameTree(expected, result.map.tree()));
  EXPECT_TRUE(isIdentity(result.report.input_to_output));
  // The floor is found, its voxels set aside and made an obstacle, but the map is not moved.
  ASSERT_TRUE(result.report.floor.plane);
  EXPECT_FALSE(result.report.floor.levelled);
  EXPECT_GT(result.report.floor.fit.tilt_deg, 1.0);
  EXPECT_GT(result.report.floor.voxels, 1000u);
  ASSERT_EQ(result.surfaces.size(), 1u);
  EXPECT_EQ(result.surfaces[0].name, "floor");
  EXPECT_EQ(reportJson(result)["input_to_output"]["matrix"],
            nlohmann::json::parse("[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]"));

  // Asked to, it levels: the tree then differs, and the transform says how.
  params.level = Level::kOn;
  const BuildResult levelled = build(params);
  EXPECT_TRUE(levelled.report.floor.levelled);
  EXPECT_FALSE(test::sameTree(expected, levelled.map.tree()));
  const mapper::Similarity& t = levelled.report.input_to_output;
  EXPECT_EQ(t.scale, 1.0);
  EXPECT_LT((t.rotation - levelled.report.levelling.linear()).norm(), 1e-15);
  EXPECT_NEAR(Eigen::AngleAxisd(t.rotation).angle() * 180 / M_PI, result.report.floor.fit.tilt_deg, 1e-6);
}

/// Every keyframe of the trajectory file, moved by input_to_output, is where the build put it.
void expectKeyframesThroughTheTransform(const BuildResult& result, const std::string& trajectory) {
  const auto input = io::readTumTrajectory(trajectory);
  ASSERT_EQ(input.size(), result.keyframes.size());
  const mapper::Similarity& t = result.report.input_to_output;
  for (std::size_t i = 0; i < input.size(); ++i) {
    EXPECT_LT((t(input[i].position) - result.keyframes[i].position).norm(), 1e-9 * (1 + input[i].position.norm()));
    const Eigen::Quaterniond q(t.rotation * input[i].orientation.toRotationMatrix());
    EXPECT_GT(std::abs(q.dot(result.keyframes[i].orientation)), 1 - 1e-12);
  }
}

TEST(PipelineFrames, InputToOutputIsTheFrameChangeOfEveryPoint) {
  // A camera's frame (ORB-SLAM's, --up -y), levelled.
  BuildParams params;
  params.inputs = {sample("simple/map_points.txt")};
  params.trajectory = sample("simple/KeyFrameTrajectory.txt");
  params.frame.up = mapper::UpAxis::kNegY;
  params.eps = 0.12;
  params.min_pts = 5;
  const BuildResult levelled = build(params);
  ASSERT_TRUE(levelled.report.floor.levelled);
  expectKeyframesThroughTheTransform(levelled, *params.trajectory);
  // With a scale, and with levelling off.
  params.frame.scale = 2.5;
  params.level = Level::kOff;
  const BuildResult scaled = build(params);
  EXPECT_FALSE(scaled.report.floor.levelled);
  EXPECT_EQ(scaled.report.input_to_output.scale, 2.5);
  expectKeyframesThroughTheTransform(scaled, *params.trajectory);
  // Aligned to a metric reference: the alignment itself.
  BuildParams aligned;
  aligned.inputs = {sample("room/map_points.txt")};
  aligned.trajectory = sample("room/KeyFrameTrajectory.txt");
  aligned.align = alignTo(sample("room/reference_trajectory.txt"));
  const BuildResult room = build(aligned);
  EXPECT_NEAR(room.report.input_to_output.scale, room.report.alignment->transform.scale, 1e-15);
  expectKeyframesThroughTheTransform(room, *aligned.trajectory);
  // The same transform is in obstacles.json, read back for checks in the input frame.
  const MapObstacles map = mapObstacles(room);
  const mapper::Similarity to_map = toMapFrame(map, QueryFrame::kInput);
  EXPECT_EQ(toMatrix(to_map), toMatrix(room.report.input_to_output));
  ObstaclesMeta meta;
  meta.input_to_output = room.report.input_to_output;
  meta.surfaces = room.surfaces;
  const nlohmann::json doc = obstaclesToJson(room.obstacles, meta);
  ObstaclesMeta back;
  obstaclesFromJson(doc, "obstacles.json", &back);
  ASSERT_TRUE(back.input_to_output);
  EXPECT_LT((toMatrix(*back.input_to_output) - toMatrix(room.report.input_to_output)).norm(), 1e-12);
  ASSERT_EQ(back.surfaces.size(), room.surfaces.size());
  EXPECT_EQ(back.surfaces[0].offset, room.surfaces[0].offset);
  EXPECT_EQ(toMatrix(toMapFrame(map, QueryFrame::kMap)), Eigen::Matrix4d::Identity());
  MapObstacles old = map;
  old.input_to_output.reset();
  try {
    toMapFrame(old, QueryFrame::kInput);
    ADD_FAILURE() << "an unknown frame change was used";
  } catch (const Error& e) {
    EXPECT_EQ(e.parameter(), "frame");
  }
}

TEST(PipelineFrames, TheFloorsSurfaceHoldsEveryFloorVoxel) {
  BuildParams params;
  params.inputs = {sample("room/map_points.txt")};
  params.trajectory = sample("room/KeyFrameTrajectory.txt");
  params.align = alignTo(sample("room/reference_trajectory.txt"));
  params.ceiling.mode = mapper::PlaneSetting::Mode::kAuto;
  const BuildResult result = build(params);
  ASSERT_FALSE(result.surfaces.empty());
  const double half = 0.5 * result.map.resolution();
  std::size_t floor_voxels = 0;
  for (const auto& surface : result.surfaces) {
    const std::int32_t label = surface.name == "floor" ? kFloorLabel : kCeilingLabel;
    const mapper::Plane& plane = *(label == kFloorLabel ? result.report.floor.plane : result.report.ceiling.plane);
    EXPECT_GE(surface.offset, plane.offset);
    double highest = -INFINITY;
    for (std::size_t i = 0; i < result.voxels.size(); ++i) {
      if (result.clusters.labels[i] != label) continue;
      floor_voxels += label == kFloorLabel;
      for (int c = 0; c < 8; ++c) {
        const V3 corner = result.voxels[i].center + half * V3(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1);
        EXPECT_LE(surface.distance(corner), 1e-9);
        highest = std::max(highest, surface.normal.dot(corner));
      }
    }
    // Not a hair more than it takes to hold them (or the plane, when that is higher).
    EXPECT_NEAR(surface.offset, std::max(highest, plane.offset), 1e-12);
  }
  EXPECT_GT(floor_voxels, 1000u);
}

/// The positions of a TUM reference written as a GPS log (small-angle ENU -> WGS84 around a fix).
std::string gpsLog(const std::string& tum_reference, const std::string& before_first_fix) {
  std::ifstream in(tum_reference);
  std::ostringstream out;
  out << std::setprecision(12) << before_first_fix;
  const double lat0 = 47.3769, lon0 = 8.5417, alt0 = 408.0, r = 6378137.0;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double t, x, y, z;
    fields >> t >> x >> y >> z;
    out << t << ' ' << lat0 + y / r * 180 / M_PI << ' ' << lon0 + x / (r * std::cos(lat0 * M_PI / 180)) * 180 / M_PI
        << ' ' << alt0 + z << '\n';
  }
  return out.str();
}

TEST(PipelineFrames, AGpsLogWhoseFirstLinesHaveNoFixAligns) {
  const auto dir = test::freshDir("gps");
  const std::string log = (dir / "gps.txt").string();
  test::writeText(log, gpsLog(sample("room/reference_trajectory.txt"), "0 0 0 0\n0.5 nan nan nan\n"));
  BuildParams params;
  params.inputs = {sample("room/map_points.txt")};
  params.trajectory = sample("room/KeyFrameTrajectory.txt");
  params.align = alignTo(log, io::ReferenceFormat::kGps);
  const BuildResult result = build(params);
  ASSERT_TRUE(result.report.alignment);
  EXPECT_EQ(result.report.alignment->matched, 60u);
  EXPECT_LT(result.report.alignment->rmse, 0.01);  // metres: the small-angle log is good to millimetres here
  EXPECT_NEAR(result.report.alignment->transform.scale, 2.7027, 1e-3);
  const std::map<std::string, std::size_t> dropped{{"no_fix", 1}, {"non_finite", 1}};
  EXPECT_EQ(result.report.reference_dropped, dropped);
  EXPECT_EQ(reportJson(result)["alignment"]["reference_dropped"]["no_fix"], 1);

  // Two valid fixes are not enough: the message says why, and what was dropped.
  test::writeText(log, "0 0 0 0\n1 0 0 0\n2 47.3769 8.5417 408\n3 47.3770 8.5417 408\n");
  try {
    build(params);
    ADD_FAILURE() << "aligned to two fixes";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.parameter(), "align") << what;
    EXPECT_NE(what.find("at least 3"), std::string::npos) << what;
    EXPECT_NE(what.find("2 lines without a fix dropped"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace hullmap::pipeline
