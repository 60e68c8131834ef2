// The build's stages after the octree: one list, wired once (kStages), each stage a function of the
// voxels' work state, timed and announced to the stage hook by the loop that runs them.
#include "cluster_stages.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ground.hpp"
#include "hullmap/clustering/auto_params.hpp"
#include "hullmap/clustering/build_warnings.hpp"
#include "hullmap/clustering/cluster_extension.hpp"
#include "hullmap/clustering/coplanar_merge.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/clustering/outlier_trim.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/mapper/floor.hpp"
#include "hullmap/mapper/level_check.hpp"
#include "hullmap/pipeline/detail/test_hooks.hpp"
#include "hullmap/pipeline/report.hpp"
#include "stages.hpp"
#include "surfaces.hpp"

namespace hullmap::pipeline {
namespace {

/// A floor kept in the input frame tilted by more than this (degrees) is warned about.
constexpr double kKeptFloorTiltDeg = 3.0;

/// What the stages hand on to each other.
struct ClusterWork {
  std::vector<Eigen::Vector3d> centers;  // every occupied voxel's centre
  std::vector<std::uint32_t> weights;    // and its map points
  std::vector<std::int32_t> labels;      // per voxel: kFloorLabel, kCeilingLabel, a cluster or kNoise
  // The voxels that are neither floor nor ceiling, which DBSCAN clusters.
  std::vector<std::size_t> obstacle_index;
  std::vector<Eigen::Vector3d> obstacle_centers;
  std::vector<std::uint32_t> obstacle_weights;
  clustering::DbscanResult clusters;         // over the obstacle voxels
  std::vector<std::int32_t> cluster_labels;  // labels with the surfaces as noise
};

// Floor and ceiling voxels stay in the map but are not clustered. The band covers the plane's
// noise (about a voxel) and half a voxel: a voxel holding floor points has its centre within it.
void separateSurfaces(BuildResult& result, ClusterWork& w) {
  const BuildReport& report = result.report;
  result.voxels = result.map.occupiedVoxels();
  const std::size_t n = result.voxels.size();
  w.centers.reserve(n);
  w.weights.reserve(n);
  for (const auto& v : result.voxels) {
    w.centers.push_back(v.center);
    w.weights.push_back(v.weight);
  }
  w.labels.assign(n, clustering::kNoise);
  if (report.floor.plane || report.ceiling.plane) {
    const auto classes =
        mapper::classifySurfaces(w.centers, report.floor.plane, report.ceiling.plane, 1.25 * result.map.resolution());
    for (std::size_t i = 0; i < n; ++i) {
      if (classes[i] == mapper::SurfaceClass::kFloor) w.labels[i] = kFloorLabel;
      if (classes[i] == mapper::SurfaceClass::kCeiling) w.labels[i] = kCeilingLabel;
    }
  }
  // The ground found in the points (a height field among the surfaces): the voxels within its band.
  for (const collision::Surface& surface : result.surfaces) {
    if (!surface.field || !result.report.ground) continue;
    const double band = groundBand(result.params.terrain, result.map.resolution());
    std::size_t& count = result.report.ground->voxels;
    count = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (w.labels[i] == clustering::kNoise && surface.distance(w.centers[i]) <= band) {
        w.labels[i] = kGroundLabel;
        ++count;
      }
  }
  w.obstacle_index.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    if (w.labels[i] == clustering::kNoise) w.obstacle_index.push_back(i);
  w.obstacle_centers.reserve(w.obstacle_index.size());
  w.obstacle_weights.reserve(w.obstacle_index.size());
  for (std::size_t i : w.obstacle_index) {
    w.obstacle_centers.push_back(w.centers[i]);
    w.obstacle_weights.push_back(w.weights[i]);
  }
}

// eps and min_pts: given, or chosen from the obstacle voxels.
void chooseParams(BuildResult& result, ClusterWork& w) {
  const BuildParams& params = result.params;
  ClusterParamsReport& chosen = result.report.cluster_params;
  chosen.used.metric = params.metric;
  chosen.eps_auto = !params.eps;
  chosen.min_pts_auto = !params.min_pts;
  if (chosen.eps_auto || chosen.min_pts_auto) {
    chosen.chosen = clustering::chooseDbscanParams(w.obstacle_centers, w.obstacle_weights, result.map.resolution(),
                                                   params.metric, params.auto_rule);
  }
  chosen.used.eps = params.eps ? *params.eps : chosen.chosen->eps;
  chosen.used.min_pts = params.min_pts ? *params.min_pts : chosen.chosen->min_pts;
}

void runDbscan(BuildResult& result, ClusterWork& w) {
  w.clusters = clustering::dbscan(w.obstacle_centers, w.obstacle_weights, result.report.cluster_params.used);
}

// The centres of the floor's, ceiling's and ground's voxels: what holds up the things standing on them.
std::vector<Eigen::Vector3d> surfaceCenters(const ClusterWork& w) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < w.labels.size(); ++i)
    if (w.labels[i] == kFloorLabel || w.labels[i] == kCeilingLabel || w.labels[i] == kGroundLabel)
      out.push_back(w.centers[i]);
  return out;
}

bool extensionOn(const BuildParams& params) { return params.extension.value_or(!params.min_pts); }

// The clusters extended, their strays trimmed, and flat clusters merged into the ones around them.
void extendClusters(BuildResult& result, ClusterWork& w) {
  const double resolution = result.map.resolution();
  ClusterParamsReport& chosen = result.report.cluster_params;
  chosen.extension_params = clustering::extensionParams(chosen.used, result.params.extension_rule);
  chosen.extension =
      clustering::extendClusters(w.obstacle_centers, w.obstacle_weights, w.clusters, *chosen.extension_params);
  // Stray map points that the eps, wide on a sparse map, took in off the surfaces go back to noise;
  // the floor's and ceiling's voxels support what stands on them (a table leg's foot).
  const std::vector<Eigen::Vector3d> surface_centers = surfaceCenters(w);
  chosen.trim_params =
      clustering::OutlierTrimParams{3.0 * resolution, std::max(3.0 * resolution, chosen.extension_params->reach)};
  chosen.trim = clustering::trimOutliers(w.obstacle_centers, w.clusters, surface_centers, *chosen.trim_params);
  // A flat cluster in the plane of a larger one around it (a wall's foot that DBSCAN cut off the
  // sparse wall above it) joins it, so that the wall's parts can merge over it.
  chosen.coplanar_params = clustering::CoplanarMergeParams{chosen.used.eps, 3.0 * resolution};
  chosen.coplanar = clustering::mergeCoplanarClusters(w.obstacle_centers, w.clusters, *chosen.coplanar_params);
}

// The occupied voxels whose closed cube holds a keyframe, with their labels (ascending by voxel).
std::vector<std::pair<std::size_t, std::int32_t>> cameraVoxels(const BuildResult& result, const ClusterWork& w) {
  std::vector<std::pair<std::size_t, std::int32_t>> out;
  if (result.keyframes.empty()) return out;
  const double half = 0.5 * result.map.resolution() * (1.0 + 1e-9);
  std::vector<Eigen::Vector3d> positions;
  for (const auto& k : result.keyframes) positions.push_back(k.position);
  std::sort(positions.begin(), positions.end(),
            [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return a.x() < b.x(); });
  for (std::size_t i = 0; i < w.centers.size(); ++i) {
    const Eigen::Vector3d& c = w.centers[i];
    auto it = std::lower_bound(positions.begin(), positions.end(), c.x() - half,
                               [](const Eigen::Vector3d& p, double x) { return p.x() < x; });
    for (; it != positions.end() && it->x() <= c.x() + half; ++it)
      if ((*it - c).cwiseAbs().maxCoeff() <= half) {
        out.emplace_back(i, w.labels[i]);
        break;
      }
  }
  return out;
}

// Every voxel's label, the surfaces' rims joined to what stands on them, a hull and footprint per
// cluster, and the floor and ceiling as half-spaces.
void makeObstacles(BuildResult& result, ClusterWork& w) {
  const double resolution = result.map.resolution();
  const BuildParams& params = result.params;
  BuildReport& report = result.report;
  const clustering::DbscanParams& used = report.cluster_params.used;
  const std::size_t n = w.centers.size();
  result.clusters.cluster_sizes = w.clusters.cluster_sizes;
  result.clusters.noise = w.clusters.noise;
  result.clusters.core.assign(n, 0);
  for (std::size_t k = 0; k < w.obstacle_index.size(); ++k) {
    w.labels[w.obstacle_index[k]] = w.clusters.labels[k];
    result.clusters.core[w.obstacle_index[k]] = w.clusters.core[k];
  }
  // A camera was where a keyframe is: the voxels around it hold no obstacle (their map points are
  // SLAM's mistakes), and no rim of a surface joins them.
  const std::vector<std::pair<std::size_t, std::int32_t>> cameras = cameraVoxels(result, w);
  for (const auto& [i, label] : cameras)
    if (label >= 0) {
      --result.clusters.cluster_sizes[std::size_t(label)];
      ++result.clusters.noise;
      w.labels[i] = clustering::kNoise;
    }
  report.camera_voxels = cameras.size();
  // The rims reach as far as the eps used, but no farther than the auto rule's upper clamp: a large
  // eps given by hand (1 m) would otherwise join most of the floor to the walls' feet.
  detail::attachSurfaceRims(w.centers, resolution, std::min(used.eps, params.auto_rule.max_eps_voxels * resolution),
                            w.labels);
  for (const auto& [i, label] : cameras) w.labels[i] = std::min(label, clustering::kNoise);
  w.cluster_labels = w.labels;
  for (auto& l : w.cluster_labels) l = std::max(l, clustering::kNoise);
  result.obstacles = hulls::buildObstacles(w.centers, w.weights, w.cluster_labels, resolution);
  for (std::size_t i = 0; i < n; ++i) {
    if (w.labels[i] == kFloorLabel) ++report.floor.voxels;
    if (w.labels[i] == kCeilingLabel) ++report.ceiling.voxels;
  }
  // The floor and ceiling as their voxels make them; the ground as found in the points.
  std::vector<collision::Surface> surfaces = boundingSurfaces(report, w.centers, w.labels, resolution);
  for (collision::Surface& s : result.surfaces)
    if (s.field) surfaces.push_back(std::move(s));
  result.surfaces = std::move(surfaces);
}

bool convexPartsOn(const BuildParams& params) { return params.convex_parts.has_value(); }

// The keyframes inside some hull, as the outputs hold them: each part's (an obstacle's whole hull
// when it has no part).
std::size_t keyframesInsideHulls(const BuildResult& result) {
  std::size_t inside = 0;
  const auto contains = [](const auto& shape, const Eigen::Vector3d& p) {
    return (p.array() >= shape.aabb_min.array()).all() && (p.array() <= shape.aabb_max.array()).all() &&
           hulls::hullContains(shape.hull, p);
  };
  for (const auto& k : result.keyframes) {
    bool in = false;
    for (const auto& o : result.obstacles) {
      if (o.parts.empty()) in = contains(o, k.position);
      for (const auto& part : o.parts) in = in || contains(part, k.position);
      if (in) break;
    }
    inside += in ? 1 : 0;
  }
  return inside;
}

// Each obstacle split into convex parts that keep out of the space the keyframes saw free.
void splitConvexParts(BuildResult& result, ClusterWork& w) {
  const BuildParams& params = result.params;
  BuildReport& report = result.report;
  const double resolution = result.map.resolution();
  hulls::KnownFreeSpace known;
  for (const auto& k : result.keyframes) known.keyframes.push_back(k.position);
  if (params.trajectory || params.origin) known.free_voxels = freeVoxelCentres(result.map);
  // G unset: the eps used, the distance at which this map's sampling connects a surface.
  hulls::ConvexPartsParams parts_params = *params.convex_parts;
  if (params.sparse_edges && !parts_params.sparse_edges) parts_params.sparse_edges = hulls::SparseEdges{};
  // Auto G is also adapted to each cluster's sampling (a sparse wall's chance holes); a G the user
  // gives is used as given.
  if (!parts_params.flat_gap) {
    parts_params.flat_gap = report.cluster_params.used.eps;
    parts_params.adapt_flat_gap = true;
  }
  // A level floor closes the shells standing on it from below (their bottom is never seen).
  if (report.floor.plane && !parts_params.floor_z)
    parts_params.floor_z = levelFloorHeight(*report.floor.plane, w.centers, resolution);
  std::optional<hulls::StrayParts> strays;
  if (extensionOn(params) && params.stray_part_voxels > 0) {
    strays.emplace();
    strays->max_voxels = params.stray_part_voxels;
    strays->core = result.clusters.core;
    strays->support = surfaceCenters(w);
  }
  report.parts = hulls::addConvexParts(result.obstacles, w.centers, w.weights, w.cluster_labels, resolution,
                                       parts_params, known, strays ? &*strays : nullptr);
  report.keyframes_inside_hulls = keyframesInsideHulls(result);
  // The stray parts' voxels are noise now.
  for (const std::size_t i : report.parts->stray_voxels) {
    --result.clusters.cluster_sizes[static_cast<std::size_t>(w.labels[i])];
    ++result.clusters.noise;
    w.labels[i] = clustering::kNoise;
    w.cluster_labels[i] = clustering::kNoise;
  }
}

// The clustering's warnings, and a kept floor's tilt or a map that looks unlevelled.
void addWarnings(BuildResult& result, const ClusterWork& w) {
  const BuildParams& params = result.params;
  BuildReport& report = result.report;
  const double resolution = result.map.resolution();
  const clustering::DbscanParams& used = report.cluster_params.used;
  report.warnings = clustering::buildWarnings({w.obstacle_index.size(), result.clusters.noise, result.obstacles.size(),
                                               used.eps, used.min_pts, used.metric, resolution});
  if (report.cluster_params.chosen) {
    if (auto sparse = clustering::sparseMapWarning(w.obstacle_centers, resolution, *report.cluster_params.chosen,
                                                   params.auto_rule, used.metric))
      report.warnings.push_back(*sparse);
  }
  if (readsOctree(params) || params.align || report.floor.levelled) return;
  const PlaneReport& floor = report.floor;
  if (floor.plane && floor.setting.mode == mapper::PlaneSetting::Mode::kAuto) {
    if (floor.fit.tilt_deg > kKeptFloorTiltDeg) {
      report.warnings.push_back({Warning::Code::kKeptFloorTilted,
                                 {{"inlier_share", floor.fit.inlier_share}, {"tilt_deg", floor.fit.tilt_deg}},
                                 ""});
    }
  } else if (auto tilted = mapper::levelWarning(w.centers, resolution, upAxisText(params.frame.up))) {
    report.warnings.push_back(*tilted);
  }
}

struct Stage {
  const char* name;                  // in report.json's timings and to the stage hook
  bool (*runs)(const BuildParams&);  // nullptr: always
  void (*run)(BuildResult&, ClusterWork&);
};

constexpr Stage kStages[] = {
    {"surfaces", nullptr, separateSurfaces}, {"auto_params", nullptr, chooseParams},
    {"dbscan", nullptr, runDbscan},          {"extension", extensionOn, extendClusters},
    {"obstacles", nullptr, makeObstacles},   {"convex_parts", convexPartsOn, splitConvexParts},
};

}  // namespace

void clusterInto(BuildResult& result, StageTimer& timer) {
  ClusterWork work;
  for (const Stage& stage : kStages) {
    if (stage.runs != nullptr && !stage.runs(result.params)) continue;
    runStage(stage.name);
    stage.run(result, work);
    timer.stage(stage.name);
  }
  result.clusters.labels = std::move(work.labels);
  addWarnings(result, work);
}

}  // namespace hullmap::pipeline
