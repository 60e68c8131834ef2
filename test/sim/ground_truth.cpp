// The scene generator's ground truth and evaluate's are one type: a generated scene's truth (every
// layout), written to ground_truth.json and read back, is the same shapes with the same signed
// distance.
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "hullmap/sim/ground_truth.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace hullmap::sim {
namespace {

using V3 = Eigen::Vector3d;

// Every field equal, exactly (the JSON's numbers read back bit for bit).
void expectSameShape(const TruthShape& a, const TruthShape& b, const std::string& where) {
  EXPECT_EQ(a.shape, b.shape) << where;
  EXPECT_EQ(a.kind, b.kind) << where;
  EXPECT_EQ(a.label, b.label) << where;
  EXPECT_EQ(a.surface, b.surface) << where;
  EXPECT_EQ(a.center, b.center) << where;
  EXPECT_EQ(a.size, b.size) << where;
  EXPECT_EQ(a.yaw, b.yaw) << where;
  EXPECT_EQ(a.aabb_min, b.aabb_min) << where;
  EXPECT_EQ(a.aabb_max, b.aabb_max) << where;
  EXPECT_TRUE(a.triangles.empty() && b.triangles.empty()) << where;
  EXPECT_EQ(a.grid.origin, b.grid.origin) << where;
  EXPECT_EQ(a.grid.step, b.grid.step) << where;
  EXPECT_EQ(a.grid.nx, b.grid.nx) << where;
  EXPECT_EQ(a.grid.ny, b.grid.ny) << where;
  EXPECT_EQ(a.grid.heights, b.grid.heights) << where;
  ASSERT_EQ(a.parts.size(), b.parts.size()) << where;
  for (std::size_t p = 0; p < a.parts.size(); ++p)
    expectSameShape(a.parts[p], b.parts[p], where + " part " + std::to_string(p));
}

TEST(TruthJson, GeneratedScenesReadBackAsTheSameTruth) {
  SceneParams obstacles;
  obstacles.points = 2000;
  obstacles.obstacles = 10;
  obstacles.seed = 3;
  SceneParams room;
  room.layout = SceneLayout::kRoom;
  room.density = 10.0;
  SceneParams outdoor = outdoorSceneParams();
  outdoor.density = 0.5;
  for (const SceneParams& p : {obstacles, room, outdoor}) {
    const bool is_room = p.layout == SceneLayout::kRoom, is_outdoor = p.layout == SceneLayout::kOutdoor;
    const std::string name = is_room ? "room" : is_outdoor ? "outdoor" : "obstacles";
    SCOPED_TRACE(name);
    const Scene scene = generateScene(p);
    const auto dir = test::freshDir("truth_json_" + name);
    writeScene(scene, p, dir.string());
    const GroundTruth back = readGroundTruth((dir / "ground_truth.json").string());
    const std::vector<TruthShape>& truth = scene.truth.shapes;
    ASSERT_EQ(back.shapes.size(), truth.size());
    std::size_t unions = 0, surfaces = 0;
    for (std::size_t i = 0; i < truth.size(); ++i) {
      expectSameShape(truth[i], back.shapes[i], truth[i].label);
      EXPECT_EQ(truth[i].label, truth[i].kind + " " + std::to_string(i));
      unions += truth[i].shape == TruthShape::Shape::kUnion;
      surfaces += truth[i].surface;
    }
    // The room has its floor and unions (tables, the shelf), the street its ground and unions (trees);
    // the obstacles are plain primitives.
    EXPECT_EQ(surfaces, is_room || is_outdoor ? 1u : 0u);
    EXPECT_EQ(unions > 0, is_room || is_outdoor);
    if (is_outdoor) {
      EXPECT_EQ(back.shapes[0].shape, TruthShape::Shape::kHeightField);
      EXPECT_EQ(back.shapes[0].kind, "ground");
      EXPECT_EQ(unions, p.trees);
    }
    EXPECT_EQ(scene.truth.primitives().size(), back.primitives().size());

    V3 lo = V3::Constant(1e300), hi = V3::Constant(-1e300);
    for (const auto& s : truth) {
      lo = lo.cwiseMin(s.aabb_min);
      hi = hi.cwiseMax(s.aabb_max);
    }
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int k = 0; k < 400; ++k) {
      const V3 q = lo - V3::Constant(0.5) + (hi - lo + V3::Constant(1.0)).cwiseProduct(V3(u(rng), u(rng), u(rng)));
      ASSERT_EQ(scene.truth.signedDistance(q), back.signedDistance(q)) << q.transpose();
    }
  }
}

}  // namespace
}  // namespace hullmap::sim
