#include "hullmap/live/rebuild_worker.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>

#include <nlohmann/json.hpp>

#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/check_json.hpp"

namespace hullmap::live {
namespace {

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

/// A number as a person reads it (6 significant digits).
std::string shortText(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

/// The least max(|x|, |y|, |z|) of `points`: what the octree must reach for any of them, in any up axis.
std::optional<double> nearestReach(const io::Points& points) {
  if (points.empty()) return std::nullopt;
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& p : points) nearest = std::min(nearest, p.cwiseAbs().maxCoeff());
  return nearest;
}

/// The occupied cells and projected map of `snapshot` (null: the empty map).
MapLayers layersOf(const Snapshot* snapshot, const NodeSettings& settings) {
  static const std::vector<hulls::Obstacle> kNone;
  static const std::vector<mapper::OccupiedVoxel> kNoVoxels;
  // The resolution the map was built at (the current setting for the empty map).
  const double resolution = snapshot ? snapshot->result.params.octree.resolution : settings.build.octree.resolution;
  MapLayers layers;
  layers.occupied_cells =
      occupiedCellMarkers(snapshot ? snapshot->result.voxels : kNoVoxels, resolution, settings.node.frame_id);
  layers.projected_map = projectedGrid(snapshot ? snapshot->result.obstacles : kNone, resolution,
                                       settings.node.occupancy_min_z, settings.node.occupancy_max_z, 2 * resolution);
  return layers;
}

}  // namespace

std::string statsJson(const NodeStats& s) {
  const nlohmann::json j = {{"messages", s.messages},
                            {"skipped", s.skipped},
                            {"folded", s.folded},
                            {"rebuilds", s.rebuilds},
                            {"failed", s.failed},
                            {"max_waiting", s.max_waiting},
                            {"pending", s.pending ? 1 : 0},
                            {"busy", s.busy},
                            {"points", s.points},
                            {"keyframes", s.keyframes},
                            {"voxels", s.voxels},
                            {"obstacles", s.obstacles},
                            {"rebuild_ms", s.rebuild_ms},
                            {"latency_ms", s.latency_ms},
                            {"lost", s.lost},
                            {"last_drop", s.last_drop},
                            {"refused_settings", s.refused_settings},
                            {"inputs", s.inputs}};
  return j.dump();
}

RebuildWorker::RebuildWorker(NodeSettings settings, Hooks hooks, std::string keyframes_name)
    : hooks_(std::move(hooks)), keyframes_name_(std::move(keyframes_name)), settings_(std::move(settings)) {
  publishStats();
  worker_ = std::thread([this] { run(); });
}

RebuildWorker::~RebuildWorker() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  worker_.join();
}

void RebuildWorker::submit(MapUpdate map) {
  const std::optional<double> reach = nearestReach(map.points);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    map_reach_ = reach;
    ++stats_.messages;
    if (pending_) ++stats_.folded;
    pending_ = std::move(map);
    stats_.max_waiting = std::max<std::uint64_t>(stats_.max_waiting, 1);
  }
  wake_.notify_one();
}

void RebuildWorker::skip(const std::string& why) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.skipped;
    stats_.last_drop = "skipped: " + why;
  }
  publishStats();
}

void RebuildWorker::setInput(const std::string& topic, const std::string& description) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.inputs[topic] = description;
  }
  publishStats();
}

void RebuildWorker::lost(std::uint64_t count, const std::string& why) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.lost += count;
    stats_.last_drop = "lost: " + why;
  }
  publishStats();
}

void RebuildWorker::setSettings(NodeSettings settings) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    settings_ = std::move(settings);
    ++settings_version_;
    stats_.refused_settings.clear();
  }
  wake_.notify_all();  // a worker waiting out min_interval waits the new one
}

std::string RebuildWorker::unbuildable(const NodeSettings& settings) const {
  std::optional<double> reach;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    reach = map_reach_;
  }
  // Keys are 16 bits a coordinate: 2^15 leaves either side of the origin.
  const double limit = settings.build.octree.resolution * 32768;
  if (!reach || *reach * settings.build.frame.scale < limit) return {};
  return "the octree could address no point of the current map: at resolution " +
         shortText(settings.build.octree.resolution) + " it reaches +-" + shortText(limit) +
         " map units around the origin, and the map's nearest point is " +
         shortText(*reach * settings.build.frame.scale) + " away along an axis (scale " +
         shortText(settings.build.frame.scale) + "); a coarser resolution or a smaller scale reaches it";
}

NodeSettings RebuildWorker::settings() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return settings_;
}

std::shared_ptr<const Snapshot> RebuildWorker::latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

NodeStats RebuildWorker::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  NodeStats s = stats_;
  s.pending = pending_.has_value();
  return s;
}

void RebuildWorker::run() {
  std::optional<Clock::time_point> last_start;
  for (;;) {
    MapUpdate map;
    std::uint64_t generation = 0;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || pending_.has_value(); });
      if (stop_) return;
      if (last_start) {
        // Re-read after each wake: min_interval may change while the worker waits.
        for (;;) {
          const auto earliest = *last_start + std::chrono::duration_cast<Clock::duration>(
                                                  std::chrono::duration<double>(settings_.node.min_interval));
          const double interval = settings_.node.min_interval;
          if (wake_.wait_until(lock, earliest, [&] { return stop_ || settings_.node.min_interval != interval; })) {
            if (stop_) return;
            continue;
          }
          break;
        }
        if (!pending_) continue;  // reset meanwhile
      }
      map = std::move(*pending_);
      pending_.reset();
      generation = generation_;
      stats_.busy = true;
    }
    last_start = Clock::now();
    rebuild(std::move(map), generation);
  }
}

std::shared_ptr<const Snapshot> RebuildWorker::build(MapUpdate map, const NodeSettings& settings,
                                                     MapLayers& layers) const {
  if (map.points.empty()) {
    layers = layersOf(nullptr, settings);
    return nullptr;
  }
  pipeline::BuildParams params = settings.build;
  if (!params.camera_frame) params.camera_frame = map.camera_frame;
  pipeline::BuildResult result =
      map.keyframes ? pipeline::buildFromPoints(std::move(map.points), *map.keyframes, params, "map", keyframes_name_)
                    : pipeline::buildFromPoints(std::move(map.points), params, "map");
  // The floor and ceiling found are obstacles for path checks, as for `hullmap check`.
  collision::HullChecker checker(result.obstacles, result.surfaces);
  auto snapshot = std::make_shared<const Snapshot>(Snapshot{std::move(result), std::move(checker)});
  layers = layersOf(snapshot.get(), settings);
  return snapshot;
}

RebuildWorker::Attempt RebuildWorker::buildOrFallBack(MapUpdate map, const NodeSettings& settings,
                                                      const std::optional<NodeSettings>& fallback) const {
  std::optional<MapUpdate> retry;
  if (fallback) retry = map;  // a copy only while the settings are untried
  Attempt a;
  try {
    a.snapshot = build(std::move(map), settings, a.layers);
  } catch (const std::exception& e) {
    a.failure = e.what();
  }
  if (!a.failure.empty() && fallback) {
    try {
      a.snapshot = build(std::move(*retry), *fallback, a.layers);
      a.refused.swap(a.failure);
    } catch (const std::exception&) {
      // The map fails with either: the map's fault, reported with the settings as set.
    }
  }
  return a;
}

void RebuildWorker::rebuild(MapUpdate map, std::uint64_t generation) {
  const auto start = Clock::now();
  NodeSettings settings;
  std::optional<NodeSettings> fallback;  // the last settings that built, while the current are untried
  std::uint64_t version = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    settings = settings_;
    version = settings_version_;
    if (good_settings_ && good_version_ != version) fallback = good_settings_;
  }
  const std::size_t points = map.points.size();
  const std::int64_t stamp_ns = map.stamp_ns;
  const Clock::time_point received = map.received;
  Attempt attempt = buildOrFallBack(std::move(map), settings, fallback);
  auto& [snapshot, layers, failure, refused] = attempt;
  const double rebuild_ms = msSince(start);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.busy = false;
    if (generation != generation_) return;  // reset while it ran
    if (!failure.empty()) {
      ++stats_.failed;
      stats_.last_drop = "rebuild of " + std::to_string(points) + " points failed: " + failure;
    } else {
      ++stats_.rebuilds;
      latest_ = snapshot;
      stats_.points = points;
      stats_.keyframes = snapshot ? snapshot->result.report.keyframes : 0;
      stats_.voxels = snapshot ? snapshot->result.voxels.size() : 0;
      stats_.obstacles = snapshot ? snapshot->result.obstacles.size() : 0;
      stats_.rebuild_ms = rebuild_ms;
      if (refused.empty()) {
        good_settings_ = settings;
        good_version_ = version;
      } else if (settings_version_ == version) {  // no newer settings meanwhile: the last good ones stay
        settings_ = *fallback;
        good_version_ = ++settings_version_;
        stats_.refused_settings = "the parameters as set failed to build a map of " + std::to_string(points) +
                                  " points that the last values that built could build (" + refused +
                                  "); the node builds with those until a parameter is set again";
      }
    }
  }
  if (!failure.empty()) {
    if (hooks_.rebuild_failed)
      hooks_.rebuild_failed("rebuild of " + std::to_string(points) + " points failed: " + failure);
    publishStats();
    return;
  }
  if (!refused.empty() && hooks_.rebuild_failed) {
    hooks_.rebuild_failed("rebuild of " + std::to_string(points) + " points failed with the parameters as set (" +
                          refused + "); built with the last values that built, which stay in use");
  }
  publishMap(snapshot, std::move(layers), stamp_ns, generation);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.latency_ms = msSince(received);
  }
  publishStats();
}

void RebuildWorker::publishMap(const std::shared_ptr<const Snapshot>& snapshot, MapLayers layers, std::int64_t stamp_ns,
                               std::uint64_t generation) {
  std::lock_guard<std::mutex> lock(publish_mutex_);
  std::string frame_id;
  {
    std::lock_guard<std::mutex> state(mutex_);
    if (generation != generation_) return;
    frame_id = settings_.node.frame_id;
  }
  static const std::vector<hulls::Obstacle> kNone;
  const auto& obstacles = snapshot ? snapshot->result.obstacles : kNone;
  MapPublication publication;
  publication.snapshot = snapshot;
  publication.stamp_ns = stamp_ns;
  publication.frame_id = frame_id;
  publication.obstacles = obstacleMarkers(obstacles, published_ids_);
  published_ids_.clear();
  for (const auto& o : obstacles) published_ids_.push_back(o.id);
  publication.occupied_cells = std::move(layers.occupied_cells);
  publication.projected_map = std::move(layers.projected_map);
  if (hooks_.publish_map) hooks_.publish_map(publication);
}

void RebuildWorker::publishStats() {
  if (hooks_.publish_stats) hooks_.publish_stats(statsJson(stats()));
}

void RebuildWorker::reset() {
  std::uint64_t generation = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_.reset();
    map_reach_.reset();
    generation = ++generation_;
    latest_.reset();
    stats_.points = stats_.keyframes = stats_.voxels = stats_.obstacles = 0;
  }
  publishMap(nullptr, layersOf(nullptr, settings()), 0, generation);
  publishStats();
}

PathCheckAnswer RebuildWorker::checkPath(const std::vector<Eigen::Vector3d>& waypoints,
                                         std::optional<double> radius) const {
  std::shared_ptr<const Snapshot> snapshot;
  double r = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    snapshot = latest_;
    r = radius.value_or(settings_.node.radius);
  }
  PathCheckAnswer answer;
  const collision::CheckRequest request{r};
  if (snapshot) {
    answer.check = snapshot->checker.checkPath(waypoints, request);
  } else {
    answer.check = collision::HullChecker(std::vector<hulls::Obstacle>{}).checkPath(waypoints, request);
  }
  for (std::size_t i = 0; i < answer.check.segments.size(); ++i) {
    answer.json_lines += pipeline::segmentCheckJsonLine(i, answer.check.segments[i]) + "\n";
  }
  answer.markers = pathCheckMarkers(waypoints, answer.check, 0.05);
  return answer;
}

SaveAnswer RebuildWorker::save() const {
  std::shared_ptr<const Snapshot> snapshot;
  std::string output_dir;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    snapshot = latest_;
    output_dir = settings_.node.output_dir;
  }
  if (!snapshot) return {false, "no map built yet"};
  try {
    pipeline::write(snapshot->result, output_dir, {true, nodeParameterSpelling});
    return {true, std::filesystem::absolute(output_dir).string()};
  } catch (const std::exception& e) {
    return {false, e.what()};
  }
}

}  // namespace hullmap::live
