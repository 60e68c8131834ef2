#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "hullmap/mapper/occupancy_map.hpp"

namespace hullmap::cli {
namespace {

// "x y z" with single spaces: Eigen's stream operator pads each column to the widest of the three.
std::string spaced(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << v.x() << ' ' << v.y() << ' ' << v.z();
  return out.str();
}

}  // namespace

void addInfoCommand(CLI::App& app, int& status) {
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("info", "Describe an octomap file: resolution, bounds, leaf counts, memory");
  cmd->add_option("map", *path, "A .bt or .ot file")->required()->check(CLI::ExistingFile);
  cmd->add_flag("--json", *json, "Print one JSON object");
  cmd->callback([path, json, &status] {
    const mapper::OccupancyMap map = mapper::readMap(*path);
    const mapper::MapInfo info = mapper::describe(map.tree());
    if (*json) {
      nlohmann::json j = {{"path", *path},
                          {"resolution", info.resolution},
                          {"min", {info.min.x(), info.min.y(), info.min.z()}},
                          {"max", {info.max.x(), info.max.y(), info.max.z()}},
                          {"occupied_leaves", info.occupied_leaves},
                          {"free_leaves", info.free_leaves},
                          {"nodes", info.nodes},
                          {"memory_bytes", info.memory_bytes}};
      std::cout << j.dump() << '\n';
    } else {
      std::cout << *path << "\n  resolution:      " << info.resolution << "\n  bounds min:      " << spaced(info.min)
                << "\n  bounds max:      " << spaced(info.max) << "\n  occupied leaves: " << info.occupied_leaves
                << "\n  free leaves:     " << info.free_leaves << "\n  nodes:           " << info.nodes
                << "\n  memory:          " << info.memory_bytes << " bytes\n";
    }
    status = 0;
  });
}

}  // namespace hullmap::cli
