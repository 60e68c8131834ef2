// hullmap::live's side of ROS 2 bags: the reader program's stream read back exactly (every double's
// bits), malformed streams refused, and the program found and its failures reported in one line
// (stand-in programs here; the real reader is tested against recorded bags in test/ros2/).
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "hullmap/live/ros2_bag.hpp"
#include "test_support.hpp"

namespace hullmap::live {
namespace {

BagTopics sample() {
  BagTopics topics;
  topics.map.type = "sensor_msgs/msg/PointCloud2";
  topics.map.messages = 5;
  topics.map.skipped = 1;
  topics.map.points = {{0.1, -2.0 / 3.0, 1e-300}, {std::nextafter(1.0, 2.0), 3, -0.0}};
  topics.keyframes.emplace(2);
  (*topics.keyframes)[0].stamp = 1403636580.25;
  (*topics.keyframes)[1].position = {1.5, -0.5, 0.1};
  (*topics.keyframes)[1].orientation = Eigen::Quaterniond(0.9238795325112867, 0, 0, 0.38268343236508984);
  return topics;
}

TEST(LiveRos2Bag, TheStreamIsReadBackBitForBit) {
  for (const bool with_keyframes : {true, false}) {
    BagTopics topics = sample();
    if (!with_keyframes) topics.keyframes.reset();
    std::stringstream stream;
    writeBagTopics(stream, topics);
    const BagTopics back = readBagTopics(stream);
    EXPECT_EQ(back.map.type, topics.map.type);
    EXPECT_EQ(back.map.messages, 5u);
    EXPECT_EQ(back.map.skipped, 1u);
    ASSERT_EQ(back.map.points.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i)
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(std::memcmp(&back.map.points[i][k], &topics.map.points[i][k], sizeof(double)), 0);
    ASSERT_EQ(back.keyframes.has_value(), with_keyframes);
    if (with_keyframes) {
      EXPECT_EQ((*back.keyframes)[0].stamp, 1403636580.25);
      EXPECT_EQ((*back.keyframes)[1].position, (*topics.keyframes)[1].position);
      EXPECT_EQ((*back.keyframes)[1].orientation.coeffs(), (*topics.keyframes)[1].orientation.coeffs());
    }
  }
}

TEST(LiveRos2Bag, AStreamThatIsNotOneIsRefused) {
  std::stringstream good;
  writeBagTopics(good, sample());
  const std::string text = good.str();
  for (const std::string& bad : {std::string(), std::string("hello\n"), text.substr(0, text.size() / 2),
                                 text.substr(0, text.size() - 4), text.substr(0, 30)}) {
    std::istringstream in(bad);
    EXPECT_THROW(readBagTopics(in), Error) << bad.size() << " bytes";
  }
}

TEST(LiveRos2Bag, BagsAreTheirDirectoryOrStorageFile) {
  const auto dir = test::freshDir("bag");
  std::ofstream(dir / "metadata.yaml") << "rosbag2_bagfile_information: {}\n";
  EXPECT_TRUE(isRos2Bag(dir));
  EXPECT_TRUE(isRos2Bag(dir / "run_0.db3"));
  EXPECT_TRUE(isRos2Bag(dir / "run_0.mcap"));
  EXPECT_FALSE(isRos2Bag(dir / "run.bag"));
  EXPECT_FALSE(isRos2Bag(dir / "metadata.yaml"));
  EXPECT_FALSE(isRos2Bag(dir.parent_path()));
}

/// A stand-in hullmap_bag_reader in a fresh prefix (PREFIX/lib/hullmap_ros2/), running `script`.
std::filesystem::path fakeReader(const std::string& script) {
  const auto prefix = test::freshDir("prefix");
  const auto program = prefix / "lib" / "hullmap_ros2" / "hullmap_bag_reader";
  std::filesystem::create_directories(program.parent_path());
  std::ofstream(program) << "#!/bin/sh\n" << script << "\n";
  std::filesystem::permissions(program, std::filesystem::perms::owner_all);
  return prefix;
}

/// Runs readRos2Bag with AMENT_PREFIX_PATH as given; the error's text, or "" when it read.
std::string readError(const std::string& ament_prefix_path, BagTopics* topics = nullptr) {
  const char* before = std::getenv("AMENT_PREFIX_PATH");
  const std::string saved = before ? before : "";
  setenv("AMENT_PREFIX_PATH", ament_prefix_path.c_str(), 1);
  std::string error;
  try {
    BagTopics read = readRos2Bag("run_bag", "/map", std::string("/keyframes"));
    if (topics) *topics = read;
  } catch (const Error& e) {
    error = e.what();
  }
  if (before) {
    setenv("AMENT_PREFIX_PATH", saved.c_str(), 1);
  } else {
    unsetenv("AMENT_PREFIX_PATH");
  }
  return error;
}

TEST(LiveRos2Bag, TheReaderIsFoundInAmentPrefixPathAndItsErrorIsOneLine) {
  const std::string missing = readError("/nonexistent:/also/not/here");
  EXPECT_EQ(missing.rfind("run_bag: a ROS 2 bag: reading it needs the ROS 2 package hullmap_ros2", 0), 0u) << missing;

  const auto failing = fakeReader(
      "echo 'rosbag2 chatter' >&2; echo 'hullmap: error: run_bag: no message on topic /map (topics: /x)' >&2; exit 2");
  EXPECT_EQ(readError("/nonexistent:" + failing.string()), "run_bag: no message on topic /map (topics: /x)");

  const auto crashing = fakeReader("echo 'Segmentation fault' >&2; exit 139");
  const std::string crash = readError(crashing.string());
  EXPECT_NE(crash.find("exit status 139"), std::string::npos) << crash;
  EXPECT_NE(crash.find("Segmentation fault"), std::string::npos) << crash;

  // A good stream, with the arguments it was given in its type line.
  std::stringstream good;
  writeBagTopics(good, sample());
  const auto stream_file = test::freshDir("stream") / "stream.bin";
  std::ofstream(stream_file, std::ios::binary) << good.str();
  const auto working =
      fakeReader("cat '" + stream_file.string() +
                 "'; [ \"$1 $2 $3 $4 $5\" = 'run_bag --topic /map --trajectory-topic /keyframes' ] || exit 3");
  BagTopics topics;
  EXPECT_EQ(readError(working.string(), &topics), "");
  EXPECT_EQ(topics.map.points.size(), 2u);
  EXPECT_EQ(topics.keyframes->size(), 2u);
}

}  // namespace
}  // namespace hullmap::live
