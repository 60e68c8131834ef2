#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/live/node_params.hpp"
#include "hullmap/live/outputs.hpp"
#include "hullmap/pipeline/pipeline.hpp"

/// The live node's engine, once for both ROS versions: maps in, rebuilt on one worker thread on the
/// newest map, published through the front end's hooks; path checks, save and reset on the latest
/// rebuild. See docs/ROS.md (Rebuilds, ~stats).
namespace hullmap::live {

using Clock = std::chrono::steady_clock;

/// A whole map as a message brought it (every map message replaces the map).
struct MapUpdate {
  io::Points points;           ///< input frame
  std::int64_t stamp_ns = 0;   ///< the message's header stamp, ns; 0: none (outputs then get the time of publishing)
  Clock::time_point received;  ///< when the message arrived (latency_ms runs from here)
  std::shared_ptr<const std::vector<io::Keyframe>> keyframes;  ///< null: a points-only octree
  /// Whether the points are in a camera's frame (ORB-SLAM's /ORB_SLAM/Map markers: its first
  /// camera's), for level auto (pipeline::BuildParams::camera_frame); nullopt: judged as a file is.
  std::optional<bool> camera_frame;
};

/// A finished rebuild: the build and the path checker made of its obstacles. Immutable once made.
struct Snapshot {
  pipeline::BuildResult result;
  collision::HullChecker checker;
};

/// The counters ~stats publishes (docs/ROS.md lists their meaning).
struct NodeStats {
  std::uint64_t messages = 0, skipped = 0, folded = 0, rebuilds = 0, failed = 0;
  std::uint64_t max_waiting = 0;  ///< the most maps ever waiting for the worker at once
  bool pending = false;           ///< a map is waiting
  bool busy = false;              ///< a rebuild is running
  std::size_t points = 0, keyframes = 0, voxels = 0, obstacles = 0;  ///< of the last rebuild
  double rebuild_ms = 0.0;  ///< wall time of the last rebuild (build + path checker)
  double latency_ms = 0.0;  ///< map message's arrival to its outputs published
  std::uint64_t lost = 0;   ///< messages the transport reported lost before they reached the node
  std::string last_drop;    ///< why the last message not rebuilt was not (lost, skipped, failed); empty: none
  /// Why the parameters as set failed to build a map that the last values that built could build
  /// (the node then builds with those); empty: the parameters as set are in use.
  std::string refused_settings;
  std::map<std::string, std::string> inputs;  ///< map input topic -> its QoS in words (ROS 2: "reliable, volatile")
};

/// The stats as the one-line JSON object ~stats holds (keys sorted).
std::string statsJson(const NodeStats& stats);

/// The layers drawn from a rebuild besides its obstacles (made with it, so that a map too big to
/// draw fails as its build would).
struct MapLayers {
  std::vector<MarkerSpec> occupied_cells;  ///< ~occupied_cells_vis_array
  ProjectedGrid projected_map;             ///< ~projected_map
};

/// One publication of the map's outputs (the empty map after a reset).
struct MapPublication {
  std::shared_ptr<const Snapshot> snapshot;  ///< null: the empty map
  std::int64_t stamp_ns = 0;                 ///< the map message's stamp; 0: the time of publishing
  std::string frame_id;                      ///< NodeParams::frame_id
  std::vector<MarkerSpec> obstacles;         ///< ~obstacles (deletions of the previous ids included)
  std::vector<MarkerSpec> occupied_cells;    ///< ~occupied_cells_vis_array
  ProjectedGrid projected_map;               ///< ~projected_map
};

/// A path checked against the latest rebuild.
struct PathCheckAnswer {
  collision::PathCheck check;       ///< one SegmentCheck per segment, the first collision
  std::string json_lines;           ///< what `hullmap check --json --path` prints, each line ending in '\n'
  std::vector<MarkerSpec> markers;  ///< ~path_check_markers
};

/// What save() did.
struct SaveAnswer {
  bool success = false;
  std::string message;  ///< the absolute output directory, or why nothing was written
};

/// The rebuild worker. submit() never blocks on a rebuild: a map that arrives while one runs waits,
/// and a newer one replaces it (counted in `folded`), so at most one map ever waits and the node
/// ends on the last message; NodeParams::min_interval spaces the starts of two rebuilds. A failed
/// rebuild is reported through Hooks::rebuild_failed and the previous outputs stay. Every member
/// function is thread-safe; the hooks are called from the worker thread and from the callers of
/// reset() and skip() (publish_map: one call at a time, in order).
class RebuildWorker {
 public:
  struct Hooks {
    std::function<void(const MapPublication&)> publish_map;
    std::function<void(const std::string& stats_json)> publish_stats;
    std::function<void(const std::string& why)> rebuild_failed;  ///< "rebuild of N points failed: ..."
  };

  /// Starts the worker thread with `settings`; publishes the first stats. `keyframes_name` names
  /// the keyframes in the build's report (its "trajectory": the topic they came on).
  RebuildWorker(NodeSettings settings, Hooks hooks, std::string keyframes_name = "keyframes");
  /// Stops the worker thread (a rebuild running is finished first).
  ~RebuildWorker();
  RebuildWorker(const RebuildWorker&) = delete;
  RebuildWorker& operator=(const RebuildWorker&) = delete;

  /// Hands a map to the worker (replacing any map still waiting).
  void submit(MapUpdate map);
  /// Counts a malformed message skipped (`why`: what was wrong) and publishes the stats.
  void skip(const std::string& why);
  /// Sets what ~stats says of a map input (its QoS, say) and publishes the stats.
  void setInput(const std::string& topic, const std::string& description);
  /// Counts `count` messages the transport lost (`why`: where and how) and publishes the stats.
  void lost(std::uint64_t count, const std::string& why);
  /// Forgets the map: a waiting map is dropped, a rebuild running is discarded, the empty outputs
  /// and the stats are published.
  void reset();
  /// New settings, used from the next rebuild on (a rebuild running finishes with the old ones). A
  /// rebuild that fails with them is tried again on the same map with the last settings that built;
  /// when that builds, those stay in use (NodeStats::refused_settings says why) until the next call.
  void setSettings(NodeSettings settings);
  /// Why `settings` could not build the last map taken (no point of it the octree could address at
  /// their resolution and scale), or empty: the check a front end makes before it accepts settings.
  std::string unbuildable(const NodeSettings& settings) const;
  NodeSettings settings() const;

  std::shared_ptr<const Snapshot> latest() const;
  NodeStats stats() const;

  /// Checks `waypoints` (map frame) for a sphere of `radius` (NodeParams::radius when nullopt) swept
  /// along them against the latest rebuild's obstacles (none before the first), as `hullmap check
  /// --path --json` does on the directory save() writes. Throws hullmap::Error naming `radius`, or
  /// on a non-finite coordinate.
  PathCheckAnswer checkPath(const std::vector<Eigen::Vector3d>& waypoints,
                            std::optional<double> radius = std::nullopt) const;

  /// Writes the latest rebuild to NodeParams::output_dir as `hullmap build -p -o DIR` writes it.
  SaveAnswer save() const;

 private:
  void run();
  /// A rebuild's outcome: built with the settings as set, or with the fallback (`refused`: why not
  /// the former), or not at all (`failure`).
  struct Attempt {
    std::shared_ptr<const Snapshot> snapshot;
    MapLayers layers;
    std::string failure, refused;
  };

  void rebuild(MapUpdate map, std::uint64_t generation);
  Attempt buildOrFallBack(MapUpdate map, const NodeSettings& settings,
                          const std::optional<NodeSettings>& fallback) const;
  std::shared_ptr<const Snapshot> build(MapUpdate map, const NodeSettings& settings, MapLayers& layers) const;
  void publishMap(const std::shared_ptr<const Snapshot>& snapshot, MapLayers layers, std::int64_t stamp_ns,
                  std::uint64_t generation);
  void publishStats();

  Hooks hooks_;
  const std::string keyframes_name_;

  mutable std::mutex mutex_;  // guards what follows
  std::condition_variable wake_;
  NodeSettings settings_;
  std::uint64_t settings_version_ = 0;         // counts setSettings()
  std::optional<NodeSettings> good_settings_;  // the last that built a map
  std::uint64_t good_version_ = 0;             // settings_version_ of the settings that last built
  std::optional<double> map_reach_;            // the last map's least max(|x|, |y|, |z|), input units
  std::optional<MapUpdate> pending_;
  bool stop_ = false;
  std::uint64_t generation_ = 0;
  std::shared_ptr<const Snapshot> latest_;
  NodeStats stats_;

  std::mutex publish_mutex_;  // guards published_ids_ and the order of map publications
  std::vector<int> published_ids_;

  std::thread worker_;  // last: started when everything above is ready
};

}  // namespace hullmap::live
