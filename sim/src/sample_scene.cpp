#include "hullmap/sim/sample_scene.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <ostream>

#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/core/number_text.hpp"
#include "outdoor_scene.hpp"
#include "scene_random.hpp"

namespace hullmap::sim {
namespace {

using core::RandomDraws;
using detail::forEachSeeded;
using detail::kCameraHeight;
using detail::kChunk;
using detail::transformPoints;

// Samples the surface of one obstacle: half the points near edges, half on visible faces.
class SurfaceSampler {
 public:
  explicit SurfaceSampler(const TruthShape& o) : o_(o) {
    const Eigen::Vector3d& s = o.size;
    if (o.shape == TruthShape::Shape::kBox) {
      face_weights_ = {s.x() * s.y(), s.x() * s.z(), s.x() * s.z(), s.y() * s.z(), s.y() * s.z()};
      edge_weights_ = {s.x(), s.x(), s.x(), s.x(), s.y(), s.y(), s.y(), s.y(), s.z(), s.z(), s.z(), s.z()};
    } else {
      const double r = 0.5 * s.x();
      face_weights_ = {kPi * r * r, 2.0 * kPi * r * s.z()};
      edge_weights_ = {1.0, 1.0};
    }
    area_ = 0.0;
    for (double w : face_weights_) area_ += w;
  }

  double area() const { return area_; }

  Eigen::Vector3d sample(core::RandomDraws& rng) const {
    const Eigen::Vector3d h = 0.5 * o_.size;
    const Eigen::Vector3d& c = o_.center;
    const bool on_edge = rng.uniform() < 0.5;
    const std::size_t i = pick(on_edge ? edge_weights_ : face_weights_, rng);
    if (o_.shape == TruthShape::Shape::kCylinder) {
      const double a = 2.0 * kPi * rng.uniform();
      const Eigen::Vector3d radial(std::cos(a), std::sin(a), 0.0);
      if (on_edge) return c + h.x() * radial + Eigen::Vector3d(0, 0, i == 0 ? h.z() : -h.z());
      if (i == 0) return c + h.x() * std::sqrt(rng.uniform()) * radial + Eigen::Vector3d(0, 0, h.z());
      return c + h.x() * radial + Eigen::Vector3d(0, 0, rng.uniform(-h.z(), h.z()));
    }
    const double u = rng.uniform(-1.0, 1.0);
    const double v = rng.uniform(-1.0, 1.0);
    if (on_edge) {
      // Edges 0-3 along x, 4-7 along y, 8-11 along z; the two low bits pick the sides.
      const double s1 = (i & 1) ? 1.0 : -1.0;
      const double s2 = (i & 2) ? 1.0 : -1.0;
      if (i < 4) return c + Eigen::Vector3d(u * h.x(), s1 * h.y(), s2 * h.z());
      if (i < 8) return c + Eigen::Vector3d(s1 * h.x(), u * h.y(), s2 * h.z());
      return c + Eigen::Vector3d(s1 * h.x(), s2 * h.y(), u * h.z());
    }
    switch (i) {
      case 0:
        return c + Eigen::Vector3d(u * h.x(), v * h.y(), h.z());
      case 1:
        return c + Eigen::Vector3d(u * h.x(), -h.y(), v * h.z());
      case 2:
        return c + Eigen::Vector3d(u * h.x(), h.y(), v * h.z());
      case 3:
        return c + Eigen::Vector3d(-h.x(), u * h.y(), v * h.z());
      default:
        return c + Eigen::Vector3d(h.x(), u * h.y(), v * h.z());
    }
  }

 private:
  static std::size_t pick(const std::vector<double>& weights, core::RandomDraws& rng) {
    double total = 0.0;
    for (double w : weights) total += w;
    double x = rng.uniform() * total;
    for (std::size_t i = 0; i + 1 < weights.size(); ++i) {
      if (x < weights[i]) return i;
      x -= weights[i];
    }
    return weights.size() - 1;
  }

  TruthShape o_;  // a box or cylinder
  std::vector<double> face_weights_;
  std::vector<double> edge_weights_;
  double area_ = 0.0;
};

double footprintGap(const TruthShape& a, const TruthShape& b) {
  const double dx = std::abs(a.center.x() - b.center.x()) - 0.5 * (a.size.x() + b.size.x());
  const double dy = std::abs(a.center.y() - b.center.y()) - 0.5 * (a.size.y() + b.size.y());
  return std::max(dx, dy);
}

// The shortest text that reads back as `value`.
std::string numberText(double value) {
  char text[core::kShortestTextMax];
  return std::string(text, core::writeShortest(text, value));
}

// kOutdoor's own checks; errors name the field (Error::inParameter).
void checkOutdoorParams(const SceneParams& p) {
  const auto require = [](bool ok, const char* field, const std::string& rule, double value) {
    if (!ok) throw Error::inParameter(field, rule + ", got " + numberText(value));
  };
  const auto within = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
  require(p.keyframes >= 3, "keyframes", "must be at least 3 on a street (to align the trajectory)",
          double(p.keyframes));
  require(within(p.track_length, 40.0, 1e5), "track_length", "must be in [40, 1e5] metres", p.track_length);
  require(within(p.track_width, 30.0, 1e4), "track_width", "must be in [30, 1e4] metres", p.track_width);
  const double nodes = (std::ceil(p.track_length) + 1.0) * (std::ceil(p.track_width) + 1.0);
  require(nodes <= 1e8, "track_length/track_width", "the terrain must have at most 1e8 nodes (1 m apart)", nodes);
  require(std::isfinite(p.density) && p.density > 0.0, "density", "must be > 0 points per m^2", p.density);
  require(p.density * nodes <= 1e9, "density", "x the area must be at most 1e9 points", p.density * nodes);
  require(within(p.edge_fraction, 0.0, 1.0), "edge_fraction", "must be in [0, 1]", p.edge_fraction);
  require(std::isfinite(p.monocular_scale) && p.monocular_scale > 0.0, "monocular_scale", "must be > 0",
          p.monocular_scale);
  require(within(p.camera_pitch_deg, 0.0, 80.0), "camera_pitch_deg", "must be in [0, 80] degrees", p.camera_pitch_deg);
  require(p.outlier_fraction < 1.0, "outlier_fraction", "must be < 1 on a street", p.outlier_fraction);
  require(within(p.slope_along, -0.2, 0.2), "slope_along", "must be in [-0.2, 0.2]", p.slope_along);
  require(within(p.slope_across, -0.2, 0.2), "slope_across", "must be in [-0.2, 0.2]", p.slope_across);
  require(p.bumps <= 10000, "bumps", "must be at most 10000", double(p.bumps));
  require(within(p.bump_height, 0.0, 5.0), "bump_height", "must be in [0, 5] metres", p.bump_height);
  require(std::isfinite(p.scale_drift) && p.scale_drift > -1.0 && p.scale_drift <= 10.0, "scale_drift",
          "must be in (-1, 10]", p.scale_drift);
  require(within(p.gps_sigma, 0.0, 1e4), "gps_sigma", "must be in [0, 1e4] metres", p.gps_sigma);
  require(within(p.gps_dropout, 0.0, 1.0), "gps_dropout", "must be in [0, 1]", p.gps_dropout);
}

void checkParams(const SceneParams& p) {
  auto require = [](bool ok, const std::string& message) {
    if (!ok) throw Error("scene parameters: " + message);
  };
  require(std::isfinite(p.room_size) && p.room_size >= 4.0, "room_size must be at least 4 m");
  require(std::isfinite(p.room_height) && p.room_height >= 1.5, "room_height must be at least 1.5 m");
  require(std::isfinite(p.noise_sigma) && p.noise_sigma >= 0.0, "noise_sigma must be >= 0");
  require(std::isfinite(p.outlier_fraction) && p.outlier_fraction >= 0.0 && p.outlier_fraction <= 1.0,
          "outlier_fraction must be in [0, 1]");
  require(p.gross_outliers <= p.points, "gross_outliers must not exceed points");
  require(p.keyframes >= 1, "keyframes must be at least 1");
  if (p.layout == SceneLayout::kObstacles) {
    require(p.obstacles >= 1, "obstacles must be at least 1");
  } else if (p.layout == SceneLayout::kOutdoor) {
    checkOutdoorParams(p);
  } else {
    require(p.keyframes >= 3, "keyframes (--keyframes) must be at least 3 in a room (to align the trajectory)");
    require(std::isfinite(p.density) && p.density > 0.0, "density (--density) must be > 0 points per m^2");
    require(p.room_width == 0.0 || (std::isfinite(p.room_width) && p.room_width >= 4.0),
            "room_width (--room-width) must be 0 (square) or at least 4 m");
    require(std::isfinite(p.loop_fraction) && p.loop_fraction > 0.0 && p.loop_fraction < 0.5,
            "loop_fraction (--loop) must be in (0, 0.5)");
    require(std::isfinite(p.wall_fraction) && p.wall_fraction >= 0.0 && p.wall_fraction <= 1.0,
            "wall_fraction (--wall-fraction) must be in [0, 1]");
    const double width = p.room_width > 0.0 ? p.room_width : p.room_size;
    require(p.density * p.room_size * std::max(width, p.room_size) <= 1e9,
            "density (--density) x room area must be at most 1e9 points");
    require(std::isfinite(p.edge_fraction) && p.edge_fraction >= 0.0 && p.edge_fraction <= 1.0,
            "edge_fraction (--edge-fraction) must be in [0, 1]");
    require(std::isfinite(p.monocular_scale) && p.monocular_scale > 0.0, "monocular_scale (--scale) must be > 0");
    require(std::isfinite(p.camera_pitch_deg) && p.camera_pitch_deg >= 0.0 && p.camera_pitch_deg <= 80.0,
            "camera_pitch_deg (--pitch) must be in [0, 80] degrees");
    require(p.outlier_fraction < 1.0, "outlier_fraction (--outliers) must be < 1 in a room");
  }
}

GroundTruth placeObstacles(const SceneParams& p, double loop_radius, core::RandomDraws& rng) {
  GroundTruth obstacles;
  const double max_height = std::min(2.5, p.room_height - 0.2);
  for (std::size_t n = 0; n < p.obstacles; ++n) {
    bool placed = false;
    for (int attempt = 0; attempt < 10000 && !placed; ++attempt) {
      const bool box = rng.uniform() < 0.5;
      const double height = rng.uniform(0.6, max_height);
      Eigen::Vector3d size;
      if (box) {
        // One draw a statement, y first (the order maps/ was made in): the arguments of one call are
        // not sequenced, and gcc and clang draw them in opposite orders.
        const double size_y = rng.uniform(0.4, 1.4);
        const double size_x = rng.uniform(0.4, 1.4);
        size = Eigen::Vector3d(size_x, size_y, height);
      } else {
        const double d = rng.uniform(0.3, 1.0);
        size = Eigen::Vector3d(d, d, height);
      }
      const double reach = loop_radius - kSceneObstacleGap - 0.5 * size.head<2>().norm();
      if (reach <= 0.0) continue;
      const double center_y = rng.uniform(-reach, reach);
      const double center_x = rng.uniform(-reach, reach);
      const Eigen::Vector3d center(center_x, center_y, 0.5 * height);
      if (center.head<2>().norm() > reach) continue;
      const TruthShape o = box ? TruthShape::box(center, size) : TruthShape::cylinder(center, size);
      placed = std::all_of(obstacles.shapes.begin(), obstacles.shapes.end(),
                           [&o](const TruthShape& other) { return footprintGap(o, other) >= kSceneObstacleGap; });
      if (placed) obstacles.add(o);
    }
    if (!placed) {
      throw Error("scene parameters: cannot place " + std::to_string(p.obstacles) + " obstacles " +
                  std::to_string(kSceneObstacleGap) + " m apart in a room of " + std::to_string(p.room_size) +
                  " m (obstacles too many for room_size)");
    }
  }
  return obstacles;
}

// Appends `x y z\n` (fixed, 6 decimals) to `out`.
void appendXyz(std::string& out, const Eigen::Vector3d& p) {
  char buf[128];
  char* end = buf;
  for (int i = 0; i < 3; ++i) {
    end = std::to_chars(end, buf + sizeof(buf), p[i], std::chars_format::fixed, 6).ptr;
    *end++ = i < 2 ? ' ' : '\n';
  }
  out.append(buf, end);
}

// Writes keyframes to `path` atomically as TUM lines `t x y z qx qy qz qw`.
void writeTum(const std::string& path, const std::vector<io::Keyframe>& keyframes) {
  core::writeFileAtomically(path, [&keyframes](std::ostream& out) {
    char line[512];
    for (const io::Keyframe& k : keyframes) {
      const Eigen::Quaterniond& q = k.orientation;
      std::snprintf(line, sizeof(line), "%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", k.stamp, k.position.x(),
                    k.position.y(), k.position.z(), q.x(), q.y(), q.z(), q.w());
      out << line;
    }
  });
}

// ground_truth.json of a kObstacles scene.
nlohmann::json obstaclesDocument(const Scene& scene, const SceneParams& params) {
  nlohmann::json j;
  j["frame"] = "z-up map";
  j["units"] = "metres";
  j["points_frame"] = params.orbslam_frame ? "orbslam (y down): read with --up -y" : "z-up map";
  j["params"] = {{"seed", params.seed},
                 {"points", params.points},
                 {"obstacles", params.obstacles},
                 {"room_size", params.room_size},
                 {"room_height", params.room_height},
                 {"noise_sigma", params.noise_sigma},
                 {"outlier_fraction", params.outlier_fraction},
                 {"gross_outliers", params.gross_outliers},
                 {"keyframes", params.keyframes}};
  j["obstacles"] = groundTruthToJson(scene.truth, false);  // plain boxes and cylinders, no "kind"
  return j;
}

// The output frame from the map frame (Scene::output_scale, _rotation, _translation) as JSON.
nlohmann::json outputFromMap(const Scene& scene) {
  const Eigen::Matrix3d& r = scene.output_rotation;
  return {{"scale", scene.output_scale},
          {"rotation", {{r(0, 0), r(0, 1), r(0, 2)}, {r(1, 0), r(1, 1), r(1, 2)}, {r(2, 0), r(2, 1), r(2, 2)}}},
          {"translation", {scene.output_translation.x(), scene.output_translation.y(), scene.output_translation.z()}}};
}

// ground_truth.json of a kRoom scene.
nlohmann::json roomDocument(const Scene& scene, const SceneParams& params) {
  nlohmann::json j;
  j["frame"] = "z-up map";
  j["units"] = "metres";
  j["layout"] = "room";
  j["points_frame"] = params.orbslam_frame ? "orbslam: the first keyframe's camera frame (x right, y down, z forward), "
                                             "monocular scale; align with reference_trajectory.txt"
                                           : "z-up map";
  j["output_from_map"] = outputFromMap(scene);
  j["params"] = {{"seed", params.seed},
                 {"layout", "room"},
                 {"points", scene.points.size()},
                 {"furniture", params.obstacles},
                 {"room_size", params.room_size},
                 {"room_width", params.room_width > 0.0 ? params.room_width : params.room_size},
                 {"room_height", params.room_height},
                 {"loop_fraction", params.loop_fraction},
                 {"placement", params.placement == FurniturePlacement::kAnywhere ? "anywhere" : "inside_loop"},
                 {"wall_fraction", params.wall_fraction},
                 {"density", params.density},
                 {"edge_fraction", params.edge_fraction},
                 {"noise_sigma", params.noise_sigma},
                 {"outlier_fraction", params.outlier_fraction},
                 {"gross_outliers", params.gross_outliers},
                 {"keyframes", params.keyframes},
                 {"monocular_scale", params.orbslam_frame ? params.monocular_scale : 1.0},
                 {"camera_pitch_deg", params.camera_pitch_deg}};
  j["obstacles"] = groundTruthToJson(scene.truth, true);
  return j;
}

// ground_truth.json of a kOutdoor scene.
nlohmann::json outdoorDocument(const Scene& scene, const SceneParams& params) {
  nlohmann::json j;
  j["frame"] = "z-up map";
  j["units"] = "metres";
  j["layout"] = "outdoor";
  j["points_frame"] = params.orbslam_frame
                          ? "orbslam: the first keyframe's camera frame (x right, y down, z forward), at a monocular "
                            "scale drifting along the street (keyframe_scales); align with reference_trajectory.txt "
                            "or gps.txt (--align-format gps)"
                          : "z-up map";
  j["output_from_map"] = outputFromMap(scene);  // at the first keyframe
  j["keyframe_scales"] = scene.keyframe_scales;
  j["geodetic_origin"] = {{"latitude_deg", kOutdoorGeodeticOrigin[0]},
                          {"longitude_deg", kOutdoorGeodeticOrigin[1]},
                          {"altitude_m", kOutdoorGeodeticOrigin[2]},
                          {"axes", "x east, y north, z up"}};
  j["params"] = {{"seed", params.seed},
                 {"layout", "outdoor"},
                 {"points", scene.points.size()},
                 {"keyframes", params.keyframes},
                 {"track_length", params.track_length},
                 {"track_width", params.track_width},
                 {"slope_along", params.slope_along},
                 {"slope_across", params.slope_across},
                 {"bumps", params.bumps},
                 {"bump_height", params.bump_height},
                 {"buildings", params.buildings},
                 {"trees", params.trees},
                 {"cars", params.cars},
                 {"posts", params.posts},
                 {"density", params.density},
                 {"edge_fraction", params.edge_fraction},
                 {"noise_sigma", params.noise_sigma},
                 {"outlier_fraction", params.outlier_fraction},
                 {"gross_outliers", params.gross_outliers},
                 {"monocular_scale", params.orbslam_frame ? params.monocular_scale : 1.0},
                 {"scale_drift", params.orbslam_frame ? params.scale_drift : 0.0},
                 {"camera_pitch_deg", params.camera_pitch_deg},
                 {"camera_height", kOutdoorCameraHeight},
                 {"path_margin", kOutdoorPathMargin},
                 {"gps_sigma", params.gps_sigma},
                 {"gps_dropout", params.gps_dropout}};
  j["obstacles"] = groundTruthToJson(scene.truth, true);
  return j;
}

}  // namespace

Eigen::Matrix3d mapToOrbSlamRotation() {
  Eigen::Matrix3d m;
  m << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  return m;
}

SceneParams outdoorSceneParams() {
  SceneParams p;
  p.layout = SceneLayout::kOutdoor;
  p.keyframes = 100;
  p.density = 3.0;
  p.noise_sigma = 0.05;
  p.camera_pitch_deg = 10.0;
  p.monocular_scale = 0.0145;
  return p;
}

Scene generateScene(const SceneParams& p) {
  checkParams(p);
  if (p.layout == SceneLayout::kRoom) return detail::generateRoomScene(p);
  if (p.layout == SceneLayout::kOutdoor) return detail::generateOutdoorScene(p);
  core::RandomDraws rng(p.seed);
  const double loop_radius = 0.4 * p.room_size;

  Scene scene;
  scene.truth = placeObstacles(p, loop_radius, rng);
  // Each camera looks toward the room's axis, slightly down.
  scene.keyframes = detail::cameraLoop(p.keyframes, loop_radius, loop_radius, [](double a, const Eigen::Vector3d&) {
    return Eigen::Vector3d(Eigen::Vector3d(-std::cos(a), -std::sin(a), -0.15).normalized());
  });

  std::vector<SurfaceSampler> samplers;
  std::vector<double> cumulative_area;
  double total_area = 0.0;
  for (const auto& o : scene.truth.shapes) {
    samplers.emplace_back(o);
    total_area += samplers.back().area();
    cumulative_area.push_back(total_area);
  }

  const std::size_t n = p.points;
  const std::size_t gross = p.gross_outliers;
  const std::size_t outliers =
      std::min(n - gross, static_cast<std::size_t>(std::llround(p.outlier_fraction * static_cast<double>(n))));
  const std::size_t surface = n - gross - outliers;
  const double half = 0.5 * p.room_size;

  // Fixed chunks with their own seeds: the same points whatever the thread count.
  scene.points.resize(n);
  forEachSeeded(n, p.seed, kChunk, [&](core::RandomDraws& local, std::size_t i, std::size_t) {
    Eigen::Vector3d& q = scene.points[i];
    if (i < surface) {
      const double x = local.uniform() * total_area;
      const std::size_t o = static_cast<std::size_t>(
          std::upper_bound(cumulative_area.begin(), cumulative_area.end() - 1, x) - cumulative_area.begin());
      q = samplers[o].sample(local);
      q += p.noise_sigma * local.normal3();
    } else if (i < surface + outliers) {
      const double z = local.uniform(0.0, p.room_height);  // z, y, x: as normal3()
      const double y = local.uniform(-half, half);
      q = Eigen::Vector3d(local.uniform(-half, half), y, z);
    } else {
      const Eigen::Vector3d direction = local.unitVector();  // then the distance: as normal3()
      q = local.uniform(1e5, 1e6) * direction;
    }
  });

  // ORB-SLAM's map points come in no spatial order; neither do ours.
  for (std::size_t i = n; i > 1; --i) std::swap(scene.points[i - 1], scene.points[rng.index(i)]);

  if (p.orbslam_frame) {
    const Eigen::Matrix3d m = mapToOrbSlamRotation();
    transformPoints(scene.points, [&](const Eigen::Vector3d& q) -> Eigen::Vector3d { return m * q; });
    const Eigen::Quaterniond mq(m);
    for (io::Keyframe& k : scene.keyframes) {
      k.position = m * k.position;
      k.orientation = (mq * k.orientation).normalized();
    }
  }
  return scene;
}

void writeScene(const Scene& scene, const SceneParams& params, const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error(dir + ": cannot create directory: " + ec.message());
  const fs::path base(dir);

  core::writeFileAtomically((base / "map_points.txt").string(), [&scene](std::ostream& out) {
    constexpr std::size_t kBlock = 1 << 20;
    constexpr std::size_t kPart = 1 << 15;
    const std::size_t n = scene.points.size();
    std::vector<std::string> parts(kBlock / kPart);
    for (std::size_t block = 0; block < n; block += kBlock) {
      const std::size_t block_end = std::min(n, block + kBlock);
      const std::size_t count = (block_end - block + kPart - 1) / kPart;
      tbb::parallel_for(std::size_t{0}, count, [&](std::size_t part) {
        std::string& text = parts[part];
        text.clear();
        const std::size_t end = std::min(block_end, block + (part + 1) * kPart);
        for (std::size_t i = block + part * kPart; i < end; ++i) appendXyz(text, scene.points[i]);
      });
      for (std::size_t part = 0; part < count; ++part) out.write(parts[part].data(), parts[part].size());
    }
  });

  writeTum((base / "KeyFrameTrajectory.txt").string(), scene.keyframes);
  if (params.layout != SceneLayout::kObstacles) writeTum((base / "reference_trajectory.txt").string(), scene.reference);
  if (params.layout == SceneLayout::kOutdoor) detail::writeGpsLog(scene.gps, (base / "gps.txt").string());

  core::writeFileAtomically((base / "ground_truth.json").string(), [&scene, &params](std::ostream& out) {
    const nlohmann::json j = params.layout == SceneLayout::kObstacles ? obstaclesDocument(scene, params)
                             : params.layout == SceneLayout::kRoom    ? roomDocument(scene, params)
                                                                      : outdoorDocument(scene, params);
    out << j.dump(2) << '\n';
  });
}

}  // namespace hullmap::sim
