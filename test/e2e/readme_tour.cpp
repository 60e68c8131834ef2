// The README's tour runs as written: its command block (after the `<!-- tour-cli` marker) is
// extracted and run from a directory that holds the checkout's maps/ and docs/ under those names,
// and what the README says of the run is checked.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_hullmap.hpp"

namespace fs = std::filesystem;

TEST(ReadmeTour, RunsAsWritten) {
  const std::string readme = hullmap::test::slurp(fs::path(HULLMAP_SOURCE_DIR) / "README.md");
  const auto commands = hullmap::test::fencedBlockAfter(readme, "<!-- tour-cli");
  ASSERT_EQ(commands.size(), 3u) << "the README's tour is three commands";
  const auto dir = hullmap::test::freshDir("readme_tour");
  fs::create_directory_symlink(fs::path(HULLMAP_SOURCE_DIR) / "maps", dir / "maps");
  fs::create_directory_symlink(fs::path(HULLMAP_SOURCE_DIR) / "docs", dir / "docs");
  std::vector<hullmap::test::CommandResult> runs;
  for (const auto& command : commands) {
    SCOPED_TRACE(command);
    ASSERT_EQ(command.rfind("hullmap ", 0), 0u) << "each line is one hullmap command";
    runs.push_back(hullmap::test::runHullmapIn(dir, command.substr(8)));
  }
  EXPECT_EQ(runs[0].status, 0) << runs[0].err;
  const auto report = nlohmann::json::parse(hullmap::test::slurp(dir / "out/simple8/report.json"));
  EXPECT_EQ(report["obstacles"], 8);
  EXPECT_EQ(report["parts"]["count"], 8);
  EXPECT_EQ(runs[1].status, 1) << "the path collides: " << runs[1].err;
  EXPECT_NE(runs[1].out.find("segment 1: COLLIDES with obstacle 2 part 0 at t=0.1976"), std::string::npos)
      << runs[1].out;
  EXPECT_EQ(runs[2].status, 0) << runs[2].err;
  EXPECT_TRUE(fs::exists(dir / "out/simple8.html"));
}
