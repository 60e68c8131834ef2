#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/pipeline/map_obstacles.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::python {

/// The module's names for library parameters in warnings (a hullmap::ParameterSpelling): the
/// keyword ("min_pts"), and "min_pts=5" or "against='octree'" with a value.
std::string keywordSpelling(std::string_view field, std::string_view value);

/// What hullmap.Map holds: a build's result (hullmap.build) or a build directory read back
/// (hullmap.load). Immutable after construction but for the checkers, made on first use (under the
/// GIL); checks themselves run without the GIL, concurrently if the caller likes.
class Map {
 public:
  /// Takes a build's result; save() writes it.
  explicit Map(pipeline::BuildResult result);
  /// Reads `dir` as `hullmap check` and `hullmap plan` do (obstacles.json with the surfaces and the
  /// frame, voxels.csv, report.json; map.bt when an octree check asks for it).
  static std::unique_ptr<Map> load(const std::filesystem::path& dir);

  /// The obstacles, surfaces and frame, as the checks and planners take them.
  const pipeline::MapObstacles& map() const { return map_; }
  const std::vector<hulls::Obstacle>& obstacles() const { return map_.obstacles; }
  const nlohmann::json& report() const { return report_; }
  double resolution() const { return resolution_; }
  const std::vector<Eigen::Vector3d>& centers() const { return centers_; }
  const std::vector<std::int32_t>& labels() const { return labels_; }
  const std::vector<std::uint32_t>& weights() const { return weights_; }
  const std::vector<std::uint8_t>& core() const { return core_; }

  /// The hull checker, made on first use.
  const collision::HullChecker& hulls();
  /// The octree checker: the build's tree, or the directory's map.bt; made on first use.
  const collision::OctreeChecker& octree();

  /// pipeline::write of the build; throws hullmap::Error for a map that load() read.
  void save(const std::filesystem::path& dir, bool parents) const;

  /// Where load() read it from (empty for a build).
  const std::filesystem::path& directory() const { return dir_; }

 private:
  Map() = default;

  std::optional<pipeline::BuildResult> result_;
  pipeline::MapObstacles map_;
  nlohmann::json report_;
  double resolution_ = 0.0;
  std::vector<Eigen::Vector3d> centers_;
  std::vector<std::int32_t> labels_;
  std::vector<std::uint32_t> weights_;
  std::vector<std::uint8_t> core_;
  std::filesystem::path dir_;
  std::unique_ptr<collision::HullChecker> hulls_;
  std::unique_ptr<collision::OctreeChecker> octree_;
};

}  // namespace hullmap::python
