// buildFromPoints with keyframes in memory casts free space exactly as build() does from a TUM file
// of the same poses, whatever the input frame (pipeline.hpp says so; hullmap_node and bag input
// with --trajectory-topic rely on it).
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/io/readers.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace {

namespace pipeline = hullmap::pipeline;
namespace mapper = hullmap::mapper;
namespace io = hullmap::io;

void expectSameBuild(const pipeline::BuildResult& a, const pipeline::BuildResult& b) {
  ASSERT_EQ(a.voxels.size(), b.voxels.size());
  for (std::size_t i = 0; i < a.voxels.size(); ++i) {
    ASSERT_EQ(a.voxels[i].center, b.voxels[i].center) << "voxel " << i;
    ASSERT_EQ(a.voxels[i].weight, b.voxels[i].weight) << "voxel " << i;
  }
  EXPECT_EQ(a.map.tree().size(), b.map.tree().size());
  EXPECT_EQ(a.clusters.labels, b.clusters.labels);
  ASSERT_EQ(a.keyframes.size(), b.keyframes.size());
  for (std::size_t i = 0; i < a.keyframes.size(); ++i)
    EXPECT_EQ(a.keyframes[i].position, b.keyframes[i].position) << "keyframe " << i;
  EXPECT_EQ(a.report.keyframes_inside_hulls, b.report.keyframes_inside_hulls);
}

TEST(PipelineKeyframesInMemory, SameTreeAsTheTrajectoryFileInOrbSlamsFrame) {
  const std::string dir = std::string(HULLMAP_SOURCE_DIR) + "/maps/simple/";
  pipeline::BuildParams params;
  params.inputs = {dir + "map_points.txt"};
  params.trajectory = dir + "KeyFrameTrajectory.txt";
  params.frame.up = mapper::UpAxis::kNegY;  // not the identity: the keyframes turn once, as the points
  params.eps = 0.12;
  params.min_pts = 5;
  const pipeline::BuildResult from_file = pipeline::build(params);

  io::PointSet set = io::readPointFile(dir + "map_points.txt");
  auto keyframes = io::readTumTrajectory(dir + "KeyFrameTrajectory.txt");
  pipeline::BuildParams memory = params;
  memory.trajectory.reset();
  const pipeline::BuildResult in_memory =
      pipeline::buildFromPoints(std::move(set.points), std::move(keyframes), memory, "points", "keyframes");
  expectSameBuild(from_file, in_memory);
}

}  // namespace
