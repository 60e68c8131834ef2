#include "commands.hpp"

#include "hullmap/mapper/error.hpp"

namespace hullmap::cli {

// Placeholder registration until the sweep subcommand lands; replaced by its owner.
void addSweepCommand(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand("sweep", "(pending)");
  cmd->callback([&status] { status = 2; throw Error("sweep: pending"); });
}

}  // namespace hullmap::cli
