#include "option_checks.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "hullmap/core/error.hpp"

namespace hullmap::cli {
namespace {

/// "" when `text` is one finite number (stored in `value`), else why not.
std::string parseFinite(const std::string& text, double& value) {
  const char* begin = text.data();
  const char* end = begin + text.size();
  if (begin != end && *begin == '+') ++begin;
  const auto r = std::from_chars(begin, end, value);
  if (r.ec == std::errc() && r.ptr == end) {
    if (!std::isfinite(value)) return "must be a finite number, got " + text;
    return "";
  }
  if (r.ec == std::errc() && r.ptr != begin && std::isalpha(static_cast<unsigned char>(*r.ptr))) {
    return "expected a number, got '" + text + "': hullmap takes no unit names; give map units (e.g. 0.05 " +
           "for 5 cm in a map in metres)";
  }
  if (r.ec == std::errc::result_out_of_range) return "must be a finite number, got " + text;
  return "expected a number, got '" + text + "'";
}

std::string shortest(double v) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
}

}  // namespace

CLI::Validator numberAbove(double low, bool inclusive) {
  return CLI::Validator(
      [low, inclusive](std::string& text) -> std::string {
        double v = 0;
        const std::string bad = parseFinite(text, v);
        if (!bad.empty()) return bad;
        if (inclusive ? v >= low : v > low) return "";
        return std::string("must be ") + (inclusive ? ">= " : "> ") + shortest(low) + ", got " + text;
      },
      low == 0.0 ? std::string(inclusive ? "NONNEGATIVE" : "POSITIVE") : (inclusive ? ">= " : "> ") + shortest(low));
}

CLI::Validator numberIn(double low, double high) {
  return CLI::Validator(
      [low, high](std::string& text) -> std::string {
        double v = 0;
        const std::string bad = parseFinite(text, v);
        if (!bad.empty()) return bad;
        if (v >= low && v <= high) return "";
        return "must be in [" + shortest(low) + ", " + shortest(high) + "], got " + text;
      },
      "[" + shortest(low) + ", " + shortest(high) + "]");
}

CLI::Validator finiteNumber() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        return parseFinite(text, v);
      },
      "FINITE");
}

CLI::Validator wholeNumberFrom(long low) {
  return CLI::Validator(
      [low](std::string& text) -> std::string {
        long v = 0;
        const char* begin = text.data();
        const char* end = begin + text.size();
        if (begin != end && *begin == '+') ++begin;
        const auto r = std::from_chars(begin, end, v);
        if (r.ec != std::errc() || r.ptr != end) return "expected a whole number, got '" + text + "'";
        if (v < low) return "must be >= " + std::to_string(low) + ", got " + text;
        return "";
      },
      ">= " + std::to_string(low));
}

CLI::Validator wordOr(const std::vector<std::string>& words, CLI::Validator inner) {
  std::string names;
  for (const auto& w : words) names += (names.empty() ? "" : ", ") + w;
  std::string description;
  for (const auto& w : words) description += w + "|";
  return CLI::Validator(
      [words, names, inner](std::string& text) -> std::string {
        for (const auto& w : words)
          if (text == w) return "";
        std::string copy = text;
        const std::string bad = inner(copy);
        // A number's own complaint stays as it is; a word that is none of them is named with them.
        if (bad.empty() || bad.rfind("expected a number", 0) != 0) return bad;
        return "expected " + names + " or a number, got '" + text + "'";
      },
      description + "NUMBER");
}

CLI::Validator existingFileOrStdin() {
  return CLI::Validator([](std::string& text) -> std::string { return text == "-" ? "" : CLI::ExistingFile(text); },
                        "FILE or -");
}

std::string inputPath(const std::string& argument) { return argument == "-" ? "/dev/stdin" : argument; }

std::vector<std::string> inputPaths(const std::vector<std::string>& inputs) {
  std::vector<std::string> paths;
  bool stdin_used = false;
  for (const auto& input : inputs) {
    if (input == "-") {
      if (stdin_used) throw Error("-: standard input can be given once");
      stdin_used = true;
    }
    paths.push_back(inputPath(input));
  }
  return paths;
}

}  // namespace hullmap::cli
