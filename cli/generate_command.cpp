#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/sim/sample_scene.hpp"

namespace hullmap::cli {
namespace {

// This command's option for a SceneParams field named by a library error ("" when the field is
// spelt as its option, "--" and dashes for underscores).
std::string generateOption(const std::string& field) {
  if (field == "monocular_scale") return "--scale";
  if (field == "camera_pitch_deg") return "--pitch";
  if (field == "outlier_fraction") return "--outliers";
  if (field == "noise_sigma") return "--noise";
  if (field == "keyframes") return "--keyframes";
  return "";
}

// kOutdoor's defaults (sim::outdoorSceneParams) for the options shared with the room layout that
// the command line left out.
void applyOutdoorDefaults(const CLI::App& cmd, sim::SceneParams& params) {
  const sim::SceneParams outdoor = sim::outdoorSceneParams();
  const auto unless = [&cmd](const char* option, auto& field, auto value) {
    if (cmd.count(option) == 0) field = value;
  };
  unless("--keyframes", params.keyframes, outdoor.keyframes);
  unless("--density", params.density, outdoor.density);
  unless("--noise", params.noise_sigma, outdoor.noise_sigma);
  unless("--pitch", params.camera_pitch_deg, outdoor.camera_pitch_deg);
  unless("--scale", params.monocular_scale, outdoor.monocular_scale);
}

void addOutdoorOptions(CLI::App& cmd, sim::SceneParams& params) {
  cmd.add_option("--track-length", params.track_length, "Outdoor layout: the area along the street (y), metres")
      ->capture_default_str();
  cmd.add_option("--track-width", params.track_width, "Outdoor layout: the area across the street (x), metres")
      ->capture_default_str();
  cmd.add_option("--slope-along", params.slope_along, "Outdoor layout: the terrain's grade along the street")
      ->capture_default_str();
  cmd.add_option("--slope-across", params.slope_across, "Outdoor layout: the terrain's grade across the street")
      ->capture_default_str();
  cmd.add_option("--bumps", params.bumps, "Outdoor layout: Gaussian bumps and dips on the terrain")
      ->capture_default_str();
  cmd.add_option("--bump-height", params.bump_height, "Outdoor layout: the largest bump's amplitude, metres")
      ->capture_default_str();
  cmd.add_option("--buildings", params.buildings, "Outdoor layout: buildings beside the street")->capture_default_str();
  cmd.add_option("--trees", params.trees, "Outdoor layout: trees on the verges")->capture_default_str();
  cmd.add_option("--cars", params.cars, "Outdoor layout: cars parked on the street's sides")->capture_default_str();
  cmd.add_option("--posts", params.posts, "Outdoor layout: posts at the kerbs")->capture_default_str();
  cmd.add_option("--scale-drift", params.scale_drift,
                 "Outdoor layout: the monocular scale grows by this share from the path's start to its end")
      ->capture_default_str();
  cmd.add_option("--gps-sigma", params.gps_sigma, "Outdoor layout: GPS noise per axis, metres")->capture_default_str();
  cmd.add_option("--gps-dropout", params.gps_dropout, "Outdoor layout: the share of GPS lines without a fix")
      ->capture_default_str();
}

}  // namespace

void addGenerateCommand(CLI::App& app, int& status) {
  auto params = std::make_shared<sim::SceneParams>();
  auto dir = std::make_shared<std::string>();
  auto zup = std::make_shared<bool>(false);
  auto* cmd =
      app.add_subcommand("generate", "Write a synthetic ORB-SLAM-like scene: map points, keyframes, ground truth");
  cmd->add_option("-o,--output", *dir, "Directory to write into")->required();
  auto layout = std::make_shared<std::string>("obstacles");
  cmd->add_option("--layout", *layout,
                  "obstacles: boxes and cylinders on an unseen floor; room: walls, floor, furniture (L-shelves, "
                  "tables), sparse, first camera's frame at a monocular scale, with a reference trajectory; "
                  "outdoor: a street on a terrain that is no plane, buildings, trees, cars, posts, at a drifting "
                  "monocular scale, with a reference trajectory and a GPS log")
      ->capture_default_str();
  cmd->add_option("--seed", params->seed, "Random seed (same seed, same scene)")->capture_default_str();
  cmd->add_option("--points", params->points, "Map points, outliers included (obstacles layout)")
      ->capture_default_str();
  cmd->add_option("--obstacles", params->obstacles, "Boxes and cylinders (room layout: pieces of furniture, 0 allowed)")
      ->capture_default_str();
  cmd->add_option("--room", params->room_size, "Room side, metres")->capture_default_str();
  cmd->add_option("--noise", params->noise_sigma, "Point noise sigma, metres (outdoor layout: 0.05)")
      ->capture_default_str();
  cmd->add_option("--outliers", params->outlier_fraction, "Fraction of uniform outliers")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--gross-outliers", params->gross_outliers, "Points far away")->capture_default_str();
  cmd->add_option("--keyframes", params->keyframes, "Keyframes on the trajectory (outdoor layout: 100)")
      ->capture_default_str();
  cmd->add_option("--density", params->density,
                  "Room and outdoor layouts: map points per m^2 of visible surface (outdoor: 3)")
      ->capture_default_str();
  cmd->add_option("--edge-fraction", params->edge_fraction, "Room and outdoor layouts: share of points on face edges")
      ->capture_default_str();
  cmd->add_option("--scale", params->monocular_scale,
                  "Room and outdoor layouts: monocular scale, map units per metre (outdoor: 0.0145, at the start)")
      ->capture_default_str();
  cmd->add_option("--pitch", params->camera_pitch_deg,
                  "Room and outdoor layouts: cameras look down by this, degrees (outdoor: 10)")
      ->capture_default_str();
  cmd->add_option("--room-width", params->room_width,
                  "Room layout: the room's side along y, metres (0: --room, a square room)")
      ->capture_default_str();
  cmd->add_option("--loop", params->loop_fraction,
                  "Room layout: the camera loop's semi-axes as a fraction of the room's sides, in (0, 0.5)")
      ->capture_default_str();
  auto placement = std::make_shared<std::string>("inside-loop");
  cmd->add_option("--placement", *placement,
                  "Room layout: inside-loop: furniture inside the camera loop; anywhere: inside or outside it, "
                  "some of it against the walls (--wall-fraction)")
      ->capture_default_str();
  cmd->add_option("--wall-fraction", params->wall_fraction,
                  "Room layout, --placement anywhere: the share of the furniture placed against a wall, in [0, 1]")
      ->capture_default_str();
  addOutdoorOptions(*cmd, *params);
  cmd->add_flag("--z-up", *zup, "Write in the z-up map frame (metres) instead of ORB-SLAM's (y down)");
  cmd->callback([cmd, params, dir, zup, layout, placement, &status] {
    if (*placement == "inside-loop") {
      params->placement = sim::FurniturePlacement::kInsideLoop;
    } else if (*placement == "anywhere") {
      params->placement = sim::FurniturePlacement::kAnywhere;
    } else {
      throw Error("--placement: expected 'inside-loop' or 'anywhere', got '" + *placement + "'");
    }
    if (*layout == "obstacles") {
      params->layout = sim::SceneLayout::kObstacles;
    } else if (*layout == "room") {
      params->layout = sim::SceneLayout::kRoom;
    } else if (*layout == "outdoor") {
      params->layout = sim::SceneLayout::kOutdoor;
      applyOutdoorDefaults(*cmd, *params);
    } else {
      throw Error("--layout: expected 'obstacles', 'room' or 'outdoor', got '" + *layout + "'");
    }
    params->orbslam_frame = !*zup;
    sim::Scene scene;
    try {
      scene = sim::generateScene(*params);
    } catch (const Error& e) {
      const std::string option = generateOption(e.parameter());
      if (option.empty()) throw;
      throw Error(option + ": " + e.detail());
    }
    std::filesystem::create_directories(*dir);
    sim::writeScene(scene, *params, *dir);
    if (params->layout == sim::SceneLayout::kRoom) {
      std::cout << "wrote " << scene.points.size() << " points, " << scene.keyframes.size() << " keyframes, "
                << scene.truth.shapes.size() << " objects (floor, 4 walls, " << params->obstacles
                << " pieces of furniture) and reference_trajectory.txt to " << *dir << "\n";
    } else if (params->layout == sim::SceneLayout::kOutdoor) {
      std::cout << "wrote " << scene.points.size() << " points, " << scene.keyframes.size() << " keyframes, "
                << scene.truth.shapes.size() << " objects (ground, " << params->buildings << " buildings, "
                << params->trees << " trees, " << params->cars << " cars, " << params->posts
                << " posts), reference_trajectory.txt and gps.txt to " << *dir << "\n";
    } else {
      std::cout << "wrote " << scene.points.size() << " points, " << scene.keyframes.size() << " keyframes, "
                << scene.truth.shapes.size() << " obstacles to " << *dir << "\n";
    }
    status = 0;
  });
}

}  // namespace hullmap::cli
