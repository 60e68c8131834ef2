#include "commands.hpp"

#include "hullmap/mapper/error.hpp"

namespace hullmap::cli {

// Placeholder registration until the cluster subcommand lands; replaced by its owner.
void addClusterCommand(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand("cluster", "(pending)");
  cmd->callback([&status] { status = 2; throw Error("cluster: pending"); });
}

}  // namespace hullmap::cli
