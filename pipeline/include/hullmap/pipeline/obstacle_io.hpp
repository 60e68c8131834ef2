#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/mapper/align.hpp"

namespace hullmap::pipeline {

/// Format tags of obstacles.json: /2 (obstacles with their convex parts) is written; /1 (whole
/// obstacles only) and /2 are read. docs/FORMATS.md describes both.
inline constexpr const char* kObstaclesFormatV1 = "hullmap-obstacles/1";
inline constexpr const char* kObstaclesFormatV2 = "hullmap-obstacles/2";

/// What an obstacles.json says about how its obstacles were made. Set the fields by name (the
/// first is the format tag).
struct ObstaclesMeta {
  std::string format = kObstaclesFormatV2;               ///< the tag read (writing always uses /2)
  std::string frame = "z-up map";                        ///< e.g. "z-up map, up=-y of input"
  nlohmann::json parameters = nlohmann::json::object();  ///< the build's settings, verbatim
  /// The floor and ceiling as solid half-spaces (top-level "surfaces"; absent in files written before
  /// them: none). Path checks count them as obstacles.
  std::vector<collision::Surface> surfaces;
  /// Input coordinates -> these coordinates (top-level "input_to_output"; absent in files written
  /// before it: unknown).
  std::optional<mapper::Similarity> input_to_output;
  /// Whether input_to_output is the whole change ("exact"; absent in older files: true). False when
  /// `--align` undid scale drift: each point moved by its own part of the path's similarities.
  bool input_to_output_exact = true;
};

/// {"scale", "rotation" (3 rows), "translation", "matrix" (the 4 x 4 homogeneous matrix, 4 rows),
/// "exact"}: how report.json and obstacles.json write a similarity (input_to_output).
nlohmann::json similarityJson(const mapper::Similarity& s, bool exact = true);

/// Reads similarityJson's object (scale, rotation and translation; matrix is not read); throws
/// hullmap::Error "<source>: <where>: <what>" when a field is missing or malformed, the scale not
/// > 0, or the rotation not a proper rotation (within 1e-6).
mapper::Similarity similarityFromJson(const nlohmann::json& j, const std::string& source, const std::string& where);

/// The obstacles.json document, format /2: format, frame, parameters, surfaces, input_to_output
/// (when known), then per obstacle id,
/// voxel_count, point_weight, aabb {min,max}, centroid, volume, hull {vertices, triangles}, footprint
/// {polygon, z_min, z_max} (the whole cluster) and "parts", one object per convex part with the same
/// fields plus concavity_bound and free_voxels_inside (empty when the obstacle was not split).
/// Coordinates in the z-up map frame, map units.
nlohmann::json obstaclesToJson(const std::vector<hulls::Obstacle>& obstacles, const ObstaclesMeta& meta);

/// Reads a /1 or /2 document (a /1 obstacle has no parts). Validates the tag and every field (types,
/// array sizes, triangle indices in range); throws hullmap::Error "<source>: <json path>: <what>".
std::vector<hulls::Obstacle> obstaclesFromJson(const nlohmann::json& doc, const std::string& source,
                                               ObstaclesMeta* meta = nullptr);

/// Writes obstaclesToJson's document to `path` atomically. Throws hullmap::Error naming `path`.
void writeObstaclesJson(const std::string& path, const std::vector<hulls::Obstacle>& obstacles,
                        const ObstaclesMeta& meta);

/// Reads an obstacles.json (/1 or /2) through obstaclesFromJson; throws hullmap::Error naming `path`
/// when it cannot be opened, is not JSON, or any field is malformed.
std::vector<hulls::Obstacle> readObstaclesJson(const std::string& path, ObstaclesMeta* meta = nullptr);

/// Writes the hulls as Wavefront OBJ: one object per convex part, `o obstacle_<id>_part_<k>` (k from
/// 0), or `o obstacle_<id>` for an obstacle without parts; `v` lines then `f` lines with 1-based
/// global indices; opens in MeshLab, CloudCompare, Blender and Open3D.
void writeObstaclesObj(std::ostream& out, const std::vector<hulls::Obstacle>& obstacles);

/// writeObstaclesObj into `path`, atomically. Throws hullmap::Error naming `path`.
void writeObstaclesObj(const std::string& path, const std::vector<hulls::Obstacle>& obstacles);

}  // namespace hullmap::pipeline
