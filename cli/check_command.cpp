#include "commands.hpp"

#include "hullmap/mapper/error.hpp"

namespace hullmap::cli {

// Placeholder registration until the check subcommand lands; replaced by its owner.
void addCheckCommand(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand("check", "(pending)");
  cmd->callback([&status] { status = 2; throw Error("check: pending"); });
}

}  // namespace hullmap::cli
