#include "hullmap/pipeline/map_obstacles.hpp"

#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::pipeline {

MapObstacles mapObstacles(const BuildResult& result) {
  MapObstacles map;
  map.obstacles = result.obstacles;
  map.surfaces = result.surfaces;
  map.input_to_output = result.report.input_to_output;
  map.input_to_output_exact = inputToOutputExact(result.report);
  map.frame = outputFrame(result);
  return map;
}

MapObstacles readMapObstacles(const std::filesystem::path& path) {
  std::filesystem::path file = path;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    file = path / "obstacles.json";
    if (!std::filesystem::exists(file, ec))
      throw Error(path.string() + ": no obstacles.json in this directory (is it a `hullmap build` output?)");
  }
  ObstaclesMeta meta;
  MapObstacles map;
  map.obstacles = readObstaclesJson(file.string(), &meta);
  map.surfaces = std::move(meta.surfaces);
  map.input_to_output = meta.input_to_output;
  map.input_to_output_exact = meta.input_to_output_exact;
  map.frame = std::move(meta.frame);
  return map;
}

QueryFrame parseQueryFrame(const std::string& text) {
  if (text == "map") return QueryFrame::kMap;
  if (text == "input") return QueryFrame::kInput;
  throw Error::inParameter("frame", "expected \"map\" or \"input\", got \"" + text + "\"");
}

mapper::Similarity toMapFrame(const MapObstacles& map, QueryFrame frame) {
  if (frame == QueryFrame::kMap) return {};
  if (!map.input_to_output)
    throw Error::inParameter("frame",
                             "this build does not record its input-to-output transform (written by an "
                             "older hullmap): rebuild it to query in the input frame");
  if (!map.input_to_output_exact)
    throw Error::inParameter("frame",
                             "this build's --align undid the map's scale drift, moving each point by its own "
                             "part of the path (report.json alignment.drift), so no one transform takes input "
                             "coordinates to the map: query in the map frame");
  return *map.input_to_output;
}

}  // namespace hullmap::pipeline
