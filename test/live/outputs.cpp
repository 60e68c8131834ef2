// hullmap::live's outputs: the projected grid against an exact polygon-square intersection oracle,
// the obstacle markers against the obstacles they draw.
#include <algorithm>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "hullmap/core/convex_hull_2d.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/live/outputs.hpp"
#include "polygon_oracle.hpp"

namespace hullmap::live {
namespace {

TEST(LiveProjectedGrid, MarksExactlyTheCellsThatTheFootprintsInTheBandTouch) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(-2.0, 2.0);
  for (int round = 0; round < 5; ++round) {
    std::vector<hulls::Obstacle> obstacles;
    for (int i = 0; i < 6; ++i) {
      std::vector<Eigen::Vector2d> cloud;
      const Eigen::Vector2d centre(coord(rng), coord(rng));
      for (int k = 0; k < 7; ++k) cloud.push_back(centre + 0.3 * Eigen::Vector2d(coord(rng), coord(rng)));
      hulls::Obstacle o;
      o.id = i;
      o.footprint.polygon = hullmap::core::convexHull2d(cloud);
      o.footprint.z_min = i;  // obstacles 0..5 span z [i, i + 0.5]
      o.footprint.z_max = i + 0.5;
      obstacles.push_back(o);
    }
    const double resolution = 0.1;
    const ProjectedGrid grid = projectedGrid(obstacles, resolution, 1.2, 3.1, 0.2);
    ASSERT_EQ(grid.data.size(), std::size_t{grid.width} * grid.height);
    EXPECT_DOUBLE_EQ(grid.origin.x() / resolution, std::round(grid.origin.x() / resolution));
    std::size_t occupied = 0;
    for (std::uint32_t r = 0; r < grid.height; ++r) {
      for (std::uint32_t c = 0; c < grid.width; ++c) {
        const Eigen::Vector2d lo(grid.origin.x() + c * resolution, grid.origin.y() + r * resolution);
        const Eigen::Vector2d hi = lo + Eigen::Vector2d::Constant(resolution);
        bool expected = false;
        for (const auto& o : obstacles) {
          if (o.footprint.z_max >= 1.2 && o.footprint.z_min <= 3.1)  // obstacles 1, 2, 3
            expected = expected || test::meetsOracle(o.footprint.polygon, lo, hi);
        }
        EXPECT_EQ(grid.data[r * grid.width + c], expected ? 100 : 0) << "cell " << r << "," << c;
        occupied += expected;
      }
    }
    EXPECT_GT(occupied, 0u);
  }
  const ProjectedGrid empty = projectedGrid({}, 0.1, 0, 1, 0.2);
  EXPECT_EQ(empty.width * empty.height, 1u);
  EXPECT_THROW(projectedGrid({}, 0.0, 0, 1, 0.2), Error);
}

TEST(LiveProjectedGrid, AGridOfMoreThanTheMostCellsIsRefusedNamingTheResolution) {
  hulls::Obstacle o;
  o.footprint.polygon = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  o.footprint.z_min = 0;
  o.footprint.z_max = 1;
  // A 10 m square: 1000^2 cells at 0.01 are drawn, 10^5^2 at 0.0001 would be 150 times the most.
  EXPECT_NO_THROW(projectedGrid({o}, 0.01, 0, 1, 0.0));
  try {
    projectedGrid({o}, 1e-4, 0, 1, 0.0);  // 10^10 cells
    FAIL() << "a grid of 10^10 cells was drawn";
  } catch (const Error& e) {
    EXPECT_EQ(e.parameter(), "resolution") << e.what();
  }
}

hulls::Obstacle cube(int id, const Eigen::Vector3d& lo, double size) {
  std::vector<Eigen::Vector3d> centers{lo + Eigen::Vector3d::Constant(size / 2)};
  auto obstacles = hulls::buildObstacles(centers, {1}, {0}, size);
  obstacles.at(0).id = id;
  return obstacles.at(0);
}

TEST(LiveObstacleMarkers, HullTrianglesFootprintsLabelsAndDeletionsOfStaleIds) {
  const std::vector<hulls::Obstacle> obstacles{cube(3, {0, 0, 0}, 1.0), cube(5, {4, 0, 0}, 0.5)};
  const auto markers = obstacleMarkers(obstacles, {1, 3, 5, 8});
  std::map<std::pair<std::string, int>, const MarkerSpec*> by_key;
  for (const auto& m : markers) by_key[{m.ns, m.id}] = &m;
  ASSERT_EQ(markers.size(), 3 * 2 + 3 * 2u);
  for (const auto& o : obstacles) {
    const auto& hull = *by_key.at({"hulls", o.id});
    EXPECT_EQ(hull.type, marker::kTriangleList);
    ASSERT_EQ(hull.points.size(), 3 * o.hull.triangles.size());
    for (std::size_t t = 0; t < o.hull.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) EXPECT_EQ(hull.points[3 * t + k], o.hull.vertices[o.hull.triangles[t][k]]);
    }
    const auto& footprint = *by_key.at({"footprints", o.id});
    EXPECT_EQ(footprint.type, marker::kLineStrip);
    ASSERT_EQ(footprint.points.size(), o.footprint.polygon.size() + 1);  // closed
    EXPECT_EQ(footprint.points.front(), footprint.points.back());
    EXPECT_EQ(footprint.points.front().z(), o.footprint.z_min);
    EXPECT_EQ(by_key.at({"labels", o.id})->text, std::to_string(o.id));
  }
  for (int stale : {1, 8}) {
    for (const char* ns : {"hulls", "footprints", "labels"}) {
      EXPECT_EQ(by_key.at({ns, stale})->action, marker::kDelete) << ns << " " << stale;
    }
  }
}

TEST(LiveOccupiedCellMarkers, OneCubeListPerDepthTheLeavesAtDepth16) {
  std::vector<mapper::OccupiedVoxel> voxels(2);
  voxels[0].center = {0.025, 0.025, 0.025};
  voxels[1].center = {1.025, 0.025, 0.025};
  const auto markers = occupiedCellMarkers(voxels, 0.05, "map");
  ASSERT_EQ(markers.size(), 17u);
  for (int depth = 0; depth <= 16; ++depth) {
    EXPECT_EQ(markers[depth].id, depth);
    EXPECT_EQ(markers[depth].ns, "map");
    EXPECT_DOUBLE_EQ(markers[depth].scale.x(), 0.05 * double(1 << (16 - depth)));
    EXPECT_EQ(markers[depth].action, depth == 16 ? marker::kAdd : marker::kDelete);
  }
  EXPECT_EQ(markers[16].points, (std::vector<Eigen::Vector3d>{voxels[0].center, voxels[1].center}));
}

}  // namespace
}  // namespace hullmap::live
