#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/clustering/obstacles.hpp"
#include "hullmap/mapper/frame.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/mapper/readers.hpp"

namespace hullmap::cli {

/// Everything `hullmap build` can be asked, with its defaults.
struct BuildOptions {
  std::vector<std::string> inputs;
  std::string output_dir = "out";
  std::optional<std::string> trajectory;
  std::optional<std::string> origin;      ///< "x,y,z": insert the points as one scan from there
  std::string up = "z";
  double scale = 1.0;
  std::optional<std::string> crop;        ///< "x0,y0,z0,x1,y1,z1"
  std::optional<double> z_min;
  std::optional<double> z_max;
  mapper::OctreeParams octree;
  clustering::DbscanParams dbscan;
  std::string metric = "xyz";
  bool write_ot = false;
};

/// Account of what happened to the input points, stage by stage.
struct PointAccount {
  std::size_t read = 0;
  std::map<std::string, std::size_t> dropped;  ///< reason -> count, over all stages
  std::size_t used = 0;
};

/// The in-memory result of the pipeline (what `build` writes).
struct BuildResult {
  std::vector<mapper::InputStats> inputs;
  PointAccount account;
  std::optional<mapper::OccupancyMap> map;
  std::vector<mapper::OccupiedVoxel> voxels;
  clustering::DbscanResult clusters;
  std::vector<clustering::Obstacle> obstacles;
  std::vector<std::pair<std::string, double>> timings_ms;  ///< stage -> ms, in order
  std::vector<std::pair<std::string, double>> peak_rss_mb; ///< stage -> process peak RSS at its end
  std::size_t keyframes = 0;
};

/// Reads and unions the map-point files (any format the mapper reads); throws hullmap::Error
/// naming them when none holds a point.
mapper::PointSet readInputPoints(const std::vector<std::string>& inputs);

/// Runs read -> frame -> filters -> octree -> DBSCAN -> obstacles. Throws hullmap::Error.
/// Point files without --trajectory and --origin are streamed: read, frame change, filters and
/// octree run batch by batch (mapper::streamPointFiles into a mapper::PointMapBuilder) and the
/// timings of those three stages are each summed over the batches; with --trajectory or --origin
/// every point is needed at once and the inputs are read whole. Both give the same outputs.
BuildResult runBuild(const BuildOptions& options);

/// Throws hullmap::Error naming `-o output_dir` when it plainly cannot be written: it exists and is
/// not a directory, or its nearest existing ancestor is not a writable directory. Called before
/// the work so that a 10M-point build does not fail at its end; writeBuild's own errors still hold.
void checkOutputDir(const std::string& output_dir);

/// Writes map.bt (+ map.ot), voxels.csv, obstacles.json, obstacles.obj, report.json into
/// options.output_dir whole or not at all: everything goes to a sibling temporary directory which
/// then replaces the output directory; a failed run leaves the previous directory as it was.
void writeBuild(const BuildOptions& options, const BuildResult& result);

/// The report.json document.
nlohmann::json buildReport(const BuildOptions& options, const BuildResult& result);

/// The frame description written into every output ("z-up map frame; input up axis ...").
std::string frameDescription(const std::string& up, double scale);

}  // namespace hullmap::cli
