#pragma once

#include <CLI/CLI.hpp>

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

/// The names of all the subcommands above. `hullmap` (front.cpp) runs `cluster` itself unless
/// another argument is one of these names (CLI11 would read it as a second subcommand), and
/// hullmap-all (main.cpp) refuses to run when the subcommands it registers are not these.
inline constexpr const char* kCommandNames[] = {"build", "info",    "generate", "cluster",  "sweep", "check",
                                                "plot",  "roadmap", "plan",     "evaluate", "view"};

}  // namespace hullmap::cli
