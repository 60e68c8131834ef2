#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

namespace hullmap::cli {

/// Registers one subcommand on the app (commands.hpp's addBuildCommand, ...).
using AddCommand = void (*)(CLI::App& app, int& status);

/// The flag that sets a library parameter (a params struct's field): "min_pts" -> "--min-pts",
/// "keyframes" -> "--trajectory", planning's "start"/"goal" -> "--from"/"--to".
std::string optionName(std::string_view field);

/// optionName with a value: "--against octree". The CLI's hullmap::ParameterSpelling, for the
/// warnings it prints and report.json.
std::string optionSpelling(std::string_view field, std::string_view value);

/// Everything `hullmap` does with its command line: the app with `commands`, parsing, running the
/// chosen one, and the one-line errors (`hullmap: error: ...`, exit 2). Returns the exit status.
int runCli(int argc, char** argv, const std::vector<AddCommand>& commands);

}  // namespace hullmap::cli
