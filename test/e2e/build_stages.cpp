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

TEST(PipelineStages, BadInputsNameTheOptionInOneLine) {
  using hullmap::test::runHullmap;
  const Room room = writeRoom("stages_bad", 2);
  const std::string map = (room.dir / "map_points.txt").string();
  const std::string traj = " --trajectory " + (room.dir / "KeyFrameTrajectory.txt").string();
  const std::string ref = (room.dir / "reference_trajectory.txt").string();
  const std::string out = " -o " + (room.dir / "out").string();
  const auto expect = hullmap::test::expectOneLineError;
  expect(runHullmap("build " + map + " --align " + ref + out), "--align: needs --trajectory");
  expect(runHullmap("build " + map + traj + " --align " + ref + " --up -y" + out), "--up");
  expect(runHullmap("build " + map + traj + " --align-format gps" + out), "--align-format");
  expect(runHullmap("build " + map + traj + " --align " + ref + " --align-format utm" + out), "--align-format");
  expect(runHullmap("build " + map + traj + " --align " + ref + " --align-tolerance -1" + out), "--align-tolerance");
  expect(runHullmap("build " + map + " --floor low" + out), "--floor");
  expect(runHullmap("build " + map + " --ceiling nan" + out), "--ceiling");
  expect(runHullmap("build " + map + " --eps 0" + out), "--eps");
  expect(runHullmap("build " + map + " --eps automatic" + out), "--eps");
  expect(runHullmap("build " + map + " --min-pts 2.5" + out), "--min-pts");
  expect(runHullmap("build " + map + " --concavity -0.1" + out), "--concavity");
  expect(runHullmap("build " + map + " --concavity some" + out), "--concavity");
  for (const char* bad : {"x", "-1", "nan"})
    expect(runHullmap("build " + map + " --flat-gap " + bad + out), "--flat-gap");
  expect(runHullmap("build " + map + " --concavity none --flat-gap 0.1" + out),
         "--flat-gap: applies only to convex parts");
  for (const char* bad : {"none", "0", "Auto"})
    expect(runHullmap("build " + map + " --extension " + bad + out), "--extension");
  // A garbage reference file is named with its line; fewer than 3 matched poses are refused.
  const auto garbage = room.dir / "garbage.txt";
  hullmap::test::writeText(garbage, "0 1 2 3\nnot a pose\n");
  expect(runHullmap("build " + map + traj + " --align " + garbage.string() + out), "garbage.txt:2");
  const auto two = room.dir / "two.txt";
  std::string text, line;
  std::ifstream in(ref);
  for (int k = 0; k < 2 && std::getline(in, line); ++k) text += line + "\n";
  hullmap::test::writeText(two, text);
  expect(runHullmap("build " + map + traj + " --align " + two.string() + out), "--align");
  const auto far = room.dir / "far.txt";
  hullmap::test::writeText(far, "1e6 0 0 0\n1e6 1 0 0\n1e6 0 1 0\n");
  expect(runHullmap("build " + map + traj + " --align " + far.string() + out), "--align");
}

}  // namespace
