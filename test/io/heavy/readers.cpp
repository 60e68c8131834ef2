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

const double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------
// A tiny PCD writer (independent of the reader): fields with TYPE/SIZE/COUNT, rows of values.

// ---------------------------------------------------------------------------------------------
// Real data

// Every real point file streams (from the file in batches of 1 and 4096, through a pipe read 4096
// bytes at a time, and 1 byte at a time for the smaller ones) to what readPointFile reads.
TEST(IoReadersReal, EveryRealPointFileStreamsAsItIsReadWhole) {
  std::size_t found = 0;
  for (const char* name : {"orbslam2_euroc_V1_01_MapPoints.txt", "orbslam2_euroc_V1_01_MapPoints.pcd",
                           "orbslam3_euroc_MH_01_mono_pointcloud.txt", "orbslam3_euroc_MH_01_mono_ref_pointcloud.txt",
                           "octomap_scan.dat", "pcl_table_scene_mug_stereo_textured.pcd", "pcl_five_people.pcd"}) {
    const std::string path = hullmap::test::realData(name);
    if (path.empty()) continue;
    ++found;
    SCOPED_TRACE(name);
    const hullmap::test::ReadOutcome want = hullmap::test::readOutcome(path, [&](const PointBatchConsumer& consume) {
      PointSet set = readPointFile(path);
      consume(set.points);
      return set.inputs.at(0);
    });
    ASSERT_EQ(want.error, "");
    ASSERT_GT(want.points.size(), 4000u);
    for (const std::size_t batch : {1, 4096}) {
      EXPECT_TRUE(hullmap::test::sameOutcome(want, hullmap::test::fileOutcome(path, batch, 1 << 20))) << batch;
    }
    const std::string bytes = hullmap::test::slurp(path);
    for (const std::size_t read_bytes : {1, 4096}) {
      if (read_bytes == 1 && bytes.size() > 300000) continue;
      const hullmap::test::FedPipe pipe(bytes);
      EXPECT_TRUE(hullmap::test::sameOutcome(want, hullmap::test::fileOutcome(pipe.path(), 4096, read_bytes)))
          << "pipe read " << read_bytes << " bytes at a time";
    }
  }
  if (found == 0) GTEST_SKIP() << "no real point file in " << HULLMAP_REAL_DATA_DIR;
}

// ---------------------------------------------------------------------------------------------
// PLY

// ---------------------------------------------------------------------------------------------
// Streaming readers: against parsePoints, the whole-input reader

/// `n` vertices `x y z` (float) and `red`, then two faces.
std::string plyCloud(const std::string& format, std::size_t n) {
  std::string out = "ply\nformat " + format + " 1.0\nelement vertex " + std::to_string(n) +
                    "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n"
                    "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
  const bool big = format == "binary_big_endian";
  char line[128];
  for (std::size_t i = 0; i < n; ++i) {
    const float x = 0.5f * float(i), y = i % 31 == 2 ? float(kInf) : -0.25f * float(i), z = 1.0f / float(i + 1);
    if (format == "ascii") {
      std::snprintf(line, sizeof line, "%.9g %.9g %.9g %d\n", double(x), double(y), double(z), int(i % 256));
      out += line;
    } else {
      put<float>(out, x, big), put<float>(out, y, big), put<float>(out, z, big);
      put<std::uint8_t>(out, std::uint8_t(i % 256), big);
    }
  }
  if (format == "ascii") return out + "3 0 1 2\n4 0 1 2 3\n";
  put<std::uint8_t>(out, 3, big);
  for (int i : {0, 1, 2}) put<std::int32_t>(out, i, big);
  put<std::uint8_t>(out, 4, big);
  for (int i : {0, 1, 2, 3}) put<std::int32_t>(out, i, big);
  return out;
}

struct StreamCase {
  std::string name;
  std::string bytes;
  bool bad;  ///< parsePoints throws
};

std::vector<StreamCase> streamCases() {
  std::vector<StreamCase> cases;
  const std::string text = textCloud(20000);
  cases.push_back({"cloud.txt", text, false});
  std::string short_line = text;
  short_line.insert(short_line.find('\n', short_line.size() / 2) + 1, "1 2 3 4 5\n");
  cases.push_back({"short.txt", short_line, true});
  for (const std::string data : {"ascii", "binary", "binary_compressed"}) {
    const std::string pcd = writePcd(pcdCloud(5000), data);
    cases.push_back({data + ".pcd", pcd, false});
    cases.push_back({"cut_" + data + ".pcd", pcd.substr(0, pcd.size() - 6), true});
  }
  for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    const std::string ply = plyCloud(format, 3000);
    cases.push_back({format + ".ply", ply, false});
    cases.push_back({"cut_" + format + ".ply", ply.substr(0, ply.size() - 9), true});
  }
  cases.push_back({"echo.txt", hullmap::test::slurp(fixture("orbslam_echo_map.txt")), false});
  cases.push_back({"echo_cut.txt", hullmap::test::slurp(fixture("orbslam_echo_truncated.txt")), false});
  std::string echo_bad = hullmap::test::slurp(fixture("orbslam_echo_map.txt"));
  // A coordinate of the map's last id 6 marker (the markers after it are not map points).
  const std::size_t last_id6 = echo_bad.rfind("ns: \"MapPoints\"\nid: 6");
  echo_bad.replace(echo_bad.find("x: ", echo_bad.find("points:", last_id6)), 3, "x: one");
  cases.push_back({"echo_bad.txt", echo_bad, true});
  cases.push_back({"empty.txt", "", false});
  cases.push_back({"blank.txt", " \n\r\n\t\n", false});
  cases.push_back({"header_only.txt", "# nothing\nx y z\n", false});
  cases.push_back({"garbage.txt", "1 2 3\n\x01\x02", true});
  return cases;
}

TEST(IoReadersStream, BatchesHoldWhatParsePointsReadsInOrderWithTheSameErrors) {
  const auto dir = hullmap::test::freshDir("readers_stream");
  for (const StreamCase& c : streamCases()) {
    SCOPED_TRACE(c.name);
    const ReadOutcome want = hullmap::test::parseOutcome(c.bytes, c.name);
    ASSERT_EQ(!want.error.empty(), c.bad) << want.error;
    const auto expectBatches = [&](const ReadOutcome& got, std::size_t batch) {
      if (c.bad) return;
      EXPECT_LE(got.largest_batch, batch);
      EXPECT_EQ(got.batches, (want.points.size() + batch - 1) / batch);
    };
    for (const std::size_t batch : {1, 2, 1000, 65536}) {
      SCOPED_TRACE("in memory, batches of " + std::to_string(batch));
      const ReadOutcome got = hullmap::test::streamOutcome(c.bytes, c.name, batch);
      EXPECT_TRUE(sameOutcome(want, got));
      expectBatches(got, batch);
    }
    const std::string path = writeFile(dir, c.name, c.bytes);
    for (const std::size_t batch : {1, 7}) {
      SCOPED_TRACE("mapped file, batches of " + std::to_string(batch));
      const ReadOutcome got = hullmap::test::fileOutcome(path, batch, 1 << 20);
      EXPECT_TRUE(sameOutcome(want, got));
      expectBatches(got, batch);
    }
    for (const std::size_t read_bytes : {1, 13, 4096}) {
      if (read_bytes == 1 && c.bytes.size() > 200000) continue;
      SCOPED_TRACE("pipe read " + std::to_string(read_bytes) + " bytes at a time");
      const FedPipe pipe(c.bytes);
      const ReadOutcome got = hullmap::test::fileOutcome(pipe.path(), 3, read_bytes);
      EXPECT_TRUE(sameOutcome(want, got));
      expectBatches(got, 3);
      if (!c.bad) {
        EXPECT_EQ(got.stats.path, pipe.path());
      }
    }
  }
}

// A text file read whole (memory, mapped) is parsed in parallel, in chunks cut at line ends; a pipe
// is read front to back. Both give the same points, counts and first error, its line counted over
// the chunks before it: bad lines are put at, just before and just after chunk cuts (every 256 KiB)
// and in a later window of chunks (8 MiB).
TEST(IoReadersStream, TextReadInParallelChunksIsTheFrontToBackRead) {
  const std::string text = textCloud(260000);
  ASSERT_GT(text.size(), std::size_t(34) << 18);  // past the first window
  std::vector<std::pair<std::string, std::string>> cases = {{"whole.txt", text}};
  std::vector<std::size_t> offsets;
  for (const std::size_t at : {std::size_t(1) << 18, std::size_t(5) << 18, std::size_t(33) << 18, text.size() - 10}) {
    for (const std::size_t delta : {std::size_t(0), std::size_t(1), std::size_t(39), std::size_t(41)}) {
      offsets.push_back(at - delta);
    }
  }
  for (const std::size_t offset : offsets) {
    const std::size_t start = text.rfind('\n', offset) + 1;  // the line holding `offset`
    const std::size_t line = 1 + std::size_t(std::count(text.begin(), text.begin() + std::ptrdiff_t(start), '\n'));
    for (const std::string bad : {"1 2 x 0 0 1\n", "1 2 3\n", "1,,3 0 0 1\n"}) {
      std::string bytes = text;
      bytes.insert(start, bad);
      const std::string name = "bad_" + std::to_string(offset) + ".txt";
      const ReadOutcome got = hullmap::test::parseOutcome(bytes, name);
      EXPECT_EQ(got.error.rfind(":" + std::to_string(line) + ": ", 0), 0u) << got.error;  // after the name
      cases.emplace_back(name, bytes);
    }
  }
  for (const auto& [name, bytes] : cases) {
    SCOPED_TRACE(name);
    const hullmap::test::FedPipe pipe(bytes);
    const ReadOutcome want = hullmap::test::fileOutcome(pipe.path(), 65536, 65536);
    const ReadOutcome got = hullmap::test::streamOutcome(bytes, name, 65536);
    EXPECT_TRUE(sameOutcome(want, got));
    if (name == "whole.txt") {
      EXPECT_EQ(got.stats.read, 260000u);
      EXPECT_EQ(got.stats.dropped.at("non_finite"), 2681u);
    }
  }
}

/// A line of /proc/self/status ("RssFile", "RssAnon") in bytes.
std::size_t statusBytes(const std::string& key) {
  // Memory freed by earlier tests stays resident in malloc's heap, where new allocations would
  // hide: handed back first, reusing it shows as growth.
  ::malloc_trim(0);
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(key + ":", 0) == 0) return std::stoull(line.substr(key.size() + 1)) * 1024;
  }
  ADD_FAILURE() << key << " not in /proc/self/status";
  return 0;
}

// 48 MiB of text through the streaming reader: neither the file's pages (resident while mapped,
// unless handed back) nor its 1.6 million points (38 MiB) may pile up.
TEST(IoReadersStream, ALargeFileIsNotHeldWholeMappedOrPiped) {
  const auto dir = hullmap::test::freshDir("readers_stream_large");
  std::string text;
  text.reserve(std::size_t(50) << 20);
  char line[64];
  for (std::size_t i = 0; text.size() < (std::size_t(48) << 20); ++i) {
    std::snprintf(line, sizeof line, "%.9f %.9f %.9f\n", 1e-6 * double(i), -2e-6 * double(i), 3.5 + 1e-7 * double(i));
    text += line;
  }
  const std::string path = writeFile(dir, "large.txt", text);
  const std::size_t lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  constexpr std::size_t kBound = std::size_t(24) << 20;
  for (const bool piped : {false, true}) {
    SCOPED_TRACE(piped ? "pipe" : "mapped file");
    std::unique_ptr<FedPipe> pipe;
    if (piped) pipe = std::make_unique<FedPipe>(text);
    const std::size_t file0 = statusBytes("RssFile");
    const std::size_t anon0 = statusBytes("RssAnon");
    std::size_t file_growth = 0;
    std::size_t anon_growth = 0;
    std::size_t points = 0;
    const InputStats stats = streamPointFile(piped ? pipe->path() : path, PointStreamParams{}, [&](Points& batch) {
      points += batch.size();
      const std::size_t file = statusBytes("RssFile");
      const std::size_t anon = statusBytes("RssAnon");
      file_growth = std::max(file_growth, file > file0 ? file - file0 : 0);
      anon_growth = std::max(anon_growth, anon > anon0 ? anon - anon0 : 0);
    });
    EXPECT_EQ(stats.read, lines);
    EXPECT_EQ(points, lines);
    EXPECT_LT(file_growth, kBound) << "file pages stay resident";
    EXPECT_LT(anon_growth, kBound) << "points or bytes pile up in memory";
  }
  // The whole-file reader, by contrast, holds every point.
  const std::size_t anon0 = statusBytes("RssAnon");
  const PointSet set = readPointFile(path);
  EXPECT_EQ(set.points.size(), lines);
  EXPECT_GT(statusBytes("RssAnon"), anon0 + kBound) << "the measurement cannot tell held points from none";
}

}  // namespace
