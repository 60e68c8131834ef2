// The realistic room (SceneLayout::kRoom): walls, floor, non-convex furniture, sparse points on
// visible surfaces only, the first camera's frame at a monocular scale, a metric reference.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hullmap/core/constants.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/align.hpp"
#include "hullmap/mapper/floor.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace hullmap::sim {
namespace {

using namespace hullmap::io;
using namespace hullmap::mapper;

using hullmap::kPi;

// Signed distance to a primitive's solid (negative inside): the oracle for "on a surface".
double signedDistance(const TruthShape& o, const Eigen::Vector3d& p) {
  const Eigen::Vector3d h = 0.5 * o.size;
  const Eigen::Vector3d d = p - o.center;
  if (o.shape == TruthShape::Shape::kBox) {
    const Eigen::Vector3d q = d.cwiseAbs() - h;
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
  }
  const double radial = std::hypot(d.x(), d.y()) - h.x();
  const double axial = std::abs(d.z()) - h.z();
  return std::hypot(std::max(radial, 0.0), std::max(axial, 0.0)) + std::min(std::max(radial, axial), 0.0);
}

SceneParams roomParams() {
  SceneParams p;
  p.layout = SceneLayout::kRoom;
  p.obstacles = 8;
  p.density = 60.0;
  return p;
}

// Back to the z-up map frame, metres.
Eigen::Vector3d toMap(const Scene& s, const Eigen::Vector3d& q) {
  return s.output_rotation.transpose() * (q - s.output_translation) / s.output_scale;
}

TEST(MapperRoomScene, PointsLieOnVisibleSurfacesAtTheAskedDensity) {
  SceneParams p = roomParams();
  p.outlier_fraction = 0.0;
  p.gross_outliers = 0;
  const Scene s = generateScene(p);
  const std::vector<TruthShape>& objects = s.truth.shapes;
  ASSERT_EQ(objects.size(), 5 + p.obstacles);
  EXPECT_EQ(objects[0].kind, "floor");
  EXPECT_TRUE(objects[0].surface);
  for (int i = 1; i <= 4; ++i) EXPECT_EQ(objects[i].kind, "wall");
  for (std::size_t i = 0; i < objects.size(); ++i)
    EXPECT_EQ(objects[i].label, objects[i].kind + " " + std::to_string(i));

  // Visible surface: floor + 4 walls (inner faces) + furniture; the points are density x that.
  const double walls = p.room_size * p.room_size + 4 * p.room_size * p.room_height;
  EXPECT_GT(static_cast<double>(s.points.size()), p.density * walls);

  std::size_t on_surface = 0, on_floor = 0, on_furniture = 0;
  for (const auto& q0 : s.points) {
    const Eigen::Vector3d q = toMap(s, q0);
    double nearest = 1e300;
    std::size_t which = 0;
    for (std::size_t o = 0; o < objects.size(); ++o) {
      for (const auto& part : objects[o].primitives()) {
        const double d = signedDistance(part, q);
        // Never deep inside a solid (noise is 1 cm).
        ASSERT_GT(d, -0.06) << q.transpose();
        if (std::abs(d) < nearest) {
          nearest = std::abs(d);
          which = o;
        }
      }
    }
    on_surface += nearest <= 0.06;
    on_floor += which == 0;
    on_furniture += which >= 5;
  }
  EXPECT_EQ(on_surface, s.points.size());
  // Floor share ~ its share of the visible area (100 of 220 m^2, less what furniture hides).
  EXPECT_GT(on_floor, s.points.size() * 3 / 10);
  EXPECT_LT(on_floor, s.points.size() * 5 / 10);
  EXPECT_GT(on_furniture, s.points.size() / 20);
}

TEST(MapperRoomScene, FurnitureIsNotConvexAndKeepsItsGaps) {
  const SceneParams p = roomParams();
  std::size_t shelves = 0, tables = 0;
  for (std::uint64_t seed : {1u, 2u, 3u, 42u}) {
    SceneParams q = p;
    q.seed = seed;
    const Scene s = generateScene(q);
    for (std::size_t i = 5; i < s.truth.shapes.size(); ++i) {
      const auto& f = s.truth.shapes[i];
      if (f.kind == "l_shelf") {
        ++shelves;
        ASSERT_EQ(f.parts.size(), 2u);
        // Two arms that touch and do not overlap: an L, not a box.
        const Eigen::Vector3d lo =
            (f.parts[0].center - 0.5 * f.parts[0].size).cwiseMax(f.parts[1].center - 0.5 * f.parts[1].size);
        const Eigen::Vector3d hi =
            (f.parts[0].center + 0.5 * f.parts[0].size).cwiseMin(f.parts[1].center + 0.5 * f.parts[1].size);
        const Eigen::Vector3d overlap = hi - lo;
        EXPECT_NEAR(std::min(overlap.x(), overlap.y()), 0.0, 1e-9);
        EXPECT_GT(std::max(overlap.x(), overlap.y()), 0.25);
      }
      if (f.kind == "table") {
        ++tables;
        ASSERT_EQ(f.parts.size(), 5u);
        const auto& top = f.parts[0];
        for (std::size_t l = 1; l < 5; ++l) {
          EXPECT_NEAR(f.parts[l].center.z() + 0.5 * f.parts[l].size.z(), top.center.z() - 0.5 * top.size.z(), 1e-9);
          EXPECT_NEAR(f.parts[l].center.z() - 0.5 * f.parts[l].size.z(), 0.0, 1e-9);
        }
      }
      // Footprints kSceneObstacleGap apart.
      for (std::size_t j = 5; j < i; ++j) {
        Eigen::Vector2d alo(1e300, 1e300), ahi(-1e300, -1e300), blo = alo, bhi = ahi;
        for (const auto& a : f.primitives()) {
          alo = alo.cwiseMin((a.center - 0.5 * a.size).head<2>());
          ahi = ahi.cwiseMax((a.center + 0.5 * a.size).head<2>());
        }
        for (const auto& b : s.truth.shapes[j].primitives()) {
          blo = blo.cwiseMin((b.center - 0.5 * b.size).head<2>());
          bhi = bhi.cwiseMax((b.center + 0.5 * b.size).head<2>());
        }
        const double gap = (alo - bhi).cwiseMax(blo - ahi).maxCoeff();
        EXPECT_GE(gap, kSceneObstacleGap - 1e-9);
      }
      // Inside the room, clear of its walls.
      for (const auto& part : f.primitives()) {
        EXPECT_LT((part.center.head<2>().cwiseAbs() + 0.5 * part.size.head<2>()).maxCoeff(),
                  0.5 * p.room_size - kSceneObstacleGap);
      }
    }
  }
  EXPECT_GT(shelves, 0u);
  EXPECT_GT(tables, 0u);
}

TEST(MapperRoomScene, OrbSlamFrameIsTheFirstCameraAtTheMonocularScale) {
  SceneParams p = roomParams();
  p.monocular_scale = 0.37;
  p.camera_pitch_deg = 20.0;
  const Scene s = generateScene(p);
  // The first keyframe is the frame's origin, unrotated (as ORB-SLAM writes it).
  EXPECT_LT(s.keyframes[0].position.norm(), 1e-12);
  EXPECT_LT(s.keyframes[0].orientation.angularDistance(Eigen::Quaterniond::Identity()), 1e-9);
  // Its camera looks down by the pitch: in the camera frame the map's up is (0, -cos, -sin)(pitch)
  // (y down, and forward has an up component of -sin(pitch)).
  const Eigen::Vector3d up = s.output_rotation * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(up.y(), -std::cos(20.0 * kPi / 180), 1e-9);
  EXPECT_NEAR(up.z(), -std::sin(20.0 * kPi / 180), 1e-9);
  EXPECT_NEAR(up.x(), 0.0, 1e-9);

  // The reference trajectory aligns the keyframes: scale 1 / 0.37, zero residual.
  std::vector<ReferencePose> ref;
  for (const auto& k : s.reference) ref.push_back({k.stamp, k.position});
  const Alignment a = alignTrajectory(s.keyframes, ref);
  EXPECT_EQ(a.matched, p.keyframes);
  EXPECT_NEAR(a.transform.scale, 1.0 / 0.37, 1e-9);
  EXPECT_LT(a.rmse, 1e-9);
  // Aligned, the map is z-up metres again and its floor is found level at z = 0.
  Points pts = s.points;
  applySimilarity(a.transform, pts);
  PlaneSearchParams fp;
  fp.band = 0.03;
  const PlaneFit floor = findBoundingPlane(pts, PlaneSide::kFloor, fp);
  ASSERT_TRUE(floor.found) << floor.reason;
  EXPECT_LT(floor.tilt_deg, 0.5);
  EXPECT_NEAR(floor.plane.offset, 0.0, 0.01);
  // Before alignment, with --up -y only, the floor is tilted by the pitch.
  Points raw = s.points;
  for (auto& q : raw) q = Eigen::Vector3d(q.x(), q.z(), -q.y());
  fp.band = 0.03 * 0.37;
  const PlaneFit tilted = findBoundingPlane(raw, PlaneSide::kFloor, fp);
  ASSERT_TRUE(tilted.found) << tilted.reason;
  EXPECT_NEAR(tilted.tilt_deg, 20.0, 0.5);
}

TEST(MapperRoomScene, WritesTheReferenceTrajectoryAndTheTruth) {
  SceneParams p = roomParams();
  p.density = 20.0;
  const Scene s = generateScene(p);
  const auto dir = test::freshDir("room_scene");
  writeScene(s, p, dir.string());
  const auto ref = readReferenceTrajectory((dir / "reference_trajectory.txt").string(), ReferenceFormat::kTum);
  const auto kf = readTumTrajectory((dir / "KeyFrameTrajectory.txt").string());
  ASSERT_EQ(ref.size(), p.keyframes);
  ASSERT_EQ(kf.size(), p.keyframes);
  const Alignment a = alignTrajectory(kf, ref);
  EXPECT_NEAR(a.transform.scale, 1.0 / p.monocular_scale, 1e-6);
  EXPECT_LT(a.rmse, 1e-6);

  std::ifstream in(dir / "ground_truth.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("layout"), "room");
  ASSERT_EQ(j.at("obstacles").size(), s.truth.shapes.size());
  for (std::size_t i = 0; i < s.truth.shapes.size(); ++i) {
    const auto& o = j.at("obstacles")[i];
    const TruthShape& truth = s.truth.shapes[i];
    EXPECT_EQ(o.at("kind"), truth.kind);
    if (truth.shape == TruthShape::Shape::kUnion) {
      EXPECT_EQ(o.at("shape"), "union");
      ASSERT_EQ(o.at("parts").size(), truth.parts.size());
      EXPECT_DOUBLE_EQ(o.at("parts")[1].at("size")[0].get<double>(), truth.parts[1].size.x());
    } else {
      EXPECT_DOUBLE_EQ(o.at("center")[2].get<double>(), truth.center.z());
    }
  }
  EXPECT_DOUBLE_EQ(j.at("output_from_map").at("scale").get<double>(), p.monocular_scale);
}

TEST(MapperRoomScene, SameSeedSameRoomAndBadParameters) {
  const Scene a = generateScene(roomParams());
  const Scene b = generateScene(roomParams());
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) ASSERT_EQ(a.points[i], b.points[i]) << i;

  SceneParams p = roomParams();
  p.obstacles = 0;  // an empty room is fine
  EXPECT_EQ(generateScene(p).truth.shapes.size(), 5u);
  for (auto bad : {+[](SceneParams& q) { q.density = 0; }, +[](SceneParams& q) { q.monocular_scale = -1; },
                   +[](SceneParams& q) { q.camera_pitch_deg = 95; }, +[](SceneParams& q) { q.edge_fraction = 2; },
                   +[](SceneParams& q) { q.obstacles = 200; }, +[](SceneParams& q) { q.keyframes = 2; }}) {
    SceneParams q = roomParams();
    bad(q);
    EXPECT_THROW(generateScene(q), Error);
  }
}

}  // namespace
}  // namespace hullmap::sim

namespace hullmap::sim {
namespace {

using namespace hullmap::io;

// maps/room is `hullmap generate --layout room -o maps/room` (seed 42, the room defaults): the files
// the generator writes are, byte for byte, the ones in the repository.
TEST(MapperRoomScene, MapsRoomIsTheDefaultRoom) {
  const std::filesystem::path dir = std::filesystem::path(HULLMAP_SOURCE_DIR) / "maps" / "room";
  SceneParams p;
  p.layout = SceneLayout::kRoom;
  const Scene s = generateScene(p);
  const auto out = test::freshDir("maps_room");
  writeScene(s, p, out.string());
  for (const char* name :
       {"map_points.txt", "KeyFrameTrajectory.txt", "reference_trajectory.txt", "ground_truth.json"}) {
    const std::string expected = hullmap::test::slurp(dir / name);
    const std::string written = hullmap::test::slurp(out / name);
    ASSERT_FALSE(expected.empty()) << (dir / name);
    const auto first = std::mismatch(expected.begin(), expected.end(), written.begin(), written.end());
    EXPECT_TRUE(expected == written) << name << ": " << written.size() << " bytes written, " << expected.size()
                                     << " in maps/room; first difference at byte " << (first.first - expected.begin());
  }
}

// Distance from p to a primitive's solid (0 inside).
double solidDistance(const TruthShape& o, const Eigen::Vector3d& p) { return std::max(0.0, signedDistance(o, p)); }

// Each segment of maps/room/segments.txt says whether it hits (closer than 0.3 m to) a true
// object, and which: checked against the truth by sampling every millimetre.
TEST(MapperRoomScene, MapsRoomSegmentLabelsMatchTheTruth) {
  const std::filesystem::path dir = std::filesystem::path(HULLMAP_SOURCE_DIR) / "maps" / "room";
  SceneParams p;
  p.layout = SceneLayout::kRoom;
  const Scene s = generateScene(p);
  std::ifstream in(dir / "segments.txt");
  std::string line;
  std::size_t hits = 0, clear = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream text(line);
    Eigen::Vector3d a, b;
    ASSERT_TRUE(text >> a.x() >> a.y() >> a.z() >> b.x() >> b.y() >> b.z()) << line;
    const std::string label = line.substr(line.find('#'));
    const auto steps = static_cast<int>(std::ceil((b - a).norm() / 0.001));
    for (std::size_t o = 0; o < s.truth.shapes.size(); ++o) {
      double d = 1e300;
      for (int k = 0; k <= steps; ++k) {
        const Eigen::Vector3d q = a + (b - a) * (static_cast<double>(k) / steps);
        for (const auto& part : s.truth.shapes[o].primitives()) d = std::min(d, solidDistance(part, q));
      }
      const std::string name = s.truth.shapes[o].label + " (";
      EXPECT_EQ(d < 0.3, label.find(name) != std::string::npos && label.find("hits") != std::string::npos)
          << line << ": object " << o << " at " << d;
    }
    (label.find("hits") != std::string::npos ? hits : clear) += 1;
  }
  EXPECT_GE(hits, 5u);
  EXPECT_GE(clear, 3u);
}

}  // namespace
}  // namespace hullmap::sim
