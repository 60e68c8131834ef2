#include "commands.hpp"

#include "hullmap/mapper/error.hpp"

namespace hullmap::cli {

// Placeholder registration until the build subcommand lands; replaced by its owner.
void addBuildCommand(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand("build", "(pending)");
  cmd->callback([&status] { status = 2; throw Error("build: pending"); });
}

}  // namespace hullmap::cli
