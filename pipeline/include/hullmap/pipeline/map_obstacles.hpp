#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/mapper/align.hpp"

/// A finished build as path checks and planners take it: the obstacles, the surfaces (floor,
/// ceiling) that are obstacles too, and the frame its coordinates are in.
namespace hullmap::pipeline {

struct BuildResult;

/// What a path check of a build needs. Coordinates in the build's output (map) frame, map units.
struct MapObstacles {
  std::vector<hulls::Obstacle> obstacles;    ///< with their convex parts
  std::vector<collision::Surface> surfaces;  ///< the floor and ceiling found or given, solid
  /// Input coordinates -> map coordinates; nullopt for an obstacles.json written before it was recorded.
  std::optional<mapper::Similarity> input_to_output;
  bool input_to_output_exact = true;  ///< false: the drift model moved each point by its part of the path
  std::string frame;                  ///< the build's description of its frame
};

/// The obstacles, surfaces and frame of a build in memory.
MapObstacles mapObstacles(const BuildResult& result);

/// Reads them from a build: `path` is a `hullmap build` directory or its obstacles.json. Throws
/// hullmap::Error naming the directory (no obstacles.json in it) or the file (see readObstaclesJson).
MapObstacles readMapObstacles(const std::filesystem::path& path);

/// The frame a query's coordinates are in: the map's (the build's outputs), or the input's (the
/// coordinates of the points the build read, before up/scale, alignment and levelling).
enum class QueryFrame { kMap, kInput };

/// "map" or "input". Throws hullmap::Error naming `frame`.
QueryFrame parseQueryFrame(const std::string& text);

/// The similarity that takes `frame` coordinates into the map frame: the identity for kMap,
/// input_to_output for kInput. Lengths scale by its `scale` (a radius does not: it is always in map
/// units). Throws hullmap::Error naming `frame` when kInput is asked of a build that does not record
/// input_to_output, or whose input_to_output is not exact (an alignment that undid scale drift).
mapper::Similarity toMapFrame(const MapObstacles& map, QueryFrame frame);

}  // namespace hullmap::pipeline
