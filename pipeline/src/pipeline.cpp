#include "hullmap/pipeline/pipeline.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <functional>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <sys/file.h>
#include <tuple>
#include <unordered_map>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/clustering/build_warnings.hpp"
#include "hullmap/mapper/level_check.hpp"
#include "hullmap/mapper/output_dir.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/pipeline/trajectory_file.hpp"
#include "input_points.hpp"

namespace hullmap::pipeline {
namespace {

namespace fs = std::filesystem;

double peakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

using Clock = std::chrono::steady_clock;

void runStage(const char* stage) {
  if (detail::stage_hook != nullptr) detail::stage_hook(stage);
}

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// Wall time of each stage, and the process's peak resident memory when it ends.
class StageTimer {
 public:
  explicit StageTimer(BuildReport& report) : report_(report) {}
  /// The stage that ends now began when the previous one ended.
  void stage(const std::string& name) { stage(name, msSince(start_)); }
  /// A stage whose time was summed over pieces interleaved with other stages.
  void stage(const std::string& name, double ms) {
    report_.timings_ms.emplace_back(name, ms);
    report_.peak_rss_mb.emplace_back(name, peakRssMb());
    start_ = Clock::now();
  }

 private:
  BuildReport& report_;
  Clock::time_point start_ = Clock::now();
};

bool isOctomapFile(const fs::path& path) {
  const std::string ext = path.extension().string();
  return ext == ".bt" || ext == ".ot";
}

void addDropped(PointAccount& account, const io::InputStats& stats) {
  for (const auto& [reason, count] : stats.dropped) account.dropped[reason] += count;
}

std::vector<std::string> pathStrings(const std::vector<fs::path>& paths) {
  std::vector<std::string> strings;
  for (const auto& p : paths) strings.push_back(p.string());
  return strings;
}

Error noPointsInBounds() {
  return Error::inParameter("crop/z_min/z_max", "no points left inside the bounds");
}

void accountForInputs(BuildResult& result) {
  for (const auto& stats : result.report.inputs) {
    result.report.points.read += stats.read;
    addDropped(result.report.points, stats);
  }
}

/// Map frame -> output frame: x -> levelling * x.
void applyIsometry(const Eigen::Isometry3d& t, io::Points& points) {
  for (auto& p : points) p = t * p;
}

void applyIsometry(const Eigen::Isometry3d& t, std::vector<io::Keyframe>& keyframes) {
  const Eigen::Quaterniond q(t.linear());
  for (auto& k : keyframes) {
    k.position = t * k.position;
    k.orientation = q * k.orientation;
  }
}

bool isIdentity(const Eigen::Isometry3d& t) { return t.matrix().isIdentity(0.0); }

/// A deterministic sample of a point stream in input order, whatever its batches: every
/// stride-th point, the stride doubling (and every second kept point dropped) whenever
/// kSamplePoints are held. The floor search runs on it.
class PointSample {
 public:
  static constexpr std::size_t kSamplePoints = std::size_t(1) << 18;
  void add(const io::Points& batch) {
    for (const auto& p : batch) {
      if (seen_++ % stride_ != 0) continue;
      points_.push_back(p);
      if (points_.size() == kSamplePoints) {
        for (std::size_t i = 0; 2 * i < points_.size(); ++i) points_[i] = points_[2 * i];
        points_.resize((points_.size() + 1) / 2);
        stride_ *= 2;
      }
    }
  }
  const io::Points& points() const { return points_; }

 private:
  io::Points points_;
  std::size_t seen_ = 0;
  std::size_t stride_ = 1;
};

/// Identity when `levelling` moves no corner of the points' bounding box by more than 5% of a
/// voxel (a map already level with its floor at z = 0): the points are then left as they are.
Eigen::Isometry3d negligibleAsIdentity(const Eigen::Isometry3d& levelling, const io::Points& points,
                                       double resolution) {
  if (points.empty() || isIdentity(levelling)) return levelling;
  if (!levelling.matrix().allFinite()) return Eigen::Isometry3d::Identity();
  Eigen::AlignedBox3d box;
  for (const auto& p : points) box.extend(p);
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d corner = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
    if ((levelling * corner - corner).norm() > 0.05 * resolution) return levelling;
  }
  return Eigen::Isometry3d::Identity();
}

/// The floor and ceiling stage on (a sample of) the points in the map frame: what was found, and
/// the levelling that puts a found floor at z = 0 (identity when aligned: REF defines up).
struct Surfaces {
  PlaneReport floor;
  PlaneReport ceiling;
  Eigen::Isometry3d levelling = Eigen::Isometry3d::Identity();
};

Surfaces searchSurfaces(const BuildParams& params, const io::Points& sample, bool level) {
  Surfaces out;
  const bool aligned = params.align.has_value();
  mapper::PlaneSearchParams search;
  search.band = params.octree.resolution;
  search.fit_tilt = !aligned;
  out.floor.setting = params.floor;
  out.ceiling.setting = params.ceiling;
  using Mode = mapper::PlaneSetting::Mode;
  if (params.floor.mode == Mode::kHeight) {
    out.floor.plane = mapper::horizontalPlane(params.floor.height, mapper::PlaneSide::kFloor);
  } else if (params.floor.mode == Mode::kAuto) {
    out.floor.fit = mapper::findBoundingPlane(sample, mapper::PlaneSide::kFloor, search);
    if (out.floor.fit.found) {
      if (!level) {
        out.floor.plane = out.floor.fit.plane;
      } else {
        out.levelling = mapper::levelingTransform(out.floor.fit.plane);
        out.floor.plane = mapper::horizontalPlane(0.0, mapper::PlaneSide::kFloor);
        out.floor.levelled = true;
      }
    }
  }
  if (params.ceiling.mode == Mode::kHeight) {
    out.ceiling.plane = mapper::horizontalPlane(params.ceiling.height, mapper::PlaneSide::kCeiling);
  } else if (params.ceiling.mode == Mode::kAuto) {
    io::Points levelled;
    const io::Points* points = &sample;
    if (!isIdentity(out.levelling)) {
      levelled = sample;
      applyIsometry(out.levelling, levelled);
      points = &levelled;
    }
    out.ceiling.fit = mapper::findBoundingPlane(*points, mapper::PlaneSide::kCeiling, search);
    if (out.ceiling.fit.found) out.ceiling.plane = out.ceiling.fit.plane;
  }
  return out;
}

Surfaces findSurfaces(const BuildParams& params, const io::Points& sample, bool level) {
  Surfaces out = searchSurfaces(params, sample, level);
  out.levelling = negligibleAsIdentity(out.levelling, sample, params.octree.resolution);
  if (out.floor.levelled && isIdentity(out.levelling)) {  // already level at z = 0
    out.floor.levelled = false;
    out.floor.plane = out.floor.fit.plane;
  }
  return out;
}

void recordSurfaces(const Surfaces& surfaces, BuildResult& result) {
  result.report.floor = surfaces.floor;
  result.report.ceiling = surfaces.ceiling;
  result.report.levelling = surfaces.levelling;
}

/// Reads the reference trajectory (or takes its poses in memory) and fits the keyframes (input frame) to it.
mapper::Alignment alignKeyframes(const AlignSettings& align, const std::vector<io::Keyframe>& keyframes,
                                 BuildReport& report) {
  io::ReferenceStats stats;
  const auto reference = align.poses ? *align.poses
                                     : io::readReferenceTrajectory(align.reference.string(), align.format, &stats);
  report.reference_dropped = stats.dropped;
  std::size_t dropped = 0;
  for (const auto& [reason, count] : stats.dropped) dropped += count;
  const std::string without_fix =
      dropped == 0 ? "" : "; " + std::to_string(dropped) + " line" + (dropped == 1 ? "" : "s") + " without a fix dropped";
  if (reference.empty()) throw Error(align.reference.string() + ": no reference poses" + without_fix);
  try {
    return mapper::alignTrajectory(keyframes, reference, align.params);
  } catch (const Error& e) {
    // Named as the parameter, so that the CLI says --align.
    const std::string text = e.what();
    if (!e.parameter().empty() || text.rfind("align: ", 0) != 0) throw;
    throw Error::inParameter("align", text.substr(7) + (without_fix.empty() ? "" : " (" + align.reference.string() +
                                                                                 without_fix.substr(1) + ")"));
  }
}

/// Input -> output frame before levelling: the alignment, or the up axis and scale.
mapper::Similarity frameTransform(const BuildParams& params, const BuildReport& report) {
  if (report.alignment) return report.alignment->transform;
  mapper::Similarity s;
  s.scale = params.frame.scale;
  s.rotation = mapper::upRotation(params.frame.up);
  return s;
}

void recordFrame(const BuildParams& params, BuildReport& report) {
  report.input_to_output = mapper::compose(mapper::fromIsometry(report.levelling), frameTransform(params, report));
}

/// The octree of points already read whole (map frame after this), with the keyframes' rays
/// (trajectory), one scan's rays (origin), or points alone.
/// `given` (keyframes in memory, input frame) stands for the trajectory file when not null.
void buildWhole(const BuildParams& params, io::Points points, BuildResult& result, StageTimer& timer,
                std::vector<io::Keyframe>* given = nullptr) {
  accountForInputs(result);
  timer.stage("read");

  runStage("frame_and_filters");
  std::vector<io::Keyframe> keyframes;
  // Keyframes in memory are in the input frame, as a trajectory file's: they change frame below
  // with the points (once).
  if (given) {
    keyframes = std::move(*given);
    if (keyframes.empty()) throw Error(params.trajectory->string() + ": no keyframes");
  } else if (params.trajectory) {
    keyframes = io::readTumTrajectory(params.trajectory->string());
    if (keyframes.empty()) throw Error(params.trajectory->string() + ": no keyframes");
  }
  std::vector<Eigen::Vector3d> origin;
  if (params.origin) origin.push_back(*params.origin);
  if (params.align) {
    result.report.alignment = alignKeyframes(*params.align, keyframes, result.report);
    mapper::applySimilarity(result.report.alignment->transform, points);
    mapper::applySimilarity(result.report.alignment->transform, keyframes);
    timer.stage("align");
  } else {
    mapper::toMapFrame(params.frame, keyframes);
    mapper::toMapFrame(params.frame, points);
    mapper::toMapFrame(params.frame, origin);
  }
  PointSample sample;
  sample.add(points);
  const Surfaces surfaces = findSurfaces(params, sample.points(), levelsMap(params, result.report.inputs));
  if (!isIdentity(surfaces.levelling)) {
    applyIsometry(surfaces.levelling, points);
    applyIsometry(surfaces.levelling, keyframes);
    applyIsometry(surfaces.levelling, origin);
  }
  recordSurfaces(surfaces, result);
  recordFrame(params, result.report);
  timer.stage("floor");
  io::InputStats filtered;
  mapper::applyFilters(params.filters, points, filtered);
  addDropped(result.report.points, filtered);
  if (points.empty()) throw noPointsInBounds();
  timer.stage("frame_and_filters");

  runStage("octree");
  io::InputStats built;
  if (params.trajectory) {
    result.map = mapper::buildWithTrajectory(points, keyframes, params.octree, built);
    result.report.keyframes = keyframes.size();
    result.keyframes = std::move(keyframes);
  } else if (params.origin) {
    result.map = mapper::buildFromScan(points, origin.front(), params.octree, built);
  } else {
    result.map = mapper::buildFromPoints(points, params.octree, built);
  }
  addDropped(result.report.points, built);
  timer.stage("octree");
}

/// One pass of the streamed build: read -> frame -> levelling -> filters -> octree batch by batch.
struct StreamPass {
  std::vector<io::InputStats> inputs;
  io::InputStats filtered;
  io::InputStats built;
  std::size_t delivered = 0;
  std::size_t kept = 0;
  double read_ms = 0.0;
  double frame_ms = 0.0;
  double octree_ms = 0.0;
  std::optional<mapper::OccupancyMap> map;
  std::exception_ptr bad_octree_params;
};

StreamPass streamPass(const BuildParams& params, const Eigen::Isometry3d& levelling, PointSample* sample) {
  StreamPass pass;
  // The whole-input path meets bad octree parameters when it builds, after the input's errors,
  // "no points" and the filters' error: they are reported in that order here too.
  std::optional<mapper::PointMapBuilder> builder;
  try {
    builder.emplace(params.octree);
  } catch (const Error&) {
    pass.bad_octree_params = std::current_exception();
  }
  const bool level = !isIdentity(levelling);
  const auto consume = [&](io::Points& batch) {
    const auto start = Clock::now();
    pass.delivered += batch.size();
    mapper::toMapFrame(params.frame, batch);
    if (sample) sample->add(batch);
    if (level) applyIsometry(levelling, batch);
    mapper::applyFilters(params.filters, batch, pass.filtered);
    pass.kept += batch.size();
    const auto filtered_at = Clock::now();
    pass.frame_ms += std::chrono::duration<double, std::milli>(filtered_at - start).count();
    if (builder) builder->add(batch, pass.built);
    pass.octree_ms += msSince(filtered_at);
  };
  const auto start = Clock::now();
  pass.inputs = io::streamPointFiles(pathStrings(params.inputs), io::PointStreamParams{}, consume);
  pass.read_ms = msSince(start) - pass.frame_ms - pass.octree_ms;
  if (builder && pass.kept > 0) {
    const auto finish_start = Clock::now();
    pass.map.emplace(builder->finish());
    pass.octree_ms += msSince(finish_start);
  }
  return pass;
}

/// Points only: read -> frame -> filters -> octree batch by batch, so neither the input files nor
/// their points are ever whole in memory; the same tree, counts, account and errors as reading
/// everything first. Times are summed over the batches per stage. The floor is searched on the
/// sample the first pass keeps; when it must be levelled, a second pass builds the levelled tree.
void buildStreamed(const BuildParams& params, BuildResult& result, StageTimer& timer) {
  PointSample sample;
  StreamPass pass = streamPass(params, Eigen::Isometry3d::Identity(), &sample);
  const std::vector<std::string> inputs = pathStrings(params.inputs);
  double read_ms = pass.read_ms, frame_ms = pass.frame_ms, octree_ms = pass.octree_ms;
  if (pass.delivered == 0) {
    result.report.inputs = pass.inputs;
    accountForInputs(result);
    throw noPoints(inputs);
  }
  const auto floor_start = Clock::now();
  const Surfaces surfaces = findSurfaces(params, sample.points(), levelsMap(params, pass.inputs));
  recordSurfaces(surfaces, result);
  recordFrame(params, result.report);
  const double floor_ms = msSince(floor_start);
  if (!isIdentity(surfaces.levelling)) {
    pass = streamPass(params, surfaces.levelling, nullptr);
    read_ms += pass.read_ms;
    frame_ms += pass.frame_ms;
    octree_ms += pass.octree_ms;
  }
  result.report.inputs = pass.inputs;
  accountForInputs(result);
  addDropped(result.report.points, pass.filtered);
  if (pass.kept == 0) throw noPointsInBounds();
  if (pass.bad_octree_params) std::rethrow_exception(pass.bad_octree_params);
  timer.stage("read", read_ms);
  timer.stage("floor", floor_ms);
  timer.stage("frame_and_filters", frame_ms);
  runStage("octree");
  result.map = std::move(*pass.map);
  timer.stage("octree", octree_ms);
  addDropped(result.report.points, pass.built);
}

void checkParams(const BuildParams& params) {
  if (!(params.frame.scale > 0.0) || !std::isfinite(params.frame.scale))
    throw Error::inParameter("scale", "must be a positive finite number");
  if (params.trajectory && params.origin)
    throw Error::inParameter("trajectory/origin", "give one or the other");
  try {
    clustering::extensionParams(clustering::DbscanParams{}, params.extension_rule);
  } catch (const Error& e) {
    throw Error::inParameter("extension_rule", e.what());
  }
  if (params.origin && !params.origin->allFinite())
    throw Error::inParameter("origin", "must be finite");
  if (params.align) {
    if (!params.trajectory)
      throw Error::inParameter("align", "needs the keyframe trajectory (trajectory) to fit to the reference");
    if (params.frame.up != mapper::UpAxis::kPosZ || params.frame.scale != 1.0)
      throw Error::inParameter("align", "the reference trajectory sets the frame and scale: leave up and scale out");
  }
  if (params.level == Level::kOn && params.align)
    throw Error::inParameter("level", "cannot be on with align: the reference trajectory sets the frame");
  if (params.level == Level::kOn && params.floor.mode != mapper::PlaneSetting::Mode::kAuto)
    throw Error::inParameter("level", "on needs the floor found (floor auto): it is the found floor that is levelled");
  if (params.eps && !(*params.eps > 0.0 && std::isfinite(*params.eps)))
    throw Error::inParameter("eps", "must be a positive finite number");
  if (params.min_pts && *params.min_pts < 1) throw Error::inParameter("min_pts", "must be at least 1");
  if (params.convex_parts &&
      !(params.convex_parts->concavity >= 0.0 && std::isfinite(params.convex_parts->concavity)))
    throw Error::inParameter("concavity", "must be a finite number >= 0 (0: the default)");
  if (params.convex_parts && params.convex_parts->flat_gap &&
      !(*params.convex_parts->flat_gap >= 0.0 && std::isfinite(*params.convex_parts->flat_gap)))
    throw Error::inParameter("flat_gap", "must be a finite number >= 0 (0: off)");
  for (const auto* plane : {&params.floor, &params.ceiling})
    if (plane->mode == mapper::PlaneSetting::Mode::kHeight && !std::isfinite(plane->height))
      throw Error::inParameter(plane == &params.floor ? "floor" : "ceiling", "height must be finite");
}

/// Every point used, or none the octree can address: an error.
void finishAccount(const BuildParams& params, BuildResult& result) {
  PointAccount& account = result.report.points;
  account.used = account.read;
  for (const auto& [reason, count] : account.dropped) account.used -= count;
  if (account.used == 0) {
    // Non-finite and cropped points were refused above; the rest fell outside the octree.
    // Keys are 16 bits a coordinate: 2^15 voxels either side of the origin.
    const double reach = params.octree.resolution * 32768;
    std::ostringstream message;
    message << "no point the octree can address: " << account.read << " read, "
            << account.dropped["out_of_octree"] << " out of its reach at resolution "
            << params.octree.resolution << " (about +-" << reach << " map units around the origin; "
            << "a coarser resolution or a smaller scale reaches further)";
    throw Error::inParameter("resolution/scale", message.str());
  }
}

ClusteredVoxels clusterStages(const mapper::OccupancyMap& map, const clustering::DbscanParams& dbscan,
                              const std::function<void()>& clustered) {
  ClusteredVoxels out;
  out.voxels = map.occupiedVoxels();
  std::vector<Eigen::Vector3d> centers;
  std::vector<std::uint32_t> weights;
  centers.reserve(out.voxels.size());
  weights.reserve(out.voxels.size());
  for (const auto& v : out.voxels) {
    centers.push_back(v.center);
    weights.push_back(v.weight);
  }
  out.clusters = clustering::dbscan(centers, weights, dbscan);
  if (clustered) clustered();
  out.obstacles = clustering::buildObstacles(centers, weights, out.clusters.labels, map.resolution());
  return out;
}

}  // namespace

namespace detail {

void attachSurfaceRims(const std::vector<Eigen::Vector3d>& centers, double resolution, double reach,
                       std::vector<std::int32_t>& labels) {
  if (centers.size() != labels.size())
    throw Error::inParameter("labels", "one label per voxel centre expected");
  // Lattice cells: centres lie at (k + 1/2) * resolution, so floor() gives k without ties.
  const auto cell = [&](double v) { return static_cast<std::int64_t>(std::floor(v / resolution)); };
  const auto columnKey = [](std::int64_t i, std::int64_t j) {
    return static_cast<std::uint64_t>(i + (std::int64_t(1) << 31)) << 32 |
           (static_cast<std::uint64_t>(j + (std::int64_t(1) << 31)) & 0xffffffffu);
  };
  const std::int64_t layers = static_cast<std::int64_t>(std::floor(std::max(2.0, reach / resolution) + 1e-9));
  // The reach in whole cells (lattice distances are compared squared, in cells^2).
  const double reach_cells = std::max(reach / resolution, 0.0);
  const double reach2 = reach_cells * reach_cells + 1e-9;
  const std::int64_t span = static_cast<std::int64_t>(std::floor(reach_cells + 1e-9));
  // The clustered voxels of each column, by layer.
  using Column = std::vector<std::pair<std::int64_t, std::int32_t>>;
  std::unordered_map<std::uint64_t, Column> columns;
  for (std::size_t i = 0; i < centers.size(); ++i)
    if (labels[i] >= 0)
      columns[columnKey(cell(centers[i].x()), cell(centers[i].y()))].emplace_back(cell(centers[i].z()), labels[i]);
  for (auto& [key, column] : columns) std::sort(column.begin(), column.end());
  // Calls f(layer, label) for the clustered voxels of column (i, j) with layers in [lo, hi], in
  // order, until f returns true; returns whether it did.
  const auto scan = [&](std::int64_t i, std::int64_t j, std::int64_t lo, std::int64_t hi, auto&& f) {
    const auto hit = columns.find(columnKey(i, j));
    if (hit == columns.end() || lo > hi) return false;
    const Column& column = hit->second;
    for (auto it = std::lower_bound(column.begin(), column.end(), std::make_pair(lo, std::int32_t(-1)));
         it != column.end() && it->first <= hi; ++it)
      if (f(it->first, it->second)) return true;
    return false;
  };
  // Whether the clustered voxel of `label` at (i, j, k) is the near end of a face of its cluster
  // that stands on the surface (sign +1, a floor) or hangs from it (-1, a ceiling): its cluster has
  // two voxels within `reach` of it (centre distance) at least 2 layers farther from the surface. One
  // is not enough: a lone stray voxel (an outlier DBSCAN took in) above a table top is no face.
  std::unordered_map<std::uint64_t, std::unordered_map<std::int64_t, bool>> face_memo[2];  // floor, ceiling
  const auto onFace = [&](std::int64_t i, std::int64_t j, std::int64_t k, std::int32_t label, std::int64_t sign) {
    auto& memo = face_memo[sign > 0 ? 0 : 1][columnKey(i, j)];
    if (const auto found = memo.find(k); found != memo.end()) return found->second;
    const std::int64_t lo = sign > 0 ? k + 2 : k - span, hi = sign > 0 ? k + span : k - 2;
    int evidence = 0;
    for (std::int64_t di = -span; di <= span && evidence < 2; ++di)
      for (std::int64_t dj = -span; dj <= span && evidence < 2; ++dj) {
        if (double(di * di + dj * dj) > reach2) continue;
        scan(i + di, j + dj, lo, hi, [&](std::int64_t layer, std::int32_t l) {
          const std::int64_t dk = layer - k;
          if (l == label && double(di * di + dj * dj + dk * dk) <= reach2) ++evidence;
          return evidence >= 2;
        });
      }
    return memo[k] = evidence >= 2;
  };
  struct Candidate {
    std::int64_t distance;  ///< squared lattice distance to the surface voxel
    std::int32_t label;
    std::int64_t i, j, k;
    bool operator<(const Candidate& o) const { return std::tie(distance, label) < std::tie(o.distance, o.label); }
  };
  std::vector<std::pair<std::size_t, std::int32_t>> joins;
  std::vector<Candidate> candidates;
  for (std::size_t v = 0; v < centers.size(); ++v) {
    if (labels[v] != kFloorLabel && labels[v] != kCeilingLabel) continue;
    const std::int64_t sign = labels[v] == kFloorLabel ? 1 : -1;
    const std::int64_t ci = cell(centers[v].x()), cj = cell(centers[v].y()), ck = cell(centers[v].z());
    // Layers from the surface voxel's on its far side (a floor's: its layer and above; a ceiling's:
    // its layer and below), up to n.
    const auto lo = [&](std::int64_t n) { return sign > 0 ? ck : ck - n; };
    const auto hi = [&](std::int64_t n) { return sign > 0 ? ck + n : ck; };
    // 1 and 2: the clustered voxels of the 3 x 3 columns on the far side within 2 * layers, nearest
    // first. Within `layers` the nearest joins (2 + layers^2 < (layers + 1)^2: these come first);
    // farther, the nearest that is the near end of a face.
    candidates.clear();
    for (std::int64_t di = -1; di <= 1; ++di)
      for (std::int64_t dj = -1; dj <= 1; ++dj)
        scan(ci + di, cj + dj, lo(2 * layers), hi(2 * layers), [&](std::int64_t layer, std::int32_t l) {
          const std::int64_t dk = layer - ck;
          candidates.push_back({di * di + dj * dj + dk * dk, l, ci + di, cj + dj, layer});
          return false;
        });
    std::sort(candidates.begin(), candidates.end());
    for (const Candidate& c : candidates)
      if (std::abs(c.k - ck) <= layers || onFace(c.i, c.j, c.k, c.label, sign)) {
        joins.emplace_back(v, c.label);
        break;
      }
  }
  for (const auto& [v, label] : joins) labels[v] = label;
}

}  // namespace detail

namespace {

/// Centres of the observed-free leaves of the map (each pruned leaf once).
std::vector<Eigen::Vector3d> freeVoxelCentres(const mapper::OccupancyMap& map) {
  std::vector<Eigen::Vector3d> free;
  const auto& tree = map.tree();
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (tree.isNodeOccupied(*it)) continue;
    const auto c = it.getCoordinate();
    free.emplace_back(c.x(), c.y(), c.z());
  }
  return free;
}

/// A floor kept in the input frame tilted by more than this (degrees) is warned about.
constexpr double kKeptFloorTiltDeg = 3.0;

/// The floor and ceiling as solid half-spaces: up to the plane, or to the far face of the highest
/// voxel set aside as that surface when it lies beyond (the voxels lie inside completely).
std::vector<collision::HalfSpace> surfaceHalfSpaces(const BuildReport& report, const std::vector<Eigen::Vector3d>& centers,
                                                    const std::vector<std::int32_t>& labels, double resolution) {
  std::vector<collision::HalfSpace> out;
  const auto add = [&](const PlaneReport& surface, std::int32_t label, const char* name) {
    if (!surface.plane) return;
    const double norm = surface.plane->normal.norm();
    collision::HalfSpace h{name, surface.plane->normal / norm, surface.plane->offset / norm};
    // The support of a voxel cube along the normal, beyond its centre.
    const double half = 0.5 * resolution * h.normal.cwiseAbs().sum();
    for (std::size_t i = 0; i < centers.size(); ++i)
      if (labels[i] == label) h.offset = std::max(h.offset, h.normal.dot(centers[i]) + half);
    out.push_back(std::move(h));
  };
  add(report.floor, kFloorLabel, "floor");
  add(report.ceiling, kCeilingLabel, "ceiling");
  return out;
}

/// The floor's height for closing shells from below, when one height serves the whole map: the
/// plane's height under the voxels' middle when its tilt moves it by at most a voxel across them
/// (a levelled or aligned floor is exactly level).
std::optional<double> levelFloorHeight(const mapper::Plane& floor, const std::vector<Eigen::Vector3d>& centers,
                                       double resolution) {
  const Eigen::Vector3d& n = floor.normal;
  if (!(std::abs(n.z()) > 0.99) || centers.empty()) return std::nullopt;
  Eigen::AlignedBox2d box;
  for (const auto& c : centers) box.extend(c.head<2>());
  const Eigen::Vector2d middle = box.center();
  const double rise = n.head<2>().norm() / std::abs(n.z()) * 0.5 * box.diagonal().norm();
  if (rise > resolution) return std::nullopt;
  return (floor.offset - n.x() * middle.x() - n.y() * middle.y()) / n.z();
}

void clusterInto(BuildResult& result, StageTimer& timer) {
  const BuildParams& params = result.params;
  BuildReport& report = result.report;
  const double resolution = result.map.resolution();
  result.voxels = result.map.occupiedVoxels();
  const std::size_t n = result.voxels.size();
  std::vector<Eigen::Vector3d> centers;
  std::vector<std::uint32_t> weights;
  centers.reserve(n);
  weights.reserve(n);
  for (const auto& v : result.voxels) {
    centers.push_back(v.center);
    weights.push_back(v.weight);
  }

  // Floor and ceiling voxels stay in the map but are not clustered. The band covers the plane's
  // noise (about a voxel) and half a voxel: a voxel holding floor points has its centre within it.
  runStage("surfaces");
  std::vector<std::int32_t> labels(n, clustering::kNoise);
  if (report.floor.plane || report.ceiling.plane) {
    const auto classes = mapper::classifySurfaces(centers, report.floor.plane, report.ceiling.plane, 1.25 * resolution);
    for (std::size_t i = 0; i < n; ++i) {
      if (classes[i] == mapper::SurfaceClass::kFloor) labels[i] = kFloorLabel;
      if (classes[i] == mapper::SurfaceClass::kCeiling) labels[i] = kCeilingLabel;
    }
  }
  std::vector<std::size_t> obstacle_index;
  obstacle_index.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    if (labels[i] == clustering::kNoise) obstacle_index.push_back(i);
  std::vector<Eigen::Vector3d> obstacle_centers;
  std::vector<std::uint32_t> obstacle_weights;
  obstacle_centers.reserve(obstacle_index.size());
  obstacle_weights.reserve(obstacle_index.size());
  for (std::size_t i : obstacle_index) {
    obstacle_centers.push_back(centers[i]);
    obstacle_weights.push_back(weights[i]);
  }
  timer.stage("surfaces");

  runStage("auto_params");
  ClusterParamsReport& chosen = report.cluster_params;
  chosen.used.metric = params.metric;
  chosen.eps_auto = !params.eps;
  chosen.min_pts_auto = !params.min_pts;
  if (chosen.eps_auto || chosen.min_pts_auto) {
    chosen.chosen = clustering::chooseDbscanParams(obstacle_centers, obstacle_weights, resolution, params.metric,
                                                   params.auto_rule);
  }
  chosen.used.eps = params.eps ? *params.eps : chosen.chosen->eps;
  chosen.used.min_pts = params.min_pts ? *params.min_pts : chosen.chosen->min_pts;
  timer.stage("auto_params");

  runStage("dbscan");
  clustering::DbscanResult sub = clustering::dbscan(obstacle_centers, obstacle_weights, chosen.used);
  timer.stage("dbscan");

  if (params.extension.value_or(!params.min_pts)) {
    runStage("extension");
    chosen.extension_params = clustering::extensionParams(chosen.used, params.extension_rule);
    chosen.extension = clustering::extendClusters(obstacle_centers, obstacle_weights, sub, *chosen.extension_params);
    // Stray map points that the eps, wide on a sparse map, took in off the surfaces go back to noise;
    // the floor's and ceiling's voxels support what stands on them (a table leg's foot).
    std::vector<Eigen::Vector3d> surface_centers;
    for (std::size_t i = 0; i < n; ++i)
      if (labels[i] == kFloorLabel || labels[i] == kCeilingLabel) surface_centers.push_back(centers[i]);
    chosen.trim_params =
        clustering::OutlierTrimParams{3.0 * resolution, std::max(3.0 * resolution, chosen.extension_params->reach)};
    chosen.trim = clustering::trimOutliers(obstacle_centers, sub, surface_centers, *chosen.trim_params);
    // A flat cluster in the plane of a larger one around it (a wall's foot that DBSCAN cut off the
    // sparse wall above it) joins it, so that the wall's parts can merge over it.
    chosen.coplanar_params = clustering::CoplanarMergeParams{chosen.used.eps, 3.0 * resolution};
    chosen.coplanar = clustering::mergeCoplanarClusters(obstacle_centers, sub, *chosen.coplanar_params);
    timer.stage("extension");
  }

  runStage("obstacles");
  result.clusters.cluster_sizes = sub.cluster_sizes;
  result.clusters.noise = sub.noise;
  result.clusters.core.assign(n, 0);
  for (std::size_t k = 0; k < obstacle_index.size(); ++k) {
    labels[obstacle_index[k]] = sub.labels[k];
    result.clusters.core[obstacle_index[k]] = sub.core[k];
  }
  // The rims reach as far as the eps used, but no farther than the auto rule's upper clamp: a large
  // eps given by hand (1 m) would otherwise join most of the floor to the walls' feet.
  detail::attachSurfaceRims(centers, resolution, std::min(chosen.used.eps, params.auto_rule.max_eps_voxels * resolution),
                            labels);
  std::vector<std::int32_t> cluster_labels(labels);
  for (auto& l : cluster_labels) l = std::max(l, clustering::kNoise);
  result.obstacles = clustering::buildObstacles(centers, weights, cluster_labels, resolution);
  for (std::size_t i = 0; i < n; ++i) {
    if (labels[i] == kFloorLabel) ++report.floor.voxels;
    if (labels[i] == kCeilingLabel) ++report.ceiling.voxels;
  }
  result.surfaces = surfaceHalfSpaces(report, centers, labels, resolution);
  timer.stage("obstacles");

  if (params.convex_parts) {
    runStage("convex_parts");
    clustering::KnownFreeSpace known;
    for (const auto& k : result.keyframes) known.keyframes.push_back(k.position);
    if (params.trajectory || params.origin) known.free_voxels = freeVoxelCentres(result.map);
    // G unset: the eps used, the distance at which this map's sampling connects a surface.
    clustering::ConvexPartsParams parts_params = *params.convex_parts;
    // Auto G is also adapted to each cluster's sampling (a sparse wall's chance holes); a G the user
    // gives is used as given.
    if (!parts_params.flat_gap) {
      parts_params.flat_gap = chosen.used.eps;
      parts_params.adapt_flat_gap = true;
    }
    // A level floor closes the shells standing on it from below (their bottom is never seen).
    if (report.floor.plane && !parts_params.floor_z) parts_params.floor_z = levelFloorHeight(*report.floor.plane, centers, resolution);
    report.parts = clustering::addConvexParts(result.obstacles, centers, weights, cluster_labels, resolution,
                                              parts_params, known);
    report.keyframes_inside_hulls = report.parts->keyframes_in_voxels;
    timer.stage("convex_parts");
  }
  result.clusters.labels = std::move(labels);

  const clustering::DbscanParams& used = chosen.used;
  report.warnings = clustering::buildWarnings({obstacle_index.size(), result.clusters.noise, result.obstacles.size(),
                                               used.eps, used.min_pts, used.metric, resolution});
  if (!readsOctree(params) && !params.align && !report.floor.levelled) {
    const PlaneReport& floor = report.floor;
    if (floor.plane && floor.setting.mode == mapper::PlaneSetting::Mode::kAuto) {
      if (floor.fit.tilt_deg > kKeptFloorTiltDeg) {
        char text[320];
        std::snprintf(text, sizeof text,
                      "the floor found (%.0f%% of the points) is %.1f degrees from level, and the map was kept in "
                      "its input frame: heights, --z-min/--z-max and footprints are slanted by as much; --level on "
                      "levels it",
                      100.0 * floor.fit.inlier_share, floor.fit.tilt_deg);
        report.warnings.push_back(text);
      }
    } else if (auto tilted = mapper::levelWarning(centers, resolution, upAxisText(params.frame.up))) {
      report.warnings.push_back(*tilted);
    }
  }
}

}  // namespace

namespace detail {
void (*stage_hook)(const char* stage) = nullptr;
}  // namespace detail

std::string upAxisText(mapper::UpAxis up) {
  const std::string text = mapper::toString(up);
  return text[0] == '+' ? text.substr(1) : text;
}

std::string frameDescription(const mapper::FrameParams& frame) {
  std::ostringstream s;
  s << "z-up map frame: input axis " << upAxisText(frame.up) << " rotated to +z";
  if (frame.scale != 1.0) s << ", scaled by " << frame.scale;
  return s.str();
}

bool readsOctree(const BuildParams& params) {
  return params.inputs.size() == 1 && isOctomapFile(params.inputs.front());
}

std::string outputFrame(const BuildResult& result) {
  if (readsOctree(result.params)) {
    return "the octree's own frame (" + result.params.inputs.front().string() +
           " read as it is: no up axis or scale applied)";
  }
  std::ostringstream s;
  if (result.report.alignment && result.params.align) {
    s << "the reference trajectory's frame (" << result.params.align->reference.string()
      << ": keyframes fitted by a similarity, scale " << result.report.alignment->transform.scale << ")";
  } else {
    s << frameDescription(result.params.frame);
  }
  if (result.report.floor.levelled) {
    s << ", then levelled: the floor rotated level and moved to z = 0 (report.json \"levelling\")";
  }
  return s.str();
}

bool levelsMap(const BuildParams& params, const std::vector<io::InputStats>& inputs) {
  if (params.align || readsOctree(params) || params.floor.mode != mapper::PlaneSetting::Mode::kAuto) return false;
  if (params.level != Level::kAuto) return params.level == Level::kOn;
  if (params.camera_frame) return *params.camera_frame;
  if (params.frame.up != mapper::UpAxis::kPosZ) return true;
  for (const auto& input : inputs)
    if (mapper::looksLikeOrbSlam(input)) return true;
  if (params.trajectory) {
    io::InputStats trajectory;  // KeyFrameTrajectory.txt: a SLAM run's keyframes, in its camera's frame
    trajectory.path = params.trajectory->string();
    trajectory.format = "tum";
    return mapper::looksLikeOrbSlam(trajectory);
  }
  return false;
}

namespace {

/// Whether levelsMap may say yes once the inputs are read: their formats are sniffed here (the first
/// bytes of each regular file); an input that cannot be sniffed without being consumed (a pipe) may.
bool mayLevel(const BuildParams& params) {
  if (params.align || params.floor.mode != mapper::PlaneSetting::Mode::kAuto || params.level == Level::kOff)
    return false;
  std::vector<io::InputStats> sniffed;
  for (const auto& input : params.inputs) {
    std::error_code ec;
    if (!fs::is_regular_file(input, ec)) return true;
    io::InputStats stats;
    stats.path = input.string();
    try {
      stats.format = io::toString(io::detectPointFormat(stats.path));
    } catch (const Error&) {
      return true;  // the read names what is wrong with it
    }
    sniffed.push_back(stats);
  }
  return levelsMap(params, sniffed);
}

}  // namespace

ClusteredVoxels clusterMap(const mapper::OccupancyMap& map, const clustering::DbscanParams& dbscan) {
  return clusterStages(map, dbscan, nullptr);
}

BuildResult build(const BuildParams& params) {
  BuildResult result;
  result.params = params;
  StageTimer timer(result.report);
  if (params.inputs.empty()) throw Error::inParameter("inputs", "no input files");
  checkParams(params);
  runStage("read");

  if (readsOctree(params)) {
    // A finished map: no points to account for, voxels weigh 1 each.
    result.map = mapper::readMap(params.inputs.front().string());
    io::InputStats stats;
    stats.path = params.inputs.front().string();
    stats.format = params.inputs.front().extension().string().substr(1);
    result.report.inputs.push_back(stats);
    timer.stage("read");
  } else {
    for (const auto& input : params.inputs)
      if (isOctomapFile(input))
        throw Error(input.string() + ": an octomap file can only be the single input of build");
    // A floor found in the streamed points may need a second pass over the inputs to level the
    // map: inputs that cannot be read twice (a FIFO, standard input) are then read whole.
    const bool readable_twice = std::all_of(params.inputs.begin(), params.inputs.end(), [](const fs::path& p) {
      std::error_code ec;
      return fs::is_regular_file(p, ec);
    });
    const bool may_level = mayLevel(params);
    // Levelling found in a streamed first pass costs a second pass (reading and octree again); inputs
    // small enough to hold (params.stream_above_bytes) are read whole once.
    std::uintmax_t input_bytes = 0;
    for (const auto& input : params.inputs) {
      std::error_code ec;
      const auto size = fs::file_size(input, ec);
      input_bytes += ec ? params.stream_above_bytes : size;
    }
    const bool small = readable_twice && input_bytes < params.stream_above_bytes;
    if (!params.trajectory && !params.origin && (readable_twice || !may_level) && !(may_level && small)) {
      buildStreamed(params, result, timer);
    } else {
      io::PointSet set = readInputPoints(pathStrings(params.inputs));
      result.report.inputs = set.inputs;
      buildWhole(params, std::move(set.points), result, timer);
    }
    finishAccount(params, result);
  }
  clusterInto(result, timer);
  return result;
}

BuildResult buildFromPoints(io::Points points, const BuildParams& params, const std::string& name) {
  return buildFromPoints(std::move(points), std::nullopt, params, name);
}

BuildResult buildFromPoints(io::Points points, std::optional<std::vector<io::Keyframe>> keyframes,
                            const BuildParams& params, const std::string& name, const std::string& keyframes_name) {
  BuildResult result;
  result.params = params;
  result.params.inputs.clear();
  if (keyframes) {
    if (params.trajectory) throw Error::inParameter("trajectory", "give a trajectory file or keyframes, not both");
    result.params.trajectory = keyframes_name;
  }
  StageTimer timer(result.report);
  checkParams(result.params);
  runStage("read");
  io::InputStats stats;
  stats.path = name;
  stats.format = "memory";
  stats.read = points.size();
  // Non-finite points are dropped as the file readers drop them.
  const auto finite_end = std::stable_partition(points.begin(), points.end(),
                                                [](const io::Point& p) { return p.allFinite(); });
  const std::size_t non_finite = static_cast<std::size_t>(points.end() - finite_end);
  points.erase(finite_end, points.end());
  if (non_finite > 0) stats.dropped["non_finite"] = non_finite;
  result.report.inputs.push_back(stats);
  if (points.empty()) throw Error(name + ": no points");
  buildWhole(result.params, std::move(points), result, timer, keyframes ? &*keyframes : nullptr);
  finishAccount(result.params, result);
  clusterInto(result, timer);
  return result;
}

std::vector<clustering::Obstacle> readObstacles(const fs::path& obstacles_json) {
  return readObstaclesJson(obstacles_json.string());
}

namespace {

nlohmann::json planeSettingJson(const mapper::PlaneSetting& setting) {
  switch (setting.mode) {
    case mapper::PlaneSetting::Mode::kAuto: return "auto";
    case mapper::PlaneSetting::Mode::kNone: return "none";
    case mapper::PlaneSetting::Mode::kHeight: break;
  }
  return setting.height;
}

nlohmann::json planeJson(const mapper::Plane& plane) {
  return {{"normal", {plane.normal.x(), plane.normal.y(), plane.normal.z()}}, {"offset", plane.offset}};
}

nlohmann::json planeReportJson(const PlaneReport& r) {
  using nlohmann::json;
  json out = {{"setting", planeSettingJson(r.setting)},
              {"found", r.plane.has_value()},
              {"plane", r.plane ? planeJson(*r.plane) : json(nullptr)},
              {"levelled", r.levelled},
              {"voxels", r.voxels}};
  if (r.setting.mode == mapper::PlaneSetting::Mode::kAuto) {
    out["search"] = {{"found", r.fit.found},
                     {"reason", r.fit.found ? json(nullptr) : json(r.fit.reason)},
                     {"candidate", planeJson(r.fit.plane)},
                     {"tilt_deg", r.fit.tilt_deg},
                     {"inliers", r.fit.inliers},
                     {"inlier_share", r.fit.inlier_share},
                     {"beyond_share", r.fit.beyond_share},
                     {"coverage", r.fit.coverage}};
  }
  return out;
}

nlohmann::json matrixRows(const Eigen::Matrix3d& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2)});
  return rows;
}

nlohmann::json alignmentJson(const mapper::Alignment& a, const std::map<std::string, std::size_t>& reference_dropped) {
  const auto& t = a.transform;
  return {{"scale", t.scale},
          {"rotation", matrixRows(t.rotation)},
          {"translation", {t.translation.x(), t.translation.y(), t.translation.z()}},
          {"rmse", a.rmse},
          {"max_error", a.max_error},
          {"matched", a.matched},
          {"unmatched", a.unmatched},
          {"reference_dropped", reference_dropped}};
}

}  // namespace

nlohmann::json parametersJson(const BuildParams& params) {
  using nlohmann::json;
  const auto numbers = [](std::initializer_list<double> values) {
    std::string text;
    for (double v : values) {
      char buffer[32];
      text += (text.empty() ? "" : ",") + std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
    }
    return text;
  };
  json origin = nullptr;
  if (params.origin) origin = numbers({params.origin->x(), params.origin->y(), params.origin->z()});
  json crop = nullptr;
  if (params.filters.crop) {
    const auto& box = *params.filters.crop;
    crop = numbers({box.min.x(), box.min.y(), box.min.z(), box.max.x(), box.max.y(), box.max.z()});
  }
  return {
      {"inputs", pathStrings(params.inputs)},
      {"trajectory", params.trajectory ? json(params.trajectory->string()) : json(nullptr)},
      {"origin", origin},
      {"up", upAxisText(params.frame.up)},
      {"scale", params.frame.scale},
      {"crop", crop},
      {"z_min", params.filters.z_min ? json(*params.filters.z_min) : json(nullptr)},
      {"z_max", params.filters.z_max ? json(*params.filters.z_max) : json(nullptr)},
      {"resolution", params.octree.resolution},
      {"hit", params.octree.sensor.hit},
      {"miss", params.octree.sensor.miss},
      {"clamp_min", params.octree.sensor.clamp_min},
      {"clamp_max", params.octree.sensor.clamp_max},
      {"occupancy_threshold", params.octree.sensor.occupancy_threshold},
      {"max_range", params.octree.max_range},
      {"align", params.align ? json(params.align->reference.string()) : json(nullptr)},
      {"align_format", params.align ? json(io::toString(params.align->format)) : json(nullptr)},
      {"align_tolerance", params.align ? json(params.align->params.stamp_tolerance) : json(nullptr)},
      {"floor", planeSettingJson(params.floor)},
      {"level", params.level == Level::kOn ? "on" : params.level == Level::kOff ? "off" : "auto"},
      {"ceiling", planeSettingJson(params.ceiling)},
      {"eps", params.eps ? json(*params.eps) : json("auto")},
      {"min_pts", params.min_pts ? json(*params.min_pts) : json("auto")},
      {"metric", clustering::toString(params.metric)},
      {"concavity", !params.convex_parts ? json("none")
                    : params.convex_parts->concavity > 0.0 ? json(params.convex_parts->concavity)
                                                           : json("default")},
      {"flat_gap", !params.convex_parts || !params.convex_parts->flat_gap ? json("auto")
                                                                           : json(*params.convex_parts->flat_gap)},
      {"extension", !params.extension ? "auto" : *params.extension ? "on" : "off"},
      {"ot", params.write_ot},
  };
}

nlohmann::json reportJson(const BuildResult& result) {
  using nlohmann::json;
  const BuildReport& report = result.report;
  json inputs = json::array();
  for (const auto& in : report.inputs) {
    inputs.push_back({{"path", in.path}, {"format", in.format}, {"points_read", in.read},
                      {"points_dropped", in.dropped}});
  }
  json timings = json::object();
  double total = 0.0;
  for (const auto& [stage, ms] : report.timings_ms) {
    timings[stage] = ms;
    total += ms;
  }
  timings["total"] = total;
  json peak = json::object();
  for (const auto& [stage, mb] : report.peak_rss_mb) peak[stage] = mb;
  const auto info = mapper::describe(result.map.tree());
  std::vector<std::size_t> largest(result.clusters.cluster_sizes);
  std::sort(largest.rbegin(), largest.rend());
  if (largest.size() > 10) largest.resize(10);
  std::size_t core = 0;
  for (auto c : result.clusters.core) core += c;

  json parameters = parametersJson(result.params);
  const ClusterParamsReport& cp = report.cluster_params;
  parameters["eps"] = cp.used.eps;
  parameters["min_pts"] = cp.used.min_pts;
  parameters["eps_auto"] = cp.eps_auto;
  parameters["min_pts_auto"] = cp.min_pts_auto;
  json clustering_params = {{"eps", cp.used.eps}, {"eps_auto", cp.eps_auto},
                            {"min_pts", cp.used.min_pts}, {"min_pts_auto", cp.min_pts_auto}};
  if (cp.chosen) {
    const auto& c = *cp.chosen;
    clustering_params["auto"] = {{"knn", std::isfinite(c.knn) ? json(c.knn) : json(nullptr)},
                                 {"eps_unclamped", std::isfinite(c.eps_unclamped) ? json(c.eps_unclamped) : json(nullptr)},
                                 {"sampled", c.sampled},
                                 {"structured", c.structured},
                                 {"eps", c.eps},
                                 {"min_pts", c.min_pts}};
  }
  clustering_params["extension"] = nullptr;
  if (cp.extension_params) {
    clustering_params["extension"] = {{"min_pts", cp.extension_params->min_pts},
                                      {"reach", cp.extension_params->reach},
                                      {"joined", cp.extension.joined},
                                      {"rounds", cp.extension.rounds}};
  }
  clustering_params["outlier_trim"] = nullptr;
  if (cp.trim_params)
    clustering_params["outlier_trim"] = {
        {"radius", cp.trim_params->radius}, {"reach", cp.trim_params->reach}, {"dropped", cp.trim.dropped}};
  clustering_params["coplanar_merge"] = nullptr;
  if (cp.coplanar_params) {
    clustering_params["coplanar_merge"] = {{"reach", cp.coplanar_params->reach},
                                           {"thickness", cp.coplanar_params->thickness},
                                           {"merged", cp.coplanar.merged},
                                           {"points", cp.coplanar.points}};
  }
  json parts = nullptr;
  if (report.parts) {
    const auto& p = *report.parts;
    std::size_t split = 0, largest = 0;
    for (const auto& o : result.obstacles) {
      split += o.parts.size() > 1;
      largest = std::max(largest, o.parts.size());
    }
    parts = {{"count", p.parts},
             {"concavity", p.concavity},
             {"flat_gap", p.flat_gap},
             {"flat_gap_max", p.flat_gap_max},
             {"flat_parts", p.flat_parts},
             {"face_parts", p.face_parts},
             {"per_obstacle", result.obstacles.empty() ? 0.0 : double(p.parts) / double(result.obstacles.size())},
             {"obstacles_split", split},
             {"most_parts_of_one_obstacle", largest},
             {"hull_volume_before", p.hull_volume_before},
             {"hull_volume_after", p.hull_volume_after},
             {"voxel_volume", p.voxel_volume},
             {"free_voxels_inside", p.free_voxels_inside},
             {"free_voxels_off_surface", p.free_voxels_off_surface},
             {"keyframes_inside_hulls", report.keyframes_inside_hulls}};
  }
  if (readsOctree(result.params)) {
    // A finished octree is read as it is: record what it holds, not parameters that were not applied.
    const auto& tree = result.map.tree();
    for (const char* key : {"trajectory", "origin", "up", "scale", "crop", "z_min", "z_max", "max_range", "level"})
      parameters[key] = nullptr;
    parameters["resolution"] = info.resolution;
    parameters["hit"] = tree.getProbHit();
    parameters["miss"] = tree.getProbMiss();
    parameters["clamp_min"] = tree.getClampingThresMin();
    parameters["clamp_max"] = tree.getClampingThresMax();
    parameters["occupancy_threshold"] = tree.getOccupancyThres();
  }
  return {
      {"hullmap_version", HULLMAP_VERSION},
      {"frame", outputFrame(result)},
      {"parameters", parameters},
      {"warnings", report.warnings},
      {"inputs", inputs},
      {"points", {{"read", report.points.read},
                  {"dropped", report.points.dropped},
                  {"used", report.points.used}}},
      {"keyframes", report.keyframes},
      {"alignment", report.alignment ? alignmentJson(*report.alignment, report.reference_dropped) : json(nullptr)},
      {"floor", readsOctree(result.params) ? json(nullptr) : planeReportJson(report.floor)},
      {"ceiling", readsOctree(result.params) ? json(nullptr) : planeReportJson(report.ceiling)},
      {"levelling", {{"rotation", matrixRows(report.levelling.linear())},
                     {"translation", {report.levelling.translation().x(), report.levelling.translation().y(),
                                      report.levelling.translation().z()}}}},
      {"input_to_output", similarityJson(report.input_to_output)},
      {"octree", {{"resolution", info.resolution},
                  {"bounds", {{"min", {info.min.x(), info.min.y(), info.min.z()}},
                              {"max", {info.max.x(), info.max.y(), info.max.z()}}}},
                  {"occupied_leaves", info.occupied_leaves},
                  {"free_leaves", info.free_leaves},
                  {"nodes", info.nodes},
                  {"memory_bytes", info.memory_bytes},
                  {"occupied_voxels", result.voxels.size()}}},
      {"clusters", {{"count", result.clusters.cluster_sizes.size()},
                    {"noise_voxels", result.clusters.noise},
                    {"core_voxels", core},
                    {"largest_voxel_counts", largest}}},
      {"clustering", clustering_params},
      {"obstacles", result.obstacles.size()},
      {"parts", parts},
      {"timings_ms", timings},
      {"peak_rss_mb", peak},
  };
}

nlohmann::json readReport(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open (is this a hullmap build directory?)");
  nlohmann::json report;
  try {
    in >> report;
  } catch (const nlohmann::json::exception& e) {
    throw Error(path.string() + ": not valid JSON: " + e.what());
  }
  const auto params = report.find("parameters");
  if (params == report.end() || !params->is_object()) throw Error(path.string() + ": no \"parameters\" object");
  const auto resolution = params->find("resolution");
  if (resolution == params->end() || !resolution->is_number() || !(resolution->get<double>() > 0.0)) {
    throw Error(path.string() + ": parameters.resolution missing or not a positive number");
  }
  return report;
}

void writeVoxelsCsv(const fs::path& path, const std::vector<mapper::OccupiedVoxel>& voxels,
                    const clustering::DbscanResult& clusters) {
  core::writeFileAtomically(path.string(), [&](std::ostream& os) {
    os << "x,y,z,weight,label,core\n" << std::setprecision(9);
    for (std::size_t i = 0; i < voxels.size(); ++i) {
      const auto& v = voxels[i];
      os << v.center.x() << ',' << v.center.y() << ',' << v.center.z() << ',' << v.weight << ','
         << clusters.labels[i] << ',' << int(clusters.core[i]) << '\n';
    }
  });
}

std::vector<VoxelRow> readVoxelsCsv(const fs::path& path) {
  const std::string name = path.string();
  std::ifstream in(path);
  if (!in) throw Error(name + ": cannot open (is this a hullmap build directory?)");
  std::string line;
  if (!std::getline(in, line) || line.rfind("x,y,z,weight,label", 0) != 0) {
    throw Error(name + ":1: expected header x,y,z,weight,label,core");
  }
  std::vector<VoxelRow> rows;
  std::size_t number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line == "\r") continue;
    std::istringstream fields(line);
    double v[6] = {0, 0, 0, 0, 0, 0};
    char comma = 0;
    bool ok = static_cast<bool>(fields >> v[0]);
    for (int i = 1; ok && i < 5; ++i) ok = (fields >> comma) && comma == ',' && (fields >> v[i]);
    if (ok && (fields >> comma)) ok = comma == ',' && (fields >> v[5]);
    if (!ok || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      throw Error(name + ":" + std::to_string(number) + ": expected x,y,z,weight,label,core numbers");
    }
    VoxelRow row;
    row.center = Eigen::Vector3d(v[0], v[1], v[2]);
    row.weight = static_cast<std::uint32_t>(v[3]);
    row.label = static_cast<std::int32_t>(v[4]);
    row.core = v[5] != 0.0;
    rows.push_back(row);
  }
  return rows;
}

namespace {

/// Holds an exclusive flock(2) on a staging directory while a run writes into it. The kernel drops
/// the lock when the process ends, however it ends (SIGKILL included), so "can this directory be
/// locked?" tells a killed run's leftovers from a live run's work. The pid in the name cannot tell:
/// pids are reused, and by the next run a killed run's pid may belong to any process.
class StagingLock {
 public:
  explicit StagingLock(const fs::path& dir) : fd_(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)) {
    if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0)
      throw Error(dir.string() + ": cannot lock staging directory: " + std::strerror(errno));
    // A run sweeping stale staging directories may have locked and removed this one in the moment
    // between its creation and the lock above.
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || st.st_nlink == 0)
      throw Error(dir.string() + ": staging directory was removed by another run into the same output");
  }
  StagingLock(const StagingLock&) = delete;
  StagingLock& operator=(const StagingLock&) = delete;
  ~StagingLock() { ::close(fd_); }

 private:
  int fd_;
};

/// Removes `.NAME.new<pid>` siblings left by runs that were killed: those nobody holds a lock on.
/// Those of a live run (another hullmap writing the same output) are locked and left alone.
void removeStaleStaging(const fs::path& parent, const std::string& name) {
  const std::string prefix = "." + name + ".new";
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(parent, ec)) {
    const std::string file = entry.path().filename().string();
    if (file.size() <= prefix.size() || file.compare(0, prefix.size(), prefix) != 0) continue;
    if (file.find_first_not_of("0123456789", prefix.size()) != std::string::npos) continue;
    const int fd = ::open(entry.path().c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {  // held while removing: a racing creator waits
      std::error_code ignored;
      fs::remove_all(entry.path(), ignored);
    }
    ::close(fd);
  }
}

}  // namespace

void checkOutputDir(const fs::path& dir, const BuildParams& params, const WriteOptions& options) {
  mapper::OutputDirPolicy policy;
  for (const auto& input : params.inputs) policy.inputs.push_back(input.string());
  if (params.trajectory) policy.inputs.push_back(params.trajectory->string());
  policy.make_parents = options.make_parents;
  mapper::checkOutputDir(dir.string(), policy);
}

void write(const BuildResult& result, const fs::path& dir, const WriteOptions& options) {
  const std::string name = dir.string();
  checkOutputDir(dir, result.params, options);  // again: the build may have run for a while
  fs::path out = fs::absolute(dir).lexically_normal();
  if (out.filename().empty()) out = out.parent_path();  // "out/" is "out"
  const fs::path parent = out.parent_path();
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec) throw Error(name + ": cannot create " + parent.string() + ": " + ec.message());
  removeStaleStaging(parent, out.filename().string());

  const fs::path staging = parent / ("." + out.filename().string() + ".new" + std::to_string(::getpid()));
  fs::remove_all(staging, ec);
  fs::create_directories(staging, ec);
  if (ec) {
    throw Error(name + ": cannot create its staging directory " + staging.string() + ": " + ec.message());
  }
  try {
    const StagingLock lock(staging);
    runStage("write");
    mapper::writeMap(result.map, (staging / "map.bt").string());
    if (result.params.write_ot) mapper::writeMap(result.map, (staging / "map.ot").string());
    runStage("wrote_map");
    writeVoxelsCsv(staging / "voxels.csv", result.voxels, result.clusters);
    runStage("wrote_voxels");
    const nlohmann::json report = reportJson(result);
    ObstaclesMeta meta;
    meta.frame = outputFrame(result);
    meta.parameters = report["parameters"];
    meta.surfaces = result.surfaces;
    meta.input_to_output = result.report.input_to_output;
    writeObstaclesJson((staging / "obstacles.json").string(), result.obstacles, meta);
    writeObstaclesObj((staging / "obstacles.obj").string(), result.obstacles);
    runStage("wrote_obstacles");
    core::writeFileAtomically((staging / "report.json").string(),
                              [&](std::ostream& os) { os << report.dump(2) << '\n'; });
    std::vector<std::string> written{"map.bt", "voxels.csv", "obstacles.json", "obstacles.obj", "report.json"};
    if (result.params.write_ot) written.push_back("map.ot");
    if (!result.keyframes.empty()) {
      writeTumTrajectory(staging / kTrajectoryFile, result.keyframes);
      written.push_back(kTrajectoryFile);
    }
    mapper::writeOutputMarker(staging.string(), written);

    runStage("move_into_place");
    checkOutputDir(dir, result.params, options);  // a file put there during the build is not removed with the old output
    // One atomic step puts the finished directory in place: a rename when there is no previous
    // output, else an exchange of the two directories (Linux renameat2), after which the staging
    // name holds the previous output. At no instant is there no OUT/ or a half-written one.
    if (!fs::exists(out)) {
      fs::rename(staging, out, ec);
      if (ec) throw Error(name + ": cannot move into place: " + ec.message());
    } else {
      if (::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, out.c_str(), RENAME_EXCHANGE) != 0)
        throw Error(name + ": cannot replace: " + std::strerror(errno));
      fs::remove_all(staging, ec);  // the previous output
    }
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    throw;
  }
}

}  // namespace hullmap::pipeline
