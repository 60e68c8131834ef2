#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hullmap/core/error.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace hullmap::sim {
namespace {

using namespace hullmap::io;

// Exact distance from p to the surface of an obstacle (the oracle for "points lie on surfaces").
double surfaceDistance(const TruthShape& o, const Eigen::Vector3d& p) {
  const Eigen::Vector3d h = 0.5 * o.size;
  const Eigen::Vector3d d = p - o.center;
  if (o.shape == TruthShape::Shape::kBox) {
    const Eigen::Vector3d q = d.cwiseAbs() - h;
    const double outside = q.cwiseMax(0.0).norm();
    const double inside = std::min(q.maxCoeff(), 0.0);
    return std::abs(outside + inside);
  }
  const double radial = std::hypot(d.x(), d.y()) - h.x();
  const double axial = std::abs(d.z()) - h.z();
  const double outside = std::hypot(std::max(radial, 0.0), std::max(axial, 0.0));
  const double inside = std::min(std::max(radial, axial), 0.0);
  return std::abs(outside + inside);
}

// Distance to the nearest edge of a box (12 segments) or a cylinder (two rims).
double edgeDistance(const TruthShape& o, const Eigen::Vector3d& p) {
  const Eigen::Vector3d h = 0.5 * o.size;
  const Eigen::Vector3d d = (p - o.center).cwiseAbs();
  if (o.shape == TruthShape::Shape::kCylinder) {
    return std::hypot(std::hypot(d.x(), d.y()) - h.x(), d.z() - h.z());
  }
  double best = 1e300;
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Vector3d q = d - h;
    q[axis] = std::max(0.0, d[axis] - h[axis]);
    best = std::min(best, q.norm());
  }
  return best;
}

SceneParams smallScene() {
  SceneParams p;
  p.points = 20000;
  p.orbslam_frame = false;
  return p;
}

TEST(MapperScene, SameSeedSameSceneOtherSeedOtherScene) {
  const Scene a = generateScene(smallScene());
  const Scene b = generateScene(smallScene());
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) ASSERT_EQ(a.points[i], b.points[i]) << i;
  ASSERT_EQ(a.truth.shapes.size(), b.truth.shapes.size());
  for (std::size_t i = 0; i < a.truth.shapes.size(); ++i) EXPECT_EQ(a.truth.shapes[i].center, b.truth.shapes[i].center);

  SceneParams other = smallScene();
  other.seed = 7;
  const Scene c = generateScene(other);
  EXPECT_NE(a.truth.shapes[0].center, c.truth.shapes[0].center);
}

TEST(MapperScene, CountsObstacleGapsAndSurfaces) {
  const SceneParams p = smallScene();
  const Scene s = generateScene(p);
  ASSERT_EQ(s.points.size(), p.points);
  const std::vector<TruthShape>& obstacles = s.truth.shapes;  // boxes and cylinders
  ASSERT_EQ(obstacles.size(), p.obstacles);
  ASSERT_EQ(s.keyframes.size(), p.keyframes);

  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const TruthShape& a = obstacles[i];
    EXPECT_TRUE(a.shape == TruthShape::Shape::kBox || a.shape == TruthShape::Shape::kCylinder);
    EXPECT_EQ(a.label, a.kind + " " + std::to_string(i));
    EXPECT_NEAR(a.center.z(), 0.5 * a.size.z(), 1e-12) << "stands on the floor";
    EXPECT_LE(std::abs(a.center.x()) + 0.5 * a.size.x(), 0.5 * p.room_size);
    EXPECT_LE(std::abs(a.center.y()) + 0.5 * a.size.y(), 0.5 * p.room_size);
    for (std::size_t j = i + 1; j < obstacles.size(); ++j) {
      const TruthShape& b = obstacles[j];
      const double gx = std::abs(a.center.x() - b.center.x()) - 0.5 * (a.size.x() + b.size.x());
      const double gy = std::abs(a.center.y() - b.center.y()) - 0.5 * (a.size.y() + b.size.y());
      EXPECT_GE(std::max(gx, gy), kSceneObstacleGap) << i << " vs " << j;
    }
  }

  std::size_t on_surface = 0, near_edge = 0, in_room = 0, gross = 0;
  const double tolerance = 6.0 * p.noise_sigma * std::sqrt(3.0);
  for (const auto& q : s.points) {
    double surface = 1e300, edge = 1e300;
    for (const auto& o : obstacles) {
      surface = std::min(surface, surfaceDistance(o, q));
      edge = std::min(edge, edgeDistance(o, q));
    }
    if (q.norm() >= 1e5 * 0.999 && q.norm() <= 1e6 * 1.001) {
      ++gross;
    } else if (surface <= tolerance) {
      ++on_surface;
      near_edge += edge <= tolerance;
    } else {
      const double half = 0.5 * p.room_size;
      EXPECT_TRUE(std::abs(q.x()) <= half && std::abs(q.y()) <= half && q.z() >= 0 && q.z() <= p.room_height)
          << q.transpose();
      ++in_room;
    }
  }
  EXPECT_EQ(gross, p.gross_outliers);
  const std::size_t outliers = static_cast<std::size_t>(std::llround(p.outlier_fraction * p.points));
  const std::size_t surface_points = p.points - outliers - p.gross_outliers;
  // Uniform outliers can land near a surface by chance; at most a few.
  EXPECT_GE(on_surface, surface_points);
  EXPECT_LE(on_surface, surface_points + outliers / 10);
  EXPECT_GE(in_room + on_surface - surface_points, outliers);
  // About half the surface points imitate ORB features on edges.
  EXPECT_GT(near_edge, surface_points * 45 / 100);
  EXPECT_LT(near_edge, surface_points * 70 / 100);
}

TEST(MapperScene, CamerasLoopAroundAndLookInward) {
  const SceneParams p = smallScene();
  const Scene s = generateScene(p);
  for (const Keyframe& k : s.keyframes) {
    EXPECT_NEAR(k.orientation.norm(), 1.0, 1e-12);
    EXPECT_NEAR(k.position.z(), 1.2, 0.06);
    const Eigen::Vector3d forward = k.orientation * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d down = k.orientation * Eigen::Vector3d::UnitY();
    EXPECT_GT(forward.dot(-k.position.normalized()), 0.9);
    EXPECT_LT(down.z(), -0.9) << "camera y axis points down";
    for (const auto& o : s.truth.shapes) {
      EXPECT_GT((k.position - o.center).head<2>().norm(), 0.5 * o.size.head<2>().norm() + kSceneObstacleGap - 1e-9);
    }
  }
  for (std::size_t i = 1; i < s.keyframes.size(); ++i) EXPECT_GT(s.keyframes[i].stamp, s.keyframes[i - 1].stamp);
}

TEST(MapperScene, OrbSlamFrameIsTheRotatedMapFrame) {
  SceneParams p = smallScene();
  const Scene map = generateScene(p);
  p.orbslam_frame = true;
  const Scene orb = generateScene(p);
  const Eigen::Matrix3d m = mapToOrbSlamRotation();
  EXPECT_NEAR(m.determinant(), 1.0, 1e-15);
  EXPECT_TRUE((m * Eigen::Vector3d::UnitZ()).isApprox(-Eigen::Vector3d::UnitY())) << "map up is ORB-SLAM -y";
  ASSERT_EQ(map.points.size(), orb.points.size());
  for (std::size_t i = 0; i < map.points.size(); ++i) {
    ASSERT_TRUE((m.transpose() * orb.points[i]).isApprox(map.points[i], 1e-12)) << i;
  }
  for (std::size_t i = 0; i < map.keyframes.size(); ++i) {
    EXPECT_TRUE((m.transpose() * orb.keyframes[i].position).isApprox(map.keyframes[i].position, 1e-12));
    const Eigen::Matrix3d back = m.transpose() * orb.keyframes[i].orientation.toRotationMatrix();
    EXPECT_TRUE(back.isApprox(map.keyframes[i].orientation.toRotationMatrix(), 1e-12));
  }
}

TEST(MapperScene, WritesTheThreeFilesItDescribes) {
  SceneParams p = smallScene();
  p.points = 5000;
  const Scene s = generateScene(p);
  const auto dir = test::freshDir("mapper_scene_write");
  writeScene(s, p, dir.string());

  std::ifstream points(dir / "map_points.txt");
  std::string line;
  std::size_t n = 0;
  while (std::getline(points, line)) {
    std::istringstream in(line);
    Eigen::Vector3d q;
    ASSERT_TRUE(in >> q.x() >> q.y() >> q.z()) << line;
    ASSERT_TRUE(q.isApprox(s.points[n], 1e-6) || (q - s.points[n]).norm() < 2e-6) << n;
    ++n;
  }
  EXPECT_EQ(n, p.points);

  std::ifstream trajectory(dir / "KeyFrameTrajectory.txt");
  std::size_t k = 0;
  while (std::getline(trajectory, line)) {
    std::istringstream in(line);
    double v[8];
    for (double& x : v) ASSERT_TRUE(in >> x) << line;
    EXPECT_NEAR(v[0], s.keyframes[k].stamp, 1e-6);
    EXPECT_NEAR(v[7], s.keyframes[k].orientation.w(), 1e-8);
    ++k;
  }
  EXPECT_EQ(k, p.keyframes);

  std::ifstream json(dir / "ground_truth.json");
  const auto j = nlohmann::json::parse(json);
  EXPECT_EQ(j.at("frame"), "z-up map");
  ASSERT_EQ(j.at("obstacles").size(), s.truth.shapes.size());
  for (std::size_t i = 0; i < s.truth.shapes.size(); ++i) {
    const auto& o = j.at("obstacles")[i];
    const TruthShape& truth = s.truth.shapes[i];
    EXPECT_EQ(o.at("shape"), truth.shape == TruthShape::Shape::kBox ? "box" : "cylinder");
    EXPECT_FALSE(o.contains("kind"));
    EXPECT_DOUBLE_EQ(o.at("center")[0].get<double>(), truth.center.x());
    EXPECT_DOUBLE_EQ(o.at("size")[2].get<double>(), truth.size.z());
  }
}

// maps/simple is `hullmap generate -o maps/simple --seed 42` (the default scene): the files the
// generator writes are, byte for byte, the ones in the repository.
TEST(MapperScene, MapsSimpleIsTheDefaultScene) {
  const std::filesystem::path dir = std::filesystem::path(HULLMAP_SOURCE_DIR) / "maps" / "simple";
  const SceneParams p;
  const Scene s = generateScene(p);
  const auto out = test::freshDir("maps_simple");
  writeScene(s, p, out.string());
  for (const char* name : {"map_points.txt", "KeyFrameTrajectory.txt", "ground_truth.json"}) {
    const std::string expected = hullmap::test::slurp(dir / name);
    const std::string written = hullmap::test::slurp(out / name);
    ASSERT_FALSE(expected.empty()) << (dir / name);
    const auto first = std::mismatch(expected.begin(), expected.end(), written.begin(), written.end());
    EXPECT_TRUE(expected == written) << name << ": " << written.size() << " bytes written, " << expected.size()
                                     << " in maps/simple; first difference at byte "
                                     << (first.first - expected.begin());
  }
  EXPECT_FALSE(std::filesystem::exists(out / "reference_trajectory.txt"));
}

TEST(MapperScene, RejectsImpossibleParameters) {
  SceneParams p = smallScene();
  p.obstacles = 500;
  EXPECT_THROW(generateScene(p), Error);
  p = smallScene();
  p.outlier_fraction = 1.5;
  EXPECT_THROW(generateScene(p), Error);
  p = smallScene();
  p.gross_outliers = p.points + 1;
  EXPECT_THROW(generateScene(p), Error);
}

}  // namespace
}  // namespace hullmap::sim
