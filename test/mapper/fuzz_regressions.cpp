// What the fuzzers (test/fuzz) found and what they start from:
// - regressions: inputs that crashed, hung or gave a wrong result, kept after the fix;
// - the seed corpus (test/fuzz/corpus, written by test/fuzz/make_corpus.py) against the points
//   make_corpus.py wrote, and every seed replayed through the checks the fuzz targets make, so a
//   gcc build without libFuzzer still runs them;
// - the exact one-line messages docs/RELIABILITY.md quotes for each kind of bad input.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fuzz_regressions_fixtures.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "read_outcome.hpp"
#include "test_support.hpp"

namespace {

Points asFloat(const Points& points) {
  Points out;
  for (const Point& p : points) out.emplace_back(float(p.x()), float(p.y()), float(p.z()));
  return out;
}

void expectPoints(const Points& got, const Points& want, double tolerance = 0.0) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_LE((got[i] - want[i]).cwiseAbs().maxCoeff(), tolerance)
        << "point " << i << ": " << got[i].transpose() << " vs " << want[i].transpose();
  }
}

/// Leaves of a tree without expanding pruned ones: {all leaves, occupied leaves}.
std::pair<std::size_t, std::size_t> leafCounts(const octomap::OcTree& tree) {
  std::size_t all = 0;
  std::size_t occupied = 0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    ++all;
    occupied += tree.isNodeOccupied(*it) ? 1 : 0;
  }
  return {all, occupied};
}

// ---------------------------------------------------------------------------------------------
// Regressions

// Found reading the TUM reader for what fuzz_tum checks (unit quaternions): the squares of 1e200
// overflow, q.norm() was inf and normalized() returned (0, 0, 0, 0), a keyframe without
// orientation.
TEST(MapperFuzzRegressions, HugeQuaternionIsNormalisedNotZeroed) {
  const auto kfs = parseTumTrajectory("0 0 0 0 1e200 0 0 0\n1 0 0 0 1e300 -1e300 0 0\n", "t.txt");
  ASSERT_EQ(kfs.size(), 2u);
  EXPECT_NEAR(kfs[0].orientation.x(), 1.0, 1e-15);
  EXPECT_NEAR(kfs[0].orientation.norm(), 1.0, 1e-15);
  EXPECT_NEAR(kfs[1].orientation.x(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(kfs[1].orientation.y(), -std::sqrt(0.5), 1e-15);
  // Tiny but not zero: still refused as a zero quaternion (below 1e-12), as before.
  EXPECT_EQ(errorOf([] { parseTumTrajectory("0 0 0 0 1e-200 0 0 0\n", "t.txt"); }), "t.txt:1: zero quaternion");
}

// A PLY element without properties and a count of 10^12 (fuzz_ply, probing counts): the reader
// walked its 10^12 empty items, a hang on a 90-byte file. Such an element holds no bytes.
TEST(MapperFuzzRegressions, PropertylessPlyElementWithHugeCountIsSkipped) {
  for (const std::string format : {"ascii", "binary_little_endian"}) {
    SCOPED_TRACE(format);
    const std::string body = format == "ascii" ? std::string("1 2 3\n") : [] {
      std::string b;
      for (float v : {1.0f, 2.0f, 3.0f}) b.append(reinterpret_cast<const char*>(&v), 4);
      return b;
    }();
    const PointSet set = parsePoints("ply\nformat " + format +
                                         " 1.0\nelement junk 1000000000000\n"
                                         "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                                         "element more_junk 1000000000000\nend_header\n" +
                                         body,
                                     "j.ply");
    expectPoints(set.points, {{1, 2, 3}});
  }
}

// corpus/bt/pruned.bt (140 bytes): an occupied leaf at depth 1 stands for 2^45 finest voxels;
// occupiedVoxels() expanded them all (hullmap build ran out of time and memory). Now refused.
TEST(MapperFuzzRegressions, PrunedLeafNearTheRootIsRefusedNotExpanded) {
  const OccupancyMap pruned = readMap((kCorpus / "bt" / "pruned.bt").string());
  EXPECT_EQ(errorOf([&] { pruned.occupiedVoxels(); }),
            "octree: its occupied leaves stand for more than 33554432 voxels of 0.05 (an occupied leaf at depth 1 "
            "covers 35184372088832); too many to cluster");
  // A pruned leaf of 8^3 voxels is still expanded.
  OccupancyMap block(OctreeParams{});
  const double r = block.resolution();
  for (int x = 0; x < 8; ++x) {
    for (int y = 0; y < 8; ++y) {
      for (int z = 0; z < 8; ++z) {
        block.tree().updateNode(octomap::point3d(float((x + 0.5) * r), float((y + 0.5) * r), float((z + 0.5) * r)),
                                true);
      }
    }
  }
  block.tree().prune();
  EXPECT_LT(block.tree().getNumLeafNodes(), 512u);
  EXPECT_EQ(block.occupiedVoxels().size(), 512u);
}

// ---------------------------------------------------------------------------------------------
// The seed corpus holds what make_corpus.py wrote

TEST(MapperFuzzCorpus, TextSeedsHoldTheWrittenPoints) {
  expectPoints(parsePoints(seed("text", "header_spaces.txt"), "a.txt").points, kSeedPoints);
  expectPoints(parsePoints(seed("text", "csv_six_columns.csv"), "a.csv").points, kSeedPoints);
  expectPoints(parsePoints(seed("text", "comments_crlf.xyz"), "a.xyz").points, kSeedPoints, 5e-7);
  const PointSet nf = parsePoints(seed("text", "non_finite.txt"), "nf.txt");
  EXPECT_EQ(nf.inputs.at(0).read, 4u);
  EXPECT_EQ(nf.inputs[0].dropped.at("non_finite"), 2u);
  expectPoints(nf.points, {{1, 2, 3}, {5, -6e-3, 700}});
  const PointSet big = parsePoints(seed("text", "exponents.txt"), "e.txt");
  EXPECT_EQ(big.inputs.at(0).read, 2u);
  expectPoints(big.points, {{1e308, -1e308, 2.5e-310}});  // 1e999 overflows to inf: dropped
  EXPECT_EQ(errorOf([] { parsePoints(seed("text", "bad_column_count.txt"), "b.txt"); }),
            "b.txt:2: expected 3 numbers like the first data line, got 2");
}

TEST(MapperFuzzCorpus, PcdSeedsHoldTheWrittenPoints) {
  expectPoints(parsePoints(seed("pcd", "ascii_xyzrgb.pcd"), "a.pcd").points, kSeedPoints);
  expectPoints(parsePoints(seed("pcd", "binary_xyzi_label.pcd"), "b.pcd").points, asFloat(kSeedPoints));
  expectPoints(parsePoints(seed("pcd", "binary_f8_pad.pcd"), "c.pcd").points, kSeedPoints);
  const PointSet org = parsePoints(seed("pcd", "compressed_organized.pcd"), "d.pcd");
  EXPECT_EQ(org.inputs.at(0).read, 6u);
  EXPECT_EQ(org.inputs[0].dropped.at("non_finite"), 2u);
  expectPoints(org.points, asFloat({kSeedPoints[0], kSeedPoints[2], kSeedPoints[3], kSeedPoints[5]}));
  Points rep;
  for (int i = 0; i < 48; ++i) rep.emplace_back(0.25 * (i % 4), 0.5, 1.0);
  expectPoints(parsePoints(seed("pcd", "compressed_backrefs.pcd"), "e.pcd").points, rep);
  EXPECT_TRUE(parsePoints(seed("pcd", "empty_ascii.pcd"), "f.pcd").points.empty());
}

TEST(MapperFuzzCorpus, PlySeedsHoldTheWrittenPoints) {
  for (const char* name :
       {"ascii_faces.ply", "binary_little_endian.ply", "binary_big_endian.ply", "binary_double_order.ply"}) {
    SCOPED_TRACE(name);
    const bool dbl = std::string(name) == "binary_double_order.ply";
    expectPoints(parsePoints(seed("ply", name), name).points, dbl ? kSeedPoints : asFloat(kSeedPoints),
                 std::string(name) == "ascii_faces.ply" ? 1e-6 : 0.0);
  }
  EXPECT_TRUE(parsePoints(seed("ply", "no_vertices.ply"), "n.ply").points.empty());
}

TEST(MapperFuzzCorpus, EchoSeedsHoldTheWrittenPoints) {
  Points map = kSeedPoints;  // id 0, then id 6 (points 3 and 4)
  map.push_back(kSeedPoints[3]);
  map.push_back(kSeedPoints[4]);
  expectPoints(parsePoints(seed("orbslam_echo", "map.txt"), "m.txt").points, map);
  expectPoints(parsePoints(seed("orbslam_echo", "cut_off.txt"), "c.txt").points, map);
  EXPECT_TRUE(parsePoints(seed("orbslam_echo", "delete_all.txt"), "d.txt").points.empty());
  EXPECT_TRUE(parsePoints(seed("orbslam_echo", "empty_points.txt"), "e.txt").points.empty());
  expectPoints(parsePoints(seed("orbslam_echo", "inline_item.txt"), "i.txt").points, {kSeedPoints[0], kSeedPoints[1]});
}

TEST(MapperFuzzCorpus, TumSeedsHoldTheWrittenPoses) {
  const auto s = parseTumTrajectory(seed("tum", "seconds.txt"), "s.txt");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_DOUBLE_EQ(s[1].stamp, 1403636580.263556);
  EXPECT_EQ(s[1].position, Eigen::Vector3d(0.1, -0.02, 0.3));
  const auto n = parseTumTrajectory(seed("tum", "nanoseconds.txt"), "n.txt");
  ASSERT_EQ(n.size(), 2u);
  EXPECT_NEAR(n[0].stamp, 1403636579.763555840, 1e-6);
  EXPECT_NEAR(n[1].orientation.w(), 0.5, 1e-15);
  const auto c = parseTumTrajectory(seed("tum", "commas_crlf.csv"), "c.csv");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0].orientation.w(), 1.0, 1e-15);  // (0, 0, 0, 2) normalised
  EXPECT_NEAR(c[1].orientation.x(), 1.0, 1e-15);
}

TEST(MapperFuzzCorpus, BtSeedsAreTheTreesMakeCorpusEncoded) {
  // chain.bt: one inner node per depth 0..15, then three occupied and one free leaf at depth 16.
  const OccupancyMap chain = readMap((kCorpus / "bt" / "chain.bt").string());
  EXPECT_DOUBLE_EQ(chain.resolution(), 0.1);
  EXPECT_EQ(chain.tree().size(), 20u);
  EXPECT_EQ(leafCounts(chain.tree()), std::make_pair(std::size_t(4), std::size_t(3)));
  EXPECT_EQ(chain.occupiedVoxels().size(), 3u);
  // pruned.bt: an occupied and a free leaf at depth 1 (each 2^45 finest voxels) and an inner
  // node holding eight occupied leaves at depth 2. Its occupied voxels are not listed here.
  const OccupancyMap pruned = readMap((kCorpus / "bt" / "pruned.bt").string());
  EXPECT_DOUBLE_EQ(pruned.resolution(), 0.05);
  EXPECT_EQ(pruned.tree().size(), 12u);
  EXPECT_EQ(leafCounts(pruned.tree()), std::make_pair(std::size_t(10), std::size_t(9)));
  const OccupancyMap empty = readMap((kCorpus / "bt" / "empty.bt").string());
  EXPECT_EQ(empty.tree().size(), 0u);
  // leaves.ot (full format): the root, an occupied and a free leaf at depth 1.
  const OccupancyMap full = readMap((kCorpus / "bt" / "leaves.ot").string());
  EXPECT_DOUBLE_EQ(full.resolution(), 0.1);
  EXPECT_EQ(full.tree().size(), 3u);
  EXPECT_EQ(leafCounts(full.tree()), std::make_pair(std::size_t(2), std::size_t(1)));
}

// Every seed through the checks the fuzz targets make (test/fuzz/fuzz_support.hpp): a result
// with finite points and read == kept + dropped, or a one-line hullmap::Error naming the input.
TEST(MapperFuzzCorpus, EverySeedParsesOrFailsWithOneLineNamingIt) {
  std::size_t seeds = 0;
  for (const char* target : {"text", "orbslam_echo", "pcd", "ply", "points", "tum"}) {
    for (const auto& entry : fs::directory_iterator(kCorpus / target)) {
      SCOPED_TRACE(entry.path().string());
      ++seeds;
      const std::string bytes = hullmap::test::slurp(entry.path());
      try {
        if (std::string(target) == "tum") {
          for (const Keyframe& k : parseTumTrajectory(bytes, "seed")) {
            EXPECT_NEAR(k.orientation.norm(), 1.0, 1e-12);
          }
          continue;
        }
        const PointSet set = parsePoints(bytes, "seed");
        ASSERT_EQ(set.inputs.size(), 1u);
        EXPECT_EQ(set.inputs[0].read, set.points.size() + set.inputs[0].droppedTotal());
        for (const Point& p : set.points) EXPECT_TRUE(p.allFinite());
      } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind("seed", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      }
    }
  }
  EXPECT_GE(seeds, 30u);
}

// ---------------------------------------------------------------------------------------------
// The messages docs/RELIABILITY.md quotes, exactly

struct BadInput {
  const char* what;  ///< the row of RELIABILITY.md
  const char* name;  ///< the file name passed to the reader
  std::string bytes;
  const char* message;  ///< hullmap::Error's whole message
};

std::vector<BadInput> pointInputs() {
  return {
      {"malformed line", "m.txt", "1 2 3\n4 five 6\n", "m.txt:2: 'five' is not a number"},
      {"short line", "m.txt", "1 2 3\n4 5\n", "m.txt:2: expected 3 numbers like the first data line, got 2"},
      {"two numbers a line", "m.txt", "1 2\n3 4\n", "m.txt:1: expected 3 numbers (x y z), got 2"},
      {"empty field", "m.csv", "1,,3\n", "m.csv:1: empty field"},
      {"binary garbage", "g.bin",
       std::string("\x7f"
                   "ELF\x02\x01",
                   6),
       "g.bin: not a point file (binary byte 0x7f at offset 0); expected ORB-SLAM text or echo dump, PCD, "
       "PLY or x y z text"},
      {"truncated ascii PCD", "t.pcd", pcdHeader("ascii") + "1 2 3\n",
       "t.pcd: truncated PCD data: POINTS 2 but the data ends after point 1"},
      {"truncated binary PCD", "t.pcd", pcdHeader("binary") + std::string(20, '\0'),
       "t.pcd: truncated binary PCD data: 2 points of 12 bytes need 24 bytes from byte offset 133, only 20 "
       "there (point 1 is incomplete)"},
      {"huge claimed point count (PCD)", "h.pcd", pcdHeader("binary", "1000000000000"),
       "h.pcd: truncated binary PCD data: 1000000000000 points of 12 bytes need 12000000000000 bytes from "
       "byte offset 157, only 0 there (point 0 is incomplete)"},
      {"absurd point count (PCD)", "h.pcd", pcdHeader("binary", "99999999999999999999"),
       "h.pcd:7: WIDTH: '99999999999999999999' is not a valid count"},
      {"bad LZF data", "z.pcd", compressedPcd(4, 24, std::string(4, '\xff')),
       "z.pcd: binary_compressed PCD: LZF data from byte offset 152 decompresses to 0 bytes, expected 24 "
       "(corrupt or truncated)"},
      {"LZF size words lie", "z.pcd", compressedPcd(1000, 24, std::string(4, '\0')),
       "z.pcd: truncated binary_compressed PCD: 1000 compressed bytes from byte offset 152, only 4 there"},
      {"no x y z fields", "f.pcd", "FIELDS a b c\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n",
       "f.pcd:1: FIELDS has no x y z"},
      {"truncated binary PLY", "t.ply", kPlyHead + std::string(16, '\0'),
       "t.ply: truncated binary PLY data: vertex 1 needs bytes up to offset 135, the file ends at 131"},
      {"huge claimed vertex count (PLY)", "h.ply",
       "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n",
       "h.ply: truncated binary PLY data: vertex 0 needs bytes up to offset 131, the file ends at 127"},
      {"PLY without end_header", "e.ply", "ply\nformat ascii 1.0\nelement vertex 1\n",
       "e.ply: PLY header has no end_header line"},
      {"echo dump: message that is not a Marker", "d.txt", "header:\n  seq: 1\n---\n",
       "d.txt:1: not a visualization_msgs/Marker message (needs header, ns, id and type fields)"},
      {"echo dump: bad coordinate", "d.txt",
       "header:\nns: \"MapPoints\"\nid: 0\ntype: 8\naction: 0\npoints:\n  -\n    x: 1.0\n    y: two\n    z: 3\n"
       "mesh_use_embedded_materials: False\n---\n",
       "d.txt:9: 'two' is not a number"},
  };
}

TEST(MapperFuzzRegressions, BadPointInputMessagesAreExact) {
  for (const BadInput& input : pointInputs()) {
    SCOPED_TRACE(input.what);
    EXPECT_EQ(errorOf([&] { parsePoints(input.bytes, input.name); }), input.message);
  }
}

// The same messages from the streaming reader, in batches of one point and through a pipe read
// one byte at a time (named by its path there).
TEST(MapperFuzzRegressions, BadPointInputMessagesAreExactStreamed) {
  for (const BadInput& input : pointInputs()) {
    SCOPED_TRACE(input.what);
    const std::string after_name = std::string(input.message).substr(std::string(input.name).size());
    EXPECT_EQ(hullmap::test::streamOutcome(input.bytes, input.name, 1).error, after_name);
    const hullmap::test::FedPipe pipe(input.bytes);
    EXPECT_EQ(hullmap::test::fileOutcome(pipe.path(), 1, 1).error, after_name);
  }
}

TEST(MapperFuzzRegressions, BadTrajectoryMessagesAreExact) {
  const BadInput inputs[] = {
      {"bad TUM quaternion", "k.txt", "0 1 2 3 0 0 0 0\n", "k.txt:1: zero quaternion"},
      {"TUM line of 7 numbers", "k.txt", "0 1 2 3 0 0 0 1\n1 1 2 3 0 0 1\n",
       "k.txt:2: expected 8 numbers (t tx ty tz qx qy qz qw), got 7"},
      {"TUM NaN", "k.txt", "0 nan 2 3 0 0 0 1\n", "k.txt:1: non-finite value in pose"},
  };
  for (const BadInput& input : inputs) {
    SCOPED_TRACE(input.what);
    EXPECT_EQ(errorOf([&] { parseTumTrajectory(input.bytes, input.name); }), input.message);
  }
}

TEST(MapperFuzzRegressions, NonFiniteAndEmptyInputsAreNotErrors) {
  const PointSet nf = parsePoints("1 2 3\nnan 0 0\n0 inf 0\n", "n.txt");
  EXPECT_EQ(nf.points.size(), 1u);
  EXPECT_EQ(nf.inputs.at(0).dropped.at("non_finite"), 2u);
  for (const char* empty : {"", "\n\n  \n", "# only a comment\n"}) {
    const PointSet set = parsePoints(empty, "e.txt");
    EXPECT_TRUE(set.points.empty());
    EXPECT_EQ(set.inputs.at(0).read, 0u);
  }
}

TEST(MapperFuzzRegressions, CorruptBtMessagesNameTheFile) {
  const fs::path dir = hullmap::test::freshDir("fuzz_regressions_bt");
  const std::string chain = seed("bt", "chain.bt");
  const std::string cut = writeFile(dir / "cut.bt", chain.substr(0, chain.size() - 3));
  const std::string text = writeFile(dir / "text.bt", "1 2 3\n");
  const std::string empty = writeFile(dir / "empty.bt", "");
  for (const std::string& path : {cut, text, empty}) {
    SCOPED_TRACE(path);
    const std::string message = errorOf([&] { readMap(path); });
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_EQ(errorOf([&] { readMap(text); }), text + ": not an OctoMap file (no '# Octomap OcTree' header)");
}

// fuzz_bt (4 min run, 2026-12-01): octomap's header parser reads tokens, so "res 0.1data" ends its
// header there, one line before the 'data' line hullmap's line-based walk found. The walk passed
// bytes octomap never read, and octomap's recursive node reader, given the bytes after "0.1data",
// overflowed the stack. readMap now parses the header strictly (nothing after a key's value) and
// hands octomap the walked node bytes alone.
TEST(MapperFuzzRegressions, HeaderOctomapParsesOtherwiseIsRefusedNotRecursedInto) {
  const fs::path dir = hullmap::test::freshDir("fuzz_regressions_bt_header");
  // The fuzzer's 167-byte input: a full (.ot) header, an empty line, a second 'data' line, then
  // nodes of one float and a child mask each, every child present down to depth 16 and past it.
  const std::string hex =
      "0300030003000302030000000003206c00ffffffffffffffff00000000000000000000000000000000000000000000000000"
      "0000000000000000000000000000000000000000000000000000000000000000000000000010000000000000000000000000"
      "00000000202800";
  std::string nodes;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) nodes += char(std::stoi(hex.substr(i, 2), nullptr, 16));
  const std::string fuzzed =
      writeFile(dir / "fuzzed.ot", "# Octomap OcTree fileS)\nid OcTree\nsize 20\nres 0.1data\n\ndata\n" + nodes);
  EXPECT_EQ(errorOf([&] { readMap(fuzzed); }), fuzzed + ": malformed OctoMap header line 'res 0.1data'");
  // The same for each header key, and for trailing words on the 'data' line, .bt and .ot alike.
  for (const std::string kind : {"binary file", "file"}) {
    for (const std::string line : {"id OcTree x", "size 0 0", "res 0.1 0.2", "data now"}) {
      std::string header = "# Octomap OcTree " + kind + "\nid OcTree\nsize 0\nres 0.1\ndata\n";
      const std::string key = line.substr(0, line.find(' '));
      const std::size_t at = header.find("\n" + key) + 1;
      header.replace(at, header.find('\n', at) - at, line);
      const std::string path = writeFile(dir / ("bad_" + key + (kind == "file" ? ".ot" : ".bt")), header);
      SCOPED_TRACE(path);
      EXPECT_EQ(errorOf([&] { readMap(path); }), path + ": malformed OctoMap header line '" + line + "'");
    }
  }
  // A well-formed empty tree still reads.
  const std::string empty =
      writeFile(dir / "empty.bt", "# Octomap OcTree binary file\nid OcTree\nsize 0\nres 0.1\ndata\n");
  EXPECT_EQ(readMap(empty).tree().size(), 0u);
}

}  // namespace
