#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "hullmap/live/ros2_bag.hpp"

namespace hullmap::cli {

/// Each subcommand registers itself on `app` and, when it runs, stores its exit status in `status`
/// (0 success, 1 "found something" where a command defines it, e.g. check; errors throw).
void addBuildCommand(CLI::App& app, int& status);
void addInfoCommand(CLI::App& app, int& status);
void addGenerateCommand(CLI::App& app, int& status);
void addClusterCommand(CLI::App& app, int& status);
void addSweepCommand(CLI::App& app, int& status);
void addCheckCommand(CLI::App& app, int& status);
void addPlotCommand(CLI::App& app, int& status);
void addRoadmapCommand(CLI::App& app, int& status);
void addPlanCommand(CLI::App& app, int& status);
void addEvaluateCommand(CLI::App& app, int& status);
void addViewCommand(CLI::App& app, int& status);

/// Reads `topic` (and `trajectory_topic`) of the ROS 1 bag at `path` for `build --topic`. Set by
/// hullmap-all (main.cpp) when it was built with ROS 1's rosbag_storage, null otherwise; `hullmap`
/// runs `build` itself only without --topic and leaves it null, so that it never loads the bag reader.
using Ros1BagReader = live::BagTopics (*)(const std::string& path, const std::string& topic,
                                          const std::optional<std::string>& trajectory_topic);
extern Ros1BagReader ros1_bag_reader;

/// The names of all the subcommands above. `hullmap` (front.cpp) runs `cluster` and `build` itself
/// unless another argument is one of these names (CLI11 would read it as a second subcommand), and
/// hullmap-all (main.cpp) refuses to run when the subcommands it registers are not these.
inline constexpr const char* kCommandNames[] = {"build", "info",    "generate", "cluster",  "sweep", "check",
                                                "plot",  "roadmap", "plan",     "evaluate", "view"};

}  // namespace hullmap::cli
