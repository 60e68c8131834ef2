#pragma once
// Helpers shared by pipeline/build_stages.cpp, pipeline/heavy/build_stages.cpp, e2e/build_stages.cpp,
// e2e/heavy/build_stages.cpp.

#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "hullmap/clustering/auto_params.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/pipeline/report.hpp"
#include "hullmap/sim/evaluate.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace {
using V3 = Eigen::Vector3d;
namespace pipeline = hullmap::pipeline;
namespace mapper = hullmap::mapper;

/// A realistic room (by default 6 m, 4 pieces of furniture, 60 points per m^2) written as
/// `generate --layout room`.
struct Room {
  hullmap::sim::SceneParams params;
  hullmap::sim::Scene scene;
  std::filesystem::path dir;
};

inline Room writeRoom(const std::string& name, std::uint64_t seed, double room_size = 6.0, std::size_t obstacles = 4,
                      double density = 60.0) {
  Room room;
  room.params.layout = hullmap::sim::SceneLayout::kRoom;
  room.params.seed = seed;
  room.params.room_size = room_size;
  room.params.obstacles = obstacles;
  room.params.density = density;
  room.scene = hullmap::sim::generateScene(room.params);
  room.dir = hullmap::test::freshDir(name);
  hullmap::sim::writeScene(room.scene, room.params, room.dir.string());
  return room;
}

inline pipeline::BuildParams alignedBuild(const Room& room) {
  pipeline::BuildParams params;
  params.inputs = {room.dir / "map_points.txt"};
  params.trajectory = room.dir / "KeyFrameTrajectory.txt";
  params.align = pipeline::AlignSettings{room.dir / "reference_trajectory.txt", {}, {}};
  return params;
}

/// A build scored against its room's truth (hullmap::sim::evaluate over its voxels), `segments` random
/// segments at r = 0.3.
inline hullmap::sim::Evaluation score(const pipeline::BuildResult& r, const Room& room, std::size_t segments) {
  std::vector<V3> centers;
  std::vector<std::uint32_t> weights;
  for (const auto& v : r.voxels) {
    centers.push_back(v.center);
    weights.push_back(v.weight);
  }
  hullmap::sim::EvaluateParams eval;
  eval.segments = segments;
  return hullmap::sim::evaluate(r.obstacles, hullmap::sim::readGroundTruth((room.dir / "ground_truth.json").string()),
                                centers, weights, eval);
}

}  // namespace
