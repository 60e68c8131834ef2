// hullmap::Warning: every code in words, its parameters named only through the front end's spelling.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "hullmap/core/warning.hpp"

namespace {

using hullmap::Warning;
using hullmap::warningText;

/// One warning of each code, with the numbers it uses.
std::vector<Warning> everyCode() {
  return {
      {Warning::Code::kEpsBelowResolution, {{"eps", 0.04}, {"resolution", 0.05}}, ""},
      {Warning::Code::kEpsBelowResolutionInColumns, {{"eps", 0.04}, {"resolution", 0.05}}, ""},
      {Warning::Code::kNoObstacle, {{"occupied_voxels", 100}, {"eps", 0.1}, {"min_pts", 10}}, ""},
      {Warning::Code::kMostlyNoise, {{"noise_voxels", 51}, {"occupied_voxels", 100}}, ""},
      {Warning::Code::kKeptFloorTilted, {{"inlier_share", 0.42}, {"tilt_deg", 4.26}}, ""},
      {Warning::Code::kMapLooksTilted, {{"inlier_share", 0.3}, {"tilt_deg", 21.0}}, "-y"},
      {Warning::Code::kOrbSlamFrame, {}, "MapPoints.txt"},
      {Warning::Code::kCheckNoObstacle, {{"occupied_voxels", 7}}, ""},
      {Warning::Code::kCheckMostlyNoise, {{"noise_voxels", 60}, {"occupied_voxels", 100}}, ""},
      {Warning::Code::kSparseForResolution, {{"resolution", 0.05}, {"spacing", 0.86}, {"suggested", 0.5}}, ""},
  };
}

}  // namespace

TEST(Warning, EveryCodeNamesItsParametersThroughTheSpelling) {
  std::set<std::string> names;
  for (const Warning& w : everyCode()) {
    std::set<std::string> fields;
    const auto marked = [&](std::string_view field, std::string_view value) {
      fields.insert(std::string(field));
      return "<" + std::string(field) + (value.empty() ? "" : "|" + std::string(value)) + ">";
    };
    const std::string text = warningText(w, marked);
    EXPECT_EQ(text.find("--"), std::string::npos) << "no command-line flag of its own: " << text;
    EXPECT_EQ(text.find('\n'), std::string::npos) << "one line: " << text;
    EXPECT_FALSE(fields.empty()) << "a remedy names a parameter: " << text;
    EXPECT_TRUE(names.insert(hullmap::warningName(w.code)).second) << "names are unique";
  }
  EXPECT_EQ(names.size(), everyCode().size());
}

TEST(Warning, NumbersAndSubjectsReachTheText) {
  const auto all = everyCode();
  EXPECT_EQ(warningText(all[0]).rfind("eps=0.04 is below the octree resolution 0.05", 0), 0u);
  EXPECT_NE(warningText(all[4]).find("(42% of the points) is 4.3 degrees from level"), std::string::npos)
      << warningText(all[4]);
  EXPECT_NE(warningText(all[4]).find("; level=on levels it"), std::string::npos);
  EXPECT_NE(warningText(all[5]).find("is 21.0 degrees from level after up=-y:"), std::string::npos);
  EXPECT_EQ(warningText(all[6]).rfind("MapPoints.txt looks like ORB-SLAM output", 0), 0u);
  EXPECT_NE(warningText(all[7]).find("although 7 voxels are occupied"), std::string::npos);
  EXPECT_EQ(warningText(all[9]).rfind("the map's points lie about 0.86 apart (17 voxels at resolution=0.05;", 0), 0u)
      << warningText(all[9]);
  EXPECT_NE(warningText(all[9]).find("; try resolution=0.5"), std::string::npos);
  const Warning unknown{Warning::Code::kCheckNoObstacle, {}, ""};
  EXPECT_EQ(warningText(unknown).rfind("the build has no obstacle: every path", 0), 0u) << "0 voxels: unknown";
  EXPECT_EQ(all[3].number("noise_voxels"), 51.0);
  EXPECT_EQ(all[3].number("absent"), 0.0);
  EXPECT_EQ(hullmap::fieldSpelling("min_pts", ""), "min_pts");
  EXPECT_EQ(hullmap::fieldSpelling("min_pts", "5"), "min_pts=5");
}
