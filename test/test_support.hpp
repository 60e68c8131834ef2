#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "hullmap/mapper/error.hpp"

namespace hullmap::test {

/// Path of a file in shared/data/real, or empty when the data is not there.
inline std::string realData(const std::string& name) {
  const std::filesystem::path p = std::filesystem::path(HULLMAP_REAL_DATA_DIR) / name;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

/// A fresh empty directory for one test, below the build tree. It is named after the running test
/// too: CTest runs tests in parallel processes, and two tests asking for the same `name` must not
/// share (and wipe) one directory.
inline std::filesystem::path freshDir(const std::string& name) {
  std::string owner = "outside_tests";
  if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info())
    owner = std::string(info->test_suite_name()) + "." + info->name();
  const auto dir = std::filesystem::path(HULLMAP_TEST_TMP) / owner / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Skips the current test, saying which real-data file is missing.
#define HULLMAP_REQUIRE_REAL_DATA(var, name)                                            \
  const std::string var = ::hullmap::test::realData(name);                               \
  if (var.empty()) {                                                                     \
    GTEST_SKIP() << "real data " << name << " not found in " << HULLMAP_REAL_DATA_DIR    \
                 << " (shared/data/real beside the checkout)";                           \
  }

}  // namespace hullmap::test

#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace hullmap::test {

struct CommandResult {
  int status = -1;     ///< exit status, or -1 when killed by a signal
  std::string out;
  std::string err;
};

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Runs the hullmap binary with `args` (already shell-quoted where needed), capturing both streams.
inline CommandResult runHullmap(const std::string& args) {
  static int counter = 0;
  const auto dir = std::filesystem::path(HULLMAP_TEST_TMP) / "cmd";
  std::filesystem::create_directories(dir);
  const std::string stem = (dir / ("run" + std::to_string(::getpid()) + "_" + std::to_string(counter++))).string();
  const std::string command = std::string("'") + HULLMAP_BINARY + "' " + args + " >" + stem + ".out 2>" +
                              stem + ".err </dev/null";
  const int raw = std::system(command.c_str());
  CommandResult r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = slurp(stem + ".out");
  r.err = slurp(stem + ".err");
  return r;
}

/// Runs `body` and returns the hullmap::Error message it throws (fails the test if none).
template <typename F>
std::string errorOf(F&& body) {
  try {
    body();
  } catch (const ::hullmap::Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected hullmap::Error";
  return "";
}

/// Number of lines in `text` (a final line without newline counts).
inline int lineCount(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n';
  if (!text.empty() && text.back() != '\n') ++n;
  return n;
}

}  // namespace hullmap::test
