#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "check_warnings.hpp"
#include "commands.hpp"
#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/pipeline/check_json.hpp"
#include "hullmap/pipeline/map_obstacles.hpp"
#include "hullmap/pipeline/path_checker.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "option_checks.hpp"
#include "path_file.hpp"
#include "planning_args.hpp"

namespace hullmap::cli {
namespace {

struct CheckOptions {
  std::string input;  ///< a `hullmap build` directory or an obstacles.json
  double radius = 0.0;
  std::string path_file;
  std::string segments_file;
  std::string segment;
  std::string against = "hulls";
  std::string frame = "map";
  bool json = false;
};

std::string describe(std::size_t index, const collision::Segment& s, const collision::SegmentCheck& c, bool json) {
  if (json) return pipeline::segmentCheckJsonLine(index, c);
  std::string line = "segment " + std::to_string(index) + ": ";
  if (!c.collides) return line + "clear, clearance " + shortestNumber(c.clearance);
  const Eigen::Vector3d p = s.a + c.t * (s.b - s.a);
  line += "COLLIDES";
  if (!c.surface.empty()) line += " with the " + c.surface;
  if (c.obstacle >= 0) line += " with obstacle " + std::to_string(c.obstacle);
  if (c.part >= 0) line += " part " + std::to_string(c.part);
  return line + " at t=" + shortestNumber(c.t) + " (" + shortestNumber(p.x()) + " " + shortestNumber(p.y()) + " " +
         shortestNumber(p.z()) + ")";
}

void runCheck(const CheckOptions& o, int& status) {
  checkRadius(o.radius);
  const int sources = !o.path_file.empty() + !o.segments_file.empty() + !o.segment.empty();
  if (sources != 1) throw Error("give exactly one of --path, --segments, --segment");
  if (o.against != "hulls" && o.against != "octree")
    throw Error("--against: expected \"hulls\" or \"octree\", got \"" + o.against + "\"");

  std::vector<collision::Segment> segments;
  std::vector<Eigen::Vector3d> waypoints;
  const bool is_path = !o.path_file.empty();
  if (is_path) {
    waypoints = readPathFile(o.path_file);
    for (std::size_t i = 0; i + 1 < waypoints.size(); ++i) segments.push_back({waypoints[i], waypoints[i + 1]});
  } else if (!o.segments_file.empty()) {
    segments = readSegmentsFile(o.segments_file);
  } else {
    const auto r = parseCommaNumbers(o.segment, 6, "--segment");
    segments.push_back({{r[0], r[1], r[2]}, {r[3], r[4], r[5]}});
  }

  // A path is checked as one (checkPath: the first collision along it); segments one by one. The
  // checks run in the map frame; t is the same fraction of a segment in either frame, so the
  // contact points printed are on the segments as given.
  const collision::CheckRequest request{o.radius};
  const pipeline::QueryFrame frame = pipeline::parseQueryFrame(o.frame);
  collision::PathCheck path;
  std::vector<std::string> warnings;
  const auto inMapFrame = [&](const pipeline::MapObstacles& map) {
    const mapper::Similarity to_map = pipeline::toMapFrame(map, frame);
    std::vector<collision::Segment> moved = segments;
    for (auto& s : moved) s = {to_map(s.a), to_map(s.b)};
    std::vector<Eigen::Vector3d> moved_waypoints = waypoints;
    for (auto& w : moved_waypoints) w = to_map(w);
    return std::make_pair(moved, moved_waypoints);
  };
  if (o.against == "octree") {
    const std::string map_bt = buildArtefact(o.input, "map.bt");
    const mapper::OccupancyMap map = mapper::readMap(map_bt);
    // The surfaces and the frame are in the build's obstacles.json beside its map.bt.
    pipeline::MapObstacles beside;
    const std::filesystem::path obstacles_json = std::filesystem::path(map_bt).parent_path() / "obstacles.json";
    if (std::filesystem::exists(obstacles_json)) {
      beside = pipeline::readMapObstacles(obstacles_json);
    } else {
      warnings.push_back(map_bt +
                         " has no obstacles.json beside it: its floor and ceiling are not known and not "
                         "checked, only its voxels");
      if (frame == pipeline::QueryFrame::kInput)
        throw Error("--frame input: " + map_bt + " has no obstacles.json beside it recording the build's frame");
    }
    const auto [moved, moved_waypoints] = inMapFrame(beside);
    const collision::OctreeChecker checker(map.tree(), beside.surfaces);
    if (is_path) {
      path = checker.checkPath(moved_waypoints, request);
    } else {
      for (const auto& s : moved) path.segments.push_back(checker.check(s, request));
    }
  } else {
    const std::string obstacles_json = buildArtefact(o.input, "obstacles.json");
    refuseOctreeAsHulls(obstacles_json);
    const pipeline::MapObstacles map = pipeline::readMapObstacles(obstacles_json);
    warnings = hullCheckWarnings(obstacles_json, map.obstacles.size());
    const auto [moved, moved_waypoints] = inMapFrame(map);
    const collision::HullChecker checker = pipeline::pathChecker(map);
    if (is_path) {
      path = checker.checkPath(moved_waypoints, request);
    } else {
      path.segments = checker.checkBatch(moved, request);
    }
  }
  if (is_path && path.first_colliding_segment) {
    const std::size_t i = *path.first_colliding_segment;
    const Eigen::Vector3d& a = waypoints[i];
    const Eigen::Vector3d& b = waypoints.size() == 1 ? a : waypoints[i + 1];
    path.first_contact = a + path.segments[i].t * (b - a);
  }
  for (const auto& warning : warnings) std::cerr << "hullmap: warning: " << warning << "\n";
  const std::vector<collision::SegmentCheck>& results = path.segments;

  std::string out;
  if (o.json) {
    for (const auto& warning : warnings) out += nlohmann::json{{"warning", warning}}.dump() + "\n";
  }
  bool any = false;
  for (std::size_t i = 0; i < results.size(); ++i) {
    out += describe(i, segments[i], results[i], o.json) + "\n";
    any = any || results[i].collides;
  }
  if (is_path && !o.json) {
    if (path.first_colliding_segment) {
      const Eigen::Vector3d& p = *path.first_contact;
      out += "path: first collision in segment " + std::to_string(*path.first_colliding_segment) + " at (" +
             shortestNumber(p.x()) + " " + shortestNumber(p.y()) + " " + shortestNumber(p.z()) + ")\n";
    } else {
      out += "path: clear\n";
    }
  }
  std::cout << out << std::flush;
  status = any ? 1 : 0;
}

}  // namespace

void addCheckCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<CheckOptions>();
  auto* cmd = app.add_subcommand(
      "check",
      "Check a path or segments, swept by a sphere of --radius, against a build's obstacles and its floor "
      "and ceiling (exit 1 if anything collides). Coordinates in the build's map frame, or with --frame "
      "input in the frame of the points it read.");
  cmd->add_option("input", options->input,
                  "a `hullmap build` directory, or an obstacles.json (or map.bt for --against octree)")
      ->required();
  cmd->add_option("--radius,-r", options->radius, "drone radius, map units (metres once aligned), in either frame")
      ->required()
      ->check(numberAbove(0, true));
  cmd->add_option("--path", options->path_file,
                  "waypoints file: x y z a line (spaces or commas, # comments, a header line), at least two");
  cmd->add_option("--segments", options->segments_file, "segments file: x0 y0 z0 x1 y1 z1 a line (same rules)");
  cmd->add_option("--segment", options->segment, "one segment: x0,y0,z0,x1,y1,z1");
  cmd->add_option("--against", options->against, "hulls (convex obstacles) or octree (every occupied voxel)")
      ->capture_default_str();
  cmd->add_option("--frame", options->frame,
                  "map: coordinates in the build's outputs' frame; input: in the frame of the points it read "
                  "(before --up/--scale, --align and levelling), answers in it too")
      ->check(CLI::IsMember({"map", "input"}))
      ->capture_default_str();
  cmd->add_flag("--json", options->json, "JSON lines: index, collides, obstacle, part, surface, t, clearance");
  cmd->callback([options, &status] {
    status = 2;
    runCheck(*options, status);
  });
}

}  // namespace hullmap::cli
