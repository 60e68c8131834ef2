// hullmap::live::RebuildWorker against the pipeline it runs: what it publishes is what
// pipeline::buildFromPoints gives on the same points and settings; folding, reset, live settings,
// path checks and save, each asserted on counts and contents (waits only time out, nothing is timed).
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hullmap/live/rebuild_worker.hpp"
#include "hullmap/pipeline/check_json.hpp"
#include "test_support.hpp"

namespace hullmap::live {
namespace {

/// Everything the worker's hooks were given.
class Recorder {
 public:
  RebuildWorker::Hooks hooks() {
    RebuildWorker::Hooks h;
    h.publish_map = [this](const MapPublication& p) { record([&] { publications_.push_back(p); }); };
    h.publish_stats = [this](const std::string& json) {
      record([&] { stats_.push_back(nlohmann::json::parse(json)); });
    };
    h.rebuild_failed = [this](const std::string& why) { record([&] { failures_.push_back(why); }); };
    return h;
  }

  /// Waits (at most 60 s) until `done` holds on what was recorded; false when it never did.
  bool waitFor(const std::function<bool(const Recorder&)>& done) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, std::chrono::seconds(60), [&] { return done(*this); });
  }

  std::vector<MapPublication> publications_;
  std::vector<nlohmann::json> stats_;
  std::vector<std::string> failures_;

 private:
  void record(const std::function<void()>& f) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      f();
    }
    changed_.notify_all();
  }

  std::mutex mutex_;
  std::condition_variable changed_;
};

/// Points on a grid filling an axis-aligned cube of half-width `half` around each centre.
io::Points boxes(const std::vector<Eigen::Vector3d>& centres, double spacing = 0.04, double half = 0.1) {
  const int n = int(std::round(2 * half / spacing));
  io::Points points;
  for (const auto& c : centres)
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j)
        for (int k = 0; k <= n; ++k)
          points.emplace_back(c + Eigen::Vector3d(-half + i * spacing, -half + j * spacing, -half + k * spacing));
  return points;
}

NodeSettings settings(double min_interval = 0.0) {
  NodeSettings s;
  s.build.octree.resolution = 0.05;
  s.build.eps = 0.1;
  s.build.min_pts = 5;
  s.build.floor.mode = mapper::PlaneSetting::Mode::kNone;
  s.build.convex_parts.reset();
  s.node.min_interval = min_interval;
  return s;
}

MapUpdate update(io::Points points, std::int64_t stamp_ns = 1) {
  return {std::move(points), stamp_ns, Clock::now(), nullptr, std::nullopt};
}

/// id -> hull vertices, the comparison of two obstacle sets.
std::map<int, std::vector<Eigen::Vector3d>> hulls(const std::vector<hulls::Obstacle>& obstacles) {
  std::map<int, std::vector<Eigen::Vector3d>> out;
  for (const auto& o : obstacles) out[o.id] = o.hull.vertices;
  return out;
}

std::size_t rebuilds(const Recorder& r) {
  return r.stats_.empty() ? 0 : r.stats_.back()["rebuilds"].get<std::size_t>();
}

TEST(LiveRebuildWorker, PublishesWhatBuildFromPointsGivesOnTheSamePoints) {
  const io::Points points = boxes({{0, 0, 1}, {2, 0, 1}, {0, 3, 0.5}});
  const pipeline::BuildResult expected = pipeline::buildFromPoints(points, settings().build, "map");
  ASSERT_EQ(expected.obstacles.size(), 3u);
  Recorder r;
  RebuildWorker worker(settings(), r.hooks());
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return !r.stats_.empty(); }));  // the first stats
  worker.submit(update(points, 42));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 1 && !r.publications_.empty(); }));
  const MapPublication& p = r.publications_.back();
  ASSERT_TRUE(p.snapshot);
  EXPECT_EQ(hulls(p.snapshot->result.obstacles), hulls(expected.obstacles));
  EXPECT_EQ(p.stamp_ns, 42);
  EXPECT_EQ(p.frame_id, "map");
  const auto markers = obstacleMarkers(expected.obstacles, {});
  ASSERT_EQ(p.obstacles.size(), markers.size());
  for (std::size_t i = 0; i < markers.size(); ++i) EXPECT_EQ(p.obstacles[i].points, markers[i].points);
  EXPECT_EQ(p.occupied_cells.back().points.size(), expected.voxels.size());
  const nlohmann::json& stats = r.stats_.back();
  EXPECT_EQ(stats["messages"], 1);
  EXPECT_EQ(stats["points"], points.size());
  EXPECT_EQ(stats["obstacles"], 3);
  EXPECT_EQ(stats["voxels"], expected.voxels.size());
}

TEST(LiveRebuildWorker, MapsArrivingWhileItWaitsFoldIntoTheNewestAndMinIntervalChangesLive) {
  Recorder r;
  RebuildWorker worker(settings(), r.hooks());
  worker.submit(update(boxes({{0, 0, 1}})));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 1; }));
  // A long min_interval holds the next rebuild back: the next nine maps all arrive while it waits.
  worker.setSettings(settings(3600.0));
  for (int i = 1; i <= 9; ++i) worker.submit(update(boxes({{0.5 * i, 0, 1}, {0.5 * i, 2, 1}})));
  EXPECT_EQ(worker.stats().folded, 8u);
  EXPECT_TRUE(worker.stats().pending);
  worker.setSettings(settings(0.0));  // the wait ends at once
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 2; }));
  const NodeStats stats = worker.stats();
  EXPECT_EQ(stats.messages, 10u);
  EXPECT_EQ(stats.rebuilds + stats.folded, 10u);
  EXPECT_EQ(stats.max_waiting, 1u);
  const auto last = pipeline::buildFromPoints(boxes({{4.5, 0, 1}, {4.5, 2, 1}}), settings().build, "map");
  EXPECT_EQ(hulls(worker.latest()->result.obstacles), hulls(last.obstacles));
}

TEST(LiveRebuildWorker, BuildSettingsApplyAtTheNextRebuild) {
  const io::Points points = boxes({{0, 0, 1}, {0.35, 0, 1}});
  NodeSettings wide = settings();
  wide.build.eps = 0.2;  // joins the two boxes 15 cm apart
  const auto apart = pipeline::buildFromPoints(points, settings().build, "map");
  const auto joined = pipeline::buildFromPoints(points, wide.build, "map");
  ASSERT_NE(apart.obstacles.size(), joined.obstacles.size());
  Recorder r;
  RebuildWorker worker(settings(), r.hooks());
  worker.submit(update(points));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 1; }));
  EXPECT_EQ(hulls(worker.latest()->result.obstacles), hulls(apart.obstacles));
  worker.setSettings(wide);
  EXPECT_EQ(hulls(worker.latest()->result.obstacles), hulls(apart.obstacles));  // nothing rebuilt yet
  worker.submit(update(points));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 2; }));
  EXPECT_EQ(hulls(worker.latest()->result.obstacles), hulls(joined.obstacles));
}

TEST(LiveRebuildWorker, AFailedRebuildIsReportedAndTheOutputsStay) {
  Recorder r;
  RebuildWorker worker(settings(), r.hooks());
  worker.submit(update(boxes({{0, 0, 1}})));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 1; }));
  const auto before = worker.latest();
  // A map the octree cannot address at resolution 0.05 (it reaches +-1638.4): no settings build it.
  worker.submit(update(boxes({{1e5, 0, 1}})));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return !r.failures_.empty(); }));
  EXPECT_NE(r.failures_.back().find("resolution"), std::string::npos) << r.failures_.back();
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return r.stats_.back()["failed"] == 1; }));
  const std::string drop = r.stats_.back()["last_drop"];
  EXPECT_EQ(drop.rfind("rebuild of 216 points failed: ", 0), 0u) << drop;
  EXPECT_EQ(worker.latest(), before);
  EXPECT_EQ(r.publications_.size(), 1u);
}

TEST(LiveRebuildWorker, SettingsThatFailToBuildGiveWayToTheLastThatBuilt) {
  const io::Points first = boxes({{0, 0, 1}}), second = boxes({{3, 0, 1}}), third = boxes({{0, 3, 1}});
  Recorder r;
  RebuildWorker worker(settings(), r.hooks());
  worker.submit(update(first));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 1; }));
  NodeSettings bad = settings();
  bad.build.eps = 0.0;  // the build refuses it
  worker.setSettings(bad);
  worker.submit(update(second));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 2; }));
  // The second map was built with the settings that built the first, and published.
  EXPECT_EQ(hulls(worker.latest()->result.obstacles),
            hulls(pipeline::buildFromPoints(second, settings().build, "map").obstacles));
  EXPECT_EQ(r.stats_.back()["failed"], 0);
  const std::string refused = r.stats_.back()["refused_settings"];
  EXPECT_NE(refused.find("eps"), std::string::npos) << refused;
  ASSERT_FALSE(r.failures_.empty());
  EXPECT_NE(r.failures_.back().find("eps"), std::string::npos) << r.failures_.back();
  EXPECT_EQ(worker.settings().build.eps, settings().build.eps);  // those stay in use
  worker.submit(update(third));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 3; }));
  EXPECT_EQ(r.failures_.size(), 1u);
  // Settings set again are tried again: good ones clear the refusal.
  worker.setSettings(settings());
  worker.submit(update(first));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 4; }));
  EXPECT_EQ(r.stats_.back()["refused_settings"], "");
}

TEST(LiveRebuildWorker, AResolutionThatReachesNoPointOfTheMapIsNamed) {
  Recorder r;
  RebuildWorker worker(settings(), r.hooks());
  NodeSettings fine = settings();
  fine.build.octree.resolution = 1e-5;        // reaches +-0.33
  EXPECT_EQ(worker.unbuildable(fine), "");    // no map yet
  worker.submit(update(boxes({{0, 0, 1}})));  // nearest point: max(|x|, |y|, |z|) = 0.9
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 1; }));
  const std::string why = worker.unbuildable(fine);
  EXPECT_NE(why.find("no point of the current map"), std::string::npos) << why;
  fine.build.octree.resolution = 1e-4;  // reaches +-3.3
  EXPECT_EQ(worker.unbuildable(fine), "");
  fine.build.frame.scale = 10.0;  // the nearest point at 9 map units
  EXPECT_NE(worker.unbuildable(fine), "");
}

TEST(LiveRebuildWorker, ResetForgetsTheMapAndDeletesItsMarkers) {
  Recorder r;
  RebuildWorker worker(settings(), r.hooks());
  worker.submit(update(boxes({{0, 0, 1}, {2, 0, 1}})));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 1; }));
  std::set<int> ids;
  for (const auto& o : worker.latest()->result.obstacles) ids.insert(o.id);
  worker.reset();
  ASSERT_EQ(r.publications_.size(), 2u);
  const MapPublication& empty = r.publications_.back();
  EXPECT_FALSE(empty.snapshot);
  EXPECT_EQ(empty.stamp_ns, 0);
  std::set<std::pair<std::string, int>> deleted;
  for (const auto& m : empty.obstacles) {
    EXPECT_EQ(m.action, marker::kDelete);
    deleted.insert({m.ns, m.id});
  }
  std::set<std::pair<std::string, int>> expected;
  for (const char* ns : {"hulls", "footprints", "labels"})
    for (int id : ids) expected.insert({ns, id});
  EXPECT_EQ(deleted, expected);
  EXPECT_FALSE(worker.latest());
  EXPECT_EQ(r.stats_.back()["obstacles"], 0);
  EXPECT_FALSE(worker.save().success);
}

TEST(LiveRebuildWorker, PathChecksAreHullCheckersOnTheLatestRebuild) {
  const io::Points points = boxes({{0, 0, 1}, {2, 0, 1}});
  const auto built = pipeline::buildFromPoints(points, settings().build, "map");
  const collision::HullChecker checker(built.obstacles);
  const std::vector<Eigen::Vector3d> path{{-1, 0, 1}, {1, 0, 1}, {1, -2, 1}};
  Recorder r;
  RebuildWorker worker(settings(), r.hooks());
  const PathCheckAnswer before = worker.checkPath(path);
  for (const auto& s : before.check.segments) EXPECT_FALSE(s.collides);  // no map yet: nothing to hit
  worker.submit(update(points));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 1; }));
  for (const double radius : {0.25, 0.0, 1.5}) {
    const PathCheckAnswer answer = radius == 0.25 ? worker.checkPath(path) : worker.checkPath(path, radius);
    const collision::PathCheck expected = checker.checkPath(path, radius);
    std::string lines;
    for (std::size_t i = 0; i < expected.segments.size(); ++i)
      lines += pipeline::segmentCheckJsonLine(i, expected.segments[i]) + "\n";
    EXPECT_EQ(answer.json_lines, lines) << radius;
    EXPECT_EQ(answer.check.first_colliding_segment, expected.first_colliding_segment);
    ASSERT_EQ(answer.markers.size(), 1u);
    EXPECT_EQ(answer.markers[0].points.size(), 4u);
  }
  EXPECT_TRUE(worker.checkPath(path).check.first_colliding_segment.has_value());
  EXPECT_THROW(worker.checkPath(path, -1.0), Error);
}

// Outdoors the node does what build does: a ground no plane explains (a rolling 40 x 40 m terrain,
// 0.8 m of relief) is fitted as a height field, and a path check through it names the ground.
TEST(LiveRebuildWorker, AGroundThatIsNoPlaneIsAnObstacleForPathChecks) {
  const auto terrain = [](double x, double y) { return 0.5 * std::sin(x / 5.0) + 0.3 * std::cos(y / 7.0); };
  io::Points points;
  for (int i = 0; i < 80; ++i)
    for (int j = 0; j < 80; ++j) {
      const double x = -20.0 + 0.5 * i + 0.13 * ((i * 7 + j * 3) % 5), y = -20.0 + 0.5 * j + 0.11 * ((i * 5 + j) % 4);
      points.emplace_back(x, y, terrain(x, y));
    }
  NodeSettings s = settings();
  s.build.floor.mode = mapper::PlaneSetting::Mode::kAuto;
  s.build.eps.reset();
  s.build.min_pts.reset();
  const auto built = pipeline::buildFromPoints(points, s.build, "map");
  ASSERT_TRUE(built.report.ground.has_value()) << "no ground found";
  ASSERT_FALSE(built.report.floor.plane.has_value());
  Recorder r;
  RebuildWorker worker(s, r.hooks());
  worker.submit(update(points));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 1; }));
  // A drop from 1.5 m over the terrain to 0.5 m under it, and a level flight 1.5 m over its top.
  const PathCheckAnswer down =
      worker.checkPath({{3.0, 4.0, terrain(3, 4) + 1.5}, {3.0, 4.0, terrain(3, 4) - 0.5}}, 0.2);
  ASSERT_TRUE(down.check.first_colliding_segment.has_value());
  EXPECT_EQ(down.check.segments[0].surface, "ground");
  EXPECT_NE(down.json_lines.find("\"surface\":\"ground\""), std::string::npos) << down.json_lines;
  const PathCheckAnswer over = worker.checkPath({{-15.0, -15.0, 2.3}, {15.0, 15.0, 2.3}}, 0.2);
  EXPECT_FALSE(over.check.first_colliding_segment.has_value()) << over.json_lines;
}

TEST(LiveRebuildWorker, SaveWritesWhatWriteWritesForTheSameBuild) {
  const io::Points points = boxes({{0, 0, 1}, {2, 0, 1}});
  const auto dir = test::freshDir("save");
  NodeSettings s = settings();
  s.node.output_dir = (dir / "saved").string();
  Recorder r;
  RebuildWorker worker(s, r.hooks());
  worker.submit(update(points));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 1; }));
  const SaveAnswer answer = worker.save();
  ASSERT_TRUE(answer.success) << answer.message;
  EXPECT_EQ(answer.message, std::filesystem::absolute(dir / "saved").string());
  pipeline::write(pipeline::buildFromPoints(points, s.build, "map"), dir / "direct");
  for (const char* file : {"map.bt", "voxels.csv", "obstacles.json", "obstacles.obj"}) {
    std::ifstream a(dir / "saved" / file, std::ios::binary), b(dir / "direct" / file, std::ios::binary);
    std::stringstream sa, sb;
    sa << a.rdbuf();
    sb << b.rdbuf();
    EXPECT_FALSE(sa.str().empty()) << file;
    EXPECT_EQ(sa.str(), sb.str()) << file;
  }
}

TEST(LiveRebuildWorker, SavedWarningsNameTheNodesParameters) {
  // eps below the resolution: report.json's warning names the node's parameters, not the CLI's flags.
  const auto dir = test::freshDir("save_warnings");
  NodeSettings s = settings();
  s.build.eps = 0.03;
  s.node.output_dir = (dir / "saved").string();
  Recorder r;
  RebuildWorker worker(s, r.hooks());
  worker.submit(update(boxes({{0, 0, 1}})));
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return rebuilds(r) == 1; }));
  ASSERT_TRUE(worker.save().success);
  const auto warnings = test::readJson(dir / "saved" / "report.json")["warnings"];
  ASSERT_FALSE(warnings.empty());
  const std::string first = warnings[0];
  EXPECT_EQ(first.rfind("eps:=0.03 is below the octree resolution 0.05", 0), 0u) << first;
  EXPECT_NE(first.find("a finer resolution"), std::string::npos) << first;
  for (const auto& w : warnings) EXPECT_EQ(w.get<std::string>().find("--"), std::string::npos) << w;
}

TEST(LiveRebuildWorker, SkippedAndLostMessagesAreCountedAndPublished) {
  Recorder r;
  RebuildWorker worker(settings(), r.hooks());
  worker.skip("a cloud without z");
  worker.lost(3, "3 messages on ~/cloud_in lost in transport");
  worker.skip("a short cloud");
  ASSERT_TRUE(r.waitFor([](const Recorder& r) { return r.stats_.back()["skipped"] == 2; }));
  EXPECT_EQ(worker.stats().messages, 0u);
  EXPECT_EQ(r.stats_.back()["lost"], 3);
  EXPECT_EQ(r.stats_.back()["last_drop"], "skipped: a short cloud");
}

}  // namespace
}  // namespace hullmap::live
