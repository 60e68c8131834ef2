#pragma once

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "hullmap/core/error.hpp"

namespace hullmap::test {

/// The voxel edge (m) of the generated test scenes that do not say otherwise.
inline constexpr double kVoxel = 0.05;

/// A point of three draws made one statement at a time, z first: the order gcc evaluates the
/// arguments of V3(draw(), draw(), draw()) in, which the tests' data was made with. The arguments of
/// one call are not sequenced (clang draws x first), so this gives the same data with any compiler.
template <class Draw>
Eigen::Vector3d drawPoint(Draw&& draw) {
  const double z = draw();
  const double y = draw();
  const double x = draw();
  return {x, y, z};
}

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
#define HULLMAP_REQUIRE_REAL_DATA(var, name)                                          \
  const std::string var = ::hullmap::test::realData(name);                            \
  if (var.empty()) {                                                                  \
    GTEST_SKIP() << "real data " << name << " not found in " << HULLMAP_REAL_DATA_DIR \
                 << " (shared/data/real beside the checkout)";                        \
  }

/// Writes `text` into `path` (a test's input file).
inline void writeText(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

/// Every byte of a file (empty when it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A JSON file hullmap wrote (report.json, obstacles.json...).
inline nlohmann::json readJson(const std::filesystem::path& path) { return nlohmann::json::parse(slurp(path)); }

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
