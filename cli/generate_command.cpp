#include "commands.hpp"

#include "hullmap/mapper/error.hpp"

namespace hullmap::cli {

// Placeholder registration until the generate subcommand lands; replaced by its owner.
void addGenerateCommand(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand("generate", "(pending)");
  cmd->callback([&status] { status = 2; throw Error("generate: pending"); });
}

}  // namespace hullmap::cli
