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
#include "hullmap/planning/fleet.hpp"
#include "hullmap/planning/ompl_planner.hpp"
#include "hullmap/planning/path_planner.hpp"
#include "hullmap/pipeline/pipeline.hpp"
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

void runSingle(const PlanOptions& o, const std::vector<clustering::Obstacle>& obstacles, int& status) {
  planning::PlanRequest request;
  request.start = point(o.from, "--from");
  request.goal = point(o.to, "--to");
  request.radius = o.radius;
  planning::PlanResult result;
  if (o.method == "ompl") {
    planning::OmplParams params;
    if (o.time_limit) params.time_limit = *o.time_limit;
    planning::OmplPlanResult found = planning::planPathOmpl(obstacles, request, params);
    result.path = std::move(found.path);
    result.length = found.length;
    result.blocked = std::move(found.blocked);
  } else {
    result = planning::planPath(obstacles, request);
  }
  if (!result.path) {
    std::cout << "no path: " << result.blocked << "\n";
    status = 1;
    return;
  }
  if (o.output.empty()) {
    for (const auto& p : *result.path)
      std::cout << shortestNumber(p.x()) << " " << shortestNumber(p.y()) << " " << shortestNumber(p.z()) << "\n";
  } else {
    writeWaypoints(o.output, *result.path);
    std::cout << "path: " << result.path->size() << " waypoints, " << shortestNumber(result.length)
              << " m, clear by " << shortestNumber(o.radius) << " (exact hull check) -> " << o.output << "\n";
  }
  status = 0;
}

void runFleet(const PlanOptions& o, const std::vector<clustering::Obstacle>& obstacles, int& status) {
  if (o.output.empty()) throw Error("--robots: give the output directory with -o");
  if (!(o.speed > 0) || !std::isfinite(o.speed)) throw Error("--speed: must be > 0 with --robots");
  if (!(o.radius > 0)) throw Error("--radius: must be > 0 with --robots");
  const auto tasks = readRobots(o.robots);
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
      obstacles, planning::buildRoadmap(obstacles, planning::roadmapParamsFor(obstacles, points, o.radius)));
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
      out << "# t x y z: seconds, metres, z-up map frame; drone " << i << " of hullmap plan --robots\n";
      for (const auto& w : *result.paths[i])
        out << shortestNumber(w.t) << " " << shortestNumber(w.position.x()) << " " << shortestNumber(w.position.y())
            << " " << shortestNumber(w.position.z()) << "\n";
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
  if (!(o.radius >= 0) || !std::isfinite(o.radius)) throw Error("--radius: must be >= 0, got " + shortestNumber(o.radius));
  const bool single = !o.from.empty() || !o.to.empty();
  if (single == !o.robots.empty()) throw Error("give either --from and --to, or --robots");
  if (single && (o.from.empty() || o.to.empty())) throw Error(o.from.empty() ? "--from is required with --to" : "--to is required with --from");
  if (o.method != "roadmap" && o.method != "ompl")
    throw Error("--method: unknown method \"" + o.method + "\" (roadmap or ompl)");
  if (o.time_limit && o.method != "ompl") throw Error("--time-limit: only with --method ompl");
  if (o.time_limit && (!(*o.time_limit > 0) || !std::isfinite(*o.time_limit) || *o.time_limit > 86400))
    throw Error("--time-limit: must be > 0 and at most 86400 seconds, got " + shortestNumber(*o.time_limit));
  if (o.method == "ompl" && !single) throw Error("--method ompl: plans one drone (--from, --to), not --robots");
  const auto obstacles = pipeline::readObstacles(obstaclesFile(o.input));
  if (single) runSingle(o, obstacles, status);
  else runFleet(o, obstacles, status);
}

}  // namespace

void addPlanCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<PlanOptions>();
  auto* cmd = app.add_subcommand(
      "plan", "A path for a drone of --radius around a build's obstacles (exit 1 when there is none, naming where it "
              "is blocked), or timed paths for several drones (--robots). Coordinates in the z-up map frame.");
  cmd->add_option("input", options->input, "a `hullmap build` directory, or an obstacles.json")->required();
  cmd->add_option("--from", options->from, "start x,y,z");
  cmd->add_option("--to", options->to, "goal x,y,z");
  cmd->add_option("--robots", options->robots, "drones file: sx sy sz gx gy gz a line, # comments");
  cmd->add_option("--radius,-r", options->radius, "drone radius, map units")->required();
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
