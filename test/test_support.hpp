#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace hullmap::test {

/// Path of a file in shared/data/real, or empty when the data is not there.
inline std::string realData(const std::string& name) {
  const std::filesystem::path p = std::filesystem::path(HULLMAP_REAL_DATA_DIR) / name;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

/// A fresh empty directory for one test, below the build tree.
inline std::filesystem::path freshDir(const std::string& name) {
  const auto dir = std::filesystem::path(HULLMAP_TEST_TMP) / name;
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
