// The street (SceneLayout::kOutdoor): the same files from the same seed; the ground first, then the
// objects, apart and clear of the camera path; points on the surfaces a camera sees; the monocular
// scale drifting as stated; the GPS log's dropout and noise, read back by the --align-format gps reader.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <string>

#include <gtest/gtest.h>

#include "hullmap/core/constants.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/io/reference_trajectory.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace hullmap::sim {
namespace {

using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;

const HeightGrid& groundOf(const Scene& s) { return s.truth.shapes.front().grid; }

// The scene without noise or outliers: every point on a true surface.
SceneParams exactParams() {
  SceneParams p = outdoorSceneParams();
  p.noise_sigma = 0.0;
  p.outlier_fraction = 0.0;
  p.gross_outliers = 0;
  return p;
}

TEST(OutdoorScene, SameSeedSameFilesOtherSeedOtherScene) {
  SceneParams p = outdoorSceneParams();
  p.seed = 5;
  const auto a = test::freshDir("outdoor_same_a"), b = test::freshDir("outdoor_same_b"),
             c = test::freshDir("outdoor_same_c");
  writeScene(generateScene(p), p, a.string());
  writeScene(generateScene(p), p, b.string());
  p.seed = 6;
  writeScene(generateScene(p), p, c.string());
  for (const char* name :
       {"map_points.txt", "KeyFrameTrajectory.txt", "reference_trajectory.txt", "gps.txt", "ground_truth.json"}) {
    const std::string first = test::slurp(a / name);
    EXPECT_GT(first.size(), 1000u) << name;
    EXPECT_EQ(first, test::slurp(b / name)) << name;
  }
  EXPECT_NE(test::slurp(a / "map_points.txt"), test::slurp(c / "map_points.txt"));
  EXPECT_NE(test::slurp(a / "ground_truth.json"), test::slurp(c / "ground_truth.json"));
}

TEST(OutdoorScene, GroundThenObjectsApartStandingInTheGround) {
  const SceneParams p = outdoorSceneParams();
  const Scene s = generateScene(p);
  const std::vector<TruthShape>& shapes = s.truth.shapes;
  ASSERT_EQ(shapes.size(), 1 + p.buildings + p.trees + p.cars + p.posts);
  EXPECT_EQ(shapes[0].shape, TruthShape::Shape::kHeightField);
  EXPECT_EQ(shapes[0].label, "ground 0");
  EXPECT_TRUE(shapes[0].surface);
  const HeightGrid& g = groundOf(s);
  EXPECT_EQ(g.corner() - g.origin, V2(p.track_width, p.track_length));
  std::map<std::string, std::size_t> kinds;
  for (std::size_t o = 1; o < shapes.size(); ++o) {
    ++kinds[shapes[o].kind];
    EXPECT_FALSE(shapes[o].surface);
    EXPECT_EQ(shapes[o].label, shapes[o].kind + " " + std::to_string(o));
    EXPECT_EQ(shapes[o].shape == TruthShape::Shape::kUnion, shapes[o].kind == "tree") << shapes[o].label;
  }
  EXPECT_EQ(kinds, (std::map<std::string, std::size_t>{
                       {"building", p.buildings}, {"tree", p.trees}, {"car", p.cars}, {"post", p.posts}}));
  // No two objects' parts meet (their boxes, grown by half the gap, are disjoint).
  for (std::size_t a = 1; a < shapes.size(); ++a)
    for (std::size_t b = a + 1; b < shapes.size(); ++b)
      for (const TruthShape& pa : shapes[a].primitives())
        for (const TruthShape& pb : shapes[b].primitives()) {
          const bool apart = (pa.aabb_max.head<2>().array() + kSceneObstacleGap <= pb.aabb_min.head<2>().array() ||
                              pb.aabb_max.head<2>().array() + kSceneObstacleGap <= pa.aabb_min.head<2>().array())
                                 .any();
          EXPECT_TRUE(apart) << shapes[a].label << " and " << shapes[b].label;
        }
  // Each object inside the area, its lowest part's bottom under the terrain everywhere under it (by
  // 0.5 m a building, 0.3 m the others), its top above it.
  for (std::size_t o = 1; o < shapes.size(); ++o) {
    const TruthShape& object = shapes[o];
    EXPECT_TRUE((object.aabb_min.head<2>().array() >= g.origin.array()).all()) << object.label;
    EXPECT_TRUE((object.aabb_max.head<2>().array() <= g.corner().array()).all()) << object.label;
    const TruthShape& foot = object.primitives()[0];  // a tree's trunk
    const double depth = object.kind == "building" ? 0.5 : 0.3;
    double deepest_gap = 1e300;
    for (double x = foot.aabb_min.x(); x <= foot.aabb_max.x(); x += 0.05)
      for (double y = foot.aabb_min.y(); y <= foot.aabb_max.y(); y += 0.05) {
        const double h = *g.heightAt(V2(x, y));
        deepest_gap = std::min(deepest_gap, h - foot.aabb_min.z());
        EXPECT_GT(object.aabb_max.z(), h + 1.0) << object.label;
      }
    EXPECT_GE(deepest_gap, depth - 1e-9) << object.label;
    EXPECT_LT(deepest_gap, depth + 0.05) << object.label;  // standing on the ground, not sunk
  }
}

TEST(OutdoorScene, KeyframesRideTheStreetClearOfEveryObject) {
  SceneParams p = outdoorSceneParams();
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    p.seed = seed;
    const Scene s = generateScene(p);
    const HeightGrid& g = groundOf(s);
    ASSERT_EQ(s.reference.size(), p.keyframes);
    for (std::size_t k = 0; k < s.reference.size(); ++k) {
      const io::Keyframe& key = s.reference[k];
      EXPECT_NEAR(key.position.z() - *g.heightAt(key.position.head<2>()), kOutdoorCameraHeight, 1e-9);
      if (k > 0) {
        EXPECT_GT(key.stamp, s.reference[k - 1].stamp);
      }
      EXPECT_EQ(s.keyframes[k].stamp, key.stamp);
      const V3 forward = key.orientation * V3::UnitZ();
      EXPECT_NEAR(forward.z(), -std::sin(p.camera_pitch_deg * kPi / 180.0), 1e-9);
      EXPECT_GT(forward.y(), 0.9);  // along the street, north
    }
    // The path, sampled every 5 cm: every object at least the margin away (3D, so no less than the
    // horizontal distance the generator keeps).
    double closest = 1e300;
    for (std::size_t k = 0; k + 1 < s.reference.size(); ++k)
      for (double t = 0.0; t < 1.0; t += 0.02) {
        const V3 q = (1.0 - t) * s.reference[k].position + t * s.reference[k + 1].position;
        for (std::size_t o = 1; o < s.truth.shapes.size(); ++o)
          closest = std::min(closest, s.truth.shapes[o].signedDistance(q));
      }
    EXPECT_GE(closest, kOutdoorPathMargin);
    EXPECT_LT(closest, kOutdoorPathMargin + 1.5);  // cars and posts line the street
  }
}

// The outward normals of the faces of `part` (a box or upright cylinder) that q lies on.
std::vector<V3> facesAt(const TruthShape& part, const V3& q) {
  std::vector<V3> normals;
  const V3 d = q - part.center, h = 0.5 * part.size;
  if (part.shape == TruthShape::Shape::kBox) {
    for (int axis = 0; axis < 3; ++axis)
      if (std::abs(std::abs(d[axis]) - h[axis]) < 1e-7) normals.push_back(V3::Unit(axis) * (d[axis] > 0 ? 1 : -1));
    return normals;
  }
  if (std::abs(std::abs(d.z()) - h.z()) < 1e-7) normals.push_back(V3::UnitZ() * (d.z() > 0 ? 1 : -1));
  if (std::abs(std::hypot(d.x(), d.y()) - h.x()) < 1e-7) normals.push_back(V3(d.x(), d.y(), 0).normalized());
  return normals;
}

TEST(OutdoorScene, PointsLieOnSurfacesACameraSees) {
  const SceneParams p = exactParams();
  const Scene s = generateScene(p);
  ASSERT_EQ(s.map_points.size(), s.points.size());
  const HeightGrid& g = groundOf(s);
  const std::vector<TruthShape> parts = s.truth.primitives();
  std::size_t on_ground = 0;
  std::map<std::string, std::size_t> on_kind;
  for (const V3& q : s.map_points) {
    const std::optional<double> h = g.heightAt(q.head<2>());
    ASSERT_TRUE(h) << q.transpose();
    EXPECT_GE(q.z(), *h - 1e-9) << "under the ground: " << q.transpose();
    std::size_t owner = 0;
    double nearest = std::abs(s.truth.shapes[0].signedDistance(q));
    for (std::size_t o = 1; o < s.truth.shapes.size(); ++o) {
      const double d = s.truth.shapes[o].signedDistance(q);
      EXPECT_GE(d, -1e-9) << "inside " << s.truth.shapes[o].label << ": " << q.transpose();
      if (std::abs(d) < nearest) {
        nearest = std::abs(d);
        owner = o;
      }
    }
    ASSERT_LE(nearest, 1e-9) << q.transpose();
    if (owner == 0) {
      ++on_ground;
      continue;
    }
    ++on_kind[s.truth.shapes[owner].kind];
    // On a face turned toward a keyframe within 40 m, never a bottom.
    bool seen = false;
    for (const TruthShape& part : s.truth.shapes[owner].primitives()) {
      if (std::abs(part.signedDistance(q)) > 1e-9) continue;
      for (const V3& n : facesAt(part, q)) {
        if (n.z() < -0.5) continue;
        for (const io::Keyframe& k : s.reference)
          seen = seen || (n.dot(k.position - q) > 0.0 && (k.position - q).norm() <= 40.0);
      }
    }
    EXPECT_TRUE(seen) << s.truth.shapes[owner].label << " at " << q.transpose();
  }
  // Mostly ground, the rest mostly buildings; every kind seen.
  const double n = double(s.map_points.size());
  EXPECT_GT(on_ground / n, 0.5);
  EXPECT_GT(on_kind["building"] / n, 0.15);
  for (const char* kind : {"tree", "car", "post"}) EXPECT_GT(on_kind[kind], 10u) << kind;
}

TEST(OutdoorScene, DefaultsMakeAnIssueSizedMapWithNoiseAndOutliers) {
  SceneParams p = outdoorSceneParams();
  for (const std::uint64_t seed : {1u, 2u}) {
    p.seed = seed;
    const Scene s = generateScene(p);
    const double n = double(s.map_points.size());
    EXPECT_GE(n, 20000);
    EXPECT_LE(n, 30000);
    std::size_t close = 0, off = 0, gross = 0;
    for (const V3& q : s.map_points) {
      if (q.norm() >= 1e5) {
        ++gross;
        continue;
      }
      const double d = std::abs(s.truth.signedDistance(q));
      close += d <= 4.0 * p.noise_sigma;
      off += d > 0.5;
    }
    EXPECT_EQ(gross, p.gross_outliers);
    // Outliers are outlier_fraction of the points; a few fall near a surface by chance.
    EXPECT_GE(close / n, 1.0 - p.outlier_fraction - 0.002);
    EXPECT_LE(close / n, 1.0 - 0.5 * p.outlier_fraction);
    EXPECT_GE(off / n, 0.5 * p.outlier_fraction);
  }
}

// Median of the ratios of written to true distances between pairs of points near keyframe k.
double localScale(const Scene& s, std::size_t k) {
  std::vector<std::size_t> near;
  for (std::size_t i = 0; i < s.map_points.size() && near.size() < 200; ++i)
    if ((s.map_points[i] - s.reference[k].position).head<2>().norm() < 6.0) near.push_back(i);
  std::vector<double> ratios;
  for (std::size_t a = 0; a < near.size(); ++a)
    for (std::size_t b = a + 1; b < near.size(); ++b) {
      const double truth = (s.map_points[near[a]] - s.map_points[near[b]]).norm();
      if (truth > 1.0) ratios.push_back((s.points[near[a]] - s.points[near[b]]).norm() / truth);
    }
  EXPECT_GT(ratios.size(), 1000u) << "keyframe " << k;
  std::nth_element(ratios.begin(), ratios.begin() + long(ratios.size() / 2), ratios.end());
  return ratios[ratios.size() / 2];
}

TEST(OutdoorScene, MonocularScaleDriftsFromStartToEnd) {
  SceneParams p = exactParams();
  p.scale_drift = 0.3;
  const Scene s = generateScene(p);
  const std::size_t last = s.keyframes.size() - 1;
  const double m = p.monocular_scale;
  // The first camera is the frame.
  EXPECT_LT(s.keyframes[0].position.norm(), 1e-12);
  EXPECT_NEAR(std::abs(s.keyframes[0].orientation.w()), 1.0, 1e-12);
  EXPECT_NEAR(s.keyframe_scales.front(), m, 1e-15);
  EXPECT_NEAR(s.keyframe_scales.back(), m * 1.3, 1e-12);
  // Keyframe steps, written over true, at the start and the end.
  const auto step = [&s](std::size_t k) {
    return (s.keyframes[k + 1].position - s.keyframes[k].position).norm() /
           (s.reference[k + 1].position - s.reference[k].position).norm();
  };
  EXPECT_NEAR(step(0) / m, 1.0, 0.005);
  EXPECT_NEAR(step(last - 1) / m, 1.3, 0.005);
  // The points around the first and the last keyframe.
  EXPECT_NEAR(localScale(s, 0) / m, 1.0, 0.015);
  EXPECT_NEAR(localScale(s, last) / m, 1.3, 0.015);

  // Without drift the map is the one similarity of the first camera.
  p.scale_drift = 0.0;
  const Scene flat = generateScene(p);
  for (std::size_t i = 0; i < flat.points.size(); ++i) {
    const V3 expected = m * (flat.output_rotation * flat.map_points[i]) + flat.output_translation;
    ASSERT_LT((flat.points[i] - expected).norm(), 1e-9 * std::max(1.0, expected.norm())) << i;
  }
  for (std::size_t k = 0; k + 1 < flat.keyframes.size(); ++k)
    EXPECT_NEAR((flat.keyframes[k + 1].position - flat.keyframes[k].position).norm() /
                    (flat.reference[k + 1].position - flat.reference[k].position).norm(),
                m, 1e-12);
}

// gps.txt read as `--align-format gps` reads it: the no-fix lines dropped and counted; the rest's
// error against the true positions (after its mean: the reader's origin is the first fix).
struct GpsReadBack {
  io::ReferenceStats stats;
  std::size_t fixes = 0;
  V3 sigma = V3::Zero();
};

GpsReadBack readGps(const Scene& s, const SceneParams& p, const std::string& name) {
  const auto dir = test::freshDir(name);
  writeScene(s, p, dir.string());
  GpsReadBack r;
  const auto poses = io::readReferenceTrajectory((dir / "gps.txt").string(), io::ReferenceFormat::kGps, &r.stats);
  r.fixes = poses.size();
  std::vector<V3> errors;
  std::size_t k = 0;
  for (const io::ReferencePose& pose : poses) {
    while (k < s.reference.size() && s.reference[k].stamp != pose.stamp) ++k;
    EXPECT_LT(k, s.reference.size()) << "no keyframe at " << pose.stamp;
    if (k == s.reference.size()) break;
    errors.push_back(pose.position - s.reference[k].position);
  }
  V3 mean = V3::Zero();
  for (const V3& e : errors) mean += e / double(errors.size());
  for (const V3& e : errors) r.sigma += (e - mean).cwiseAbs2() / double(errors.size() - 1);
  r.sigma = r.sigma.cwiseSqrt();
  return r;
}

TEST(OutdoorScene, GpsLogHasTheAskedDropoutAndNoise) {
  SceneParams p = outdoorSceneParams();
  p.density = 0.2;
  p.keyframes = 500;
  const Scene s = generateScene(p);
  ASSERT_EQ(s.gps.size(), 500u);
  const GpsReadBack noisy = readGps(s, p, "outdoor_gps");
  EXPECT_EQ(noisy.stats.dropped, (std::map<std::string, std::size_t>{{"no_fix", 50}}));
  EXPECT_EQ(noisy.fixes, 450u);
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(noisy.sigma[axis], p.gps_sigma, 0.35) << axis;

  p.gps_sigma = 0.0;
  p.gps_dropout = 0.0;
  const GpsReadBack exact = readGps(generateScene(p), p, "outdoor_gps_exact");
  EXPECT_TRUE(exact.stats.dropped.empty());
  EXPECT_EQ(exact.fixes, 500u);
  EXPECT_LT(exact.sigma.maxCoeff(), 0.005);  // the written decimals, the reader's tangent plane
}

TEST(OutdoorScene, BadParametersNameTheirField) {
  const std::pair<std::string, std::function<void(SceneParams&)>> cases[] = {
      {"scale_drift", [](SceneParams& p) { p.scale_drift = -1.0; }},
      {"gps_sigma", [](SceneParams& p) { p.gps_sigma = -0.5; }},
      {"gps_dropout", [](SceneParams& p) { p.gps_dropout = 1.5; }},
      {"track_length", [](SceneParams& p) { p.track_length = 20.0; }},
      {"track_width", [](SceneParams& p) { p.track_width = std::nan(""); }},
      {"slope_along", [](SceneParams& p) { p.slope_along = 0.5; }},
      {"bump_height", [](SceneParams& p) { p.bump_height = -1.0; }},
      {"density", [](SceneParams& p) { p.density = 0.0; }},
      {"keyframes", [](SceneParams& p) { p.keyframes = 2; }},
      {"buildings", [](SceneParams& p) { p.buildings = 200; }},
      {"posts", [](SceneParams& p) { p.posts = 2000; }},
  };
  for (const auto& [field, change] : cases) {
    SceneParams p = outdoorSceneParams();
    change(p);
    try {
      generateScene(p);
      ADD_FAILURE() << field << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.parameter(), field) << e.what();
    }
  }
}

}  // namespace
}  // namespace hullmap::sim
