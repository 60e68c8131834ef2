#include "hullmap/mapper/align.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "hullmap/core/error.hpp"

namespace hullmap::mapper {
namespace {

// Singular values of the centred positions (3 x n), largest first: the square roots of the
// eigenvalues of their 3 x 3 scatter matrix (an SVD of the 3 x n matrix itself instantiates
// Eigen's dynamic-size QR preconditioners, most of this file's compile time, for the same values).
Eigen::Vector3d spread(const Eigen::Matrix3Xd& positions) {
  const Eigen::Vector3d mean = positions.rowwise().mean();
  const Eigen::Matrix3Xd centred = positions.colwise() - mean;
  const Eigen::Matrix3d scatter = centred * centred.transpose();
  const Eigen::Vector3d ascending = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();
  return ascending.reverse().cwiseMax(0.0).cwiseSqrt();
}

bool collinear(const Eigen::Matrix3Xd& positions) {
  const Eigen::Vector3d s = spread(positions);
  return !(s[0] > 0.0) || !(s[1] > 1e-6 * s[0]);
}

}  // namespace

Alignment alignTrajectory(const std::vector<io::Keyframe>& keyframes, const std::vector<io::ReferencePose>& reference,
                          const AlignParams& params) {
  if (!(params.stamp_tolerance >= 0.0) || !std::isfinite(params.stamp_tolerance)) {
    throw Error("align: the timestamp tolerance must be finite and >= 0");
  }
  std::vector<io::ReferencePose> sorted = reference;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const io::ReferencePose& a, const io::ReferencePose& b) { return a.stamp < b.stamp; });

  Alignment result;
  std::vector<Eigen::Vector3d> from, to;
  for (const io::Keyframe& k : keyframes) {
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), k.stamp,
                                     [](const io::ReferencePose& r, double t) { return r.stamp < t; });
    const io::ReferencePose* best = nullptr;
    if (it != sorted.end()) best = &*it;
    if (it != sorted.begin() && (best == nullptr || k.stamp - std::prev(it)->stamp <= best->stamp - k.stamp)) {
      best = &*std::prev(it);
    }
    if (best != nullptr && std::abs(best->stamp - k.stamp) <= params.stamp_tolerance) {
      from.push_back(k.position);
      to.push_back(best->position);
    } else {
      ++result.unmatched;
    }
  }
  result.matched = from.size();
  if (result.matched < 3) {
    throw Error("align: " + std::to_string(result.matched) + " of " + std::to_string(keyframes.size()) +
                " keyframes match a reference pose within " + std::to_string(params.stamp_tolerance) +
                " s; at least 3 are needed");
  }
  Eigen::Matrix3Xd src(3, result.matched), dst(3, result.matched);
  for (std::size_t i = 0; i < result.matched; ++i) {
    src.col(static_cast<Eigen::Index>(i)) = from[i];
    dst.col(static_cast<Eigen::Index>(i)) = to[i];
  }
  if (collinear(src)) {
    throw Error("align: the matched keyframe positions are coincident or collinear; the fit is degenerate");
  }
  if (collinear(dst)) {
    throw Error("align: the matched reference positions are coincident or collinear; the fit is degenerate");
  }
  const Eigen::Matrix4d t = Eigen::umeyama(src, dst, true);
  Similarity& s = result.transform;
  const Eigen::Matrix3d sr = t.topLeftCorner<3, 3>();
  s.scale = std::cbrt(sr.determinant());
  if (!(s.scale > 0.0) || !std::isfinite(s.scale)) throw Error("align: the fit is degenerate (scale not positive)");
  s.rotation = sr / s.scale;
  s.translation = t.topRightCorner<3, 1>();
  double sum = 0.0;
  for (std::size_t i = 0; i < result.matched; ++i) {
    const double e = (s(from[i]) - to[i]).norm();
    sum += e * e;
    result.max_error = std::max(result.max_error, e);
  }
  result.rmse = std::sqrt(sum / static_cast<double>(result.matched));
  return result;
}

Similarity compose(const Similarity& second, const Similarity& first) {
  Similarity out;
  out.scale = second.scale * first.scale;
  out.rotation = second.rotation * first.rotation;
  out.translation = second(first.translation);
  return out;
}

Similarity inverse(const Similarity& s) {
  Similarity out;
  out.scale = 1.0 / s.scale;
  out.rotation = s.rotation.transpose();
  out.translation = -out.scale * (out.rotation * s.translation);
  return out;
}

Similarity fromIsometry(const Eigen::Isometry3d& t) {
  Similarity out;
  out.rotation = t.linear();
  out.translation = t.translation();
  return out;
}

Eigen::Matrix4d toMatrix(const Similarity& s) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = s.scale * s.rotation;
  m.topRightCorner<3, 1>() = s.translation;
  return m;
}

void applySimilarity(const Similarity& s, io::Points& points) {
  for (io::Point& p : points) p = s(p);
}

void applySimilarity(const Similarity& s, std::vector<io::Keyframe>& keyframes) {
  const Eigen::Quaterniond q(s.rotation);
  for (io::Keyframe& k : keyframes) {
    k.position = s(k.position);
    k.orientation = (q * k.orientation).normalized();
  }
}

}  // namespace hullmap::mapper
