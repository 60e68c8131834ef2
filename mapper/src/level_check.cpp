#include "hullmap/mapper/level_check.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "hullmap/mapper/floor.hpp"

namespace hullmap::mapper {

std::optional<Warning> levelWarning(const std::vector<Eigen::Vector3d>& points, double resolution,
                                    const std::string& up) {
  PlaneSearchParams params;
  params.band = resolution;
  params.max_tilt_deg = 45.0;
  params.min_inlier_share = kFloorMinShare;
  // Sparse SLAM maps hold a few percent of points under their floor (5.1% of V1_01's voxels): a
  // warning may speak on a plane a little less clean than the one the floor search accepts.
  params.max_beyond_share = 0.10;
  const PlaneFit floor = findBoundingPlane(points, PlaneSide::kFloor, params);
  if (!floor.found || floor.tilt_deg <= kFloorMaxTiltDeg) return std::nullopt;
  return Warning{
      Warning::Code::kMapLooksTilted, {{"inlier_share", floor.inlier_share}, {"tilt_deg", floor.tilt_deg}}, up};
}

bool looksLikeOrbSlam(const io::InputStats& input) {
  if (input.format == "orbslam_echo") return true;
  std::string name = std::filesystem::path(input.path).filename().string();
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (const char* word : {"mappoints", "keyframe", "orbslam", "orb_slam", "orb-slam"})
    if (name.find(word) != std::string::npos) return true;
  return false;
}

std::optional<Warning> orbSlamUpHint(const std::vector<io::InputStats>& inputs, bool up_given) {
  if (up_given) return std::nullopt;
  for (const auto& input : inputs)
    if (looksLikeOrbSlam(input)) return Warning{Warning::Code::kOrbSlamFrame, {}, input.path};
  return std::nullopt;
}

}  // namespace hullmap::mapper
