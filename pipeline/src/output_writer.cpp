// write(): a build's output directory, whole or not at all, through a locked staging directory.
#include "hullmap/pipeline/pipeline.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/parallel_invoke.h>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/pipeline/output_dir.hpp"
#include "hullmap/pipeline/report.hpp"
#include "hullmap/pipeline/trajectory_file.hpp"
#include "hullmap/pipeline/voxels_csv.hpp"
#include "stages.hpp"

namespace hullmap::pipeline {

namespace fs = std::filesystem;

namespace {

/// Holds an exclusive flock(2) on a staging directory while a run writes into it. The kernel drops
/// the lock when the process ends, however it ends (SIGKILL included), so "can this directory be
/// locked?" tells a killed run's leftovers from a live run's work. The pid in the name cannot tell:
/// pids are reused, and by the next run a killed run's pid may belong to any process.
class StagingLock {
 public:
  explicit StagingLock(const fs::path& dir) : fd_(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)) {
    if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0)
      throw Error(dir.string() + ": cannot lock staging directory: " + std::strerror(errno));
    // A run sweeping stale staging directories may have locked and removed this one in the moment
    // between its creation and the lock above.
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || st.st_nlink == 0)
      throw Error(dir.string() + ": staging directory was removed by another run into the same output");
  }
  StagingLock(const StagingLock&) = delete;
  StagingLock& operator=(const StagingLock&) = delete;
  ~StagingLock() { ::close(fd_); }

 private:
  int fd_;
};

/// Removes `.NAME.new<pid>` siblings left by runs that were killed: those nobody holds a lock on.
/// Those of a live run (another hullmap writing the same output) are locked and left alone.
void removeStaleStaging(const fs::path& parent, const std::string& name) {
  const std::string prefix = "." + name + ".new";
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(parent, ec)) {
    const std::string file = entry.path().filename().string();
    if (file.size() <= prefix.size() || file.compare(0, prefix.size(), prefix) != 0) continue;
    if (file.find_first_not_of("0123456789", prefix.size()) != std::string::npos) continue;
    const int fd = ::open(entry.path().c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {  // held while removing: a racing creator waits
      std::error_code ignored;
      fs::remove_all(entry.path(), ignored);
    }
    ::close(fd);
  }
}

}  // namespace

OutputDirPolicy outputPolicy(const BuildParams& params, const WriteOptions& options) {
  OutputDirPolicy policy;
  for (const auto& input : params.inputs) policy.inputs.push_back(input.string());
  if (params.trajectory) policy.inputs.push_back(params.trajectory->string());
  policy.make_parents = options.make_parents;
  return policy;
}

void write(const BuildResult& result, const fs::path& dir, const WriteOptions& options) {
  const std::string name = dir.string();
  const OutputDirPolicy policy = outputPolicy(result.params, options);
  checkOutputDir(name, policy);  // again: the build may have run for a while
  fs::path out = fs::absolute(dir).lexically_normal();
  if (out.filename().empty()) out = out.parent_path();  // "out/" is "out"
  const fs::path parent = out.parent_path();
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec) throw Error(name + ": cannot create " + parent.string() + ": " + ec.message());
  removeStaleStaging(parent, out.filename().string());

  const fs::path staging = parent / ("." + out.filename().string() + ".new" + std::to_string(::getpid()));
  fs::remove_all(staging, ec);
  fs::create_directories(staging, ec);
  if (ec) {
    throw Error(name + ": cannot create its staging directory " + staging.string() + ": " + ec.message());
  }
  try {
    const StagingLock lock(staging);
    runStage("write");
    const nlohmann::json report = reportJson(result, options.spelling);
    ObstaclesMeta meta;
    meta.frame = outputFrame(result);
    meta.parameters = report["parameters"];
    meta.surfaces = result.surfaces;
    meta.input_to_output = result.report.input_to_output;
    meta.input_to_output_exact = inputToOutputExact(result.report);
    // The files are independent: written side by side (voxels.csv and obstacles.json take longest).
    tbb::parallel_invoke(
        [&] {
          mapper::writeMap(result.map, (staging / "map.bt").string());
          if (result.params.write_ot) mapper::writeMap(result.map, (staging / "map.ot").string());
        },
        [&] { writeVoxelsCsv(staging / "voxels.csv", result.voxels, result.clusters); },
        [&] { writeObstaclesJson((staging / "obstacles.json").string(), result.obstacles, meta); },
        [&] { writeObstaclesObj((staging / "obstacles.obj").string(), result.obstacles); });
    runStage("wrote_map");
    runStage("wrote_voxels");
    runStage("wrote_obstacles");
    core::writeFileAtomically((staging / "report.json").string(),
                              [&](std::ostream& os) { os << report.dump(2) << '\n'; });
    std::vector<std::string> written{"map.bt", "voxels.csv", "obstacles.json", "obstacles.obj", "report.json"};
    if (result.params.write_ot) written.push_back("map.ot");
    if (!result.keyframes.empty()) {
      writeTumTrajectory(staging / kTrajectoryFile, result.keyframes);
      written.push_back(kTrajectoryFile);
    }
    writeOutputMarker(staging.string(), written);

    runStage("move_into_place");
    checkOutputDir(name, policy);  // a file put there during the build is not removed with the old output
    // One atomic step puts the finished directory in place: a rename when there is no previous
    // output, else an exchange of the two directories (Linux renameat2), after which the staging
    // name holds the previous output. At no instant is there no OUT/ or a half-written one.
    if (!fs::exists(out)) {
      fs::rename(staging, out, ec);
      if (ec) throw Error(name + ": cannot move into place: " + ec.message());
    } else {
      if (::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, out.c_str(), RENAME_EXCHANGE) != 0)
        throw Error(name + ": cannot replace: " + std::strerror(errno));
      fs::remove_all(staging, ec);  // the previous output
    }
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    throw;
  }
}

}  // namespace hullmap::pipeline
