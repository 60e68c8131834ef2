#include "commands.hpp"

#include "hullmap/mapper/error.hpp"

namespace hullmap::cli {

// Placeholder registration until the plot subcommand lands; replaced by its owner.
void addPlotCommand(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand("plot", "(pending)");
  cmd->callback([&status] { status = 2; throw Error("plot: pending"); });
}

}  // namespace hullmap::cli
