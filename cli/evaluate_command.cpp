#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/pipeline/trajectory_file.hpp"
#include "hullmap/sim/evaluate.hpp"

namespace hullmap::cli {
namespace {

struct EvaluateOptions {
  std::string dir;
  std::string truth;
  std::string points;
  sim::EvaluateParams params;
  bool json = false;
  std::optional<double> false_tolerance;  ///< unset: one voxel of the build
};

/// The observed map points of a build: voxels.csv's voxel centres weighted by their map points
/// (already in the map frame; a hull holds a voxel's points exactly when it holds the whole voxel).
void readVoxelPoints(const std::string& path, std::vector<Eigen::Vector3d>& points,
                     std::vector<std::uint32_t>& weights) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open (is this a hullmap build directory? or give --points)");
  std::string line;
  if (!std::getline(in, line) || line.rfind("x,y,z,weight", 0) != 0)
    throw Error(path + ":1: expected header x,y,z,weight,label,core");
  for (std::size_t number = 2; std::getline(in, line); ++number) {
    if (line.empty() || line == "\r") continue;
    std::istringstream fields(line);
    double v[4];
    char comma = 0;
    bool ok = static_cast<bool>(fields >> v[0]);
    for (int i = 1; ok && i < 4; ++i) ok = (fields >> comma) && comma == ',' && (fields >> v[i]);
    if (!ok || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]) || !(v[3] >= 1))
      throw Error(path + ":" + std::to_string(number) + ": expected x,y,z,weight,label,core numbers");
    points.emplace_back(v[0], v[1], v[2]);
    weights.push_back(std::uint32_t(v[3]));
  }
}

std::string percent(double part, double whole, bool small = false) {
  if (!(whole > 0)) return "-";
  std::ostringstream out;
  const double share = 100.0 * part / whole;
  // `small`: shares below 1 % keep two significant digits (0.049%), so that they do not read as nothing.
  const int digits = small && share > 0 && share < 0.1 ? 3 : small && share > 0 && share < 1 ? 2 : 1;
  out << std::fixed << std::setprecision(digits) << share << "%";
  return out.str();
}

void runEvaluate(const EvaluateOptions& o) {
  namespace fs = std::filesystem;
  const std::string obstacles_path = fs::is_directory(o.dir) ? (fs::path(o.dir) / "obstacles.json").string() : o.dir;
  pipeline::ObstaclesMeta meta;
  const auto obstacles = pipeline::readObstaclesJson(obstacles_path, &meta);  // meta.surfaces: the floor is checked too
  sim::EvaluateParams params = o.params;
  // False parts: farther than a voxel of the build (its resolution) from every true obstacle, unless given.
  std::string tolerance_why = "given";
  if (o.false_tolerance) {
    params.false_tolerance = *o.false_tolerance;
  } else if (meta.parameters.contains("resolution") && meta.parameters["resolution"].is_number()) {
    params.false_tolerance = meta.parameters["resolution"].get<double>();
    tolerance_why = "one voxel of the build";
  } else {
    tolerance_why = "the default: no resolution in " + obstacles_path;
  }
  if (params.ends == sim::SegmentEnds::kCorridor) {
    const auto keyframes = fs::is_directory(o.dir) ? pipeline::readBuildTrajectory(o.dir) : std::nullopt;
    if (!keyframes || keyframes->empty())
      throw Error::inParameter("ends", "corridor needs the build's keyframe path: " + o.dir +
                                           " has no trajectory.txt (build with --trajectory)");
    for (const auto& k : *keyframes) params.path.push_back(k.position);
  }
  const sim::GroundTruth truth = sim::readGroundTruth(o.truth);
  std::vector<Eigen::Vector3d> points;
  std::vector<std::uint32_t> weights;
  if (!o.points.empty()) {
    points = io::readPointFile(o.points).points;
  } else {
    if (!fs::is_directory(o.dir)) throw Error(o.dir + ": not a build directory; give --points for the map points");
    readVoxelPoints((fs::path(o.dir) / "voxels.csv").string(), points, weights);
  }
  const sim::Evaluation e = sim::evaluate(obstacles, truth, points, weights, params, meta.surfaces);
  if (o.json) {
    std::cout << sim::evaluationToJson(e, params).dump(1) << '\n';
    return;
  }
  std::cout << "truth: " << truth.shapes.size() << " obstacles; hulls: " << e.parts << "\n";
  for (const auto& t : e.truth)
    std::cout << "  " << t.label << ": " << percent(t.points_inside, t.points_near) << " of its " << t.points_near
              << " observed points inside hulls, " << t.parts.size() << " hulls representing it, "
              << t.parts_touching.size() << " touching"
              << (t.surface ? " (a bounding surface: left out of the obstacles)" : "") << "\n";
  std::cout << std::setprecision(4) << "volume: hulls " << e.hull_volume << ", union " << e.union_volume
            << ", outside the truth " << e.outside_volume << " +- " << e.outside_volume_se << ", farther than "
            << o.params.far_margin << ": " << e.far_volume << " +- " << e.far_volume_se << " ("
            << percent(e.far_volume, e.union_volume) << " of the union)\n";
  // False parts: how many, how much space they take, how far off they are.
  std::cout << "false parts (no closer than " << params.false_tolerance << " to any true obstacle: " << tolerance_why
            << "): " << e.false_parts.size() << " of " << e.parts << " hulls";
  if (!e.false_parts.empty()) {
    std::size_t single = 0;
    const sim::FalsePart* largest = &e.false_parts.front();
    double farthest = 0.0;
    std::array<std::size_t, 4> by_distance{};  // up to 0.1, 0.2, 0.5, beyond
    for (const auto& f : e.false_parts) {
      single += f.voxels == 1;
      if (f.volume > largest->volume) largest = &f;
      farthest = std::max(farthest, f.distance);
      ++by_distance[f.distance <= 0.1 ? 0 : f.distance <= 0.2 ? 1 : f.distance <= 0.5 ? 2 : 3];
    }
    std::cout << ", " << single << " of them one voxel; " << e.false_volume << " in all ("
              << percent(e.false_volume, e.hull_volume, true) << " of the hulls' volume), the largest "
              << largest->volume << " (" << largest->voxels << (largest->voxels == 1 ? " voxel, " : " voxels, ")
              << largest->distance << " away); away from the truth: " << by_distance[0] << " up to 0.1, "
              << by_distance[1] << " up to 0.2, " << by_distance[2] << " up to 0.5, " << by_distance[3]
              << " farther (at most " << farthest << ")";
  }
  std::cout << "\n";
  std::cout << "segments (r = " << o.params.radius;
  if (o.params.margin > 0) std::cout << ", hulls checked at r + " << o.params.margin;
  std::cout << "): " << e.segments << "; deep collisions " << e.deep << ", missed " << e.missed << "; clear " << e.clear
            << ", false alarms " << e.false_alarms << " (" << percent(double(e.false_alarms), double(e.clear)) << ")\n";
  // Said only when there are such: maps/room's figures read as before.
  if (e.deep_unseen > 0)
    std::cout << "unseen: " << e.deep_unseen << " of the deep collisions hold fewer than " << o.params.seen_points
              << " map points within r (" << e.missed_unseen
              << " of the missed): the map never saw where they collide, or saw a stray point or two\n";
}

}  // namespace

void addEvaluateCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<EvaluateOptions>();
  auto* cmd =
      app.add_subcommand("evaluate", "Score a build's obstacles against ground truth (boxes, cylinders, OBJ mesh)");
  cmd->add_option("dir", options->dir,
                  "Directory written by `hullmap build` (obstacles.json, voxels.csv), "
                  "or an obstacles.json with --points")
      ->required();
  cmd->add_option("--truth", options->truth, "Ground truth: JSON as maps/room/ground_truth.json, or an OBJ mesh")
      ->required();
  cmd->add_option("--radius", options->params.radius, "Drone radius for the segment checks, map units (default 0.3)");
  cmd->add_option("--points", options->points,
                  "Map points in the map frame (any point format); default: the build's voxels.csv, weighted");
  cmd->add_option("--segments", options->params.segments, "Random segments in the free volume (default 2000)");
  cmd->add_option("--seed", options->params.seed, "Seed of every random draw (default 1)");
  cmd->add_option("--clear-margin", options->params.clear_margin,
                  "A clear segment keeps --radius plus this from every true obstacle, map units (default 0.1)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--margin", options->params.margin,
                  "Check the hulls and surfaces at --radius plus this (a planner's safety margin); deep and clear "
                  "stay defined at --radius, map units (default 0)")
      ->check(CLI::NonNegativeNumber);
  auto ends = std::make_shared<std::string>("free");
  cmd->add_option("--ends", *ends,
                  "Segment endpoints: free (around the truth, both free), in-box (anywhere in the truth's box: "
                  "a room's inside) or corridor (free, near the build's keyframe path: a street; needs the build's "
                  "trajectory.txt; default free)");
  cmd->add_option("--segment-length", options->params.segment_length,
                  "Segments are 0.2 to this long, map units (default 2)")
      ->check(CLI::Range(0.2, 1e9));
  cmd->add_option("--seen-points", options->params.seen_points,
                  "A deep segment whose capsule holds fewer map points than this is unseen (default 3)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--corridor-width", options->params.corridor_width,
                  "With --ends corridor: ends within this of the keyframe path in (x, y), map units (default 10)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--corridor-height", options->params.corridor_height,
                  "With --ends corridor: ends at most this above the nearest keyframe, map units (default 3)")
      ->check(CLI::PositiveNumber);
  cmd->callback([options, ends, &status] {
    if (*ends == "free") {
      options->params.ends = sim::SegmentEnds::kFree;
    } else if (*ends == "in-box") {
      options->params.ends = sim::SegmentEnds::kInTruthBox;
    } else if (*ends == "corridor") {
      options->params.ends = sim::SegmentEnds::kCorridor;
    } else {
      throw Error("--ends: expected 'free', 'in-box' or 'corridor', got '" + *ends + "'");
    }
    runEvaluate(*options);
    status = 0;
  });
  cmd->add_flag("--json", options->json, "Print the result as JSON");
  cmd->add_option("--false-tolerance", options->false_tolerance,
                  "A hull no closer than this to any true obstacle is a false part, map units (default: one voxel of "
                  "the build, its resolution)")
      ->check(CLI::NonNegativeNumber);
}

}  // namespace hullmap::cli
