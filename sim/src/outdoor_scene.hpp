#pragma once

// The steps of the kOutdoor scene (sample_outdoor.cpp: terrain, street, objects, output frame;
// outdoor_points.cpp: the points; outdoor_gps.cpp: the GPS log). Not installed.

#include <string>
#include <vector>

#include "hullmap/io/readers.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "scene_random.hpp"

namespace hullmap::sim::detail {

/// The map points of a kOutdoor scene whose truth (the ground first, then the objects) and
/// reference keyframes are made: tries on the visible surfaces kept where a keyframe sees them,
/// with noise, then outliers and gross outliers, shuffled with `rng`; into scene.map_points (z-up
/// map frame, metres). Parameters already checked.
void sampleOutdoorPoints(const SceneParams& params, core::RandomDraws& rng, Scene& scene);

/// gps.txt's lines for the reference keyframes (see generateScene's kOutdoor notes), drawn from `rng`.
std::vector<GpsFix> gpsLog(const SceneParams& params, const std::vector<io::Keyframe>& reference,
                           core::RandomDraws& rng);

/// Writes `log` to `path` atomically, `t lat lon alt` a line (stamp 6 decimals, degrees 9, metres
/// 3), `t 0 0 0` without a fix.
void writeGpsLog(const std::vector<GpsFix>& log, const std::string& path);

}  // namespace hullmap::sim::detail
