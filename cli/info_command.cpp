#include "commands.hpp"

#include "hullmap/mapper/error.hpp"

namespace hullmap::cli {

// Placeholder registration until the info subcommand lands; replaced by its owner.
void addInfoCommand(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand("info", "(pending)");
  cmd->callback([&status] { status = 2; throw Error("info: pending"); });
}

}  // namespace hullmap::cli
