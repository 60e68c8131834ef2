// hullmap-all: every subcommand. `hullmap` (front.cpp) runs the light ones itself and hands every
// other command line to this program unchanged.
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <iterator>

#include "cli_main.hpp"
#include "commands.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace {

// Test-only (test/e2e/build.cpp): HULLMAP_TEST_KILL_AT=<stage> makes the run SIGKILL itself when
// the pipeline reaches that stage, so that "a run killed there" is a fact, not a race with a timer.
const char* kill_at = nullptr;

void killAtStage(const char* stage) {
  if (std::strcmp(stage, kill_at) == 0) std::raise(SIGKILL);
}

}  // namespace

int main(int argc, char** argv) {
  kill_at = std::getenv("HULLMAP_TEST_KILL_AT");
  if (kill_at != nullptr) hullmap::pipeline::detail::stage_hook = killAtStage;
  using namespace hullmap::cli;
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
