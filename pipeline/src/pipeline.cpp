#include "hullmap/pipeline/pipeline.hpp"

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"

namespace hullmap::cli {
namespace {

namespace fs = std::filesystem;

double peakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// Wall time of each stage, and the process's peak resident memory when it ends.
class StageTimer {
 public:
  explicit StageTimer(BuildResult& result) : result_(result) {}
  /// The stage that ends now began when the previous one ended.
  void stage(const std::string& name) { stage(name, msSince(start_)); }
  /// A stage whose time was summed over pieces interleaved with other stages.
  void stage(const std::string& name, double ms) {
    result_.timings_ms.emplace_back(name, ms);
    result_.peak_rss_mb.emplace_back(name, peakRssMb());
    start_ = Clock::now();
  }

 private:
  BuildResult& result_;
  Clock::time_point start_ = Clock::now();
};

bool isOctomapFile(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  return ext == ".bt" || ext == ".ot";
}

void addDropped(PointAccount& account, const mapper::InputStats& stats) {
  for (const auto& [reason, count] : stats.dropped) account.dropped[reason] += count;
}

Error noPoints(const std::vector<std::string>& inputs) {
  std::string names;
  for (const auto& input : inputs) names += (names.empty() ? "" : ", ") + input;
  return Error(names + ": no points");
}

void accountForInputs(BuildResult& result) {
  for (const auto& stats : result.inputs) {
    result.account.read += stats.read;
    addDropped(result.account, stats);
  }
}

/// With --trajectory or --origin: every point is needed at once (the keyframe rule groups the
/// points per keyframe; --origin inserts them as one scan), so the inputs are read whole.
void buildWhole(const BuildOptions& options, const mapper::FrameParams& frame,
                const mapper::FilterParams& filters, BuildResult& result, StageTimer& timer) {
  mapper::PointSet set = readInputPoints(options.inputs);
  result.inputs = set.inputs;
  accountForInputs(result);
  timer.stage("read");

  std::vector<mapper::Keyframe> keyframes;
  if (options.trajectory) {
    keyframes = mapper::readTumTrajectory(*options.trajectory);
    if (keyframes.empty()) throw Error(*options.trajectory + ": no keyframes");
    mapper::toMapFrame(frame, keyframes);
  }
  mapper::toMapFrame(frame, set.points);
  mapper::InputStats filtered;
  mapper::applyFilters(filters, set.points, filtered);
  addDropped(result.account, filtered);
  if (set.points.empty()) throw Error("--crop/--z-min/--z-max: no points left inside the bounds");
  timer.stage("frame_and_filters");

  mapper::InputStats built;
  if (options.trajectory) {
    result.map.emplace(mapper::buildWithTrajectory(set.points, keyframes, options.octree, built));
    result.keyframes = keyframes.size();
  } else {
    Eigen::Vector3d origin = mapper::parseVector3("--origin", *options.origin);
    std::vector<Eigen::Vector3d> one{origin};
    mapper::toMapFrame(frame, one);
    origin = one.front();
    result.map.emplace(options.octree);
    mapper::Points addressable;
    addressable.reserve(set.points.size());
    for (const auto& p : set.points) {
      if (mapper::addressable(result.map->tree(), p)) addressable.push_back(p);
      else ++built.dropped["out_of_octree"];
    }
    mapper::insertScan(result.map->tree(), addressable, origin, options.octree.max_range);
    auto& counts = result.map->pointCounts();
    for (const auto& p : addressable) ++counts[result.map->tree().coordToKey(p.x(), p.y(), p.z())];
  }
  addDropped(result.account, built);
  timer.stage("octree");
}

/// Points only: read -> frame -> filters -> octree batch by batch, so neither the input files nor
/// their points are ever whole in memory; the same tree, counts, account and errors as reading
/// everything first. Times are summed over the batches per stage.
void buildStreamed(const BuildOptions& options, const mapper::FrameParams& frame,
                   const mapper::FilterParams& filters, BuildResult& result, StageTimer& timer) {
  // The whole-input path meets bad octree parameters when it builds, after the input's errors,
  // "no points" and the filters' error: they are reported in that order here too.
  std::optional<mapper::PointMapBuilder> builder;
  std::exception_ptr bad_octree_params;
  try {
    builder.emplace(options.octree);
  } catch (const Error&) {
    bad_octree_params = std::current_exception();
  }
  mapper::InputStats filtered;
  mapper::InputStats built;
  std::size_t delivered = 0;
  std::size_t kept = 0;
  double frame_ms = 0.0;
  double octree_ms = 0.0;
  const auto consume = [&](mapper::Points& batch) {
    const auto start = Clock::now();
    delivered += batch.size();
    mapper::toMapFrame(frame, batch);
    mapper::applyFilters(filters, batch, filtered);
    kept += batch.size();
    const auto filtered_at = Clock::now();
    frame_ms += std::chrono::duration<double, std::milli>(filtered_at - start).count();
    if (builder) builder->add(batch, built);
    octree_ms += msSince(filtered_at);
  };
  const auto start = Clock::now();
  result.inputs = mapper::streamPointFiles(options.inputs, mapper::PointStreamParams{}, consume);
  const double stream_ms = msSince(start);
  accountForInputs(result);
  if (delivered == 0) throw noPoints(options.inputs);
  addDropped(result.account, filtered);
  if (kept == 0) throw Error("--crop/--z-min/--z-max: no points left inside the bounds");
  if (bad_octree_params) std::rethrow_exception(bad_octree_params);
  timer.stage("read", stream_ms - frame_ms - octree_ms);
  timer.stage("frame_and_filters", frame_ms);
  const auto finish_start = Clock::now();
  result.map.emplace(builder->finish());
  timer.stage("octree", octree_ms + msSince(finish_start));
  addDropped(result.account, built);
}

}  // namespace

std::string frameDescription(const std::string& up, double scale) {
  std::ostringstream s;
  s << "z-up map frame: input axis " << up << " rotated to +z";
  if (scale != 1.0) s << ", scaled by " << scale;
  return s.str();
}

mapper::PointSet readInputPoints(const std::vector<std::string>& inputs) {
  mapper::PointSet set = mapper::readPointFiles(inputs);
  if (set.points.empty()) throw noPoints(inputs);
  return set;
}

BuildResult runBuild(const BuildOptions& options) {
  BuildResult result;
  StageTimer timer(result);
  if (options.inputs.empty()) throw Error("build: no input files");
  if (!(options.scale > 0.0) || !std::isfinite(options.scale))
    throw Error("--scale: must be a positive finite number");
  if (options.trajectory && options.origin)
    throw Error("--trajectory and --origin: give one or the other");

  const mapper::FrameParams frame{mapper::parseUpAxis(options.up), options.scale};
  mapper::FilterParams filters;
  if (options.crop) filters.crop = mapper::parseBox("--crop", *options.crop);
  filters.z_min = options.z_min;
  filters.z_max = options.z_max;
  clustering::DbscanParams dbscan = options.dbscan;
  dbscan.metric = clustering::parseMetric(options.metric);

  if (options.inputs.size() == 1 && isOctomapFile(options.inputs.front())) {
    // A finished map: no points to account for, voxels weigh 1 each.
    result.map.emplace(mapper::readMap(options.inputs.front()));
    mapper::InputStats stats;
    stats.path = options.inputs.front();
    stats.format = fs::path(stats.path).extension().string().substr(1);
    result.inputs.push_back(stats);
    timer.stage("read");
  } else {
    for (const auto& input : options.inputs)
      if (isOctomapFile(input))
        throw Error(input + ": an octomap file can only be the single input of build");
    if (!options.trajectory && !options.origin) {
      buildStreamed(options, frame, filters, result, timer);
    } else {
      buildWhole(options, frame, filters, result, timer);
    }
    result.account.used = result.account.read;
    for (const auto& [reason, count] : result.account.dropped) result.account.used -= count;
    if (result.account.used == 0) {
      // Non-finite and cropped points were refused above; the rest fell outside the octree.
      // Keys are 16 bits a coordinate: 2^15 voxels either side of the origin.
      const double reach = options.octree.resolution * 32768;
      std::ostringstream message;
      message << "no point the octree can address: " << result.account.read << " read, "
              << result.account.dropped["out_of_octree"] << " out of its reach at resolution "
              << options.octree.resolution << " (about +-" << reach << " map units around the origin; "
              << "a coarser --resolution or a smaller --scale reaches further)";
      throw Error(message.str());
    }
  }

  result.voxels = result.map->occupiedVoxels();
  std::vector<Eigen::Vector3d> centers;
  std::vector<std::uint32_t> weights;
  centers.reserve(result.voxels.size());
  weights.reserve(result.voxels.size());
  for (const auto& v : result.voxels) {
    centers.push_back(v.center);
    weights.push_back(v.weight);
  }
  result.clusters = clustering::dbscan(centers, weights, dbscan);
  timer.stage("dbscan");
  result.obstacles =
      clustering::buildObstacles(centers, weights, result.clusters.labels, result.map->resolution());
  timer.stage("obstacles");
  return result;
}

nlohmann::json buildReport(const BuildOptions& options, const BuildResult& result) {
  using nlohmann::json;
  json inputs = json::array();
  for (const auto& in : result.inputs) {
    inputs.push_back({{"path", in.path}, {"format", in.format}, {"points_read", in.read},
                      {"points_dropped", in.dropped}});
  }
  json timings = json::object();
  double total = 0.0;
  for (const auto& [stage, ms] : result.timings_ms) {
    timings[stage] = ms;
    total += ms;
  }
  timings["total"] = total;
  json peak = json::object();
  for (const auto& [stage, mb] : result.peak_rss_mb) peak[stage] = mb;
  const auto info = mapper::describe(result.map->tree());
  std::vector<std::size_t> largest(result.clusters.cluster_sizes);
  std::sort(largest.rbegin(), largest.rend());
  if (largest.size() > 10) largest.resize(10);
  std::size_t core = 0;
  for (auto c : result.clusters.core) core += c;

  json parameters = {
      {"inputs", options.inputs},
      {"trajectory", options.trajectory ? json(*options.trajectory) : json(nullptr)},
      {"origin", options.origin ? json(*options.origin) : json(nullptr)},
      {"up", options.up},
      {"scale", options.scale},
      {"crop", options.crop ? json(*options.crop) : json(nullptr)},
      {"z_min", options.z_min ? json(*options.z_min) : json(nullptr)},
      {"z_max", options.z_max ? json(*options.z_max) : json(nullptr)},
      {"resolution", options.octree.resolution},
      {"hit", options.octree.sensor.hit},
      {"miss", options.octree.sensor.miss},
      {"clamp_min", options.octree.sensor.clamp_min},
      {"clamp_max", options.octree.sensor.clamp_max},
      {"occupancy_threshold", options.octree.sensor.occupancy_threshold},
      {"max_range", options.octree.max_range},
      {"eps", options.dbscan.eps},
      {"min_pts", options.dbscan.min_pts},
      {"metric", options.metric},
      {"ot", options.write_ot},
  };
  return {
      {"hullmap_version", HULLMAP_VERSION},
      {"frame", frameDescription(options.up, options.scale)},
      {"parameters", parameters},
      {"inputs", inputs},
      {"points", {{"read", result.account.read},
                  {"dropped", result.account.dropped},
                  {"used", result.account.used}}},
      {"keyframes", result.keyframes},
      {"octree", {{"resolution", info.resolution},
                  {"bounds", {{"min", {info.min.x(), info.min.y(), info.min.z()}},
                              {"max", {info.max.x(), info.max.y(), info.max.z()}}}},
                  {"occupied_leaves", info.occupied_leaves},
                  {"free_leaves", info.free_leaves},
                  {"nodes", info.nodes},
                  {"memory_bytes", info.memory_bytes},
                  {"occupied_voxels", result.voxels.size()}}},
      {"clusters", {{"count", result.clusters.cluster_sizes.size()},
                    {"noise_voxels", result.clusters.noise},
                    {"core_voxels", core},
                    {"largest_voxel_counts", largest}}},
      {"obstacles", result.obstacles.size()},
      {"timings_ms", timings},
      {"peak_rss_mb", peak},
  };
}

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

void checkOutputDir(const std::string& output_dir) {
  const fs::path out = fs::absolute(output_dir).lexically_normal();
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec)) {
    throw Error("-o " + output_dir + ": exists and is not a directory");
  }
  fs::path ancestor = out.parent_path();
  while (!fs::exists(ancestor, ec) && ancestor.has_parent_path() && ancestor != ancestor.parent_path()) {
    ancestor = ancestor.parent_path();
  }
  if (!fs::is_directory(ancestor, ec)) {
    throw Error("-o " + output_dir + ": cannot create it: " + ancestor.string() + " is not a directory");
  }
  if (::access(ancestor.c_str(), W_OK | X_OK) != 0) {
    throw Error("-o " + output_dir + ": cannot create it in " + ancestor.string() + ": " + std::strerror(errno));
  }
}

void writeBuild(const BuildOptions& options, const BuildResult& result) {
  checkOutputDir(options.output_dir);  // again: the build may have run for a while
  const fs::path out = fs::absolute(options.output_dir).lexically_normal();
  const fs::path parent = out.parent_path();
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec) throw Error("-o " + options.output_dir + ": cannot create " + parent.string() + ": " + ec.message());
  removeStaleStaging(parent, out.filename().string());

  const fs::path staging = parent / ("." + out.filename().string() + ".new" + std::to_string(::getpid()));
  fs::remove_all(staging, ec);
  fs::create_directories(staging, ec);
  if (ec) {
    throw Error("-o " + options.output_dir + ": cannot create its staging directory " + staging.string() + ": " +
                ec.message());
  }
  try {
    const StagingLock lock(staging);
    mapper::writeMap(*result.map, (staging / "map.bt").string());
    if (options.write_ot) mapper::writeMap(*result.map, (staging / "map.ot").string());

    core::writeFileAtomically((staging / "voxels.csv").string(), [&](std::ostream& os) {
      os << "x,y,z,weight,label,core\n" << std::setprecision(9);
      for (std::size_t i = 0; i < result.voxels.size(); ++i) {
        const auto& v = result.voxels[i];
        os << v.center.x() << ',' << v.center.y() << ',' << v.center.z() << ',' << v.weight << ','
           << result.clusters.labels[i] << ',' << int(result.clusters.core[i]) << '\n';
      }
    });
    nlohmann::json report = buildReport(options, result);
    writeObstaclesJson((staging / "obstacles.json").string(), result.obstacles,
                       ObstaclesMeta{frameDescription(options.up, options.scale), report["parameters"]});
    writeObstaclesObj((staging / "obstacles.obj").string(), result.obstacles);
    core::writeFileAtomically((staging / "report.json").string(),
                                [&](std::ostream& os) { os << report.dump(2) << '\n'; });

    // One atomic step puts the finished directory in place: a rename when there is no previous
    // output, else an exchange of the two directories (Linux renameat2), after which the staging
    // name holds the previous output. At no instant is there no OUT/ or a half-written one.
    if (!fs::exists(out)) {
      fs::rename(staging, out, ec);
      if (ec) throw Error(options.output_dir + ": cannot move into place: " + ec.message());
    } else {
      if (::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, out.c_str(), RENAME_EXCHANGE) != 0)
        throw Error(options.output_dir + ": cannot replace: " + std::strerror(errno));
      fs::remove_all(staging, ec);  // the previous output
    }
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    throw;
  }
}

}  // namespace hullmap::cli
