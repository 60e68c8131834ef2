// The build up to the octree: the inputs read whole or streamed in two passes, the frame, the floor
// and the filters; then cluster_stages.cpp's stage list from the voxels to the obstacles.
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/pipeline/detail/test_hooks.hpp"

#include <sys/resource.h>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>
#include <tuple>
#include <unordered_map>

#include "cluster_stages.hpp"
#include "ground.hpp"
#include "hullmap/clustering/build_warnings.hpp"
#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/mapper/level_check.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/pipeline/report.hpp"
#include "hullmap/pipeline/voxels_csv.hpp"
#include "input_points.hpp"
#include "resolution.hpp"
#include "stage_timer.hpp"
#include "stages.hpp"
#include "surfaces.hpp"

namespace hullmap::pipeline {
namespace {

namespace fs = std::filesystem;

bool isOctomapFile(const fs::path& path) {
  const std::string ext = path.extension().string();
  return ext == ".bt" || ext == ".ot";
}

void addDropped(PointAccount& account, const io::InputStats& stats) {
  for (const auto& [reason, count] : stats.dropped) account.dropped[reason] += count;
}

Error noPointsInBounds() { return Error::inParameter("crop/z_min/z_max", "no points left inside the bounds"); }

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
  std::size_t stride() const { return stride_; }

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
  const auto reference =
      align.poses ? *align.poses : io::readReferenceTrajectory(align.reference.string(), align.format, &stats);
  report.reference_dropped = stats.dropped;
  std::size_t dropped = 0;
  for (const auto& [reason, count] : stats.dropped) dropped += count;
  const std::string without_fix =
      dropped == 0 ? ""
                   : "; " + std::to_string(dropped) + " line" + (dropped == 1 ? "" : "s") + " without a fix dropped";
  if (reference.empty()) throw Error(align.reference.string() + ": no reference poses" + without_fix);
  try {
    return mapper::alignTrajectory(keyframes, reference, align.params);
  } catch (const Error& e) {
    // Named as the parameter, so that the CLI says --align.
    const std::string text = e.what();
    if (!e.parameter().empty() || text.rfind("align: ", 0) != 0) throw;
    throw Error::inParameter(
        "align",
        text.substr(7) + (without_fix.empty() ? "" : " (" + align.reference.string() + without_fix.substr(1) + ")"));
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
    mapper::applyAlignment(*result.report.alignment, points);
    mapper::applyAlignment(*result.report.alignment, keyframes);
    timer.stage("align");
  } else {
    mapper::toMapFrame(params.frame, keyframes);
    mapper::toMapFrame(params.frame, points);
    mapper::toMapFrame(params.frame, origin);
  }
  PointSample sample;
  sample.add(points);
  // `params` may be result.params itself: copied before result.params records the resolution used.
  const BuildParams used =
      atResolution(params, chooseResolution(params, sample.points(), sample.stride(), result.report));
  result.params.octree.resolution = used.octree.resolution;
  const Surfaces surfaces = findSurfaces(used, sample.points(), levelsMap(used, result.report.inputs));
  if (!isIdentity(surfaces.levelling)) {
    applyIsometry(surfaces.levelling, points);
    applyIsometry(surfaces.levelling, keyframes);
    applyIsometry(surfaces.levelling, origin);
  }
  recordSurfaces(surfaces, result);
  recordFrame(used, result.report);
  recordGround(used, sample.points(), keyframes, result);
  timer.stage("floor");
  io::InputStats filtered;
  mapper::applyFilters(used.filters, points, filtered);
  addDropped(result.report.points, filtered);
  if (points.empty()) throw noPointsInBounds();
  timer.stage("frame_and_filters");

  runStage("octree");
  io::InputStats built;
  if (used.trajectory) {
    result.map = mapper::buildWithTrajectory(points, keyframes, used.octree, built);
    result.report.keyframes = keyframes.size();
    result.keyframes = std::move(keyframes);
  } else if (used.origin) {
    result.map = mapper::buildFromScan(points, origin.front(), used.octree, built);
  } else {
    result.map = mapper::buildFromPoints(points, used.octree, built);
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
  // `params` may be result.params itself: copied before result.params records the resolution used.
  const BuildParams used =
      atResolution(params, chooseResolution(params, sample.points(), sample.stride(), result.report));
  result.params.octree.resolution = used.octree.resolution;
  const Surfaces surfaces = findSurfaces(used, sample.points(), levelsMap(used, pass.inputs));
  recordSurfaces(surfaces, result);
  recordFrame(used, result.report);
  recordGround(used, sample.points(), {}, result);
  const double floor_ms = msSince(floor_start);
  // A second pass when the map must be levelled or the first pass's octree has another resolution.
  if (!isIdentity(surfaces.levelling) || used.octree.resolution != params.octree.resolution) {
    pass = streamPass(used, surfaces.levelling, nullptr);
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
  if (params.trajectory && params.origin) throw Error::inParameter("trajectory/origin", "give one or the other");
  try {
    clustering::extensionParams(clustering::DbscanParams{}, params.extension_rule);
  } catch (const Error& e) {
    throw Error::inParameter("extension_rule", e.what());
  }
  if (params.origin && !params.origin->allFinite()) throw Error::inParameter("origin", "must be finite");
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
  if (params.convex_parts && !(params.convex_parts->concavity >= 0.0 && std::isfinite(params.convex_parts->concavity)))
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
    message << "no point the octree can address: " << account.read << " read, " << account.dropped["out_of_octree"]
            << " out of its reach at resolution " << params.octree.resolution << " (about +-" << reach
            << " map units around the origin; "
            << "a coarser resolution or a smaller scale reaches further)";
    throw Error::inParameter("resolution/scale", message.str());
  }
}

}  // namespace

namespace detail {
void (*stage_hook)(const char* stage) = nullptr;
}  // namespace detail

bool readsOctree(const BuildParams& params) {
  return params.inputs.size() == 1 && isOctomapFile(params.inputs.front());
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
  out.obstacles = hulls::buildObstacles(centers, weights, out.clusters.labels, map.resolution());
  return out;
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
      if (isOctomapFile(input)) throw Error(input.string() + ": an octomap file can only be the single input of build");
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
    finishAccount(result.params, result);
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
  const auto finite_end =
      std::stable_partition(points.begin(), points.end(), [](const io::Point& p) { return p.allFinite(); });
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

std::vector<hulls::Obstacle> readObstacles(const fs::path& obstacles_json) {
  return readObstaclesJson(obstacles_json.string());
}

}  // namespace hullmap::pipeline
