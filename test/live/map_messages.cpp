// hullmap::live's messages to points: each against a direct statement of what the message means (a
// cloud's bytes laid out by hand, ORB-SLAM's map as the echo reader takes it, the bag rule by hand).
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/live/map_messages.hpp"

namespace hullmap::live {
namespace {

struct P {
  double x, y, z;
};

/// A cloud of `points` laid out by hand: a 4-byte something, then x, y, z of `datatype`, `pad` bytes
/// after each row; `width` points a row.
struct Cloud {
  CloudLayout layout;
  std::vector<std::uint8_t> data;
};

Cloud cloudOf(const std::vector<P>& points, std::uint32_t width, std::uint8_t datatype, std::uint32_t pad = 8) {
  Cloud c;
  const std::uint32_t size = datatype == kFloat32 ? 4 : 8;
  c.layout.fields = {{"x", 4, datatype}, {"y", 4 + size, datatype}, {"z", 4 + 2 * size, datatype}};
  c.layout.point_step = 4 + 3 * size + 4;
  c.layout.width = width;
  c.layout.height = static_cast<std::uint32_t>(points.size() / width);
  c.layout.row_step = c.layout.point_step * width + pad;
  c.data.assign(std::size_t{c.layout.row_step} * c.layout.height, 0xAB);
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::uint8_t* at = c.data.data() + (i / width) * c.layout.row_step + (i % width) * c.layout.point_step + 4;
    const double v[3] = {points[i].x, points[i].y, points[i].z};
    for (int k = 0; k < 3; ++k) {
      if (datatype == kFloat32) {
        const float f = static_cast<float>(v[k]);
        std::memcpy(at + 4 * k, &f, 4);
      } else {
        std::memcpy(at + 8 * k, &v[k], 8);
      }
    }
  }
  return c;
}

io::Points read(const Cloud& c, std::size_t* non_finite = nullptr) {
  return cloudPoints(c.layout, c.data.data(), c.data.size(), non_finite);
}

TEST(LiveCloudPoints, ReadsFloat32AndFloat64RowsWithPaddingAndCountsNonFinitePoints) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<P> points{{1.5, 2, 3},     {nan, 0, 0},
                              {4, 5, 6},       {7, 8, std::numeric_limits<double>::infinity()},
                              {-1, -2, -3.25}, {0.1, 0.2, 0.3}};
  for (const std::uint8_t datatype : {kFloat32, kFloat64}) {
    std::size_t non_finite = 0;
    const io::Points got = read(cloudOf(points, 3, datatype), &non_finite);
    EXPECT_EQ(non_finite, 2u);
    const double last = datatype == kFloat32 ? double(0.1f) : 0.1;
    ASSERT_EQ(got.size(), 4u);
    EXPECT_EQ(got[0], Eigen::Vector3d(1.5, 2, 3));
    EXPECT_EQ(got[2], Eigen::Vector3d(-1, -2, -3.25));
    EXPECT_EQ(got[3].x(), last) << "FLOAT64 keeps every bit, FLOAT32 its float";
  }
}

TEST(LiveCloudPoints, AMissingOrWrongFieldOrShortDataIsNamed) {
  const Cloud good = cloudOf({{1, 2, 3}}, 1, kFloat32);
  auto expectError = [](const Cloud& c, const std::string& what) {
    try {
      read(c);
      ADD_FAILURE() << "read: " << what;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  Cloud no_z = good;
  no_z.layout.fields.pop_back();
  expectError(no_z, "PointCloud2: no field z");
  Cloud ints = good;
  ints.layout.fields[0].datatype = 5;  // INT32
  expectError(ints, "field x is of datatype 5");
  Cloud beyond = good;
  beyond.layout.fields[2].offset = beyond.layout.point_step - 2;
  expectError(beyond, "lies beyond point_step");
  Cloud short_data = good;
  short_data.data.resize(10);
  expectError(short_data, "data holds 10 bytes");
  Cloud big = good;
  big.layout.is_bigendian = true;
  expectError(big, "big-endian");
}

struct MarkerPoint {
  double x, y, z;
};

bool add(OrbSlamMapMarkers& map, const std::string& ns, int id, const std::vector<MarkerPoint>& points,
         int action = marker::kAdd, int type = marker::kPoints) {
  return map.add(MarkerKey{ns, id, type, action}, points);
}

TEST(LiveOrbSlamMapMarkers, TheMapIsTheLatestId0PlusTheLatestId6) {
  OrbSlamMapMarkers map;
  EXPECT_TRUE(map.empty());
  EXPECT_TRUE(add(map, "MapPoints", 6, {{9, 9, 9}}));
  EXPECT_TRUE(add(map, "MapPoints", 0, {{1, 0, 0}}));
  EXPECT_TRUE(add(map, "MapPoints", 0, {{2, 0, 0}, {3, 0, 0}}));
  EXPECT_FALSE(add(map, "KeyFrames", 1, {{5, 5, 5}}));
  EXPECT_FALSE(add(map, "MapPoints", 2, {{5, 5, 5}}));  // another id: not map points
  EXPECT_FALSE(add(map, "MapPoints", 0, {{5, 5, 5}}, marker::kAdd, marker::kLineList));
  EXPECT_EQ(map.points(), (io::Points{{2, 0, 0}, {3, 0, 0}, {9, 9, 9}}));
  EXPECT_TRUE(add(map, "MapPoints", 6, {}, marker::kDelete));
  EXPECT_FALSE(add(map, "MapPoints", 6, {}, marker::kDelete));  // nothing left to delete
  EXPECT_EQ(map.points(), (io::Points{{2, 0, 0}, {3, 0, 0}}));
  EXPECT_TRUE(add(map, "MapPoints", 0, {}, marker::kDeleteAll));
  EXPECT_TRUE(map.empty());
}

TEST(LiveOrbSlamMapMarkers, ANonFinitePointRefusesTheMarkerAndKeepsTheMap) {
  OrbSlamMapMarkers map;
  add(map, "MapPoints", 0, {{1, 2, 3}});
  try {
    add(map, "MapPoints", 0, {{0, 0, 0}, {std::numeric_limits<double>::quiet_NaN(), 1, 1}});
    FAIL() << "a NaN was taken";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "MapPoints id 0: point 1 is not finite");
  }
  EXPECT_EQ(map.points(), (io::Points{{1, 2, 3}}));
}

TEST(LiveTopicMap, CloudsEndOnTheLastWellFormedCloudAndMarkersOnTheirMap) {
  TopicMap clouds;
  const Cloud first = cloudOf({{1, 1, 1}}, 1, kFloat64);
  const Cloud second = cloudOf({{2, 2, 2}, {3, 3, 3}}, 2, kFloat64);
  Cloud no_z = cloudOf({{4, 4, 4}}, 1, kFloat64);
  no_z.layout.fields.pop_back();
  for (const Cloud* c : {&first, &second, static_cast<const Cloud*>(&no_z)})
    clouds.addCloud("PointCloud2", c->layout, c->data.data(), c->data.size());
  const BagMap cloud_map = clouds.result();
  EXPECT_EQ(cloud_map.points, (io::Points{{2, 2, 2}, {3, 3, 3}}));
  EXPECT_EQ(cloud_map.messages, 3u);
  EXPECT_EQ(cloud_map.skipped, 1u);
  EXPECT_EQ(cloud_map.type, "PointCloud2");

  TopicMap markers;
  const std::vector<MarkerPoint> all{{1, 0, 0}}, reference{{0, 6, 0}};
  const std::vector<MarkerPoint> bad{{std::numeric_limits<double>::infinity(), 0, 0}};
  markers.addMarker("Marker", {"MapPoints", 0, marker::kPoints, marker::kAdd}, all);
  markers.addMarker("Marker", {"MapPoints", 6, marker::kPoints, marker::kAdd}, reference);
  markers.addMarker("Marker", {"MapPoints", 0, marker::kPoints, marker::kAdd}, bad);
  markers.addMarker("Marker", {"KeyFrames", 1, marker::kLineList, marker::kAdd}, all);
  const BagMap marker_map = markers.result();
  EXPECT_EQ(marker_map.points, (io::Points{{1, 0, 0}, {0, 6, 0}}));
  EXPECT_EQ(marker_map.messages, 4u);
  EXPECT_EQ(marker_map.skipped, 1u);
}

TEST(LiveKeyframes, NormalisedWhenFiniteRefusedWhole) {
  std::vector<io::Keyframe> k(2);
  k[0].orientation = Eigen::Quaterniond(2, 0, 0, 0);
  k[1].orientation = Eigen::Quaterniond(0, 0, 0, 3);
  EXPECT_TRUE(normaliseKeyframes(k));
  EXPECT_DOUBLE_EQ(k[0].orientation.w(), 1.0);
  EXPECT_DOUBLE_EQ(k[1].orientation.z(), 1.0);
  auto zero = k;
  zero[1].orientation = Eigen::Quaterniond(0, 0, 0, 0);
  EXPECT_FALSE(normaliseKeyframes(zero));
  auto nan = k;
  nan[0].position.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(normaliseKeyframes(nan));
}

TEST(LiveSequenceGaps, CountsTheNumbersSkippedPerPublisher) {
  SequenceGaps gaps;
  EXPECT_EQ(gaps.missed("a", 5), 0u);  // the first seen: nothing known before it
  EXPECT_EQ(gaps.missed("a", 6), 0u);
  EXPECT_EQ(gaps.missed("b", 1), 0u);
  EXPECT_EQ(gaps.missed("a", 9), 2u);  // 7 and 8
  EXPECT_EQ(gaps.missed("b", 2), 0u);  // b's numbers are its own
  EXPECT_EQ(gaps.missed("a", 9), 0u);  // not newer: no gap, and the last stays 9
  EXPECT_EQ(gaps.missed("a", 10), 0u);
  gaps.clear();
  EXPECT_EQ(gaps.missed("a", 20), 0u);
}

}  // namespace
}  // namespace hullmap::live
