#include <cmath>
#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/map_obstacles.hpp"
#include "hullmap/planning/roadmap.hpp"
#include "planning_args.hpp"

namespace hullmap::cli {
namespace {

struct RoadmapOptions {
  std::string input;  ///< a `hullmap build` directory or an obstacles.json
  double radius = 0.0;
  std::string band;
  std::string bounds;
  double tolerance = 1e-3;
  std::string output;
};

void runRoadmap(const RoadmapOptions& o, int& status) {
  if (!(o.radius >= 0) || !std::isfinite(o.radius))
    throw Error("--radius: must be >= 0, got " + shortestNumber(o.radius));
  planning::RoadmapParams params;
  params.min_clearance = o.radius;
  params.tolerance = o.tolerance;
  if (!(o.tolerance > 0) || !std::isfinite(o.tolerance)) throw Error("--tolerance: must be > 0");
  if (!o.band.empty()) {
    const auto z = parseCommaNumbers(o.band, 2, "--band");
    if (!(z[0] <= z[1])) throw Error("--band: need z0 <= z1, got " + o.band);
    params.z0 = z[0];
    params.z1 = z[1];
  }
  if (!o.bounds.empty()) {
    const auto b = parseCommaNumbers(o.bounds, 4, "--bounds");
    if (!(b[0] < b[2] && b[1] < b[3])) throw Error("--bounds: need x0 < x1 and y0 < y1, got " + o.bounds);
    params.bounds = planning::Bounds2d{b[0], b[1], b[2], b[3]};
  }
  const std::string output = o.output.empty() ? defaultOutput(o.input, "roadmap.json") : o.output;
  const pipeline::MapObstacles map = pipeline::readMapObstacles(obstaclesFile(o.input));
  const planning::Roadmap roadmap = planning::buildRoadmap(map.obstacles, params, map.surfaces);
  planning::writeRoadmapJson(output, roadmap);
  double length = 0;
  for (const auto& e : roadmap.edges) length += e.length;
  std::cout << "roadmap: " << roadmap.nodes.size() << " nodes, " << roadmap.edges.size() << " edges ("
            << shortestNumber(length) << " m, clearance >= " << shortestNumber(o.radius) << ") around "
            << roadmap.footprints.size() << " obstacles";
  if (roadmap.z0 != params.z0 || roadmap.z1 != params.z1)
    std::cout << " in the band " << shortestNumber(roadmap.z0) << " .. " << shortestNumber(roadmap.z1)
              << " between the floor and ceiling";
  std::cout << " -> " << output << "\n";
  status = 0;
}

}  // namespace

void addRoadmapCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<RoadmapOptions>();
  auto* cmd = app.add_subcommand(
      "roadmap",
      "The exact Voronoi roadmap of a build's obstacle footprints (z-up map frame): the edges that keep "
      "--radius from every obstacle, as roadmap.json (docs/PLANNING.md).");
  cmd->add_option("input", options->input, "a `hullmap build` directory, or an obstacles.json")->required();
  cmd->add_option("--radius,-r", options->radius, "drone radius, map units: narrower edges are dropped")->required();
  cmd->add_option("--band", options->band,
                  "z0,z1: only obstacles whose z range meets this band (default: all), cut to what lies between the "
                  "build's floor and ceiling");
  cmd->add_option("--bounds", options->bounds, "x0,y0,x1,y1 (default: the footprints' bounds grown by 1)");
  cmd->add_option("--tolerance", options->tolerance, "parabolic arcs sampled within this distance")
      ->capture_default_str();
  cmd->add_option("-o,--output", options->output, "roadmap file (default: roadmap.json beside the obstacles)");
  cmd->callback([options, &status] {
    status = 2;
    runRoadmap(*options, status);
  });
}

}  // namespace hullmap::cli
