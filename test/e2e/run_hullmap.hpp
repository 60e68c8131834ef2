#pragma once

// The end-to-end tests' way to run the hullmap command (HULLMAP_BINARY): only test/e2e/ includes it.

#include <sys/wait.h>
#include <unistd.h>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace hullmap::test {

struct CommandResult {
  int status = -1;  ///< exit status, or -1 when killed by a signal
  std::string out;
  std::string err;
};

/// The lines of the first fenced block after the line holding `marker`.
inline std::vector<std::string> fencedBlockAfter(const std::string& text, const std::string& marker) {
  std::istringstream in(text);
  std::string line;
  bool seen = false;
  bool inside = false;
  std::vector<std::string> lines;
  while (std::getline(in, line)) {
    if (!seen) {
      seen = line.find(marker) != std::string::npos;
    } else if (!inside) {
      inside = line.rfind("```", 0) == 0;
    } else {
      if (line.rfind("```", 0) == 0) return lines;
      lines.push_back(line);
    }
  }
  return {};
}

/// `p` in single quotes, for a shell command line.
inline std::string quoted(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

/// Runs `command` (a shell command line without output redirections), capturing both streams.
inline CommandResult runShell(const std::string& command) {
  static int counter = 0;
  const auto dir = std::filesystem::path(HULLMAP_TEST_TMP) / "cmd";
  std::filesystem::create_directories(dir);
  const std::string stem = (dir / ("run" + std::to_string(::getpid()) + "_" + std::to_string(counter++))).string();
  const std::string line = command + " >" + stem + ".out 2>" + stem + ".err";
  const int raw = std::system(line.c_str());
  CommandResult r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = slurp(stem + ".out");
  r.err = slurp(stem + ".err");
  return r;
}

/// Runs the hullmap binary with `args` (already shell-quoted where needed), capturing both streams.
inline CommandResult runHullmap(const std::string& args) {
  return runShell(std::string("'") + HULLMAP_BINARY + "' " + args + " </dev/null");
}

/// Runs the hullmap binary with `args` from the working directory `cwd`, standard input from `input`.
inline CommandResult runHullmapIn(const std::filesystem::path& cwd, const std::string& args,
                                  const std::string& input = "/dev/null") {
  return runShell("cd '" + cwd.string() + "' && '" + std::string(HULLMAP_BINARY) + "' " + args + " <'" + input + "'");
}

/// A run that failed as bad input does: exit 2, one line on stderr, "hullmap: error: ", holding `needle`.
inline void expectOneLineError(const CommandResult& r, const std::string& needle) {
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("hullmap: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << "expected '" << needle << "' in: " << r.err;
}

}  // namespace hullmap::test
