#pragma once

#include <vector>

#include <CLI/CLI.hpp>

namespace hullmap::cli {

/// Registers one subcommand on the app (commands.hpp's addBuildCommand, ...).
using AddCommand = void (*)(CLI::App& app, int& status);

/// Everything `hullmap` does with its command line: the app with `commands`, parsing, running the
/// chosen one, and the one-line errors (`hullmap: error: ...`, exit 2). Returns the exit status.
int runCli(int argc, char** argv, const std::vector<AddCommand>& commands);

}  // namespace hullmap::cli
