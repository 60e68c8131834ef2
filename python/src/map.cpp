#include "map.hpp"

#include <system_error>

#include "hullmap/core/error.hpp"
#include "hullmap/core/number_text.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/pipeline/report.hpp"
#include "hullmap/pipeline/voxels_csv.hpp"

namespace hullmap::python {

std::string keywordSpelling(std::string_view field, std::string_view value) {
  std::string out(field);
  if (value.empty()) return out;
  double number = 0.0;
  const bool numeric = core::parseDouble(value, number);
  return out.append("=").append(numeric ? "" : "'").append(value).append(numeric ? "" : "'");
}

Map::Map(pipeline::BuildResult result) : result_(std::move(result)) {
  const pipeline::BuildResult& r = *result_;
  map_ = pipeline::mapObstacles(r);
  report_ = pipeline::reportJson(r, keywordSpelling);
  resolution_ = r.map.resolution();
  centers_.reserve(r.voxels.size());
  weights_.reserve(r.voxels.size());
  for (const auto& v : r.voxels) {
    centers_.push_back(v.center);
    weights_.push_back(v.weight);
  }
  labels_ = r.clusters.labels;
  core_ = r.clusters.core;
}

std::unique_ptr<Map> Map::load(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw Error(dir.string() + ": not a directory (load reads what hullmap build -o DIR or Map.save wrote)");
  std::unique_ptr<Map> map(new Map());
  map->dir_ = dir;
  map->map_ = pipeline::readMapObstacles(dir / "obstacles.json");
  map->report_ = pipeline::readReport(dir / "report.json");
  const auto rows = pipeline::readVoxelsCsv(dir / "voxels.csv");
  for (const auto& row : rows) {
    map->centers_.push_back(row.center);
    map->weights_.push_back(row.weight);
    map->labels_.push_back(row.label);
    map->core_.push_back(row.core ? 1 : 0);
  }
  // report.json's octree resolution is the tree's (a .bt input keeps its own); readReport has
  // checked the parameters' one, which a build from points shares.
  const auto& octree = map->report_.value("octree", nlohmann::json::object());
  map->resolution_ = octree.contains("resolution") && octree["resolution"].is_number()
                         ? octree["resolution"].get<double>()
                         : map->report_["parameters"]["resolution"].get<double>();
  return map;
}

const collision::HullChecker& Map::hulls() {
  if (!hulls_) hulls_ = std::make_unique<collision::HullChecker>(map_.obstacles, map_.surfaces);
  return *hulls_;
}

const collision::OctreeChecker& Map::octree() {
  if (!octree_) {
    if (result_) {
      octree_ = std::make_unique<collision::OctreeChecker>(result_->map.tree(), map_.surfaces);
    } else {
      const mapper::OccupancyMap map = mapper::readMap((dir_ / "map.bt").string());
      octree_ = std::make_unique<collision::OctreeChecker>(map.tree(), map_.surfaces);
    }
  }
  return *octree_;
}

void Map::save(const std::filesystem::path& dir, bool parents) const {
  if (!result_)
    throw Error("save: this Map was read from " + dir_.string() +
                " by load(), which keeps no octree and no report of its own to write; copy that directory instead");
  pipeline::write(*result_, dir, pipeline::WriteOptions{parents, keywordSpelling});
}

}  // namespace hullmap::python
