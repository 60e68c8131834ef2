// The roll about a nearly straight reference path, set by the keyframes' cameras when the reference
// leaves it undetermined (align_roll.hpp).
#include "align_roll.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "hullmap/core/constants.hpp"

namespace hullmap::mapper {

RollFit fitRoll(const std::vector<Eigen::Vector3d>& to, const std::vector<Eigen::Quaterniond>& orientations,
                const Similarity& s, double rmse) {
  RollFit fit;
  fit.transform = s;
  const std::size_t n = to.size();
  if (n < 3) return fit;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : to) mean += p;
  mean /= static_cast<double>(n);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : to) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  const Eigen::Vector3d axis = eigen.eigenvectors().col(2).normalized();  // the path's main axis
  const double across = eigen.eigenvalues()[0] + eigen.eigenvalues()[1];  // squared distances from it
  const double noise = rmse / std::sqrt(3.0);
  fit.sigma = across > 0.0 ? noise / std::sqrt(across) : std::numeric_limits<double>::infinity();
  if (!(fit.sigma > kRollSigmaMax)) return fit;

  // up(t): the reference's z turned back by t about the axis; a roll of t levels the cameras' x
  // axes when they are perpendicular to up(t).
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const double along = z.dot(axis);
  const Eigen::Vector3d p = z - along * axis, b = axis.cross(p);
  if (p.norm() < 0.5) return fit;  // a line steeper than 60 degrees
  Eigen::Matrix3d xx = Eigen::Matrix3d::Zero();
  Eigen::Vector3d down = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n && i < orientations.size(); ++i) {
    const Eigen::Matrix3d camera = s.rotation * orientations[i].toRotationMatrix();
    xx += camera.col(0) * camera.col(0).transpose();
    down += camera.col(1);
  }
  constexpr int kSteps = 3600;  // 0.1 degree
  double best = std::numeric_limits<double>::infinity(), least = best, most = -best, turn = 0.0;
  for (int k = 0; k < kSteps; ++k) {
    const double t = 2.0 * kPi * k / kSteps;
    const Eigen::Vector3d up = along * axis + std::cos(t) * p - std::sin(t) * b;
    const double level = up.dot(xx * up);
    least = std::min(least, level);
    most = std::max(most, level);
    if (up.dot(down) < 0.0 && level < best) {
      best = level;
      turn = t;
    }
  }
  if (most - least < 0.25 * static_cast<double>(n) || !std::isfinite(best)) return fit;
  if (turn > kPi) turn -= 2.0 * kPi;
  const Eigen::Matrix3d q = Eigen::AngleAxisd(turn, axis).toRotationMatrix();
  fit.from_cameras = true;
  fit.turn = turn;
  fit.transform.rotation = q * s.rotation;
  fit.transform.translation = q * (s.translation - mean) + mean;
  return fit;
}

}  // namespace hullmap::mapper
