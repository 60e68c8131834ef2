#pragma once

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"

namespace hullmap::test {

/// The voxel edge (m) of the generated test scenes that do not say otherwise.
inline constexpr double kVoxel = 0.05;

/// A point of three draws made one statement at a time, z first: the order gcc evaluates the
/// arguments of V3(draw(), draw(), draw()) in, which the tests' data was made with. The arguments of
/// one call are not sequenced (clang draws x first), so this gives the same data with any compiler.
template <class Draw>
Eigen::Vector3d drawPoint(Draw&& draw) {
  const double z = draw();
  const double y = draw();
  const double x = draw();
  return {x, y, z};
}

/// Path of a file in shared/data/real, or empty when the data is not there.
inline std::string realData(const std::string& name) {
  const std::filesystem::path p = std::filesystem::path(HULLMAP_REAL_DATA_DIR) / name;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

/// A fresh empty directory for one test, below the build tree. It is named after the running test
/// too: CTest runs tests in parallel processes, and two tests asking for the same `name` must not
/// share (and wipe) one directory.
inline std::filesystem::path freshDir(const std::string& name) {
  std::string owner = "outside_tests";
  if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info())
    owner = std::string(info->test_suite_name()) + "." + info->name();
  const auto dir = std::filesystem::path(HULLMAP_TEST_TMP) / owner / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Skips the current test, saying which real-data file is missing.
#define HULLMAP_REQUIRE_REAL_DATA(var, name)                                          \
  const std::string var = ::hullmap::test::realData(name);                            \
  if (var.empty()) {                                                                  \
    GTEST_SKIP() << "real data " << name << " not found in " << HULLMAP_REAL_DATA_DIR \
                 << " (shared/data/real beside the checkout)";                        \
  }

}  // namespace hullmap::test

#include <csignal>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <nlohmann/json.hpp>

namespace hullmap::test {

struct CommandResult {
  int status = -1;  ///< exit status, or -1 when killed by a signal
  std::string out;
  std::string err;
};

/// Writes `text` into `path` (a test's input file).
inline void writeText(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

/// Every byte of a file (empty when it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A JSON file hullmap wrote (report.json, obstacles.json...).
inline nlohmann::json readJson(const std::filesystem::path& path) { return nlohmann::json::parse(slurp(path)); }

/// Runs the hullmap binary with `args` (already shell-quoted where needed), capturing both streams.
inline CommandResult runHullmap(const std::string& args) {
  static int counter = 0;
  const auto dir = std::filesystem::path(HULLMAP_TEST_TMP) / "cmd";
  std::filesystem::create_directories(dir);
  const std::string stem = (dir / ("run" + std::to_string(::getpid()) + "_" + std::to_string(counter++))).string();
  const std::string command =
      std::string("'") + HULLMAP_BINARY + "' " + args + " >" + stem + ".out 2>" + stem + ".err </dev/null";
  const int raw = std::system(command.c_str());
  CommandResult r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = slurp(stem + ".out");
  r.err = slurp(stem + ".err");
  return r;
}

/// Runs the hullmap binary with `args` from the working directory `cwd`, standard input from `input`.
inline CommandResult runHullmapIn(const std::filesystem::path& cwd, const std::string& args,
                                  const std::string& input = "/dev/null") {
  static int counter = 0;
  const auto dir = std::filesystem::path(HULLMAP_TEST_TMP) / "cmd";
  std::filesystem::create_directories(dir);
  const std::string stem = (dir / ("in" + std::to_string(::getpid()) + "_" + std::to_string(counter++))).string();
  const std::string command = "cd '" + cwd.string() + "' && '" + std::string(HULLMAP_BINARY) + "' " + args + " >" +
                              stem + ".out 2>" + stem + ".err <'" + input + "'";
  const int raw = std::system(command.c_str());
  CommandResult r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = slurp(stem + ".out");
  r.err = slurp(stem + ".err");
  return r;
}

/// Runs `body` and returns the hullmap::Error message it throws (fails the test if none).
template <typename F>
std::string errorOf(F&& body) {
  try {
    body();
  } catch (const ::hullmap::Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected hullmap::Error";
  return "";
}

/// Number of lines in `text` (a final line without newline counts).
inline int lineCount(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n';
  if (!text.empty() && text.back() != '\n') ++n;
  return n;
}

/// A pipe that a thread fills with `bytes`, then closes: path() ("/dev/fd/N", its read end) is a
/// non-regular file for the readers, which read it in chunks. A reader that stops early (an error)
/// makes the writer's write fail with EPIPE (SIGPIPE is ignored) and the writer end.
class FedPipe {
 public:
  explicit FedPipe(std::string bytes) {
    std::signal(SIGPIPE, SIG_IGN);
    int fds[2] = {-1, -1};
    if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe2 failed");
    read_fd_ = fds[0];
    writer_ = std::thread([fd = fds[1], bytes = std::move(bytes)] {
      std::size_t done = 0;
      while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n <= 0) break;
        done += static_cast<std::size_t>(n);
      }
      ::close(fd);
    });
  }
  ~FedPipe() {
    ::close(read_fd_);
    writer_.join();
  }
  FedPipe(const FedPipe&) = delete;
  FedPipe& operator=(const FedPipe&) = delete;

  std::string path() const { return "/dev/fd/" + std::to_string(read_fd_); }

 private:
  int read_fd_ = -1;
  std::thread writer_;
};

/// What one read of a point input gave: its points (the batches concatenated) and InputStats, or
/// its error with the input's name cut off the front (so that a pipe, named /dev/fd/N, and the
/// file it carries compare equal).
struct ReadOutcome {
  io::Points points;
  io::InputStats stats;
  std::string error;
  std::size_t batches = 0;
  std::size_t largest_batch = 0;
};

/// Runs `read(consume)` (a streaming reader call returning InputStats) for the input `name`.
template <typename Read>
ReadOutcome readOutcome(const std::string& name, Read&& read) {
  ReadOutcome o;
  const io::PointBatchConsumer consume = [&o](io::Points& batch) {
    ++o.batches;
    o.largest_batch = std::max(o.largest_batch, batch.size());
    o.points.insert(o.points.end(), batch.begin(), batch.end());
  };
  try {
    o.stats = read(consume);
  } catch (const Error& e) {
    o.error = e.what();
    if (o.error.rfind(name, 0) == 0)
      o.error.erase(0, name.size());
    else
      o.error = "(the message does not start with " + name + ") " + o.error;
    o.points.clear();
  }
  return o;
}

/// The same points bit for bit in the same order, the same counts and format, or the same error.
inline ::testing::AssertionResult sameOutcome(const ReadOutcome& want, const ReadOutcome& got) {
  if (want.error != got.error) {
    return ::testing::AssertionFailure() << "error '" << got.error << "', expected '" << want.error << "'";
  }
  if (want.points.size() != got.points.size()) {
    return ::testing::AssertionFailure() << got.points.size() << " points, expected " << want.points.size();
  }
  for (std::size_t i = 0; i < want.points.size(); ++i) {
    if (want.points[i] != got.points[i]) {
      return ::testing::AssertionFailure() << "point " << i << " is (" << got.points[i].transpose() << "), expected ("
                                           << want.points[i].transpose() << ")";
    }
  }
  if (want.stats.read != got.stats.read || want.stats.dropped != got.stats.dropped ||
      want.stats.format != got.stats.format) {
    return ::testing::AssertionFailure() << "stats differ: read " << got.stats.read << " (expected " << want.stats.read
                                         << "), dropped " << got.stats.droppedTotal() << " (expected "
                                         << want.stats.droppedTotal() << "), format " << got.stats.format
                                         << " (expected " << want.stats.format << ")";
  }
  return ::testing::AssertionSuccess();
}

/// parsePoints's outcome: the whole-input reader, the reference of the streaming ones.
inline ReadOutcome parseOutcome(const std::string& bytes, const std::string& name) {
  return readOutcome(name, [&](const io::PointBatchConsumer& consume) {
    io::PointSet set = io::parsePoints(bytes, name);
    if (!set.points.empty()) consume(set.points);
    return set.inputs.at(0);
  });
}

/// streamPoints (bytes in memory) with `batch_points`.
inline ReadOutcome streamOutcome(const std::string& bytes, const std::string& name, std::size_t batch_points) {
  io::PointStreamParams params;
  params.batch_points = batch_points;
  return readOutcome(
      name, [&](const io::PointBatchConsumer& consume) { return io::streamPoints(bytes, name, params, consume); });
}

/// streamPointFile on `path` (a file holding the bytes, or a pipe carrying them).
inline ReadOutcome fileOutcome(const std::string& path, std::size_t batch_points, std::size_t read_bytes) {
  io::PointStreamParams params;
  params.batch_points = batch_points;
  params.read_bytes = read_bytes;
  return readOutcome(path,
                     [&](const io::PointBatchConsumer& consume) { return io::streamPointFile(path, params, consume); });
}

}  // namespace hullmap::test
