#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/mapper/sample_scene.hpp"

namespace hullmap::cli {

void addGenerateCommand(CLI::App& app, int& status) {
  auto params = std::make_shared<mapper::SceneParams>();
  auto dir = std::make_shared<std::string>();
  auto zup = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand(
      "generate", "Write a synthetic ORB-SLAM-like scene: map points, keyframes, ground truth");
  cmd->add_option("-o,--output", *dir, "Directory to write into")->required();
  cmd->add_option("--seed", params->seed, "Random seed (same seed, same scene)")->capture_default_str();
  cmd->add_option("--points", params->points, "Map points, outliers included")->capture_default_str();
  cmd->add_option("--obstacles", params->obstacles, "Boxes and cylinders")->capture_default_str();
  cmd->add_option("--room", params->room_size, "Room side, metres")->capture_default_str();
  cmd->add_option("--noise", params->noise_sigma, "Point noise sigma, metres")->capture_default_str();
  cmd->add_option("--outliers", params->outlier_fraction, "Fraction of uniform outliers")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  cmd->add_option("--gross-outliers", params->gross_outliers, "Points far away")->capture_default_str();
  cmd->add_option("--keyframes", params->keyframes, "Keyframes on the trajectory")->capture_default_str();
  cmd->add_flag("--z-up", *zup, "Write in the z-up map frame instead of ORB-SLAM's (y down)");
  cmd->callback([params, dir, zup, &status] {
    params->orbslam_frame = !*zup;
    std::filesystem::create_directories(*dir);
    const mapper::Scene scene = mapper::generateScene(*params);
    mapper::writeScene(scene, *params, *dir);
    std::cout << "wrote " << scene.points.size() << " points, " << scene.keyframes.size()
              << " keyframes, " << scene.obstacles.size() << " obstacles to " << *dir << "\n";
    status = 0;
  });
}

}  // namespace hullmap::cli
