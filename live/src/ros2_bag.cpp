#include "hullmap/live/ros2_bag.hpp"

#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <istream>
#include <ostream>
#include <sstream>

#include "hullmap/core/error.hpp"

extern char** environ;

namespace hullmap::live {
namespace {

constexpr const char* kMagic = "hullmap bag topics 1";

void writeDoubles(std::ostream& out, const double* values, std::size_t n) {
  // x86-64 and aarch64 are little-endian, as the format.
  out.write(reinterpret_cast<const char*>(values), static_cast<std::streamsize>(n * sizeof(double)));
}

Error streamError(const std::string& what) { return Error("bag reader stream: " + what); }

std::string line(std::istream& in, const std::string& key) {
  std::string text;
  if (!std::getline(in, text)) throw streamError("ended before '" + key + "'");
  if (text.compare(0, key.size() + 1, key + " ") != 0) throw streamError("expected '" + key + "', got '" + text + "'");
  return text.substr(key.size() + 1);
}

std::size_t count(std::istream& in, const std::string& key) {
  const std::string text = line(in, key);
  std::size_t used = 0;
  unsigned long long n = 0;
  try {
    n = std::stoull(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) throw streamError("'" + key + "' is not a count: '" + text + "'");
  return static_cast<std::size_t>(n);
}

void readDoubles(std::istream& in, double* values, std::size_t n, const char* what) {
  in.read(reinterpret_cast<char*>(values), static_cast<std::streamsize>(n * sizeof(double)));
  if (!in) throw streamError(std::string("ended inside the ") + what);
}

/// Runs `argv` with stdout and stderr read into `out` and `err`; returns its exit status (128 +
/// signal when killed). Throws hullmap::Error when it cannot be started.
int run(const std::vector<std::string>& argv, std::string& out, std::string& err) {
  int out_pipe[2], err_pipe[2];
  if (pipe(out_pipe) != 0) throw Error(std::string("pipe: ") + std::strerror(errno));
  if (pipe(err_pipe) != 0) {
    close(out_pipe[0]);
    close(out_pipe[1]);
    throw Error(std::string("pipe: ") + std::strerror(errno));
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out_pipe[1], 1);
  posix_spawn_file_actions_adddup2(&actions, err_pipe[1], 2);
  for (int fd : {out_pipe[0], out_pipe[1], err_pipe[0], err_pipe[1]}) posix_spawn_file_actions_addclose(&actions, fd);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(out_pipe[1]);
  close(err_pipe[1]);
  if (spawned != 0) {
    close(out_pipe[0]);
    close(err_pipe[0]);
    throw Error(argv[0] + ": cannot run: " + std::strerror(spawned));
  }
  // Both pipes at once: a reader blocked on one while the program fills the other would hang.
  pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
  std::string* sinks[2] = {&out, &err};
  int open_pipes = 2;
  char buffer[1 << 16];
  while (open_pipes > 0) {
    if (poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      const ssize_t n = read(fds[i].fd, buffer, sizeof buffer);
      if (n > 0) {
        sinks[i]->append(buffer, static_cast<std::size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        close(fds[i].fd);
        fds[i].fd = -1;
        --open_pipes;
      }
    }
  }
  for (auto& f : fds)
    if (f.fd >= 0) close(f.fd);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace

bool isRos2Bag(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return std::filesystem::exists(path / "metadata.yaml", ec);
  const std::string extension = path.extension().string();
  return extension == ".db3" || extension == ".mcap";
}

void writeBagTopics(std::ostream& out, const BagTopics& topics) {
  const BagMap& map = topics.map;
  out << kMagic << "\ntype " << map.type << "\nmessages " << map.messages << "\nskipped " << map.skipped << "\npoints "
      << map.points.size() << "\n";
  for (const auto& p : map.points) writeDoubles(out, p.data(), 3);
  if (topics.keyframes) {
    out << "keyframes " << topics.keyframes->size() << "\n";
    for (const auto& k : *topics.keyframes) {
      const double values[8] = {k.stamp,           k.position.x(),    k.position.y(),    k.position.z(),
                                k.orientation.x(), k.orientation.y(), k.orientation.z(), k.orientation.w()};
      writeDoubles(out, values, 8);
    }
  } else {
    out << "keyframes none\n";
  }
  out << "end\n";
}

BagTopics readBagTopics(std::istream& in) {
  std::string first;
  if (!std::getline(in, first) || first != kMagic)
    throw streamError("does not start with '" + std::string(kMagic) + "'");
  BagTopics topics;
  BagMap& map = topics.map;
  map.type = line(in, "type");
  map.messages = count(in, "messages");
  map.skipped = count(in, "skipped");
  const std::size_t points = count(in, "points");
  map.points.resize(points);
  for (auto& p : map.points) readDoubles(in, p.data(), 3, "points");
  const std::string keyframes = line(in, "keyframes");
  if (keyframes != "none") {
    std::istringstream text("keyframes " + keyframes);
    const std::size_t n = count(text, "keyframes");
    topics.keyframes.emplace(n);
    for (auto& k : *topics.keyframes) {
      double values[8];
      readDoubles(in, values, 8, "keyframes");
      k.stamp = values[0];
      k.position = {values[1], values[2], values[3]};
      k.orientation = Eigen::Quaterniond(values[7], values[4], values[5], values[6]);
    }
  }
  std::string end;
  if (!std::getline(in, end) || end != "end") throw streamError("does not end with 'end'");
  return topics;
}

std::optional<std::filesystem::path> findRos2BagReader() {
  const char* prefixes = std::getenv("AMENT_PREFIX_PATH");
  if (!prefixes) return std::nullopt;
  std::istringstream list(prefixes);
  std::string prefix;
  while (std::getline(list, prefix, ':')) {
    if (prefix.empty()) continue;
    const auto candidate = std::filesystem::path(prefix) / "lib" / "hullmap_ros2" / "hullmap_bag_reader";
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return std::nullopt;
}

BagTopics readRos2Bag(const std::string& path, const std::string& topic,
                      const std::optional<std::string>& trajectory_topic) {
  const auto reader = findRos2BagReader();
  if (!reader) {
    throw Error(path +
                ": a ROS 2 bag: reading it needs the ROS 2 package hullmap_ros2 (its hullmap_bag_reader, "
                "not found in AMENT_PREFIX_PATH): source ROS 2 and the workspace that holds it");
  }
  std::vector<std::string> argv = {reader->string(), path, "--topic", topic};
  if (trajectory_topic) {
    argv.push_back("--trajectory-topic");
    argv.push_back(*trajectory_topic);
  }
  std::string out, err;
  const int status = run(argv, out, err);
  if (status != 0) {
    // The reader says what went wrong in one line "hullmap: error: ..."; anything else is its crash.
    const std::string marker = "hullmap: error: ";
    const auto at = err.rfind(marker);
    if (at != std::string::npos) {
      const auto end = err.find('\n', at);
      throw Error(
          err.substr(at + marker.size(), end == std::string::npos ? std::string::npos : end - at - marker.size()));
    }
    std::string last = err.substr(0, err.find_last_not_of("\n") + 1);
    last = last.substr(last.find_last_of('\n') + 1);
    throw Error(path + ": " + reader->string() + " failed (exit status " + std::to_string(status) + ")" +
                (last.empty() ? "" : ": " + last));
  }
  std::istringstream stream(out);
  try {
    return readBagTopics(stream);
  } catch (const Error& e) {
    throw Error(path + ": " + reader->string() + ": " + e.what());
  }
}

}  // namespace hullmap::live
