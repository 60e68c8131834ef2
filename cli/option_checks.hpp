#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace hullmap::cli {

/// Validators for numeric options whose errors say what is wrong in the option's own terms. CLI11
/// prefixes the option's name: "--resolution: must be > 0, got 0" (CLI11's own range check printed
/// "Value 0 not in range 0.000000 to 1797693..." with a 309-digit bound). A value with a unit,
/// "5cm", is named as such: hullmap takes map units and no unit names.

/// A finite number > low (or >= low when `inclusive`).
CLI::Validator numberAbove(double low, bool inclusive = false);
/// A finite number in [low, high].
CLI::Validator numberIn(double low, double high);
/// Any finite number.
CLI::Validator finiteNumber();
/// A whole number >= low.
CLI::Validator wholeNumberFrom(long low);

/// One of `words` (e.g. "auto", "none"), or a value `inner` accepts; inner's message for a bad
/// number ("must be > 0, got -1"), "expected auto, none or a number, got 'x'" for anything else.
CLI::Validator wordOr(const std::vector<std::string>& words, CLI::Validator inner);

/// An existing file, or "-" for standard input.
CLI::Validator existingFileOrStdin();

/// The path to read for an input argument: "-" is /dev/stdin.
std::string inputPath(const std::string& argument);

/// `inputs` with "-" replaced by /dev/stdin; throws hullmap::Error when "-" is given twice.
std::vector<std::string> inputPaths(const std::vector<std::string>& inputs);

}  // namespace hullmap::cli
