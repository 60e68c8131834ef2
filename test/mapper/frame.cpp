// Frame change (up axis, scale) and filters (crop box, z bounds), and the option parsers.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/mapper/frame.hpp"
#include "test_support.hpp"

namespace {

using hullmap::Error;
using namespace hullmap::mapper;
using namespace hullmap::io;

using hullmap::test::errorOf;

struct AxisCase {
  const char* text;
  UpAxis up;
  Eigen::Vector3d axis;
};

const std::vector<AxisCase> kAxes = {
    {"x", UpAxis::kPosX, {1, 0, 0}},   {"-x", UpAxis::kNegX, {-1, 0, 0}}, {"y", UpAxis::kPosY, {0, 1, 0}},
    {"-y", UpAxis::kNegY, {0, -1, 0}}, {"z", UpAxis::kPosZ, {0, 0, 1}},   {"-z", UpAxis::kNegZ, {0, 0, -1}},
};

TEST(MapperFrame, EachUpAxisGoesToPlusZByAProperRotation) {
  for (const auto& c : kAxes) {
    SCOPED_TRACE(c.text);
    const Eigen::Matrix3d r = upRotation(c.up);
    EXPECT_EQ(r * c.axis, Eigen::Vector3d(0, 0, 1));  // exact: entries are 0 and ±1
    EXPECT_EQ(r.determinant(), 1.0);
    EXPECT_TRUE((r.transpose() * r).isIdentity(0.0));
  }
}

TEST(MapperFrame, OrbSlamCameraFrameBecomesZUp) {
  // ORB-SLAM: x right, y down, z forward. With up = -y: forward -> +y, down -> -z.
  const Eigen::Matrix3d r = upRotation(UpAxis::kNegY);
  EXPECT_EQ(r * Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(r * Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, -1));
  EXPECT_EQ(r * Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 0, 0));
  // It is the -90 degree rotation about x.
  EXPECT_TRUE(r.isApprox(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix(), 1e-15));
}

TEST(MapperFrame, ParseUpAxisAndToStringRoundTrip) {
  for (const auto& c : kAxes) {
    EXPECT_EQ(parseUpAxis(c.text), c.up) << c.text;
    EXPECT_EQ(parseUpAxis(toString(c.up)), c.up) << c.text;
  }
  EXPECT_EQ(parseUpAxis("+Z"), UpAxis::kPosZ);
  EXPECT_EQ(toString(UpAxis::kNegY), "-y");
  for (const std::string bad : {"", "w", "up", "--y", "xy"}) {
    const std::string msg = errorOf([&] { parseUpAxis(bad); });
    EXPECT_EQ(msg.rfind("up: ", 0), 0u) << msg;  // the library names the parameter, not a flag
    EXPECT_NE(msg.find("'" + bad + "'"), std::string::npos) << msg;
  }
}

TEST(MapperFrame, ToMapFrameScalesThenRotates) {
  Points points = {{1, 2, 3}, {0, 0, 0}, {-1, 0.5, 0}};
  toMapFrame(FrameParams{UpAxis::kNegY, 2.0}, points);
  // (x, y, z) -> 2 * (x, z, -y)
  EXPECT_EQ(points[0], Eigen::Vector3d(2, 6, -4));
  EXPECT_EQ(points[1], Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(points[2], Eigen::Vector3d(-2, 0, -1));
  Points unchanged = {{1, 2, 3}};
  toMapFrame(FrameParams{}, unchanged);
  EXPECT_EQ(unchanged[0], Eigen::Vector3d(1, 2, 3));
  for (const double bad : {0.0, -1.0, std::nan("")}) {
    try {
      toMapFrame(FrameParams{UpAxis::kPosZ, bad}, unchanged);
      ADD_FAILURE() << "scale " << bad << " accepted";
    } catch (const hullmap::Error& e) {
      EXPECT_EQ(e.parameter(), "scale") << e.what();
    }
  }
}

TEST(MapperFrame, KeyframesArePositionedAndOrientedInTheMapFrame) {
  Keyframe k;
  k.position = Eigen::Vector3d(1, 2, 3);
  k.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, -1).normalized()));
  const Eigen::Vector3d in_camera(0.2, -0.4, 1.5);
  const Eigen::Vector3d in_input = k.orientation * in_camera + k.position;  // camera-to-input
  for (const auto& c : kAxes) {
    SCOPED_TRACE(c.text);
    std::vector<Keyframe> kfs = {k};
    const FrameParams frame{c.up, 0.5};
    toMapFrame(frame, kfs);
    Points p = {in_input};
    toMapFrame(frame, p);
    // The camera-to-map pose maps the camera-frame point to where the points were moved: the
    // rotation part must be R * q (scale applies to translations only).
    const Eigen::Vector3d via_pose = kfs[0].orientation * (0.5 * in_camera) + kfs[0].position;
    EXPECT_TRUE(via_pose.isApprox(p[0], 1e-12)) << via_pose.transpose() << " vs " << p[0].transpose();
    EXPECT_NEAR(kfs[0].orientation.norm(), 1.0, 1e-12);
  }
}

TEST(MapperFrame, FiltersCountEachDroppedPointOnceAndKeepOrder) {
  const Points input = {
      {0, 0, 0},      // kept (on the crop's min corner: inclusive)
      {5, 0, 1},      // outside crop (x)
      {1, 1, -0.5},   // below z_min
      {2, 2, 2},      // kept (max corner, z == z_max)
      {1, 1, 2.5},    // outside crop (z > 2) before z_max is considered
      {0.5, 0.5, 1},  // kept
      {-0.1, 1, 1},   // outside crop
  };
  FilterParams f;
  f.crop = Box{Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(2, 2, 2)};
  f.z_min = -0.25;
  f.z_max = 2.0;
  Points points = input;
  InputStats stats;
  applyFilters(f, points, stats);
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[0], input[0]);
  EXPECT_EQ(points[1], input[3]);
  EXPECT_EQ(points[2], input[5]);
  EXPECT_EQ(stats.dropped.at("outside_crop"), 3u);
  EXPECT_EQ(stats.dropped.at("below_z_min"), 1u);
  EXPECT_EQ(stats.dropped.count("above_z_max"), 0u);
  EXPECT_EQ(stats.droppedTotal(), 4u);

  // z bounds alone; brute-force count as the oracle.
  FilterParams z;
  z.z_min = 0.5;
  z.z_max = 1.5;
  Points zp = input;
  InputStats zs;
  applyFilters(z, zp, zs);
  std::size_t below = 0, above = 0;
  for (const auto& p : input) below += p.z()<0.5, above += p.z()> 1.5;
  EXPECT_EQ(zs.dropped.at("below_z_min"), below);
  EXPECT_EQ(zs.dropped.at("above_z_max"), above);
  EXPECT_EQ(zp.size(), input.size() - below - above);
  for (const auto& p : zp) EXPECT_TRUE(p.z() >= 0.5 && p.z() <= 1.5);

  // No filters: nothing moves, nothing counted.
  Points all = input;
  InputStats none;
  applyFilters(FilterParams{}, all, none);
  EXPECT_EQ(all, input);
  EXPECT_TRUE(none.dropped.empty());
}

TEST(MapperFrame, ParseVector3AndBox) {
  EXPECT_EQ(parseVector3("--origin", "1, -2.5,3e1"), Eigen::Vector3d(1, -2.5, 30));
  const Box b = parseBox("--crop", "-1,-2,-3,1,2,3");
  EXPECT_EQ(b.min, Eigen::Vector3d(-1, -2, -3));
  EXPECT_EQ(b.max, Eigen::Vector3d(1, 2, 3));
  for (const std::string bad : {"", "1,2", "1,2,3,4", "1,,3", "a,b,c", "1,2,nan", "1;2;3"}) {
    const std::string msg = errorOf([&] { parseVector3("--origin", bad); });
    EXPECT_NE(msg.find("--origin: expected x,y,z"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'" + bad + "'"), std::string::npos) << msg;
  }
  EXPECT_NE(errorOf([] { parseBox("--crop", "0,0,0,1,1"); }).find("--crop: expected x0,y0,z0,x1,y1,z1"),
            std::string::npos);
  EXPECT_NE(errorOf([] { parseBox("--crop", "0,5,0,1,1,1"); }).find("--crop: min corner exceeds max corner on y"),
            std::string::npos);
}

}  // namespace
