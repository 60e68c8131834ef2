#include "hullmap/mapper/level_check.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <random>

#include <Eigen/Eigenvalues>

namespace hullmap::mapper {
namespace {

constexpr double kPi = 3.14159265358979323846;

double tiltDeg(const Eigen::Vector3d& unit_normal) {
  return std::acos(std::min(1.0, std::abs(unit_normal.z()))) * 180.0 / kPi;
}

/// Least-squares plane through `points` (smallest-eigenvalue eigenvector of their covariance).
Eigen::Vector3d refitNormal(const std::vector<Eigen::Vector3d>& points, Eigen::Vector3d& centroid) {
  centroid.setZero();
  for (const auto& p : points) centroid += p;
  centroid /= double(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const auto& p : points) covariance += (p - centroid) * (p - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  return solver.eigenvectors().col(0).normalized();
}

}  // namespace

std::optional<PlaneFit> fitFloorPlane(const std::vector<Eigen::Vector3d>& points, const PlaneFitParams& params) {
  if (points.size() < 3) return std::nullopt;
  std::mt19937 rng(params.seed);
  std::vector<Eigen::Vector3d> sample;
  if (points.size() <= params.max_sample) {
    sample = points;
  } else {
    std::vector<std::size_t> index(points.size());
    std::iota(index.begin(), index.end(), std::size_t{0});
    for (std::size_t i = 0; i < params.max_sample; ++i) {
      std::uniform_int_distribution<std::size_t> pick(i, index.size() - 1);
      std::swap(index[i], index[pick(rng)]);
      sample.push_back(points[index[i]]);
    }
  }
  const double cos_max_tilt = std::cos(params.max_tilt_deg * kPi / 180.0);
  std::uniform_int_distribution<std::size_t> any(0, sample.size() - 1);
  std::optional<PlaneFit> best;
  for (int it = 0; it < params.iterations; ++it) {
    const Eigen::Vector3d& a = sample[any(rng)];
    const Eigen::Vector3d& b = sample[any(rng)];
    const Eigen::Vector3d& c = sample[any(rng)];
    Eigen::Vector3d n = (b - a).cross(c - a);
    const double norm = n.norm();
    if (!(norm > 1e-12)) continue;
    n /= norm;
    if (n.z() < 0) n = -n;
    if (n.z() < cos_max_tilt) continue;
    const double offset = n.dot(a);
    std::size_t inliers = 0;
    for (const auto& p : sample) inliers += std::abs(n.dot(p) - offset) <= params.inlier_distance;
    if (!best || inliers > best->inliers) best = PlaneFit{n, offset, inliers, sample.size(), 0.0};
  }
  if (!best) return std::nullopt;
  std::vector<Eigen::Vector3d> support;
  for (const auto& p : sample)
    if (std::abs(best->normal.dot(p) - best->offset) <= params.inlier_distance) support.push_back(p);
  if (support.size() >= 3) {
    Eigen::Vector3d centroid;
    Eigen::Vector3d n = refitNormal(support, centroid);
    if (n.z() < 0) n = -n;
    best->normal = n;
    best->offset = n.dot(centroid);
  }
  best->tilt_deg = tiltDeg(best->normal);
  return best;
}

std::optional<std::string> levelWarning(const std::vector<Eigen::Vector3d>& points, double resolution,
                                        const std::string& up) {
  PlaneFitParams params;
  params.inlier_distance = resolution;
  const auto plane = fitFloorPlane(points, params);
  if (!plane || double(plane->inliers) < kFloorMinShare * double(plane->sampled)) return std::nullopt;
  if (plane->tilt_deg <= kFloorMaxTiltDeg) return std::nullopt;
  char text[400];
  std::snprintf(text, sizeof text,
                "the map's main floor-like plane (%.0f%% of the occupied voxels) is %.1f degrees from level "
                "after --up %s: if it is the floor, the map is tilted (SLAM maps start in the first camera's "
                "frame), and heights, --z-min/--z-max and footprints are slanted by as much",
                100.0 * double(plane->inliers) / double(plane->sampled), plane->tilt_deg, up.c_str());
  return std::string(text);
}

bool looksLikeOrbSlam(const InputStats& input) {
  if (input.format == "orbslam_echo") return true;
  std::string name = std::filesystem::path(input.path).filename().string();
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (const char* word : {"mappoints", "keyframe", "orbslam", "orb_slam", "orb-slam"})
    if (name.find(word) != std::string::npos) return true;
  return false;
}

std::optional<std::string> orbSlamUpHint(const std::vector<InputStats>& inputs, bool up_given) {
  if (up_given) return std::nullopt;
  for (const auto& input : inputs) {
    if (looksLikeOrbSlam(input)) {
      return input.path + " looks like ORB-SLAM output, whose frame is the first camera's (x right, y down, "
                          "z forward): it likely needs --up -y (--up was left at z)";
    }
  }
  return std::nullopt;
}

}  // namespace hullmap::mapper
