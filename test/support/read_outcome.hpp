#pragma once

// Streaming readers against the whole-input reader: a pipe fed by a thread, and what one read gave.

#include <fcntl.h>
#include <unistd.h>
#include <csignal>
#include <stdexcept>
#include <string>
#include <thread>

#include "hullmap/io/readers.hpp"
#include "test_support.hpp"

namespace hullmap::test {

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
