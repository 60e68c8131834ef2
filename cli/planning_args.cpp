#include "planning_args.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>

#include "hullmap/core/error.hpp"

namespace hullmap::cli {

std::string shortestNumber(double value) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

std::vector<double> parseCommaNumbers(const std::string& text, std::size_t count, const std::string& option) {
  std::vector<double> values;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    const char* first = text.data() + begin;
    const char* last = text.data() + end;
    while (first < last && *first == ' ') ++first;
    double v = 0;
    const auto r = std::from_chars(first, last, v);
    if (r.ec != std::errc() || r.ptr != last || first == last)
      throw Error(option + ": not a number: \"" + std::string(first, last) + "\" (expected " + std::to_string(count) +
                  " comma-separated numbers)");
    if (!std::isfinite(v)) throw Error(option + ": non-finite number");
    values.push_back(v);
    begin = end + 1;
  }
  if (values.size() != count)
    throw Error(option + ": expected " + std::to_string(count) + " comma-separated numbers, got " +
                std::to_string(values.size()));
  return values;
}

std::string buildArtefact(const std::string& input, const std::string& name) {
  namespace fs = std::filesystem;
  if (fs::is_directory(input)) {
    const fs::path p = fs::path(input) / name;
    if (!fs::exists(p)) throw Error(input + ": no " + name + " in this directory (is it a `hullmap build` output?)");
    return p.string();
  }
  if (!fs::exists(input)) throw Error(input + ": no such file or directory");
  return input;
}

std::string obstaclesFile(const std::string& input) { return buildArtefact(input, "obstacles.json"); }

std::string defaultOutput(const std::string& input, const std::string& name) {
  namespace fs = std::filesystem;
  if (fs::is_directory(input)) return (fs::path(input) / name).string();
  return (fs::path(input).parent_path() / name).string();
}

}  // namespace hullmap::cli
