// The stages issue 13 adds to the build (align, floor, auto eps/minPts, convex parts with known free
// space) on a generated room in ORB-SLAM's frame at a monocular scale, and their bad inputs.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "build_stages_fixtures.hpp"
#include "hullmap/clustering/auto_params.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/pipeline/report.hpp"
#include "hullmap/sim/evaluate.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "run_hullmap.hpp"

namespace {

namespace pipeline = hullmap::pipeline;
namespace mapper = hullmap::mapper;

TEST(PipelineStages, FlatGapOptionReachesTheReportAndZeroTurnsItOff) {
  // The room's walls and floor-standing furniture are sparse surfaces: at the default (auto: G = the
  // eps used) their parts pass as flat and span the gaps between map points; --flat-gap 0 keeps
  // every part within T, so the same walls break into more parts and none is flat.
  using hullmap::test::runHullmap;
  // Points only (no rays: fast), put in metres by the generator's own scale and levelled by the floor.
  const Room room = writeRoom("stages_flat_gap", 5);
  std::ostringstream scale;
  scale << std::setprecision(17) << 1.0 / room.scene.output_scale;
  const std::string args = "build " + (room.dir / "map_points.txt").string() + " --up -y --scale " + scale.str() +
                           " -o " + (room.dir / "out_").string();
  struct Run {
    nlohmann::json report;
    nlohmann::json obstacles;
    std::string out;
  };
  const auto run = [&](const std::string& name, const std::string& flat_gap) {
    const auto r = runHullmap(args + name + flat_gap);
    EXPECT_EQ(r.status, 0) << r.err;
    const auto dir = room.dir / ("out_" + name);
    return Run{nlohmann::json::parse(hullmap::test::slurp(dir / "report.json")),
               nlohmann::json::parse(hullmap::test::slurp(dir / "obstacles.json")), r.out};
  };
  const auto flatInObstacles = [](const nlohmann::json& obstacles) {
    std::size_t flat = 0;
    for (const auto& o : obstacles["obstacles"])
      for (const auto& part : o["parts"]) flat += part["flat"].get<bool>() ? 1 : 0;
    return flat;
  };
  const Run automatic = run("auto", "");
  const Run off = run("off", " --flat-gap 0");
  const Run given = run("given", " --flat-gap 0.5");

  const auto& a = automatic.report["parts"];
  EXPECT_EQ(automatic.report["parameters"]["flat_gap"], "auto");
  EXPECT_DOUBLE_EQ(a["flat_gap"].get<double>(), automatic.report["clustering"]["eps"].get<double>());
  ASSERT_GT(a["flat_gap"].get<double>(), a["concavity"].get<double>()) << "the room's auto eps should exceed T";
  EXPECT_GT(a["flat_parts"].get<std::size_t>(), 0u);
  EXPECT_EQ(flatInObstacles(automatic.obstacles), a["flat_parts"].get<std::size_t>());
  // Auto G is adapted per cluster (hullmap::hulls::adaptedFlatGap): between G and 2 G.
  EXPECT_GE(a["flat_gap_max"].get<double>(), a["flat_gap"].get<double>());
  EXPECT_LE(a["flat_gap_max"].get<double>(), 2.0 * a["flat_gap"].get<double>() + 1e-12);
  std::ostringstream line;
  line << "flat gap " << std::setprecision(4) << a["flat_gap"].get<double>() << ": " << a["flat_parts"]
       << " flat parts";
  EXPECT_NE(automatic.out.find(line.str()), std::string::npos)
      << "expected '" << line.str() << "' in: " << automatic.out;

  const auto& o = off.report["parts"];
  EXPECT_EQ(off.report["parameters"]["flat_gap"], 0.0);
  EXPECT_EQ(o["flat_gap"], o["concavity"]);
  EXPECT_EQ(o["flat_gap_max"], o["concavity"]);
  EXPECT_EQ(o["flat_parts"], 0);
  EXPECT_EQ(flatInObstacles(off.obstacles), 0u);
  EXPECT_GT(o["count"].get<std::size_t>(), a["count"].get<std::size_t>());
  EXPECT_NE(off.out.find("flat gap off"), std::string::npos) << off.out;

  EXPECT_EQ(given.report["parameters"]["flat_gap"], 0.5);
  EXPECT_EQ(given.report["parts"]["flat_gap"], 0.5);
  EXPECT_EQ(given.report["parts"]["flat_gap_max"], 0.5) << "a G given is used as given";
  EXPECT_EQ(flatInObstacles(given.obstacles), given.report["parts"]["flat_parts"].get<std::size_t>());
  std::size_t faces = 0;
  for (const auto& obstacle : given.obstacles["obstacles"])
    for (const auto& part : obstacle["parts"]) {
      const bool relaxed = part["flat"].get<bool>() || part["faces"].get<bool>();
      faces += part["faces"].get<bool>() ? 1 : 0;
      EXPECT_LE(part["concavity_bound"].get<double>(),
                (relaxed ? 0.5 : given.report["parts"]["concavity"].get<double>()) + 1e-12);
    }
  EXPECT_EQ(faces, given.report["parts"]["face_parts"].get<std::size_t>());
  // G = T: no face-hole rule either.
  EXPECT_EQ(o["face_parts"], 0);
}

}  // namespace
