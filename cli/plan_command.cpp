#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/map_obstacles.hpp"
#include "hullmap/planning/fleet.hpp"
#include "hullmap/planning/ompl_planner.hpp"
#include "hullmap/planning/path_planner.hpp"
#include "planning_args.hpp"

namespace hullmap::cli {
namespace {

struct PlanOptions {
  std::string input;  ///< a `hullmap build` directory or an obstacles.json
  std::string from;
  std::string to;
  std::string robots;
  double radius = 0.0;
  double speed = 0.0;
  std::string output;
  std::string method = "roadmap";
  std::optional<double> time_limit;  ///< seconds, --method ompl
  std::string frame = "map";
};

/// The query's frame: points in go through to_map, paths out come back through from_map.
struct Frames {
  mapper::Similarity to_map;
  mapper::Similarity from_map;
};

Eigen::Vector3d point(const std::string& text, const std::string& option) {
  const auto v = parseCommaNumbers(text, 3, option);
  return {v[0], v[1], v[2]};
}

/// robots.txt: `sx sy sz gx gy gz` a line; blank lines and `#` comments skipped.
std::vector<planning::FleetTask> readRobots(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open");
  std::vector<planning::FleetTask> tasks;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    std::vector<double> v;
    std::string word;
    while (fields >> word) {
      std::size_t used = 0;
      double x = 0;
      try {
        x = std::stod(word, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != word.size() || !std::isfinite(x))
        throw Error(path + ":" + std::to_string(number) + ": not a number: \"" + word + "\"");
      v.push_back(x);
    }
    if (v.empty()) continue;
    if (v.size() != 6)
      throw Error(path + ":" + std::to_string(number) + ": expected 6 numbers (sx sy sz gx gy gz), got " +
                  std::to_string(v.size()));
    tasks.push_back({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}});
  }
  if (tasks.empty()) throw Error(path + ": no drones");
  return tasks;
}

void writeWaypoints(const std::string& path, const std::vector<Eigen::Vector3d>& waypoints) {
  core::writeFileAtomically(path, [&](std::ostream& out) {
    for (const auto& p : waypoints)
      out << shortestNumber(p.x()) << " " << shortestNumber(p.y()) << " " << shortestNumber(p.z()) << "\n";
  });
}

void runSingle(const PlanOptions& o, const pipeline::MapObstacles& map, const Frames& frames, int& status) {
  planning::PlanRequest request;
  request.start = frames.to_map(point(o.from, "--from"));
  request.goal = frames.to_map(point(o.to, "--to"));
  request.radius = o.radius;
  planning::PlanResult result;
  if (o.method == "ompl") {
    planning::OmplParams params;
    if (o.time_limit) params.time_limit = *o.time_limit;
    planning::OmplPlanResult found = planning::planPathOmpl(map.obstacles, request, params, map.surfaces);
    result.path = std::move(found.path);
    result.length = found.length;
    result.blocked = std::move(found.blocked);
  } else {
    result = planning::planPath(map.obstacles, request, std::nullopt, map.surfaces);
  }
  if (!result.path) {
    std::cout << "no path: " << result.blocked << "\n";
    status = 1;
    return;
  }
  for (auto& p : *result.path) p = frames.from_map(p);
  if (o.output.empty()) {
    for (const auto& p : *result.path)
      std::cout << shortestNumber(p.x()) << " " << shortestNumber(p.y()) << " " << shortestNumber(p.z()) << "\n";
  } else {
    writeWaypoints(o.output, *result.path);
    std::cout << "path: " << result.path->size() << " waypoints, " << shortestNumber(result.length) << " m, clear by "
              << shortestNumber(o.radius) << " (exact hull check) -> " << o.output << "\n";
  }
  status = 0;
}

void runFleet(const PlanOptions& o, const pipeline::MapObstacles& map, const Frames& frames, int& status) {
  const auto& obstacles = map.obstacles;
  if (o.output.empty()) throw Error("--robots: give the output directory with -o");
  if (!(o.speed > 0) || !std::isfinite(o.speed)) throw Error("--speed: must be > 0 with --robots");
  if (!(o.radius > 0)) throw Error("--radius: must be > 0 with --robots");
  auto tasks = readRobots(o.robots);
  for (auto& t : tasks) t = {frames.to_map(t.start), frames.to_map(t.goal)};
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(o.output, ec);
  if (!fs::is_directory(o.output)) throw Error("-o " + o.output + ": cannot make this directory");

  std::vector<Eigen::Vector3d> points;
  for (const auto& t : tasks) {
    points.push_back(t.start);
    points.push_back(t.goal);
  }
  const planning::PathPlanner planner(
      obstacles,
      planning::buildRoadmap(obstacles, planning::roadmapParamsFor(obstacles, points, o.radius), map.surfaces),
      map.surfaces);
  planning::FleetParams params;
  params.radius = o.radius;
  params.speed = o.speed;
  const planning::FleetResult result = planning::planFleet(planner, tasks, params);
  std::size_t written = 0;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const std::string path = (fs::path(o.output) / ("robot_" + std::to_string(i) + ".txt")).string();
    fs::remove(path, ec);  // a stale file from an earlier run must not pass for this one's
    if (!result.paths[i]) continue;
    core::writeFileAtomically(path, [&](std::ostream& out) {
      out << "# t x y z: seconds, map units, " << (o.frame == "input" ? "the build's input frame" : "z-up map frame")
          << "; drone " << i << " of hullmap plan --robots\n";
      for (const auto& w : *result.paths[i]) {
        const Eigen::Vector3d p = frames.from_map(w.position);
        out << shortestNumber(w.t) << " " << shortestNumber(p.x()) << " " << shortestNumber(p.y()) << " "
            << shortestNumber(p.z()) << "\n";
      }
    });
    ++written;
  }
  std::cout << "fleet: " << written << " of " << tasks.size() << " drones routed, min separation "
            << shortestNumber(result.min_separation) << " m (>= 2 x " << shortestNumber(o.radius) << "), step "
            << shortestNumber(result.time_step) << " s -> " << o.output << "\n";
  if (!result.unrouted.empty()) {
    for (const auto& why : result.reasons) std::cout << why << "\n";
    std::string names;
    for (const auto i : result.unrouted) names += (names.empty() ? "" : ", ") + std::to_string(i);
    std::cout << "not routed: drone" << (result.unrouted.size() > 1 ? "s " : " ") << names << "\n";
    status = 1;
    return;
  }
  status = 0;
}

void runPlan(const PlanOptions& o, int& status) {
  if (!(o.radius >= 0) || !std::isfinite(o.radius))
    throw Error("--radius: must be >= 0, got " + shortestNumber(o.radius));
  const bool single = !o.from.empty() || !o.to.empty();
  if (single == !o.robots.empty()) throw Error("give either --from and --to, or --robots");
  if (single && (o.from.empty() || o.to.empty()))
    throw Error(o.from.empty() ? "--from is required with --to" : "--to is required with --from");
  if (o.method != "roadmap" && o.method != "ompl")
    throw Error("--method: unknown method \"" + o.method + "\" (roadmap or ompl)");
  if (o.time_limit && o.method != "ompl") throw Error("--time-limit: only with --method ompl");
  if (o.time_limit && (!(*o.time_limit > 0) || !std::isfinite(*o.time_limit) || *o.time_limit > 86400))
    throw Error("--time-limit: must be > 0 and at most 86400 seconds, got " + shortestNumber(*o.time_limit));
  if (o.method == "ompl" && !single) throw Error("--method ompl: plans one drone (--from, --to), not --robots");
  const pipeline::MapObstacles map = pipeline::readMapObstacles(obstaclesFile(o.input));
  Frames frames;
  frames.to_map = pipeline::toMapFrame(map, pipeline::parseQueryFrame(o.frame));
  frames.from_map = mapper::inverse(frames.to_map);
  if (single)
    runSingle(o, map, frames, status);
  else
    runFleet(o, map, frames, status);
}

}  // namespace

void addPlanCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<PlanOptions>();
  auto* cmd = app.add_subcommand(
      "plan",
      "A path for a drone of --radius around a build's obstacles (exit 1 when there is none, naming where it "
      "is blocked), or timed paths for several drones (--robots). The build's floor and ceiling are obstacles too. "
      "Coordinates in the build's map frame, or with --frame input in the frame of the points it read.");
  cmd->add_option("input", options->input, "a `hullmap build` directory, or an obstacles.json")->required();
  cmd->add_option("--from", options->from, "start x,y,z");
  cmd->add_option("--to", options->to, "goal x,y,z");
  cmd->add_option("--robots", options->robots, "drones file: sx sy sz gx gy gz a line, # comments");
  cmd->add_option("--radius,-r", options->radius, "drone radius, map units (metres once aligned), in either frame")
      ->required();
  cmd->add_option("--frame", options->frame,
                  "map: coordinates in the build's outputs' frame; input: in the frame of the points it read (paths "
                  "are written in it too)")
      ->check(CLI::IsMember({"map", "input"}))
      ->capture_default_str();
  cmd->add_option("--method", options->method,
                  "roadmap (default: the Voronoi roadmap in the flight plane) or ompl (RRT* in 3D, exact capsule "
                  "sweep as motion check)");
  cmd->add_option("--time-limit", options->time_limit, "seconds of RRT* with --method ompl (default 1)");
  cmd->add_option("--speed", options->speed, "top speed with --robots, map units per second");
  cmd->add_option("-o,--output", options->output,
                  "waypoints file (x y z a line, what check --path reads; default: stdout), or with --robots the "
                  "directory for robot_<i>.txt (t x y z a line)");
  cmd->callback([options, &status] {
    status = 2;
    runPlan(*options, status);
  });
}

}  // namespace hullmap::cli
