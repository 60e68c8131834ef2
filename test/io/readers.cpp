// Point readers: every format against points written by an independent writer in this file,
// the real ORB-SLAM and PCL files against their twins, and every kind of bad input.
#include <malloc.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <liblzf/lzf.h>

#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "read_outcome.hpp"
#include "readers_fixtures.hpp"
#include "test_support.hpp"

namespace {

bool hasNonFinite(const std::vector<double>& row) {
  for (double v : row) {
    if (!std::isfinite(v)) return true;
  }
  return false;
}

void expectPoints(const Points& got, const std::vector<Eigen::Vector3d>& want, double tol = 0.0) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(got[i][a], want[i][a], tol) << "point " << i << " axis " << a;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// A tiny PCD writer (independent of the reader): fields with TYPE/SIZE/COUNT, rows of values.

/// Organized 4x3 cloud `x y z rgb intensity` (F4 xyz, U4 rgb, F4 intensity) with three NaN pixels.
PcdCloud organizedCloud() {
  PcdCloud c;
  c.fields = {{"x", 'F', 4}, {"y", 'F', 4}, {"z", 'F', 4}, {"rgb", 'U', 4}, {"intensity", 'F', 4}};
  c.width = 4;
  c.height = 3;
  for (int i = 0; i < 12; ++i) {
    if (i == 1 || i == 6 || i == 11) {
      c.rows.push_back({kNaN, kNaN, kNaN, 0, 0});
    } else {
      c.rows.push_back({0.25 * i, -0.5 * i, 1.0 + 0.125 * i, double(0x00ff0000u + i), 0.75});
    }
  }
  return c;
}

std::vector<Eigen::Vector3d> finiteXyz(const PcdCloud& c, std::array<int, 3> cols) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& row : c.rows) {
    if (hasNonFinite({row[cols[0]], row[cols[1]], row[cols[2]]})) continue;
    out.emplace_back(row[cols[0]], row[cols[1]], row[cols[2]]);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Real data

TEST(IoReadersReal, OrbSlam2TextAndPcdHoldTheSame8704Points) {
  HULLMAP_REQUIRE_REAL_DATA(txt, "orbslam2_euroc_V1_01_MapPoints.txt");
  HULLMAP_REQUIRE_REAL_DATA(pcd, "orbslam2_euroc_V1_01_MapPoints.pcd");
  const PointSet a = readPointFile(txt);
  const PointSet b = readPointFile(pcd);
  EXPECT_EQ(a.inputs.at(0).format, "text");
  EXPECT_EQ(b.inputs.at(0).format, "pcd");
  ASSERT_EQ(a.points.size(), 8704u);
  ASSERT_EQ(b.points.size(), 8704u);
  EXPECT_EQ(a.inputs[0].read, 8704u);
  EXPECT_EQ(b.inputs[0].droppedTotal(), 0u);
  // The text has 7 decimals, the PCD float32 values: they agree to well under 1e-6.
  double worst = 0;
  for (std::size_t i = 0; i < a.points.size(); ++i)
    worst = std::max(worst, (a.points[i] - b.points[i]).cwiseAbs().maxCoeff());
  EXPECT_LT(worst, 1e-6);
  EXPECT_NEAR(a.points.front().x(), 0.2103370, 1e-12);
  EXPECT_NEAR(a.points.back().z(), 1.2398679, 1e-12);
}

TEST(IoReadersReal, OrbSlam3PointCloudsUnionTo12292) {
  HULLMAP_REQUIRE_REAL_DATA(plain, "orbslam3_euroc_MH_01_mono_pointcloud.txt");
  HULLMAP_REQUIRE_REAL_DATA(ref, "orbslam3_euroc_MH_01_mono_ref_pointcloud.txt");
  const PointSet set = readPointFiles({plain, ref});
  ASSERT_EQ(set.inputs.size(), 2u);
  EXPECT_EQ(set.inputs[0].read, 4492u);  // no header line
  EXPECT_EQ(set.inputs[1].read, 7800u);  // `pos_x, pos_y, pos_z` header
  EXPECT_EQ(set.inputs[0].path, plain);
  EXPECT_EQ(set.inputs[1].path, ref);
  ASSERT_EQ(set.points.size(), 12292u);
  EXPECT_NEAR(set.points[0].x(), 2.651035, 1e-12);     // first line of pointcloud.txt
  EXPECT_NEAR(set.points[4492].z(), 0.288764, 1e-12);  // first data line of ref_pointcloud.txt
}

std::vector<Eigen::Vector3d> readXzTwin(const std::string& path, bool& ok) {
  std::vector<Eigen::Vector3d> out;
  ok = false;
  if (std::system("command -v xz >/dev/null 2>&1") != 0) return out;
  FILE* pipe = popen(("xz -dc '" + path + "'").c_str(), "r");
  if (!pipe) return out;
  char line[256];
  while (std::fgets(line, sizeof line, pipe)) {
    char* end = line;
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) p[a] = std::strtod(end, &end);
    out.push_back(p);
  }
  ok = pclose(pipe) == 0;
  return out;
}

void checkPclCloud(const std::string& pcd, const std::string& twin, std::size_t finite) {
  bool ok = false;
  const auto want = readXzTwin(twin, ok);
  if (!ok) GTEST_SKIP() << "xz is not installed (or failed): cannot decompress " << twin;
  ASSERT_EQ(want.size(), finite);
  const PointSet set = readPointFile(pcd);
  EXPECT_EQ(set.inputs.at(0).read, 640u * 480u);
  EXPECT_EQ(set.inputs[0].dropped.at("non_finite"), 640u * 480u - finite);
  expectPoints(set.points, want, 1e-5);  // the twin has 5 decimals
}

TEST(IoReadersReal, PclTableSceneBinaryCompressedMatchesItsXyzTwin) {
  HULLMAP_REQUIRE_REAL_DATA(pcd, "pcl_table_scene_mug_stereo_textured.pcd");
  HULLMAP_REQUIRE_REAL_DATA(twin, "pcl_table_scene_mug_stereo_textured_finite.xyz.xz");
  checkPclCloud(pcd, twin, 209280);
}

TEST(IoReadersReal, PclFivePeopleBinaryCompressedMatchesItsXyzTwin) {
  HULLMAP_REQUIRE_REAL_DATA(pcd, "pcl_five_people.pcd");
  HULLMAP_REQUIRE_REAL_DATA(twin, "pcl_five_people_finite.xyz.xz");
  checkPclCloud(pcd, twin, 239075);
}

TEST(IoReadersReal, OrbSlam3KeyFrameTrajectoryNanosecondStamps) {
  HULLMAP_REQUIRE_REAL_DATA(path, "orbslam3_euroc_MH_01_mono_KeyFrameTrajectory.txt");
  const auto kfs = readTumTrajectory(path);
  ASSERT_EQ(kfs.size(), 310u);
  EXPECT_NEAR(kfs.front().stamp, 1403636579.763555840, 1e-6);
  EXPECT_NEAR(kfs.back().stamp, 1403636763.413555712, 1e-6);
  for (std::size_t i = 1; i < kfs.size(); ++i) EXPECT_GT(kfs[i].stamp, kfs[i - 1].stamp) << i;
  for (const auto& k : kfs) EXPECT_NEAR(k.orientation.norm(), 1.0, 1e-12);
  EXPECT_TRUE(kfs.front().position.isZero());
  EXPECT_NEAR(kfs.front().orientation.w(), 1.0, 1e-12);
  EXPECT_NEAR(kfs[1].position.y(), 0.006067876, 1e-12);
}

TEST(IoReadersReal, OctomapBinaryTreeIsNotAPointFile) {
  HULLMAP_REQUIRE_REAL_DATA(bt, "octomap_geb079.bt");
  const std::string msg = errorOf([&] { readPointFile(bt); });
  EXPECT_NE(msg.find(bt), std::string::npos) << msg;
  EXPECT_NE(msg.find("not a point file"), std::string::npos) << msg;
}

// ---------------------------------------------------------------------------------------------
// ORB-SLAM (v1) rostopic echo dumps

// The last publication in test/data/orbslam_echo_map.txt (k = 2): id 0 then id 6.
std::vector<Eigen::Vector3d> lastPublication() {
  std::vector<Eigen::Vector3d> want;
  for (int i = 0; i < 5; ++i) want.emplace_back(0.1 * i + 2, -0.05 * i, 1.0 + 0.01 * i);
  want.emplace_back(12.0, 22.0, 30.0);
  want.emplace_back(12.0, 22.0, 30.5);
  return want;
}

TEST(IoReadersEcho, MapIsLastId0PlusLastId6) {
  const PointSet set = readPointFile(fixture("orbslam_echo_map.txt"));
  EXPECT_EQ(set.inputs.at(0).format, "orbslam_echo");
  EXPECT_EQ(set.inputs[0].read, 7u);
  expectPoints(set.points, lastPublication());
}

TEST(IoReadersEcho, DumpCutOffMidMessageKeepsLastCompleteOne) {
  const PointSet set = readPointFile(fixture("orbslam_echo_truncated.txt"));
  EXPECT_EQ(set.inputs.at(0).read, 7u);
  expectPoints(set.points, lastPublication());
}

std::string echoMarker(const std::string& ns, int id, int type, int action, const std::string& points_block,
                       bool terminated = true) {
  std::string s =
      "header: \n  seq: 7\n  stamp: \n    secs: 12\n    nsecs: 500\n  frame_id: \"/ORB_SLAM/World\"\n"
      "ns: \"" +
      ns + "\"\nid: " + std::to_string(id) + "\ntype: " + std::to_string(type) + "\naction: " + std::to_string(action) +
      "\npose: \n  position: \n    x: 9.0\n    y: 9.0\n    z: 9.0\n  orientation: \n    x: 0.0\n    y: 0.0\n"
      "    z: 0.0\n    w: 1.0\nscale: \n  x: 0.01\n  y: 0.01\n  z: 0.0\ncolor: \n  r: 0.0\n  g: 0.0\n  b: 0.0\n"
      "  a: 1.0\nlifetime: \n  secs: 0\n  nsecs:         0\nframe_locked: False\n" +
      points_block + "colors: []\ntext: ''\nmesh_resource: ''\nmesh_use_embedded_materials: False\n";
  return terminated ? s + "---\n" : s;
}

TEST(IoReadersEcho, InlineListItemsNonFiniteAndOtherNamespaces) {
  // `- x: 1` (item and first key on one line), nan/inf coordinates, and a KeyFrames LINE_LIST with
  // points that must not be taken.
  const std::string text =
      echoMarker("KeyFrames", 1, 5, 0, "points: \n  - x: 100.0\n    y: 100.0\n    z: 100.0\n") +
      echoMarker("MapPoints", 0, 8, 0,
                 "points: \n  - x: 1.5\n    y: -2.0\n    z: 3e-2\n  - x: nan\n    y: 0.0\n    z: 0.0\n"
                 "  - \n    x: 4.0\n    y: inf\n    z: 0.0\n  - \n    x: -1.0\n    y: -1.0\n    z: -1.0\n");
  const PointSet set = parsePoints(text, "dump.txt");
  EXPECT_EQ(set.inputs.at(0).read, 4u);
  EXPECT_EQ(set.inputs[0].dropped.at("non_finite"), 2u);
  expectPoints(set.points, {{1.5, -2.0, 0.03}, {-1.0, -1.0, -1.0}});
}

TEST(IoReadersEcho, DeleteActionAndEmptyPointLists) {
  const std::string one = "points: \n  - \n    x: 1.0\n    y: 2.0\n    z: 3.0\n";
  // id 6 deleted after being sent; id 0 sent with points then re-sent empty: no points at all.
  const std::string text = echoMarker("MapPoints", 0, 8, 0, one) + echoMarker("MapPoints", 6, 8, 0, one) +
                           echoMarker("MapPoints", 6, 8, 2, "points: []\n") +
                           echoMarker("MapPoints", 0, 8, 0, "points: []\n");
  const PointSet set = parsePoints(text, "dump.txt");
  EXPECT_TRUE(set.points.empty());
  EXPECT_EQ(set.inputs.at(0).read, 0u);
  // An unterminated last message that did arrive whole (has its last field) counts.
  const PointSet last = parsePoints(echoMarker("MapPoints", 6, 8, 0, one, false), "dump.txt");
  expectPoints(last.points, {{1.0, 2.0, 3.0}});
}

TEST(IoReadersEcho, MalformedCoordinateNamesFileAndLine) {
  const std::string text = echoMarker("MapPoints", 0, 8, 0, "points: \n  - \n    x: 1.0\n    y: 2.O\n    z: 3.0\n");
  const std::string msg = errorOf([&] { parsePoints(text, "dump.txt"); });
  // Line 31 of the message is `    y: 2.O`.
  std::istringstream lines(text);
  std::string line;
  int n = 0, bad = 0;
  while (std::getline(lines, line)) {
    ++n;
    if (line == "    y: 2.O") bad = n;
  }
  EXPECT_NE(msg.find("dump.txt:" + std::to_string(bad) + ":"), std::string::npos) << msg;
  EXPECT_NE(msg.find("2.O"), std::string::npos) << msg;
  // A point missing z.
  const std::string missing = echoMarker("MapPoints", 0, 8, 0, "points: \n  - \n    x: 1.0\n    y: 2.0\n");
  EXPECT_NE(errorOf([&] { parsePoints(missing, "d.txt"); }).find("without x, y and z"), std::string::npos);
}

TEST(IoReadersEcho, MessageThatIsNotAMarkerIsAnError) {
  const std::string text = "header: \n  seq: 1\n  stamp: \n    secs: 0\n    nsecs: 0\n  frame_id: ''\ndata: 5\n---\n";
  const std::string msg = errorOf([&] { parsePoints(text, "imu.txt"); });
  EXPECT_NE(msg.find("imu.txt:1:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("Marker"), std::string::npos) << msg;
}

// ---------------------------------------------------------------------------------------------
// Plain text (ORB-SLAM2/3 map points, .xyz)

TEST(IoReadersText, SpacesCommasHeaderCommentsBlankLinesCrlf) {
  const std::string text =
      "# ORB-SLAM3 map points\r\n"
      "pos_x, pos_y, pos_z\r\n"
      "\r\n"
      "1.0, 2.0, 3.0\r\n"
      "  -4.5\t5e-1   6   # trailing comment\n"
      "+7,-8.25 ,9\n"
      "\n";
  const PointSet set = parsePoints(text, "map.txt");
  EXPECT_EQ(set.inputs.at(0).format, "text");
  EXPECT_EQ(set.inputs[0].read, 3u);
  expectPoints(set.points, {{1, 2, 3}, {-4.5, 0.5, 6}, {7, -8.25, 9}});
}

TEST(IoReadersText, XyzWithExtraColumnsTakesTheFirstThree) {
  const PointSet set = parsePoints("x y z nx ny nz\n1 2 3 0 0 1\n4 5 6 0 1 0\n", "cloud.xyz");
  expectPoints(set.points, {{1, 2, 3}, {4, 5, 6}});
  const std::string msg = errorOf([] { parsePoints("1 2 3 0 0 1\n4 5 6\n", "cloud.xyz"); });
  EXPECT_NE(msg.find("cloud.xyz:2: expected 6 numbers"), std::string::npos) << msg;
}

TEST(IoReadersText, NonFiniteValuesAreDroppedAndCounted) {
  const PointSet set = parsePoints("1 2 3\nnan 0 0\n0 inf 0\n0 0 -inf\n4 5 6\n1e999 0 0\n", "m.txt");
  EXPECT_EQ(set.inputs.at(0).read, 6u);
  EXPECT_EQ(set.inputs[0].dropped.at("non_finite"), 4u);
  EXPECT_EQ(set.inputs[0].droppedTotal(), 4u);
  expectPoints(set.points, {{1, 2, 3}, {4, 5, 6}});
}

TEST(IoReadersText, MalformedLinesNameFileAndLine) {
  struct Case {
    std::string text;
    std::string expect;
  } cases[] = {
      {"1 2 3\n# c\n1 2\n", "m.txt:3: expected 3 numbers"},      {"1 2 3\n4 5 abc\n", "m.txt:2: 'abc' is not a number"},
      {"1.0.0 2 3\n", "m.txt:1: '1.0.0' is not a number"},       {"hello\n", "m.txt:1: 'hello' is not a number"},
      {"1 2\n", "m.txt:1: expected 3 numbers (x y z), got 2"},   {"1,,3\n", "m.txt:1: empty field"},
      {"x y z\n1 2 3\nx y z\n", "m.txt:3: 'x' is not a number"},
  };
  for (const auto& c : cases) {
    const std::string msg = errorOf([&] { parsePoints(c.text, "m.txt"); });
    EXPECT_NE(msg.find(c.expect), std::string::npos) << "input: " << c.text << "\nmessage: " << msg;
  }
}

TEST(IoReadersText, EmptyAndBlankFilesGiveZeroPoints) {
  const auto dir = hullmap::test::freshDir("readers_empty");
  for (const std::string name : {"empty.txt", "empty.pcd", "blank.xyz"}) {
    const std::string path = writeFile(dir, name, name == "blank.xyz" ? " \n\n\t\n" : "");
    const PointSet set = readPointFile(path);
    EXPECT_TRUE(set.points.empty()) << name;
    ASSERT_EQ(set.inputs.size(), 1u);
    EXPECT_EQ(set.inputs[0].read, 0u);
    EXPECT_EQ(set.inputs[0].path, path);
  }
  EXPECT_EQ(readPointFile((dir / "empty.pcd").string()).inputs[0].format, "pcd");
  // Only comments and a header: a file with no points, not an error.
  EXPECT_TRUE(parsePoints("# nothing yet\npos_x, pos_y, pos_z\n", "h.txt").points.empty());
}

TEST(IoReadersText, MissingFileAndDirectoryNameThePath) {
  const auto dir = hullmap::test::freshDir("readers_missing");
  const std::string missing = (dir / "nope.txt").string();
  std::string msg = errorOf([&] { readPointFile(missing); });
  EXPECT_NE(msg.find(missing + ": cannot open"), std::string::npos) << msg;
  msg = errorOf([&] { readPointFiles({writeFile(dir, "ok.txt", "1 2 3\n"), missing}); });
  EXPECT_NE(msg.find(missing), std::string::npos) << msg;
  msg = errorOf([&] { readPointFile(dir.string()); });
  EXPECT_NE(msg.find("is a directory"), std::string::npos) << msg;
  msg = errorOf([&] { readTumTrajectory(missing); });
  EXPECT_NE(msg.find(missing), std::string::npos) << msg;
}

TEST(IoReadersText, BinaryGarbageIsNotAPointFile) {
  std::string garbage = "1 2 3\n";
  for (int i = 0; i < 200; ++i) garbage += static_cast<char>((i * 37 + 11) & 0xff);
  const std::string msg = errorOf([&] { parsePoints(garbage, "blob.bin"); });
  EXPECT_NE(msg.find("blob.bin: not a point file"), std::string::npos) << msg;
}

TEST(IoReadersText, FormatComesFromContentNotExtension) {
  const auto dir = hullmap::test::freshDir("readers_detect");
  PcdCloud c;
  c.fields = {{"x", 'F', 4}, {"y", 'F', 4}, {"z", 'F', 4}};
  c.width = 1;
  c.rows = {{1, 2, 3}};
  const std::string pcd_as_txt = writeFile(dir, "cloud.txt", writePcd(c, "binary"));
  EXPECT_EQ(detectPointFormat(pcd_as_txt), PointFormat::kPcd);
  expectPoints(readPointFile(pcd_as_txt).points, {{1, 2, 3}});
  const std::string text_as_pcd = writeFile(dir, "points.pcd", "4 5 6\n");
  EXPECT_EQ(detectPointFormat(text_as_pcd), PointFormat::kText);
  expectPoints(readPointFile(text_as_pcd).points, {{4, 5, 6}});
  const std::string ply_as_dat = writeFile(dir, "mesh.dat",
                                           "ply\nformat ascii 1.0\nelement vertex 1\n"
                                           "property float x\nproperty float y\nproperty float z\n"
                                           "end_header\n7 8 9\n");
  EXPECT_EQ(detectPointFormat(ply_as_dat), PointFormat::kPly);
  expectPoints(readPointFile(ply_as_dat).points, {{7, 8, 9}});
  EXPECT_EQ(detectPointFormat(fixture("orbslam_echo_map.txt")), PointFormat::kOrbSlamEcho);
  EXPECT_EQ(toString(PointFormat::kOrbSlamEcho), "orbslam_echo");
}

// ---------------------------------------------------------------------------------------------
// PCD

class IoReadersPcd : public ::testing::TestWithParam<std::string> {};

TEST_P(IoReadersPcd, OrganizedCloudWithNaNsAndExtraFieldsRoundTrips) {
  const PcdCloud c = organizedCloud();
  const PointSet set = parsePoints(writePcd(c, GetParam()), "org.pcd");
  EXPECT_EQ(set.inputs.at(0).format, "pcd");
  EXPECT_EQ(set.inputs[0].read, 12u);
  EXPECT_EQ(set.inputs[0].dropped.at("non_finite"), 3u);
  expectPoints(set.points, finiteXyz(c, {0, 1, 2}));  // exact: every value is a float
}

TEST_P(IoReadersPcd, DoubleFieldsCountsAndXyzAfterOtherFields) {
  // `normal` has COUNT 3, `label` is I2, `z y x` are F8 in an unusual order.
  PcdCloud c;
  c.fields = {{"normal", 'F', 4, 3}, {"label", 'I', 2}, {"z", 'F', 8}, {"y", 'F', 8}, {"x", 'F', 8}, {"a", 'U', 1}};
  c.width = 50;
  for (int i = 0; i < 50; ++i) {
    c.rows.push_back({0, 0, 1, double(i - 20), 1.0 / 3.0 + i, -0.1 * i, 1e-9 * i + 1234.5678901234, double(i % 7)});
  }
  const PointSet set = parsePoints(writePcd(c, GetParam()), "f8.pcd");
  EXPECT_EQ(set.inputs.at(0).read, 50u);
  std::vector<Eigen::Vector3d> want;
  for (const auto& r : c.rows) want.emplace_back(r[6], r[5], r[4]);
  // ascii is written with %.17g: doubles survive exactly as in binary.
  expectPoints(set.points, want);
}

TEST_P(IoReadersPcd, TruncatedDataIsAnErrorNamingTheFile) {
  const PcdCloud c = organizedCloud();
  std::string bytes = writePcd(c, GetParam());
  bytes.resize(bytes.size() - 6);
  const std::string msg = errorOf([&] { parsePoints(bytes, "cut.pcd"); });
  EXPECT_NE(msg.find("cut.pcd"), std::string::npos) << msg;
  if (GetParam() == "binary") {
    // 12 points of 20 bytes; 6 bytes missing: point 11 is incomplete.
    EXPECT_NE(msg.find("point 11 is incomplete"), std::string::npos) << msg;
  } else if (GetParam() == "ascii") {
    EXPECT_NE(msg.find("cut.pcd:"), std::string::npos) << msg;  // the last line, now short
  } else {
    EXPECT_NE(msg.find("truncated binary_compressed"), std::string::npos) << msg;
  }
}

TEST_P(IoReadersPcd, HugePointCountIsRefusedBeforeAllocating) {
  PcdCloud c;
  c.fields = {{"x", 'F', 4}, {"y", 'F', 4}, {"z", 'F', 4}};
  c.width = 1000000000000;  // 10^12 points claimed, none present
  const std::string bytes = pcdHeader(c, GetParam()) + (GetParam() == "binary_compressed" ? "" : "1 2 3\n");
  const std::string msg = errorOf([&] { parsePoints(bytes, "huge.pcd"); });
  EXPECT_NE(msg.find("huge.pcd"), std::string::npos) << msg;
  EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
}

INSTANTIATE_TEST_SUITE_P(DataTypes, IoReadersPcd, ::testing::Values("ascii", "binary", "binary_compressed"));

TEST(IoReadersPcdErrors, BadHeadersNameTheLine) {
  const std::string head = "# .PCD v0.7\nVERSION 0.7\n";
  struct Case {
    std::string header;
    std::string expect;
  } cases[] = {
      {"FIELDS x y z\nSIZE 4 4\n", "bad.pcd:4: SIZE has 2 entries for 3 FIELDS"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F Q\n", "bad.pcd:5: TYPE must be F, I or U"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary_lz4\n",
       "bad.pcd:9: unknown PCD DATA type 'binary_lz4'"},
      {"FIELDS a b c\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n", "bad.pcd:3: FIELDS has no x y z"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 3\nDATA ascii\n",
       "bad.pcd:9: POINTS 3 differs from WIDTH * HEIGHT = 2"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH -1\n", "bad.pcd:6: WIDTH: '-1' is not a valid count"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F U\nWIDTH 1\nDATA ascii\n", "bad.pcd:3: field z must be F4 or F8"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\n", "bad.pcd: PCD header has no DATA line"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nCOLOR red\n", "bad.pcd:7: unknown PCD header line"},
  };
  for (const auto& c : cases) {
    const std::string msg = errorOf([&] { parsePoints(head + c.header, "bad.pcd"); });
    EXPECT_NE(msg.find(c.expect), std::string::npos) << "header:\n" << c.header << "message: " << msg;
  }
}

TEST(IoReadersPcdErrors, CorruptCompressedDataAndAsciiLines) {
  const PcdCloud c = organizedCloud();
  std::string bytes = writePcd(c, "binary_compressed");
  const std::size_t data = pcdHeader(c, "binary_compressed").size();
  // Claim more compressed bytes than there are.
  std::string lying = bytes;
  const std::uint32_t big = 1u << 30;
  std::memcpy(lying.data() + data, &big, 4);
  EXPECT_NE(errorOf([&] { parsePoints(lying, "z.pcd"); }).find("z.pcd: truncated binary_compressed"),
            std::string::npos);
  // Uncompressed size that does not match POINTS * point size.
  std::string wrong = bytes;
  const std::uint32_t odd = 7;
  std::memcpy(wrong.data() + data + 4, &odd, 4);
  EXPECT_NE(errorOf([&] { parsePoints(wrong, "z.pcd"); }).find("uncompressed size 7"), std::string::npos);
  // Scrambled LZF stream.
  std::string scrambled = bytes;
  for (std::size_t i = data + 8; i < scrambled.size(); ++i) scrambled[i] = static_cast<char>(0xff);
  EXPECT_NE(errorOf([&] { parsePoints(scrambled, "z.pcd"); }).find("z.pcd: binary_compressed"), std::string::npos);
  // ASCII: a value that is not a number, a short line, an extra line.
  const std::string head = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nDATA ascii\n";
  EXPECT_NE(errorOf([&] { parsePoints(head + "1 2 3\n1 x 3\n", "a.pcd"); }).find("a.pcd:7: 'x' is not a number"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { parsePoints(head + "1 2 3\n1 2\n", "a.pcd"); }).find("a.pcd:7: expected 3 values, got 2"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { parsePoints(head + "1 2 3\n1 2 3\n4 5 6\n", "a.pcd"); }).find("a.pcd:8: more data lines"),
            std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// PLY

const std::vector<PlyVertex> kPlyVertices = {
    {0.5, -1.25, 2.0, 10, 0.1f}, {kNaN, 0, 0, 20, 0.2f}, {3.0, 4.0, -5.5, 30, 0.3f}, {1e3, 2e-3, 7.0, 40, 0.4f}};

/// A PLY with a `camera` element before the vertices, faces (list property) after, `red` and `nx`
/// vertex properties around x y z.
std::string writePly(const std::string& format, bool dbl) {
  const std::string t = dbl ? "double" : "float";
  std::string out = "ply\nformat " + format +
                    " 1.0\ncomment made by hullmap's tests\n"
                    "element camera 1\nproperty float view_px\nproperty list uchar int tags\n"
                    "element vertex " +
                    std::to_string(kPlyVertices.size()) +
                    "\n"
                    "property uchar red\nproperty " +
                    t + " x\nproperty " + t + " y\nproperty " + t +
                    " z\n"
                    "property float nx\n"
                    "element face 2\nproperty list uchar int vertex_indices\nproperty uchar flags\nend_header\n";
  const bool big = format == "binary_big_endian";
  if (format == "ascii") {
    out += "1.5 2 7 8\n";
    char buf[160];
    for (const auto& v : kPlyVertices) {
      std::snprintf(buf, sizeof buf, "%d %.17g %.17g %.17g %.9g\n", v.red, v.x, v.y, v.z, double(v.nx));
      out += buf;
    }
    out += "3 0 1 2 0\n4 0 1 2 3 1\n";
    return out;
  }
  put<float>(out, 1.5f, big);
  put<std::uint8_t>(out, 2, big);
  put<std::int32_t>(out, 7, big);
  put<std::int32_t>(out, 8, big);
  for (const auto& v : kPlyVertices) {
    put<std::uint8_t>(out, v.red, big);
    if (dbl) {
      put<double>(out, v.x, big), put<double>(out, v.y, big), put<double>(out, v.z, big);
    } else {
      put<float>(out, float(v.x), big), put<float>(out, float(v.y), big), put<float>(out, float(v.z), big);
    }
    put<float>(out, v.nx, big);
  }
  put<std::uint8_t>(out, 3, big);
  for (int i : {0, 1, 2}) put<std::int32_t>(out, i, big);
  put<std::uint8_t>(out, 0, big);
  put<std::uint8_t>(out, 4, big);
  for (int i : {0, 1, 2, 3}) put<std::int32_t>(out, i, big);
  put<std::uint8_t>(out, 1, big);
  return out;
}

TEST(IoReadersPly, AsciiAndBinaryFloatAndDoubleWithExtraPropertiesAndFaces) {
  for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    for (const bool dbl : {false, true}) {
      SCOPED_TRACE(format + (dbl ? " double" : " float"));
      const PointSet set = parsePoints(writePly(format, dbl), "mesh.ply");
      EXPECT_EQ(set.inputs.at(0).format, "ply");
      EXPECT_EQ(set.inputs[0].read, 4u);
      EXPECT_EQ(set.inputs[0].dropped.at("non_finite"), 1u);
      std::vector<Eigen::Vector3d> want;
      for (const auto& v : kPlyVertices) {
        if (std::isnan(v.x)) continue;
        want.emplace_back(dbl ? v.x : double(float(v.x)), dbl ? v.y : double(float(v.y)),
                          dbl ? v.z : double(float(v.z)));
      }
      expectPoints(set.points, want, format == "ascii" && !dbl ? 1e-6 : 0.0);
    }
  }
}

TEST(IoReadersPly, TruncatedAndMalformedPlyNameTheFile) {
  std::string bytes = writePly("binary_little_endian", false);
  // Cut inside vertex 2: header, camera (1+4+1+8 = 13 bytes)... keep 2.5 vertices of 17 bytes.
  const std::size_t header = bytes.find("end_header\n") + 11;
  const std::string cut = bytes.substr(0, header + 13 + 17 * 2 + 8);
  std::string msg = errorOf([&] { parsePoints(cut, "cut.ply"); });
  EXPECT_NE(msg.find("cut.ply: truncated binary PLY data: vertex 2"), std::string::npos) << msg;
  // Faces cut short: still an error, not a silent success.
  const std::string no_faces = bytes.substr(0, bytes.size() - 3);
  msg = errorOf([&] { parsePoints(no_faces, "f.ply"); });
  EXPECT_NE(msg.find("f.ply: truncated binary PLY data: face 1"), std::string::npos) << msg;
  // ASCII: a word where a number belongs, on its line.
  std::string ascii = writePly("ascii", false);
  ascii.replace(ascii.find("1000 "), 4, "lots");
  msg = errorOf([&] { parsePoints(ascii, "a.ply"); });
  EXPECT_NE(msg.find("a.ply:21: 'lots' is not a number"), std::string::npos) << msg;
  const std::string short_ascii = writePly("ascii", false).substr(0, writePly("ascii", false).size() - 8);
  EXPECT_NE(errorOf([&] { parsePoints(short_ascii, "s.ply"); }).find("s.ply: truncated PLY data: face"),
            std::string::npos);
  // Header errors.
  EXPECT_NE(errorOf([] {
              parsePoints("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n", "h.ply");
            }).find("h.ply:3: PLY vertex element has no scalar x y z"),
            std::string::npos);
  EXPECT_NE(errorOf([] {
              parsePoints("ply\nformat ascii 1.0\nelement vertex 1\nproperty half x\n", "h.ply");
            }).find("h.ply:4: unknown PLY property type 'half'"),
            std::string::npos);
  EXPECT_NE(errorOf([] {
              parsePoints("ply\nformat ascii 1.0\nelement vertex 1\n", "h.ply");
            }).find("h.ply: PLY header has no end_header"),
            std::string::npos);
  // 10^12 vertices claimed in a few bytes: refused as truncated, without allocating for them.
  msg = errorOf([] {
    parsePoints(
        "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\n"
        "property float y\nproperty float z\nend_header\n",
        "huge.ply");
  });
  EXPECT_NE(msg.find("huge.ply: truncated binary PLY data: vertex 0"), std::string::npos) << msg;
  // 10^12 items of an element without properties take no bytes: skipped, not walked one by one.
  const PointSet empty_element = parsePoints(
      "ply\nformat binary_little_endian 1.0\nelement nothing 1000000000000\nelement vertex 1\n"
      "property float x\nproperty float y\nproperty float z\nend_header\n" +
          std::string(12, '\0'),
      "e.ply");
  expectPoints(empty_element.points, {{0, 0, 0}});
}

// ---------------------------------------------------------------------------------------------
// Streaming readers: against parsePoints, the whole-input reader

// Lines of plain decimals after the first data line take a fast path of their own in the parallel
// read (no from_chars): it must give the points, bit for bit (signed zeros too), the counts and the
// errors that the front-to-back read of a pipe gives, which parses every token with from_chars.
// Tokens at its edges (19 and 20 digits, 2^53 and 2^53 + 1, -0, a '+', exponents, "1.", ".5") and
// every separator forEachToken knows, then one bad line after a good start.
TEST(IoReadersStream, PlainDecimalFastPathReadsAsFromChars) {
  std::mt19937_64 rng(17);
  const auto pick = [&rng](std::size_t n) { return std::size_t(rng() % n); };
  const std::vector<std::string> edges = {"-0",
                                          "0",
                                          "-0.000",
                                          "0.0",
                                          "9007199254740992",
                                          "9007199254740993",
                                          "-9007199254740993.5",
                                          "900719925474099.3",
                                          "1234567890123456789",
                                          "12345678901234567890",
                                          "0.1234567890123456789",
                                          "0.30000000000000004",
                                          "1.7976931348623157",
                                          "4.9406564584124654",
                                          "000123.4500",
                                          "+4",
                                          "+0.5",
                                          "1e3",
                                          "-2E-3",
                                          "1.",
                                          ".5",
                                          "-.5",
                                          "nan",
                                          "-inf",
                                          "1e999",
                                          "7.0e-400"};
  const auto token = [&]() -> std::string {
    if (pick(8) == 0) return edges[pick(edges.size())];
    std::string t = pick(3) == 0 ? "-" : "";
    const std::size_t whole = 1 + pick(12), decimals = pick(3) == 0 ? 0 : 1 + pick(14);
    for (std::size_t i = 0; i < whole; ++i) t += char('0' + pick(10));
    if (decimals > 0) t += '.';
    for (std::size_t i = 0; i < decimals; ++i) t += char('0' + pick(10));
    return t;
  };
  const std::vector<std::string> separators = {" ", "\t", ",", ", ", " ,\t", "  ", "\v", " , "};
  const std::vector<std::string> ends = {"\n", "\r\n", " \n", "\t# note\n", "\r\r\n"};
  const auto line = [&](std::size_t tokens) {
    std::string l = pick(10) == 0 ? " " : "";
    for (std::size_t t = 0; t < tokens; ++t) l += (t ? separators[pick(separators.size())] : "") + token();
    return l + ends[pick(ends.size())];
  };
  std::string good = "1 2 3\n";
  for (int i = 0; i < 20000; ++i) {
    if (pick(50) == 0) good += pick(2) ? "\n" : "# comment\n";
    good += line(3);
  }
  // A long first data line, then short ones: each chunk's points overflow the slice the first line's
  // length made room for, and go on in order.
  std::string long_first = "1.000000000000000000 2.000000000000000000 3.000000000000000000\n";
  for (int i = 0; i < 100000; ++i)
    long_first += std::to_string(pick(10)) + " " + std::to_string(pick(100)) + " -" + std::to_string(pick(10)) + "\n";
  std::vector<std::pair<std::string, std::string>> cases = {{"good.txt", good}, {"long_first.txt", long_first}};
  const std::vector<std::string> bad_lines = {"1 2 3,\n",  "1,,2 3\n",   "1 2\n",       "1 2 3 4\n",  "- 1 2\n",
                                              "1 2 3x\n",  "1..2 3 4\n", ",1 2 3\n",    "1 2 0x10\n", "1 2 3 ,\r\n",
                                              "1 2 --3\n", "1 2 3\f,\n", "1\x01 2 3\n", "1 2 3,# c\n"};
  for (std::size_t b = 0; b < bad_lines.size(); ++b) {
    std::string bytes = "1 2 3\n";
    for (int i = 0; i < 40; ++i) bytes += line(3);
    cases.emplace_back("bad" + std::to_string(b) + ".txt", bytes + bad_lines[b] + line(3));
  }
  for (int b = 0; b < 150; ++b) {
    std::string bytes = "1 2 3\n";
    for (int i = 0; i < 40; ++i) bytes += line(3);
    cases.emplace_back("random" + std::to_string(b) + ".txt", bytes + line(2 + pick(3)) + line(2 + pick(3)));
  }
  std::size_t errors = 0;
  for (const auto& [name, bytes] : cases) {
    SCOPED_TRACE(name);
    const hullmap::test::FedPipe pipe(bytes);
    const ReadOutcome want = hullmap::test::fileOutcome(pipe.path(), 1 << 20, 4096);
    const ReadOutcome got = hullmap::test::parseOutcome(bytes, name);
    ASSERT_TRUE(sameOutcome(want, got));
    // Bit for bit (memcmp: -0 and 0 differ); an empty vector's data() may be null, which memcmp may not take.
    if (!want.points.empty()) {
      ASSERT_EQ(std::memcmp(want.points.data(), got.points.data(), want.points.size() * sizeof(Point)), 0);
    }
    errors += want.error.empty() ? 0 : 1;
    if (name == "good.txt") {
      EXPECT_EQ(want.error, "");
      EXPECT_GT(want.points.size(), 19000u);
    }
  }
  EXPECT_GE(errors, bad_lines.size());  // each bad line is an error, and some random ones
}

TEST(IoReadersStream, SeveralFilesStreamInOrderAndStopAtTheFirstError) {
  const auto dir = hullmap::test::freshDir("readers_stream_files");
  const std::string a = writeFile(dir, "a.txt", textCloud(3000));
  const std::string b = writeFile(dir, "b.pcd", writePcd(pcdCloud(2000), "binary"));
  const std::string bad = writeFile(dir, "bad.txt", "1 2 3\n4 5\n");
  const PointSet whole = readPointFiles({a, b});
  Points streamed;
  PointStreamParams params;
  params.batch_points = 100;
  const auto inputs = streamPointFiles({a, b}, params, [&](Points& batch) {
    EXPECT_LE(batch.size(), 100u);
    streamed.insert(streamed.end(), batch.begin(), batch.end());
  });
  ASSERT_EQ(inputs.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(inputs[i].path, whole.inputs[i].path);
    EXPECT_EQ(inputs[i].format, whole.inputs[i].format);
    EXPECT_EQ(inputs[i].read, whole.inputs[i].read);
    EXPECT_EQ(inputs[i].dropped, whole.inputs[i].dropped);
  }
  EXPECT_EQ(inputs[1].format, "pcd");
  EXPECT_EQ(streamed, whole.points);
  // The first file's points are delivered before the second's error; a batch never spans two
  // files, and the bad file's first point waits in its unfinished batch.
  std::size_t delivered = 0;
  const std::string msg = errorOf([&] {
    streamPointFiles({a, bad}, params, [&](Points& batch) { delivered += batch.size(); });
  });
  EXPECT_EQ(msg, bad + ":2: expected 3 numbers like the first data line, got 2");
  EXPECT_EQ(delivered, readPointFile(a).points.size());
}

TEST(IoReadersStream, ZeroBatchOrReadSizeIsAnError) {
  PointStreamParams params;
  params.batch_points = 0;
  const PointBatchConsumer ignore = [](Points&) {};
  EXPECT_EQ(errorOf([&] { streamPoints("1 2 3\n", "p.txt", params, ignore); }),
            "PointStreamParams::batch_points must be at least 1");
  params = PointStreamParams{};
  params.read_bytes = 0;
  EXPECT_EQ(errorOf([&] { streamPointFile(fixture("orbslam_echo_map.txt"), params, ignore); }),
            "PointStreamParams::read_bytes must be at least 1");
}

// ---------------------------------------------------------------------------------------------
// TUM trajectories

TEST(IoReadersTum, SecondsNanosecondsCommentsAndNormalisation) {
  const auto kfs = parseTumTrajectory(
      "# timestamp tx ty tz qx qy qz qw\n"
      "1.5 1 2 3 0 0 0 2\n"
      "\n"
      "1403636579763555840.000000, 0, 0, 0, 0, 0, 1, 1\n",
      "traj.txt");
  ASSERT_EQ(kfs.size(), 2u);
  EXPECT_DOUBLE_EQ(kfs[0].stamp, 1.5);
  EXPECT_EQ(kfs[0].position, Eigen::Vector3d(1, 2, 3));
  EXPECT_NEAR(kfs[0].orientation.w(), 1.0, 1e-15);  // (0,0,0,2) normalised
  EXPECT_NEAR(kfs[1].stamp, 1403636579.76355584, 1e-6);
  EXPECT_NEAR(kfs[1].orientation.z(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(kfs[1].orientation.w(), std::sqrt(0.5), 1e-15);
}

TEST(IoReadersTum, BadLinesNameFileAndLine) {
  EXPECT_NE(errorOf([] {
              parseTumTrajectory("0 1 2 3 0 0 0 1\n0 1 2 3 0 0 1\n", "t.txt");
            }).find("t.txt:2: expected 8 numbers"),
            std::string::npos);
  EXPECT_NE(errorOf([] { parseTumTrajectory("0 1 2 3 0 0 0 0\n", "t.txt"); }).find("t.txt:1: zero quaternion"),
            std::string::npos);
  EXPECT_NE(errorOf([] { parseTumTrajectory("0 nan 2 3 0 0 0 1\n", "t.txt"); }).find("t.txt:1: non-finite"),
            std::string::npos);
  EXPECT_NE(errorOf([] { parseTumTrajectory("\n\n0 1 2 3 0 0 0 one\n", "t.txt"); }).find("t.txt:3: 'one'"),
            std::string::npos);
  EXPECT_TRUE(parseTumTrajectory("", "t.txt").empty());
  // Components whose squares overflow still normalise to a unit quaternion.
  const auto big = parseTumTrajectory("0 0 0 0 1e200 0 0 1e200\n", "t.txt");
  EXPECT_NEAR(big.at(0).orientation.x(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(big.at(0).orientation.w(), std::sqrt(0.5), 1e-15);
}

}  // namespace
