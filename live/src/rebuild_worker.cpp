#include "hullmap/live/rebuild_worker.hpp"

#include <algorithm>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/check_json.hpp"

namespace hullmap::live {
namespace {

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

}  // namespace

std::string statsJson(const NodeStats& s) {
  const nlohmann::json j = {{"messages", s.messages},       {"skipped", s.skipped},
                            {"folded", s.folded},           {"rebuilds", s.rebuilds},
                            {"failed", s.failed},           {"max_waiting", s.max_waiting},
                            {"pending", s.pending ? 1 : 0}, {"busy", s.busy},
                            {"points", s.points},           {"keyframes", s.keyframes},
                            {"voxels", s.voxels},           {"obstacles", s.obstacles},
                            {"rebuild_ms", s.rebuild_ms},   {"latency_ms", s.latency_ms}};
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
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.messages;
    if (pending_) ++stats_.folded;
    pending_ = std::move(map);
    stats_.max_waiting = std::max<std::uint64_t>(stats_.max_waiting, 1);
  }
  wake_.notify_one();
}

void RebuildWorker::skip() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.skipped;
  }
  publishStats();
}

void RebuildWorker::setSettings(NodeSettings settings) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    settings_ = std::move(settings);
  }
  wake_.notify_all();  // a worker waiting out min_interval waits the new one
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

void RebuildWorker::rebuild(MapUpdate map, std::uint64_t generation) {
  const auto start = Clock::now();
  pipeline::BuildParams params = settings().build;
  if (!params.camera_frame) params.camera_frame = map.camera_frame;
  std::shared_ptr<const Snapshot> snapshot;
  std::string failure;
  const std::size_t points = map.points.size();
  if (!map.points.empty()) {
    try {
      pipeline::BuildResult result = map.keyframes ? pipeline::buildFromPoints(std::move(map.points), *map.keyframes,
                                                                               params, "map", keyframes_name_)
                                                   : pipeline::buildFromPoints(std::move(map.points), params, "map");
      // The floor and ceiling found are obstacles for path checks, as for `hullmap check`.
      collision::HullChecker checker(result.obstacles, result.surfaces);
      snapshot = std::make_shared<const Snapshot>(Snapshot{std::move(result), std::move(checker)});
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  const double rebuild_ms = msSince(start);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.busy = false;
    if (generation != generation_) return;  // reset while it ran
    if (!failure.empty()) {
      ++stats_.failed;
    } else {
      ++stats_.rebuilds;
      latest_ = snapshot;
      stats_.points = points;
      stats_.keyframes = snapshot ? snapshot->result.report.keyframes : 0;
      stats_.voxels = snapshot ? snapshot->result.voxels.size() : 0;
      stats_.obstacles = snapshot ? snapshot->result.obstacles.size() : 0;
      stats_.rebuild_ms = rebuild_ms;
    }
  }
  if (!failure.empty()) {
    if (hooks_.rebuild_failed)
      hooks_.rebuild_failed("rebuild of " + std::to_string(points) + " points failed: " + failure);
    publishStats();
    return;
  }
  publishMap(snapshot, map.stamp_ns, generation);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.latency_ms = msSince(map.received);
  }
  publishStats();
}

void RebuildWorker::publishMap(const std::shared_ptr<const Snapshot>& snapshot, std::int64_t stamp_ns,
                               std::uint64_t generation) {
  std::lock_guard<std::mutex> lock(publish_mutex_);
  NodeSettings settings;
  {
    std::lock_guard<std::mutex> state(mutex_);
    if (generation != generation_) return;
    settings = settings_;
  }
  static const std::vector<hulls::Obstacle> kNone;
  static const std::vector<mapper::OccupiedVoxel> kNoVoxels;
  const auto& obstacles = snapshot ? snapshot->result.obstacles : kNone;
  // The resolution the map was built at (the current setting for the empty map).
  const double resolution = snapshot ? snapshot->result.params.octree.resolution : settings.build.octree.resolution;
  MapPublication publication;
  publication.snapshot = snapshot;
  publication.stamp_ns = stamp_ns;
  publication.frame_id = settings.node.frame_id;
  publication.obstacles = obstacleMarkers(obstacles, published_ids_);
  published_ids_.clear();
  for (const auto& o : obstacles) published_ids_.push_back(o.id);
  publication.occupied_cells =
      occupiedCellMarkers(snapshot ? snapshot->result.voxels : kNoVoxels, resolution, settings.node.frame_id);
  publication.projected_map = projectedGrid(obstacles, resolution, settings.node.occupancy_min_z,
                                            settings.node.occupancy_max_z, 2 * resolution);
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
    generation = ++generation_;
    latest_.reset();
    stats_.points = stats_.keyframes = stats_.voxels = stats_.obstacles = 0;
  }
  publishMap(nullptr, 0, generation);
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
