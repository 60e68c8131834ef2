// hullmap::ros1's message conversions, without a ROS master: each against a direct statement of
// what the message means (an ORB-SLAM map as the echo reader takes it, a cloud's bytes, an exact
// polygon-square intersection test for the projected map).
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "hullmap/core/convex_hull_2d.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/ros1/messages.hpp"
#include "polygon_oracle.hpp"

namespace hullmap::ros1 {
namespace {

visualization_msgs::Marker mapPoints(int id, const std::vector<Eigen::Vector3d>& points) {
  visualization_msgs::Marker m;
  m.ns = "MapPoints";
  m.id = id;
  m.type = visualization_msgs::Marker::POINTS;
  for (const auto& p : points) {
    geometry_msgs::Point q;
    q.x = p.x();
    q.y = p.y();
    q.z = p.z();
    m.points.push_back(q);
  }
  return m;
}

TEST(OrbSlamMapMarkers, TheMapIsTheLatestId0PlusTheLatestId6) {
  OrbSlamMapMarkers map;
  EXPECT_TRUE(map.empty());
  EXPECT_TRUE(map.add(mapPoints(6, {{9, 9, 9}})));
  EXPECT_TRUE(map.add(mapPoints(0, {{1, 0, 0}})));
  EXPECT_TRUE(map.add(mapPoints(0, {{2, 0, 0}, {3, 0, 0}})));
  auto keyframes = mapPoints(1, {{5, 5, 5}});
  keyframes.ns = "KeyFrames";
  EXPECT_FALSE(map.add(keyframes));
  auto graph = mapPoints(2, {{5, 5, 5}});  // MapPoints namespace, another id: not map points
  EXPECT_FALSE(map.add(graph));
  EXPECT_EQ(map.points(), (io::Points{{2, 0, 0}, {3, 0, 0}, {9, 9, 9}}));

  auto remove = mapPoints(6, {});
  remove.action = visualization_msgs::Marker::DELETE;
  EXPECT_TRUE(map.add(remove));
  EXPECT_EQ(map.points(), (io::Points{{2, 0, 0}, {3, 0, 0}}));
  auto all = mapPoints(0, {});
  all.action = visualization_msgs::Marker::DELETEALL;
  EXPECT_TRUE(map.add(all));
  EXPECT_TRUE(map.empty());
}

TEST(OrbSlamMapMarkers, ANonFinitePointRefusesTheMarkerAndKeepsTheMap) {
  OrbSlamMapMarkers map;
  map.add(mapPoints(0, {{1, 2, 3}}));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  try {
    map.add(mapPoints(0, {{0, 0, 0}, {nan, 1, 1}}));
    FAIL() << "a NaN was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 1 is not finite"), std::string::npos) << e.what();
  }
  EXPECT_THROW(map.add(mapPoints(6, {{std::numeric_limits<double>::infinity(), 0, 0}})), Error);
  EXPECT_EQ(map.points(), (io::Points{{1, 2, 3}}));
}

/// A cloud of FLOAT32 x, y, z plus a padding byte block, two rows with row padding.
sensor_msgs::PointCloud2 floatCloud(const std::vector<Eigen::Vector3f>& points, std::uint32_t width) {
  sensor_msgs::PointCloud2 c;
  for (const char* name : {"x", "y", "z"}) {
    sensor_msgs::PointField f;
    f.name = name;
    f.offset = 4 * static_cast<std::uint32_t>(c.fields.size()) + 4;  // 4 bytes of something first
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    c.fields.push_back(f);
  }
  c.point_step = 20;
  c.width = width;
  c.height = static_cast<std::uint32_t>(points.size() / width);
  c.row_step = c.point_step * width + 8;
  c.data.assign(std::size_t{c.row_step} * c.height, 0xAB);
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::uint8_t* p = c.data.data() + (i / width) * c.row_step + (i % width) * c.point_step;
    for (int k = 0; k < 3; ++k) std::memcpy(p + 4 + 4 * k, &points[i][k], 4);
  }
  return c;
}

TEST(CloudPoints, ReadsEveryFiniteXyzAndCountsTheOthers) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Eigen::Vector3f> points{{1.5f, 2, 3},     {nan, 0, 0},
                                            {4, 5, 6},        {7, 8, std::numeric_limits<float>::infinity()},
                                            {-1, -2, -3.25f}, {0, 0, 0}};
  std::size_t non_finite = 0;
  const io::Points got = cloudPoints(floatCloud(points, 3), &non_finite);
  EXPECT_EQ(non_finite, 2u);
  EXPECT_EQ(got, (io::Points{{1.5, 2, 3}, {4, 5, 6}, {-1, -2, -3.25}, {0, 0, 0}}));
}

TEST(CloudPoints, AMissingFieldOrShortDataIsNamed) {
  auto c = floatCloud({{1, 2, 3}}, 1);
  auto no_z = c;
  no_z.fields.pop_back();
  try {
    cloudPoints(no_z);
    FAIL() << "a cloud without z was read";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "PointCloud2: no field z");
  }
  auto short_data = c;
  short_data.data.resize(10);
  EXPECT_THROW(cloudPoints(short_data), Error);
  auto ints = c;
  ints.fields[0].datatype = sensor_msgs::PointField::INT32;
  EXPECT_THROW(cloudPoints(ints), Error);
}

hulls::Obstacle cube(int id, const Eigen::Vector3d& lo, double size) {
  std::vector<Eigen::Vector3d> centers{lo + Eigen::Vector3d::Constant(size / 2)};
  auto obstacles = hulls::buildObstacles(centers, {1}, {0}, size);
  obstacles.at(0).id = id;
  return obstacles.at(0);
}

TEST(ObstacleMarkers, HullTrianglesFootprintsLabelsAndDeletesForStaleIds) {
  const std::vector<hulls::Obstacle> obstacles{cube(3, {0, 0, 0}, 1.0), cube(5, {4, 0, 0}, 0.5)};
  std_msgs::Header header;
  header.frame_id = "map";
  const auto array = obstacleMarkers(obstacles, {1, 3, 5, 8}, header);
  std::map<std::pair<std::string, int>, const visualization_msgs::Marker*> by_key;
  for (const auto& m : array.markers) by_key[{m.ns, m.id}] = &m;
  ASSERT_EQ(array.markers.size(), 3 * 2 + 3 * 2u);
  for (const auto& o : obstacles) {
    const auto& hull = *by_key.at({"hulls", o.id});
    EXPECT_EQ(hull.type, visualization_msgs::Marker::TRIANGLE_LIST);
    ASSERT_EQ(hull.points.size(), 3 * o.hull.triangles.size());
    for (std::size_t t = 0; t < o.hull.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const auto& v = o.hull.vertices[o.hull.triangles[t][k]];
        EXPECT_EQ(hull.points[3 * t + k].x, v.x());
        EXPECT_EQ(hull.points[3 * t + k].z, v.z());
      }
    }
    const auto& footprint = *by_key.at({"footprints", o.id});
    EXPECT_EQ(footprint.points.size(), o.footprint.polygon.size() + 1);  // closed
    EXPECT_EQ(by_key.at({"labels", o.id})->text, std::to_string(o.id));
    EXPECT_EQ(hull.header.frame_id, "map");
  }
  for (int stale : {1, 8}) {
    for (const char* ns : {"hulls", "footprints", "labels"}) {
      EXPECT_EQ(by_key.at({ns, stale})->action, visualization_msgs::Marker::DELETE) << ns << " " << stale;
    }
  }
}

TEST(ProjectedMap, MarksExactlyTheCellsTheFootprintsInTheBandTouch) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-2.0, 2.0);
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
  const auto grid = projectedMap(obstacles, resolution, 1.2, 3.1, 0.2, std_msgs::Header());
  ASSERT_GT(grid.info.width * grid.info.height, 1u);
  std::size_t occupied = 0;
  for (std::uint32_t r = 0; r < grid.info.height; ++r) {
    for (std::uint32_t c = 0; c < grid.info.width; ++c) {
      const Eigen::Vector2d lo(grid.info.origin.position.x + c * resolution,
                               grid.info.origin.position.y + r * resolution);
      const Eigen::Vector2d hi = lo + Eigen::Vector2d::Constant(resolution);
      bool expected = false;
      for (const auto& o : obstacles) {
        if (o.footprint.z_max >= 1.2 && o.footprint.z_min <= 3.1)  // obstacles 1, 2, 3
          expected = expected || test::meetsOracle(o.footprint.polygon, lo, hi);
      }
      EXPECT_EQ(grid.data[r * grid.info.width + c], expected ? 100 : 0) << "cell " << r << "," << c;
      occupied += expected;
    }
  }
  EXPECT_GT(occupied, 0u);
}

TEST(OccupiedCellMarkers, OneCubeListPerDepthAsOctomapServer) {
  std::vector<mapper::OccupiedVoxel> voxels(2);
  voxels[0].center = {0.025, 0.025, 0.025};
  voxels[1].center = {1.025, 0.025, 0.025};
  std_msgs::Header header;
  header.frame_id = "map";
  const auto array = occupiedCellMarkers(voxels, 0.05, header);
  ASSERT_EQ(array.markers.size(), 17u);
  EXPECT_EQ(array.markers[16].type, visualization_msgs::Marker::CUBE_LIST);
  EXPECT_EQ(array.markers[16].points.size(), 2u);
  EXPECT_DOUBLE_EQ(array.markers[16].scale.x, 0.05);
  EXPECT_EQ(array.markers[16].ns, "map");
  EXPECT_EQ(array.markers[3].action, visualization_msgs::Marker::DELETE);
}

}  // namespace
}  // namespace hullmap::ros1
