#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hullmap/clustering/obstacles.hpp"

namespace hullmap::pipeline {

/// Version tag written in, and required of, every obstacles.json.
inline constexpr const char* kObstaclesFormat = "hullmap-obstacles/1";

/// What an obstacles.json says about how its obstacles were made.
struct ObstaclesMeta {
  std::string frame = "z-up map";                        ///< e.g. "z-up map, up=-y of input"
  nlohmann::json parameters = nlohmann::json::object();  ///< the build's settings, verbatim
};

/// Writes `obstacles.json` atomically: format, frame, parameters, then per obstacle id, voxel_count,
/// point_weight, aabb {min,max}, centroid, volume, hull {vertices, triangles}, footprint {polygon,
/// z_min, z_max}. Coordinates in the z-up map frame, map units. Throws hullmap::Error naming `path`.
void writeObstaclesJson(const std::string& path, const std::vector<clustering::Obstacle>& obstacles,
                        const ObstaclesMeta& meta);

/// Reads an obstacles.json written by writeObstaclesJson. Validates the format tag and every field
/// (types, array sizes, triangle indices in range); throws hullmap::Error "<path>: <what>" otherwise.
std::vector<clustering::Obstacle> readObstaclesJson(const std::string& path, ObstaclesMeta* meta = nullptr);

/// Writes the hulls as Wavefront OBJ, one object `o obstacle_<id>` per obstacle, `v` lines then `f`
/// lines with 1-based global indices; opens in MeshLab, CloudCompare, Blender and Open3D. Atomic.
void writeObstaclesObj(const std::string& path, const std::vector<clustering::Obstacle>& obstacles);

}  // namespace hullmap::pipeline
