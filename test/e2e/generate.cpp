// hullmap generate --layout room and --layout outdoor: the files they write (the outdoor GPS log as
// `hullmap build --align-format gps` reads it, the street's ground as build, check and plot take it),
// and bad input (exit 2, one line).
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/align.hpp"
#include "run_hullmap.hpp"

namespace {

using hullmap::test::runHullmap;

TEST(GenerateCommand, RoomLayoutWritesPointsTrajectoriesAndTruth) {
  const auto dir = hullmap::test::freshDir("generate_room");
  const auto r = runHullmap("generate --layout room --density 20 --scale 2.5 --obstacles 4 -o '" + dir.string() + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("9 objects (floor, 4 walls, 4 pieces of furniture)"), std::string::npos) << r.out;
  const auto kf = hullmap::io::readTumTrajectory((dir / "KeyFrameTrajectory.txt").string());
  const auto ref = hullmap::io::readReferenceTrajectory((dir / "reference_trajectory.txt").string(),
                                                        hullmap::io::ReferenceFormat::kTum);
  const auto a = hullmap::mapper::alignTrajectory(kf, ref);
  EXPECT_NEAR(a.transform.scale, 1.0 / 2.5, 1e-6);
  std::ifstream in(dir / "ground_truth.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("obstacles").size(), 9u);
  EXPECT_EQ(j.at("obstacles")[0].at("kind"), "floor");
  EXPECT_GT(hullmap::io::readPointFile((dir / "map_points.txt").string()).points.size(), 4000u);
}

TEST(GenerateCommand, BadRoomOptionsExitTwoWithOneLine) {
  const auto dir = hullmap::test::freshDir("generate_bad");
  const std::pair<const char*, const char*> cases[] = {{"--layout rooom", "--layout"},
                                                       {"--layout room --density 0", "--density"},
                                                       {"--layout room --scale -1", "--scale"},
                                                       {"--layout room --pitch 95", "--pitch"},
                                                       {"--layout room --edge-fraction 1.5", "--edge-fraction"},
                                                       {"--layout room --keyframes 2", "--keyframes"},
                                                       {"--layout room --obstacles 100", "obstacles"}};
  for (const auto& [args, name] : cases) {
    const auto r = runHullmap(std::string("generate ") + args + " -o '" + (dir / "x").string() + "'");
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_NE(r.err.find(name), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
  }
}

// A small street: 80 x 40 m, 14 objects, 40 keyframes.
const char* kSmallStreet =
    "generate --layout outdoor --track-length 80 --track-width 40 --buildings 4 --trees 4 --cars 3 --posts 3 "
    "--keyframes 40 --density 1";

TEST(GenerateCommand, OutdoorLayoutWritesAGpsLogThatBuildAligns) {
  const auto dir = hullmap::test::freshDir("generate_outdoor");
  const std::string d = "'" + dir.string() + "/";
  const auto r = runHullmap(std::string(kSmallStreet) + " -o " + d + "street'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("40 keyframes, 15 objects (ground, 4 buildings, 4 trees, 3 cars, 3 posts)"), std::string::npos)
      << r.out;
  const std::string in = d + "street/map_points.txt' --trajectory " + d + "street/KeyFrameTrajectory.txt' ";
  // The GPS log: 4 of its 40 lines without a fix, the rest matched; its noise (3 m) in the fit.
  const auto gps = runHullmap("build " + in + "--align " + d + "street/gps.txt' --align-format gps -o " + d + "gps'");
  ASSERT_EQ(gps.status, 0) << gps.err;
  const auto a = hullmap::test::readJson(dir / "gps" / "report.json").at("alignment");
  EXPECT_EQ(a.at("matched"), 36);
  EXPECT_EQ(a.at("unmatched"), 4);
  EXPECT_EQ(a.at("reference_dropped"), (nlohmann::json{{"no_fix", 4}}));
  EXPECT_GT(a.at("rmse").get<double>(), 2.0);
  EXPECT_LT(a.at("rmse").get<double>(), 10.0);
  // The metric reference: the scale between the start's 1 / 0.0145 and the end's 1 / (0.0145 x 1.15).
  const auto ref =
      runHullmap("build " + in + "--align " + d + "street/reference_trajectory.txt' -o " + d + "reference'");
  ASSERT_EQ(ref.status, 0) << ref.err;
  const double scale = hullmap::test::readJson(dir / "reference" / "report.json").at("alignment").at("scale");
  EXPECT_GT(scale, 1.0 / (0.0145 * 1.15));
  EXPECT_LT(scale, 1.0 / 0.0145);
  // The GPS log's noise hides the drift: one similarity. The reference shows it: the drift model,
  // its local scales spanning the drift, each point moved by its own part of the path, so no one
  // transform takes input coordinates to the map and `check --frame input` says so.
  EXPECT_EQ(a.at("model"), "similarity");
  // A street is nearly a line: the GPS noise leaves the roll about it to the cameras, which level the
  // map, so its ground is found (this short street's is a plane: the floor).
  EXPECT_EQ(a.at("roll").at("from"), "cameras");
  EXPECT_GT(a.at("roll").at("sigma_deg").get<double>(), 1.0);
  const auto gps_report = hullmap::test::readJson(dir / "gps" / "report.json");
  EXPECT_TRUE(gps_report.at("floor").at("found").get<bool>() || !gps_report.at("ground").is_null());
  EXPECT_TRUE(hullmap::test::readJson(dir / "gps" / "report.json").at("input_to_output").at("exact").get<bool>());
  const auto report = hullmap::test::readJson(dir / "reference" / "report.json");
  const auto& fit = report.at("alignment");
  EXPECT_EQ(fit.at("model"), "drift");
  EXPECT_LT(fit.at("rmse").get<double>(), 0.1 * fit.at("similarity_rmse").get<double>());
  EXPECT_EQ(fit.at("drift").at("anchors").size(), 40u);
  EXPECT_GT(fit.at("drift").at("scale_max").get<double>(), 1.1 * fit.at("drift").at("scale_min").get<double>());
  EXPECT_FALSE(report.at("input_to_output").at("exact").get<bool>());
  EXPECT_FALSE(
      hullmap::test::readJson(dir / "reference" / "obstacles.json").at("input_to_output").at("exact").get<bool>());
  const auto input_frame = runHullmap("check " + d + "reference' -r 0.3 --frame input --segment=0,0,1,1,1,1");
  EXPECT_EQ(input_frame.status, 2);
  EXPECT_NE(input_frame.err.find("--frame"), std::string::npos) << input_frame.err;
  EXPECT_NE(input_frame.err.find("scale drift"), std::string::npos) << input_frame.err;
  // Asked for one similarity, the build keeps it.
  const auto one = runHullmap("build " + in + "--align " + d + "street/reference_trajectory.txt' --align-model " +
                              "similarity -o " + d + "similarity'");
  ASSERT_EQ(one.status, 0) << one.err;
  const auto one_report = hullmap::test::readJson(dir / "similarity" / "report.json");
  EXPECT_EQ(one_report.at("alignment").at("model"), "similarity");
  EXPECT_TRUE(one_report.at("input_to_output").at("exact").get<bool>());
  EXPECT_EQ(runHullmap("build " + in + "--align-model drift -o " + d + "no_align'").status, 2);
}

// A street built at the defaults: the resolution fits its spacing, the ground is a height field in
// obstacles.json, report.json and voxels.csv, and `check` and `plot` take it as the build wrote it.
TEST(GenerateCommand, AStreetsGroundIsAHeightFieldThatChecksHit) {
  const auto dir = hullmap::test::freshDir("generate_street_ground");
  const std::string d = "'" + dir.string() + "/";
  ASSERT_EQ(runHullmap(std::string(kSmallStreet) + " -o " + d + "street'").status, 0);
  const auto b =
      runHullmap("build " + d + "street/map_points.txt' --trajectory " + d + "street/KeyFrameTrajectory.txt' --align " +
                 d + "street/reference_trajectory.txt' -o " + d + "out'");
  ASSERT_EQ(b.status, 0) << b.err;
  const auto report = hullmap::test::readJson(dir / "out" / "report.json");
  EXPECT_TRUE(report.at("resolution").at("adapted").get<bool>()) << report.at("resolution");
  EXPECT_GT(report.at("parameters").at("resolution").get<double>(), 0.05);
  ASSERT_TRUE(report.at("ground").is_object()) << "no ground in report.json";
  const auto& ground = report.at("ground");
  EXPECT_GT(ground.at("coverage").get<double>(), 0.2);
  EXPECT_GT(ground.at("voxels").get<std::size_t>(), 0u);
  EXPECT_EQ(ground.at("grid").at("step"), 2.0);
  const auto obstacles = hullmap::test::readJson(dir / "out" / "obstacles.json");
  const auto& surfaces = obstacles.at("surfaces");
  ASSERT_EQ(surfaces.size(), 1u) << surfaces.dump();
  EXPECT_EQ(surfaces[0].at("kind"), "heightfield");
  EXPECT_EQ(surfaces[0].at("name"), "ground");
  EXPECT_EQ(surfaces[0].at("heights").size(),
            surfaces[0].at("nx").get<std::size_t>() * surfaces[0].at("ny").get<std::size_t>());
  std::ifstream voxels(dir / "out" / "voxels.csv");
  std::string line;
  std::size_t ground_rows = 0;
  while (std::getline(voxels, line)) ground_rows += line.find(",-4,") != std::string::npos ? 1 : 0;
  EXPECT_EQ(ground_rows, ground.at("voxels").get<std::size_t>());
  // A drop through the ground at the first keyframe: it collides, with the ground.
  std::ifstream trajectory(dir / "out" / "trajectory.txt");
  double t = 0, x = 0, y = 0, z = 0;
  while (std::getline(trajectory, line))
    if (!line.empty() && line[0] != '#' && std::istringstream(line) >> t >> x >> y >> z) break;
  std::ostringstream segment;
  segment << x << "," << y << "," << z << "," << x << "," << y << "," << z - 30.0;
  const auto c = runHullmap("check " + d + "out' --radius 0.3 --segment " + segment.str() + " --json");
  EXPECT_EQ(c.status, 1) << c.out << c.err;
  EXPECT_NE(c.out.find("\"surface\":\"ground\""), std::string::npos) << c.out;
  // plot captions the ground's coverage.
  const auto p = runHullmap("plot " + d + "out' -o " + d + "plot.svg'");
  ASSERT_EQ(p.status, 0) << p.err;
  std::ifstream svg(dir / "plot.svg");
  const std::string text((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("ground: "), std::string::npos);
  EXPECT_NE(text.find("% measured"), std::string::npos);
}

TEST(GenerateCommand, BadOutdoorOptionsExitTwoWithOneLine) {
  const auto dir = hullmap::test::freshDir("generate_outdoor_bad");
  const std::pair<const char*, const char*> cases[] = {{"--scale-drift -1", "--scale-drift"},
                                                       {"--gps-sigma -3", "--gps-sigma"},
                                                       {"--gps-dropout 1.5", "--gps-dropout"},
                                                       {"--track-length 30", "--track-length"},
                                                       {"--track-width 10", "--track-width"},
                                                       {"--slope-across 0.9", "--slope-across"},
                                                       {"--bump-height 9", "--bump-height"},
                                                       {"--buildings 300", "--buildings"},
                                                       {"--density 0", "--density"},
                                                       {"--scale 0", "--scale"},
                                                       {"--pitch 90", "--pitch"},
                                                       {"--keyframes 2", "--keyframes"}};
  for (const auto& [args, name] : cases) {
    const auto r = runHullmap(std::string("generate --layout outdoor ") + args + " -o '" + (dir / "x").string() + "'");
    hullmap::test::expectOneLineError(r, name);
    EXPECT_EQ(r.err.find("--trajectory"), std::string::npos) << r.err;
  }
}

}  // namespace
