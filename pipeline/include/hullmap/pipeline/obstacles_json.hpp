#pragma once

#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hullmap/clustering/obstacles.hpp"

namespace hullmap::pipeline {

/// Format tags of obstacles.json: /2 is written, /1 and /2 are read (docs/FORMATS_OBSTACLES.md).
inline constexpr const char* kObstaclesFormatV1 = "hullmap-obstacles/1";
inline constexpr const char* kObstaclesFormatV2 = "hullmap-obstacles/2";

/// What an obstacles.json says about how its obstacles were made.
struct ObstaclesDocMeta {
  std::string format = kObstaclesFormatV2;               ///< the tag read (writing always uses /2)
  std::string frame = "z-up map";                        ///< e.g. "z-up map, up=-y of input"
  nlohmann::json parameters = nlohmann::json::object();  ///< the build's settings, verbatim
};

/// The obstacles.json document, format /2: /1's fields per obstacle (describing the whole cluster)
/// plus "parts", one object per convex part: voxel_count, point_weight, aabb {min,max}, centroid,
/// volume, hull {vertices, triangles}, footprint {polygon, z_min, z_max}, concavity_bound,
/// free_voxels_inside. Coordinates in the z-up map frame, map units.
nlohmann::json obstaclesToJson(const std::vector<clustering::Obstacle>& obstacles, const ObstaclesDocMeta& meta);

/// Reads a /1 or /2 document (a /1 obstacle has no parts). Validates the tag and every field (types,
/// array sizes, triangle indices in range); throws hullmap::Error "<source>: <json path>: <what>".
std::vector<clustering::Obstacle> obstaclesFromJson(const nlohmann::json& doc, const std::string& source,
                                                    ObstaclesDocMeta* meta = nullptr);

/// Parses the file and calls obstaclesFromJson; throws hullmap::Error naming `path` when it cannot be
/// opened or is not JSON.
std::vector<clustering::Obstacle> readObstaclesFile(const std::string& path, ObstaclesDocMeta* meta = nullptr);

/// Wavefront OBJ of the hulls: one object per part, `o obstacle_<id>_part_<k>` (k from 0), or
/// `o obstacle_<id>` for an obstacle without parts; `v` then `f` lines, 1-based global indices.
void writeObstaclesObj(std::ostream& out, const std::vector<clustering::Obstacle>& obstacles);

}  // namespace hullmap::pipeline
