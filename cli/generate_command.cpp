#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/sim/sample_scene.hpp"

namespace hullmap::cli {

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
                  "tables), sparse, first camera's frame at a monocular scale, with a reference trajectory")
      ->capture_default_str();
  cmd->add_option("--seed", params->seed, "Random seed (same seed, same scene)")->capture_default_str();
  cmd->add_option("--points", params->points, "Map points, outliers included (obstacles layout)")
      ->capture_default_str();
  cmd->add_option("--obstacles", params->obstacles, "Boxes and cylinders (room layout: pieces of furniture, 0 allowed)")
      ->capture_default_str();
  cmd->add_option("--room", params->room_size, "Room side, metres")->capture_default_str();
  cmd->add_option("--noise", params->noise_sigma, "Point noise sigma, metres")->capture_default_str();
  cmd->add_option("--outliers", params->outlier_fraction, "Fraction of uniform outliers")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--gross-outliers", params->gross_outliers, "Points far away")->capture_default_str();
  cmd->add_option("--keyframes", params->keyframes, "Keyframes on the trajectory")->capture_default_str();
  cmd->add_option("--density", params->density, "Room layout: map points per m^2 of visible surface")
      ->capture_default_str();
  cmd->add_option("--edge-fraction", params->edge_fraction, "Room layout: share of points on face edges")
      ->capture_default_str();
  cmd->add_option("--scale", params->monocular_scale, "Room layout: monocular scale, map units per metre")
      ->capture_default_str();
  cmd->add_option("--pitch", params->camera_pitch_deg, "Room layout: cameras look down by this, degrees")
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
  cmd->add_flag("--z-up", *zup, "Write in the z-up map frame (metres) instead of ORB-SLAM's (y down)");
  cmd->callback([params, dir, zup, layout, placement, &status] {
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
    } else {
      throw Error("--layout: expected 'obstacles' or 'room', got '" + *layout + "'");
    }
    params->orbslam_frame = !*zup;
    const sim::Scene scene = sim::generateScene(*params);
    std::filesystem::create_directories(*dir);
    sim::writeScene(scene, *params, *dir);
    if (params->layout == sim::SceneLayout::kRoom) {
      std::cout << "wrote " << scene.points.size() << " points, " << scene.keyframes.size() << " keyframes, "
                << scene.truth.shapes.size() << " objects (floor, 4 walls, " << params->obstacles
                << " pieces of furniture) and reference_trajectory.txt to " << *dir << "\n";
    } else {
      std::cout << "wrote " << scene.points.size() << " points, " << scene.keyframes.size() << " keyframes, "
                << scene.truth.shapes.size() << " obstacles to " << *dir << "\n";
    }
    status = 0;
  });
}

}  // namespace hullmap::cli
