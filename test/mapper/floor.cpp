// Floor and ceiling: RANSAC + least squares on generated tilted rooms, maps without a floor, the
// real EuRoC V1_01 map; levelling; the --floor parser; voxel classification.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/core/constants.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/floor.hpp"
#include "hullmap/mapper/frame.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace {

using hullmap::test::errorOf;
using namespace hullmap::mapper;
using namespace hullmap::io;
using namespace hullmap::sim;

using hullmap::kPi;

// A z-up room: a 6 x 6 m floor at z = 0 (`floor_points`), four walls (x or y = +-3, z 0..2.5) and a
// table top at z = 0.75, with 1 cm noise, then uniform outliers in the room's volume; finally
// rotated by `tilt` and lifted by `lift`.
Points room(std::size_t floor_points, double noise, std::size_t outliers, const Eigen::Matrix3d& tilt,
            const Eigen::Vector3d& lift, std::uint64_t seed = 5) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 3.0), h(0.0, 2.5);
  std::normal_distribution<double> n(0.0, noise);
  Points pts;
  for (std::size_t i = 0; i < floor_points; ++i) pts.emplace_back(u(rng), u(rng), n(rng));
  for (int i = 0; i < 4000; ++i) {
    const double s = (i % 2) ? 3.0 : -3.0;
    if (i % 4 < 2)
      pts.emplace_back(s + n(rng), u(rng), h(rng));
    else
      pts.emplace_back(u(rng), s + n(rng), h(rng));
  }
  for (int i = 0; i < 2000; ++i) pts.emplace_back(0.5 * u(rng), 0.3 * u(rng), 0.75 + n(rng));
  for (std::size_t i = 0; i < outliers; ++i) pts.emplace_back(u(rng), u(rng), h(rng));
  for (Point& p : pts) p = tilt * p + lift;
  return pts;
}

TEST(MapperFloor, FindsATiltedNoisyFloorUnderWallsAndATable) {
  for (const double tilt_deg : {0.0, 8.0, 21.0}) {
    SCOPED_TRACE(tilt_deg);
    const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 0).normalized();
    const Eigen::Matrix3d r = Eigen::AngleAxisd(tilt_deg * kPi / 180, axis).toRotationMatrix();
    const Eigen::Vector3d lift(0.3, -0.2, -1.4);
    const Points pts = room(3000, 0.01, 500, r, lift);
    const PlaneFit fit = findBoundingPlane(pts, PlaneSide::kFloor);
    ASSERT_TRUE(fit.found) << fit.reason;
    const Eigen::Vector3d true_normal = r * Eigen::Vector3d::UnitZ();
    EXPECT_LT(std::acos(std::min(1.0, fit.plane.normal.dot(true_normal))) * 180 / kPi, 0.5);
    EXPECT_NEAR(fit.tilt_deg, tilt_deg, 0.5);
    EXPECT_NEAR(fit.plane.offset, true_normal.dot(lift), 0.01);
    // The floor's points are the inliers (+- the walls' feet and outliers within the band).
    EXPECT_GE(fit.inliers, 2900u);
    EXPECT_LE(fit.inliers, 3200u);
    EXPECT_GT(fit.coverage, 0.8);

    // Levelling puts it at z = 0, level.
    const Eigen::Isometry3d level = levelingTransform(fit.plane);
    const Eigen::Vector3d on_floor = r * Eigen::Vector3d(1.0, -2.0, 0.0) + lift;
    EXPECT_NEAR((level * on_floor).z(), 0.0, 0.01);
    EXPECT_TRUE((level.linear() * fit.plane.normal).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
    EXPECT_NEAR(level.linear().determinant(), 1.0, 1e-12);
  }
}

// The counts are taken over the points as columns (vectorised): every point counted as
// Plane::signedDistance places it, the points on the band's edges included.
TEST(MapperFloor, CountsAreThoseOfEveryPointsSignedDistance) {
  for (const double tilt_deg : {0.0, 13.0}) {
    SCOPED_TRACE(tilt_deg);
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(tilt_deg * kPi / 180, Eigen::Vector3d(2, -1, 0).normalized()).toRotationMatrix();
    Points pts = room(3000, 0.01, 500, r, Eigen::Vector3d(0.1, 0.4, 0.7));
    PlaneSearchParams params;
    params.band = 0.02;
    const PlaneFit first = findBoundingPlane(pts, PlaneSide::kFloor, params);
    ASSERT_TRUE(first.found) << first.reason;
    // Points put on the found plane's band edges, and just inside and outside them.
    const Eigen::Vector3d n = first.plane.normal;
    const Eigen::Vector3d on = n * first.plane.offset;
    for (const double d : {params.band, -params.band, std::nextafter(params.band, 1.0),
                           std::nextafter(-params.band, -1.0), std::nextafter(params.band, 0.0)}) {
      for (int k = 0; k < 20; ++k) pts.push_back(on + n.unitOrthogonal() * (0.1 * k) + n * d);
    }
    const PlaneFit fit = findBoundingPlane(pts, PlaneSide::kFloor, params);
    ASSERT_TRUE(fit.found) << fit.reason;
    std::size_t inliers = 0, beyond = 0;
    for (const Point& p : pts) {
      const double d = fit.plane.signedDistance(p);
      if (std::abs(d) <= params.band)
        ++inliers;
      else if (d < -params.band)
        ++beyond;
    }
    EXPECT_EQ(fit.inliers, inliers);
    EXPECT_EQ(fit.inlier_share, static_cast<double>(inliers) / static_cast<double>(pts.size()));
    EXPECT_EQ(fit.beyond_share, static_cast<double>(beyond) / static_cast<double>(pts.size()));
  }
}

TEST(MapperFloor, FixedTiltFindsOnlyTheHeight) {
  const Points pts = room(3000, 0.01, 500, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 2.0));
  PlaneSearchParams params;
  params.fit_tilt = false;
  const PlaneFit fit = findBoundingPlane(pts, PlaneSide::kFloor, params);
  ASSERT_TRUE(fit.found) << fit.reason;
  EXPECT_EQ(fit.plane.normal, Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(fit.plane.offset, 2.0, 0.005);
  EXPECT_EQ(fit.tilt_deg, 0.0);
}

TEST(MapperFloor, FindsTheCeilingWhenThereIsOne) {
  Points pts = room(3000, 0.01, 500, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int i = 0; i < 2500; ++i) pts.emplace_back(u(rng), u(rng), 2.5);
  const PlaneFit ceiling = findBoundingPlane(pts, PlaneSide::kCeiling);
  ASSERT_TRUE(ceiling.found) << ceiling.reason;
  EXPECT_TRUE(ceiling.plane.normal.isApprox(-Eigen::Vector3d::UnitZ(), 1e-3));
  EXPECT_NEAR(-ceiling.plane.offset, 2.5, 0.005);
  // Without ceiling points the top of the walls is not taken as a ceiling.
  const PlaneFit none = findBoundingPlane(room(3000, 0.01, 500, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()),
                                          PlaneSide::kCeiling);
  EXPECT_FALSE(none.found);
}

TEST(MapperFloor, AMapWithoutFloorHasNone) {
  // Walls and a table only.
  const Points walls = room(0, 0.01, 500, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
  const PlaneFit a = findBoundingPlane(walls, PlaneSide::kFloor);
  EXPECT_FALSE(a.found) << "inliers " << a.inliers << " coverage " << a.coverage;
  EXPECT_FALSE(a.reason.empty());

  // Blobs floating at random heights (nothing stands on anything): no plane under them.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-5.0, 5.0), h(0.0, 3.0);
  std::normal_distribution<double> n(0.0, 0.15);
  Points blobs;
  for (int b = 0; b < 30; ++b) {
    const Eigen::Vector3d c(u(rng), u(rng), h(rng));
    for (int i = 0; i < 300; ++i) blobs.push_back(c + Eigen::Vector3d(n(rng), n(rng), n(rng)));
  }
  const PlaneFit c = findBoundingPlane(blobs, PlaneSide::kFloor);
  EXPECT_FALSE(c.found) << "inliers " << c.inliers << " coverage " << c.coverage;

  EXPECT_FALSE(findBoundingPlane(Points{{0, 0, 0}, {1, 0, 0}}, PlaneSide::kFloor).found);
}

TEST(MapperFloor, BoxesOnAnUnseenFloorShowItByTheirFeet) {
  // The simple generated scene has no floor points, but its boxes and cylinders stand on z = 0 and
  // their bottom edges lie on it: that plane is the floor, level, at the right height.
  SceneParams p;
  p.orbslam_frame = false;
  const Scene scene = generateScene(p);
  const PlaneFit b = findBoundingPlane(scene.points, PlaneSide::kFloor);
  ASSERT_TRUE(b.found) << b.reason;
  EXPECT_LT(b.tilt_deg, 1.0);
  EXPECT_NEAR(b.plane.offset, 0.0, 0.01);
}

TEST(MapperFloor, RejectsBadParameters) {
  PlaneSearchParams p;
  p.band = 0.0;
  EXPECT_NE(errorOf([&] { findBoundingPlane({}, PlaneSide::kFloor, p); }).rfind("floor: ", 0), std::string::npos);
  p = {};
  p.up = Eigen::Vector3d::Zero();
  EXPECT_NE(errorOf([&] { findBoundingPlane({}, PlaneSide::kFloor, p); }).rfind("floor: ", 0), std::string::npos);
  p = {};
  p.max_tilt_deg = 90.0;
  EXPECT_NE(errorOf([&] { findBoundingPlane({}, PlaneSide::kFloor, p); }).find("tilt"), std::string::npos);
  const Points bad = {{0, 0, 0}, {1, 0, 0}, {0, 1, std::nan("")}};
  EXPECT_NE(errorOf([&] { findBoundingPlane(bad, PlaneSide::kFloor); }).find("non-finite"), std::string::npos);
}

TEST(MapperFloor, ParsesTheFloorSetting) {
  EXPECT_EQ(parsePlaneSetting("--floor", "auto").mode, PlaneSetting::Mode::kAuto);
  EXPECT_EQ(parsePlaneSetting("--floor", "none").mode, PlaneSetting::Mode::kNone);
  const PlaneSetting s = parsePlaneSetting("--floor", "-0.25");
  EXPECT_EQ(s.mode, PlaneSetting::Mode::kHeight);
  EXPECT_EQ(s.height, -0.25);
  for (const std::string bad : {"", "floor", "1m", "nan", "inf"}) {
    const std::string msg = errorOf([&] { parsePlaneSetting("--ceiling", bad); });
    EXPECT_NE(msg.find("--ceiling"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'" + bad + "'"), std::string::npos) << msg;
  }
}

TEST(MapperFloor, ClassifiesVoxelsWithinTheBand) {
  const Plane floor = horizontalPlane(0.0, PlaneSide::kFloor);
  const Plane ceiling = horizontalPlane(2.5, PlaneSide::kCeiling);
  const std::vector<Eigen::Vector3d> c = {{0, 0, 0.025}, {0, 0, 0.075}, {0, 0, -1.0}, {0, 0, 1.2},
                                          {0, 0, 2.475}, {0, 0, 2.425}, {0, 0, 7.0}};
  const auto k = classifySurfaces(c, floor, ceiling, 0.05);
  const std::vector<SurfaceClass> want = {SurfaceClass::kFloor,    SurfaceClass::kObstacle, SurfaceClass::kFloor,
                                          SurfaceClass::kObstacle, SurfaceClass::kCeiling,  SurfaceClass::kObstacle,
                                          SurfaceClass::kCeiling};
  EXPECT_EQ(k, want);
  // Brute force against the definition on a random tilted plane.
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  Plane tilted;
  tilted.normal = Eigen::Vector3d(0.1, -0.2, 1.0).normalized();
  tilted.offset = 0.3;
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 1000; ++i) pts.emplace_back(u(rng), u(rng), u(rng));
  const auto only_floor = classifySurfaces(pts, tilted, std::nullopt, 0.1);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double d = tilted.normal.dot(pts[i]) - 0.3;
    EXPECT_EQ(only_floor[i] == SurfaceClass::kFloor, d <= 0.1) << i;
  }
  EXPECT_NE(errorOf([&] { classifySurfaces(c, floor, std::nullopt, -1.0); }).rfind("floor: ", 0), std::string::npos);
  EXPECT_EQ(classifySurfaces(c, std::nullopt, std::nullopt, 0.05), std::vector<SurfaceClass>(c.size()));
}

TEST(MapperFloor, RealEurocV101FloorIsTiltedInOrbSlamsFrame) {
  HULLMAP_REQUIRE_REAL_DATA(path, "orbslam2_euroc_V1_01_MapPoints.txt");
  PointSet set = readPointFile(path);
  toMapFrame(FrameParams{UpAxis::kNegY, 1.0}, set.points);
  PlaneSearchParams params;
  params.band = 0.05;
  const PlaneFit fit = findBoundingPlane(set.points, PlaneSide::kFloor, params);
  std::cout << "V1_01 floor: found " << fit.found << " (" << fit.reason << ") tilt " << fit.tilt_deg << " deg, normal "
            << fit.plane.normal.transpose() << ", offset " << fit.plane.offset << ", inliers " << fit.inliers << " ("
            << fit.inlier_share << "), beyond " << fit.beyond_share << ", coverage " << fit.coverage << "\n";
  ASSERT_TRUE(fit.found) << fit.reason;
  // ORB-SLAM's first camera was pitched down: --up -y leaves the floor far from level.
  EXPECT_GT(fit.tilt_deg, 10.0);
  EXPECT_LT(fit.tilt_deg, 30.0);
  EXPECT_LT(fit.beyond_share, 0.05);
}

TEST(MapperFloor, RealEurocMh01FloorIsTiltedInOrbSlamsFrame) {
  HULLMAP_REQUIRE_REAL_DATA(a, "orbslam3_euroc_MH_01_mono_pointcloud.txt");
  HULLMAP_REQUIRE_REAL_DATA(b, "orbslam3_euroc_MH_01_mono_ref_pointcloud.txt");
  PointSet set = readPointFiles({a, b});
  toMapFrame(FrameParams{UpAxis::kNegY, 1.0}, set.points);
  PlaneSearchParams params;
  params.band = 0.05;  // map units (monocular: not metres)
  const PlaneFit fit = findBoundingPlane(set.points, PlaneSide::kFloor, params);
  std::cout << "MH_01 floor: found " << fit.found << " (" << fit.reason << ") tilt " << fit.tilt_deg << " deg, normal "
            << fit.plane.normal.transpose() << ", offset " << fit.plane.offset << ", inliers " << fit.inliers << " ("
            << fit.inlier_share << "), beyond " << fit.beyond_share << ", coverage " << fit.coverage << "\n";
  ASSERT_TRUE(fit.found) << fit.reason;
  EXPECT_GT(fit.tilt_deg, 5.0);
  EXPECT_LT(fit.tilt_deg, 30.0);
}

}  // namespace
