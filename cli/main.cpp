// hullmap-all: every subcommand. `hullmap` (front.cpp) runs `cluster` and `build` (without --topic)
// itself and hands every other command line to this program unchanged.
#include <iostream>
#include <iterator>
#include <optional>
#include <string>

#include "cli_main.hpp"
#include "commands.hpp"
#ifdef HULLMAP_HAS_ROSBAG
#include "hullmap/ros1/bag_map.hpp"
#endif

namespace {

#ifdef HULLMAP_HAS_ROSBAG
// `build --topic` on a ROS 1 bag: Debian's rosbag_storage, loaded by this program only.
hullmap::live::BagTopics readRos1Bag(const std::string& path, const std::string& topic,
                                     const std::optional<std::string>& trajectory_topic) {
  hullmap::live::BagTopics bag;
  bag.map = hullmap::ros1::readBagMap(path, topic);
  if (trajectory_topic) bag.keyframes = hullmap::ros1::readBagKeyframes(path, *trajectory_topic);
  return bag;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  using namespace hullmap::cli;
#ifdef HULLMAP_HAS_ROSBAG
  ros1_bag_reader = readRos1Bag;
#endif
  const std::vector<AddCommand> commands = {addBuildCommand, addInfoCommand,     addGenerateCommand, addClusterCommand,
                                            addSweepCommand, addCheckCommand,    addPlotCommand,     addRoadmapCommand,
                                            addPlanCommand,  addEvaluateCommand, addViewCommand};
  // front.cpp decides what it runs itself by kCommandNames: they must be the names registered here.
  CLI::App names;
  int unused = 0;
  for (const AddCommand add : commands) add(names, unused);
  const std::vector<CLI::App*> registered = names.get_subcommands({});
  bool same = registered.size() == std::size(kCommandNames);
  for (std::size_t i = 0; same && i < registered.size(); ++i) same = registered[i]->get_name() == kCommandNames[i];
  if (!same) {
    std::cerr << "hullmap: error: internal: commands.hpp's kCommandNames are not the registered subcommands\n";
    return 2;
  }
  return runCli(argc, argv, commands);
}
