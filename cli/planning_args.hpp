#pragma once

#include <string>
#include <vector>

namespace hullmap::cli {

/// Shortest text that reads back as `value`.
std::string shortestNumber(double value);

/// `count` finite numbers separated by commas ("1,2.5,-3"); errors name `option`.
std::vector<double> parseCommaNumbers(const std::string& text, std::size_t count, const std::string& option);

/// The file `name` (obstacles.json, map.bt, ...) of a `hullmap build` directory, or `input` itself
/// when it is a file; an Error naming `input` when it or the file in it does not exist.
std::string buildArtefact(const std::string& input, const std::string& name);

/// buildArtefact(input, "obstacles.json").
std::string obstaclesFile(const std::string& input);

/// `name` inside the build directory `input`, or beside `input` when it is a file.
std::string defaultOutput(const std::string& input, const std::string& name);

}  // namespace hullmap::cli
