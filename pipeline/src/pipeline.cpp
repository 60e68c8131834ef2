#include "hullmap/pipeline/pipeline.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <functional>
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
#include "hullmap/clustering/build_warnings.hpp"
#include "hullmap/mapper/level_check.hpp"
#include "hullmap/mapper/output_dir.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"

namespace hullmap::pipeline {
namespace {

namespace fs = std::filesystem;

double peakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

using Clock = std::chrono::steady_clock;

void runStage(const char* stage) {
  if (detail::stage_hook != nullptr) detail::stage_hook(stage);
}

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// Wall time of each stage, and the process's peak resident memory when it ends.
class StageTimer {
 public:
  explicit StageTimer(BuildReport& report) : report_(report) {}
  /// The stage that ends now began when the previous one ended.
  void stage(const std::string& name) { stage(name, msSince(start_)); }
  /// A stage whose time was summed over pieces interleaved with other stages.
  void stage(const std::string& name, double ms) {
    report_.timings_ms.emplace_back(name, ms);
    report_.peak_rss_mb.emplace_back(name, peakRssMb());
    start_ = Clock::now();
  }

 private:
  BuildReport& report_;
  Clock::time_point start_ = Clock::now();
};

bool isOctomapFile(const fs::path& path) {
  const std::string ext = path.extension().string();
  return ext == ".bt" || ext == ".ot";
}

void addDropped(PointAccount& account, const mapper::InputStats& stats) {
  for (const auto& [reason, count] : stats.dropped) account.dropped[reason] += count;
}

std::vector<std::string> pathStrings(const std::vector<fs::path>& paths) {
  std::vector<std::string> strings;
  for (const auto& p : paths) strings.push_back(p.string());
  return strings;
}

Error noPoints(const std::vector<std::string>& inputs) {
  std::string names;
  for (const auto& input : inputs) names += (names.empty() ? "" : ", ") + input;
  return Error(names + ": no points");
}

Error noPointsInBounds() {
  return Error::inParameter("crop/z_min/z_max", "no points left inside the bounds");
}

void accountForInputs(BuildResult& result) {
  for (const auto& stats : result.report.inputs) {
    result.report.points.read += stats.read;
    addDropped(result.report.points, stats);
  }
}

/// The octree of points already read whole (map frame after this), with the keyframes' rays
/// (trajectory), one scan's rays (origin), or points alone.
/// `given` (keyframes in memory, input frame) stands for the trajectory file when not null.
void buildWhole(const BuildParams& params, mapper::Points points, BuildResult& result, StageTimer& timer,
                std::vector<mapper::Keyframe>* given = nullptr) {
  accountForInputs(result);
  timer.stage("read");

  runStage("frame_and_filters");
  std::vector<mapper::Keyframe> keyframes;
  if (given) {
    keyframes = std::move(*given);
    if (keyframes.empty()) throw Error(params.trajectory->string() + ": no keyframes");
    mapper::toMapFrame(params.frame, keyframes);
  } else if (params.trajectory) {
    keyframes = mapper::readTumTrajectory(params.trajectory->string());
    if (keyframes.empty()) throw Error(params.trajectory->string() + ": no keyframes");
    mapper::toMapFrame(params.frame, keyframes);
  }
  mapper::toMapFrame(params.frame, points);
  mapper::InputStats filtered;
  mapper::applyFilters(params.filters, points, filtered);
  addDropped(result.report.points, filtered);
  if (points.empty()) throw noPointsInBounds();
  timer.stage("frame_and_filters");

  runStage("octree");
  mapper::InputStats built;
  if (params.trajectory) {
    result.map = mapper::buildWithTrajectory(points, keyframes, params.octree, built);
    result.report.keyframes = keyframes.size();
  } else if (params.origin) {
    std::vector<Eigen::Vector3d> origin{*params.origin};
    mapper::toMapFrame(params.frame, origin);
    result.map = mapper::buildFromScan(points, origin.front(), params.octree, built);
  } else {
    result.map = mapper::buildFromPoints(points, params.octree, built);
  }
  addDropped(result.report.points, built);
  timer.stage("octree");
}

/// Points only: read -> frame -> filters -> octree batch by batch, so neither the input files nor
/// their points are ever whole in memory; the same tree, counts, account and errors as reading
/// everything first. Times are summed over the batches per stage.
void buildStreamed(const BuildParams& params, BuildResult& result, StageTimer& timer) {
  // The whole-input path meets bad octree parameters when it builds, after the input's errors,
  // "no points" and the filters' error: they are reported in that order here too.
  std::optional<mapper::PointMapBuilder> builder;
  std::exception_ptr bad_octree_params;
  try {
    builder.emplace(params.octree);
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
    mapper::toMapFrame(params.frame, batch);
    mapper::applyFilters(params.filters, batch, filtered);
    kept += batch.size();
    const auto filtered_at = Clock::now();
    frame_ms += std::chrono::duration<double, std::milli>(filtered_at - start).count();
    if (builder) builder->add(batch, built);
    octree_ms += msSince(filtered_at);
  };
  const auto start = Clock::now();
  const std::vector<std::string> inputs = pathStrings(params.inputs);
  result.report.inputs = mapper::streamPointFiles(inputs, mapper::PointStreamParams{}, consume);
  const double stream_ms = msSince(start);
  accountForInputs(result);
  if (delivered == 0) throw noPoints(inputs);
  addDropped(result.report.points, filtered);
  if (kept == 0) throw noPointsInBounds();
  if (bad_octree_params) std::rethrow_exception(bad_octree_params);
  timer.stage("read", stream_ms - frame_ms - octree_ms);
  timer.stage("frame_and_filters", frame_ms);
  runStage("octree");
  const auto finish_start = Clock::now();
  result.map = builder->finish();
  timer.stage("octree", octree_ms + msSince(finish_start));
  addDropped(result.report.points, built);
}

void checkParams(const BuildParams& params) {
  if (!(params.frame.scale > 0.0) || !std::isfinite(params.frame.scale))
    throw Error::inParameter("scale", "must be a positive finite number");
  if (params.trajectory && params.origin)
    throw Error::inParameter("trajectory/origin", "give one or the other");
  if (params.origin && !params.origin->allFinite())
    throw Error::inParameter("origin", "must be finite");
}

/// Every point used, or none the octree can address: an error.
void finishAccount(const BuildParams& params, BuildResult& result) {
  PointAccount& account = result.report.points;
  account.used = account.read;
  for (const auto& [reason, count] : account.dropped) account.used -= count;
  if (account.used == 0) {
    // Non-finite and cropped points were refused above; the rest fell outside the octree.
    // Keys are 16 bits a coordinate: 2^15 voxels either side of the origin.
    const double reach = params.octree.resolution * 32768;
    std::ostringstream message;
    message << "no point the octree can address: " << account.read << " read, "
            << account.dropped["out_of_octree"] << " out of its reach at resolution "
            << params.octree.resolution << " (about +-" << reach << " map units around the origin; "
            << "a coarser resolution or a smaller scale reaches further)";
    throw Error::inParameter("resolution/scale", message.str());
  }
}

ClusteredVoxels clusterStages(const mapper::OccupancyMap& map, const clustering::DbscanParams& dbscan,
                              const std::function<void()>& clustered) {
  ClusteredVoxels out;
  out.voxels = map.occupiedVoxels();
  std::vector<Eigen::Vector3d> centers;
  std::vector<std::uint32_t> weights;
  centers.reserve(out.voxels.size());
  weights.reserve(out.voxels.size());
  for (const auto& v : out.voxels) {
    centers.push_back(v.center);
    weights.push_back(v.weight);
  }
  out.clusters = clustering::dbscan(centers, weights, dbscan);
  if (clustered) clustered();
  out.obstacles = clustering::buildObstacles(centers, weights, out.clusters.labels, map.resolution());
  return out;
}

void clusterInto(BuildResult& result, StageTimer& timer) {
  runStage("dbscan");
  ClusteredVoxels clustered = clusterStages(result.map, result.params.dbscan, [&] {
    timer.stage("dbscan");
    runStage("obstacles");
  });
  timer.stage("obstacles");
  result.voxels = std::move(clustered.voxels);
  result.clusters = std::move(clustered.clusters);
  result.obstacles = std::move(clustered.obstacles);
  const clustering::DbscanParams& dbscan = result.params.dbscan;
  result.report.warnings = clustering::buildWarnings(
      {result.voxels.size(), result.clusters.noise, result.obstacles.size(), dbscan.eps, dbscan.min_pts,
       dbscan.metric, result.map.resolution()});
  if (!readsOctree(result.params)) {
    std::vector<Eigen::Vector3d> centers;
    centers.reserve(result.voxels.size());
    for (const auto& v : result.voxels) centers.push_back(v.center);
    if (auto tilted = mapper::levelWarning(centers, result.map.resolution(), upAxisText(result.params.frame.up)))
      result.report.warnings.push_back(*tilted);
  }
}

}  // namespace

namespace detail {
void (*stage_hook)(const char* stage) = nullptr;
}  // namespace detail

std::string upAxisText(mapper::UpAxis up) {
  const std::string text = mapper::toString(up);
  return text[0] == '+' ? text.substr(1) : text;
}

std::string frameDescription(const mapper::FrameParams& frame) {
  std::ostringstream s;
  s << "z-up map frame: input axis " << upAxisText(frame.up) << " rotated to +z";
  if (frame.scale != 1.0) s << ", scaled by " << frame.scale;
  return s.str();
}

bool readsOctree(const BuildParams& params) {
  return params.inputs.size() == 1 && isOctomapFile(params.inputs.front());
}

std::string outputFrame(const BuildResult& result) {
  if (readsOctree(result.params)) {
    return "the octree's own frame (" + result.params.inputs.front().string() +
           " read as it is: no up axis or scale applied)";
  }
  return frameDescription(result.params.frame);
}

mapper::PointSet readInputPoints(const std::vector<std::string>& inputs) {
  mapper::PointSet set = mapper::readPointFiles(inputs);
  if (set.points.empty()) throw noPoints(inputs);
  return set;
}

ClusteredVoxels clusterMap(const mapper::OccupancyMap& map, const clustering::DbscanParams& dbscan) {
  return clusterStages(map, dbscan, nullptr);
}

BuildResult build(const BuildParams& params) {
  BuildResult result;
  result.params = params;
  StageTimer timer(result.report);
  if (params.inputs.empty()) throw Error::inParameter("inputs", "no input files");
  checkParams(params);
  runStage("read");

  if (readsOctree(params)) {
    // A finished map: no points to account for, voxels weigh 1 each.
    result.map = mapper::readMap(params.inputs.front().string());
    mapper::InputStats stats;
    stats.path = params.inputs.front().string();
    stats.format = params.inputs.front().extension().string().substr(1);
    result.report.inputs.push_back(stats);
    timer.stage("read");
  } else {
    for (const auto& input : params.inputs)
      if (isOctomapFile(input))
        throw Error(input.string() + ": an octomap file can only be the single input of build");
    if (!params.trajectory && !params.origin) {
      buildStreamed(params, result, timer);
    } else {
      mapper::PointSet set = readInputPoints(pathStrings(params.inputs));
      result.report.inputs = set.inputs;
      buildWhole(params, std::move(set.points), result, timer);
    }
    finishAccount(params, result);
  }
  clusterInto(result, timer);
  return result;
}

BuildResult buildFromPoints(mapper::Points points, const BuildParams& params, const std::string& name) {
  return buildFromPoints(std::move(points), std::nullopt, params, name);
}

BuildResult buildFromPoints(mapper::Points points, std::optional<std::vector<mapper::Keyframe>> keyframes,
                            const BuildParams& params, const std::string& name, const std::string& keyframes_name) {
  BuildResult result;
  result.params = params;
  result.params.inputs.clear();
  if (keyframes) {
    if (params.trajectory) throw Error::inParameter("trajectory", "give a trajectory file or keyframes, not both");
    result.params.trajectory = keyframes_name;
  }
  StageTimer timer(result.report);
  checkParams(result.params);
  runStage("read");
  mapper::InputStats stats;
  stats.path = name;
  stats.format = "memory";
  stats.read = points.size();
  // Non-finite points are dropped as the file readers drop them.
  const auto finite_end = std::stable_partition(points.begin(), points.end(),
                                                [](const mapper::Point& p) { return p.allFinite(); });
  const std::size_t non_finite = static_cast<std::size_t>(points.end() - finite_end);
  points.erase(finite_end, points.end());
  if (non_finite > 0) stats.dropped["non_finite"] = non_finite;
  result.report.inputs.push_back(stats);
  if (points.empty()) throw Error(name + ": no points");
  buildWhole(result.params, std::move(points), result, timer, keyframes ? &*keyframes : nullptr);
  finishAccount(result.params, result);
  clusterInto(result, timer);
  return result;
}

std::vector<clustering::Obstacle> readObstacles(const fs::path& obstacles_json) {
  return readObstaclesJson(obstacles_json.string());
}

nlohmann::json parametersJson(const BuildParams& params) {
  using nlohmann::json;
  const auto numbers = [](std::initializer_list<double> values) {
    std::string text;
    for (double v : values) {
      char buffer[32];
      text += (text.empty() ? "" : ",") + std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
    }
    return text;
  };
  json origin = nullptr;
  if (params.origin) origin = numbers({params.origin->x(), params.origin->y(), params.origin->z()});
  json crop = nullptr;
  if (params.filters.crop) {
    const auto& box = *params.filters.crop;
    crop = numbers({box.min.x(), box.min.y(), box.min.z(), box.max.x(), box.max.y(), box.max.z()});
  }
  return {
      {"inputs", pathStrings(params.inputs)},
      {"trajectory", params.trajectory ? json(params.trajectory->string()) : json(nullptr)},
      {"origin", origin},
      {"up", upAxisText(params.frame.up)},
      {"scale", params.frame.scale},
      {"crop", crop},
      {"z_min", params.filters.z_min ? json(*params.filters.z_min) : json(nullptr)},
      {"z_max", params.filters.z_max ? json(*params.filters.z_max) : json(nullptr)},
      {"resolution", params.octree.resolution},
      {"hit", params.octree.sensor.hit},
      {"miss", params.octree.sensor.miss},
      {"clamp_min", params.octree.sensor.clamp_min},
      {"clamp_max", params.octree.sensor.clamp_max},
      {"occupancy_threshold", params.octree.sensor.occupancy_threshold},
      {"max_range", params.octree.max_range},
      {"eps", params.dbscan.eps},
      {"min_pts", params.dbscan.min_pts},
      {"metric", clustering::toString(params.dbscan.metric)},
      {"ot", params.write_ot},
  };
}

nlohmann::json reportJson(const BuildResult& result) {
  using nlohmann::json;
  const BuildReport& report = result.report;
  json inputs = json::array();
  for (const auto& in : report.inputs) {
    inputs.push_back({{"path", in.path}, {"format", in.format}, {"points_read", in.read},
                      {"points_dropped", in.dropped}});
  }
  json timings = json::object();
  double total = 0.0;
  for (const auto& [stage, ms] : report.timings_ms) {
    timings[stage] = ms;
    total += ms;
  }
  timings["total"] = total;
  json peak = json::object();
  for (const auto& [stage, mb] : report.peak_rss_mb) peak[stage] = mb;
  const auto info = mapper::describe(result.map.tree());
  std::vector<std::size_t> largest(result.clusters.cluster_sizes);
  std::sort(largest.rbegin(), largest.rend());
  if (largest.size() > 10) largest.resize(10);
  std::size_t core = 0;
  for (auto c : result.clusters.core) core += c;

  json parameters = parametersJson(result.params);
  if (readsOctree(result.params)) {
    // A finished octree is read as it is: record what it holds, not parameters that were not applied.
    const auto& tree = result.map.tree();
    for (const char* key : {"trajectory", "origin", "up", "scale", "crop", "z_min", "z_max", "max_range"})
      parameters[key] = nullptr;
    parameters["resolution"] = info.resolution;
    parameters["hit"] = tree.getProbHit();
    parameters["miss"] = tree.getProbMiss();
    parameters["clamp_min"] = tree.getClampingThresMin();
    parameters["clamp_max"] = tree.getClampingThresMax();
    parameters["occupancy_threshold"] = tree.getOccupancyThres();
  }
  return {
      {"hullmap_version", HULLMAP_VERSION},
      {"frame", outputFrame(result)},
      {"parameters", parameters},
      {"warnings", report.warnings},
      {"inputs", inputs},
      {"points", {{"read", report.points.read},
                  {"dropped", report.points.dropped},
                  {"used", report.points.used}}},
      {"keyframes", report.keyframes},
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

nlohmann::json readReport(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open (is this a hullmap build directory?)");
  nlohmann::json report;
  try {
    in >> report;
  } catch (const nlohmann::json::exception& e) {
    throw Error(path.string() + ": not valid JSON: " + e.what());
  }
  const auto params = report.find("parameters");
  if (params == report.end() || !params->is_object()) throw Error(path.string() + ": no \"parameters\" object");
  const auto resolution = params->find("resolution");
  if (resolution == params->end() || !resolution->is_number() || !(resolution->get<double>() > 0.0)) {
    throw Error(path.string() + ": parameters.resolution missing or not a positive number");
  }
  return report;
}

void writeVoxelsCsv(const fs::path& path, const std::vector<mapper::OccupiedVoxel>& voxels,
                    const clustering::DbscanResult& clusters) {
  core::writeFileAtomically(path.string(), [&](std::ostream& os) {
    os << "x,y,z,weight,label,core\n" << std::setprecision(9);
    for (std::size_t i = 0; i < voxels.size(); ++i) {
      const auto& v = voxels[i];
      os << v.center.x() << ',' << v.center.y() << ',' << v.center.z() << ',' << v.weight << ','
         << clusters.labels[i] << ',' << int(clusters.core[i]) << '\n';
    }
  });
}

std::vector<VoxelRow> readVoxelsCsv(const fs::path& path) {
  const std::string name = path.string();
  std::ifstream in(path);
  if (!in) throw Error(name + ": cannot open (is this a hullmap build directory?)");
  std::string line;
  if (!std::getline(in, line) || line.rfind("x,y,z,weight,label", 0) != 0) {
    throw Error(name + ":1: expected header x,y,z,weight,label,core");
  }
  std::vector<VoxelRow> rows;
  std::size_t number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line == "\r") continue;
    std::istringstream fields(line);
    double v[6] = {0, 0, 0, 0, 0, 0};
    char comma = 0;
    bool ok = static_cast<bool>(fields >> v[0]);
    for (int i = 1; ok && i < 5; ++i) ok = (fields >> comma) && comma == ',' && (fields >> v[i]);
    if (ok && (fields >> comma)) ok = comma == ',' && (fields >> v[5]);
    if (!ok || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      throw Error(name + ":" + std::to_string(number) + ": expected x,y,z,weight,label,core numbers");
    }
    VoxelRow row;
    row.center = Eigen::Vector3d(v[0], v[1], v[2]);
    row.weight = static_cast<std::uint32_t>(v[3]);
    row.label = static_cast<std::int32_t>(v[4]);
    row.core = v[5] != 0.0;
    rows.push_back(row);
  }
  return rows;
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

void checkOutputDir(const fs::path& dir, const BuildParams& params, const WriteOptions& options) {
  mapper::OutputDirPolicy policy;
  for (const auto& input : params.inputs) policy.inputs.push_back(input.string());
  if (params.trajectory) policy.inputs.push_back(params.trajectory->string());
  policy.make_parents = options.make_parents;
  mapper::checkOutputDir(dir.string(), policy);
}

void write(const BuildResult& result, const fs::path& dir, const WriteOptions& options) {
  const std::string name = dir.string();
  checkOutputDir(dir, result.params, options);  // again: the build may have run for a while
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
    mapper::writeMap(result.map, (staging / "map.bt").string());
    if (result.params.write_ot) mapper::writeMap(result.map, (staging / "map.ot").string());
    runStage("wrote_map");
    writeVoxelsCsv(staging / "voxels.csv", result.voxels, result.clusters);
    runStage("wrote_voxels");
    const nlohmann::json report = reportJson(result);
    ObstaclesMeta meta;
    meta.frame = outputFrame(result);
    meta.parameters = report["parameters"];
    writeObstaclesJson((staging / "obstacles.json").string(), result.obstacles, meta);
    writeObstaclesObj((staging / "obstacles.obj").string(), result.obstacles);
    runStage("wrote_obstacles");
    core::writeFileAtomically((staging / "report.json").string(),
                              [&](std::ostream& os) { os << report.dump(2) << '\n'; });
    std::vector<std::string> written{"map.bt", "voxels.csv", "obstacles.json", "obstacles.obj", "report.json"};
    if (result.params.write_ot) written.push_back("map.ot");
    mapper::writeOutputMarker(staging.string(), written);

    runStage("move_into_place");
    checkOutputDir(dir, result.params, options);  // a file put there during the build is not removed with the old output
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
