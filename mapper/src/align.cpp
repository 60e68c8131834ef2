#include "hullmap/mapper/align.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "align_roll.hpp"
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

/// The matched keyframes, in the keyframes' order (inTimeOrder sorts them by stamp): stamp, keyframe
/// position, reference position, keyframe orientation.
struct Matches {
  std::vector<double> stamps;
  std::vector<Eigen::Vector3d> from, to;
  std::vector<Eigen::Quaterniond> orientations;  ///< the keyframes'
};

struct Residuals {
  double rmse = 0.0;
  double max = 0.0;
};

/// RMS and largest distance between moved(from[i], i) and to[i].
template <class Move>
Residuals residuals(const Matches& m, Move moved) {
  Residuals r;
  double sum = 0.0;
  for (std::size_t i = 0; i < m.from.size(); ++i) {
    const double e = (moved(m.from[i], i) - m.to[i]).norm();
    sum += e * e;
    r.max = std::max(r.max, e);
  }
  r.rmse = std::sqrt(sum / static_cast<double>(m.from.size()));
  return r;
}

/// The matches in time order (stable: equal stamps keep the keyframes' order).
Matches inTimeOrder(const Matches& m) {
  std::vector<std::size_t> order(m.stamps.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return m.stamps[a] < m.stamps[b]; });
  Matches out;
  for (std::size_t i : order) {
    out.stamps.push_back(m.stamps[i]);
    out.from.push_back(m.from[i]);
    out.to.push_back(m.to[i]);
    out.orientations.push_back(m.orientations[i]);
  }
  return out;
}

struct LocalFit {
  double scale = 1.0;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

/// The least-squares scale and translation (rotation fixed) of the matches [lo, hi) but `skip`:
/// with a, b their centred keyframe and reference positions, scale = sum (R a).b / sum |a|^2,
/// translation = mean(to) - scale R mean(from). Keyframes that coincide (or a negative fit) keep
/// `fallback_scale`.
LocalFit localFit(const Matches& m, const Eigen::Matrix3d& rotation, std::size_t lo, std::size_t hi, std::size_t skip,
                  double fallback_scale) {
  Eigen::Vector3d mean_from = Eigen::Vector3d::Zero(), mean_to = Eigen::Vector3d::Zero();
  double count = 0.0;
  for (std::size_t j = lo; j < hi; ++j) {
    if (j == skip) continue;
    mean_from += m.from[j];
    mean_to += m.to[j];
    count += 1.0;
  }
  mean_from /= count;
  mean_to /= count;
  double num = 0.0, den = 0.0;
  for (std::size_t j = lo; j < hi; ++j) {
    if (j == skip) continue;
    const Eigen::Vector3d a = m.from[j] - mean_from;
    num += (rotation * a).dot(m.to[j] - mean_to);
    den += a.squaredNorm();
  }
  LocalFit fit;
  fit.scale = den > 0.0 && num > 0.0 ? num / den : fallback_scale;
  fit.translation = mean_to - fit.scale * (rotation * mean_from);
  return fit;
}

/// The drift model of `m` (in time order): per match i, the local fit of the matches within the
/// half window of it. `holdout_rmse`: the RMS distance of each match from the fit of its window
/// without it (how well the model predicts a pose it was not fitted to).
DriftCorrection fitDrift(const Matches& m, const Eigen::Matrix3d& rotation, double whole_scale, double& holdout_rmse) {
  const std::size_t n = m.from.size();
  DriftCorrection d;
  d.half_window =
      std::max<std::size_t>(3, static_cast<std::size_t>(std::lround(kDriftWindowShare * static_cast<double>(n))));
  d.stamps = m.stamps;
  d.anchors = m.from;
  d.scales.resize(n);
  d.translations.resize(n);
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t lo = i >= d.half_window ? i - d.half_window : 0;
    const std::size_t hi = std::min(n, i + d.half_window + 1);
    const LocalFit fit = localFit(m, rotation, lo, hi, n, whole_scale);
    d.scales[i] = fit.scale;
    d.translations[i] = fit.translation;
    const LocalFit without = localFit(m, rotation, lo, hi, i, whole_scale);
    sum += (without.scale * (rotation * m.from[i]) + without.translation - m.to[i]).squaredNorm();
  }
  holdout_rmse = std::sqrt(sum / static_cast<double>(n));
  return d;
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
  Matches m;
  for (const io::Keyframe& k : keyframes) {
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), k.stamp,
                                     [](const io::ReferencePose& r, double t) { return r.stamp < t; });
    const io::ReferencePose* best = nullptr;
    if (it != sorted.end()) best = &*it;
    if (it != sorted.begin() && (best == nullptr || k.stamp - std::prev(it)->stamp <= best->stamp - k.stamp)) {
      best = &*std::prev(it);
    }
    if (best != nullptr && std::abs(best->stamp - k.stamp) <= params.stamp_tolerance) {
      m.stamps.push_back(k.stamp);
      m.from.push_back(k.position);
      m.to.push_back(best->position);
      m.orientations.push_back(k.orientation);
    } else {
      ++result.unmatched;
    }
  }
  result.matched = m.from.size();
  if (result.matched < 3) {
    throw Error("align: " + std::to_string(result.matched) + " of " + std::to_string(keyframes.size()) +
                " keyframes match a reference pose within " + std::to_string(params.stamp_tolerance) +
                " s; at least 3 are needed");
  }
  Eigen::Matrix3Xd src(3, result.matched), dst(3, result.matched);
  for (std::size_t i = 0; i < result.matched; ++i) {
    src.col(static_cast<Eigen::Index>(i)) = m.from[i];
    dst.col(static_cast<Eigen::Index>(i)) = m.to[i];
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
  const Residuals umeyama = residuals(m, [&](const Eigen::Vector3d& p, std::size_t) { return s(p); });
  const RollFit roll = fitRoll(m.to, m.orientations, s, umeyama.rmse);
  s = roll.transform;
  result.roll_sigma = roll.sigma;
  result.roll_from_cameras = roll.from_cameras;
  result.roll_turn = roll.turn;
  const Residuals whole = residuals(m, [&](const Eigen::Vector3d& p, std::size_t) { return s(p); });
  result.similarity_rmse = result.rmse = whole.rmse;
  result.max_error = whole.max;
  if (params.model == AlignModel::kSimilarity || result.matched < kDriftMinAnchors) return result;

  const Matches ordered = inTimeOrder(m);
  double holdout_rmse = 0.0;
  DriftCorrection drift = fitDrift(ordered, s.rotation, s.scale, holdout_rmse);
  drift.holdout_rmse = holdout_rmse;
  const Residuals local = residuals(ordered, [&](const Eigen::Vector3d& p, std::size_t i) {
    return drift.scales[i] * (s.rotation * p) + drift.translations[i];
  });
  const double spread_rms = spread(dst).norm() / std::sqrt(static_cast<double>(result.matched));
  const bool worth = whole.rmse > 1e-3 * spread_rms && holdout_rmse < 0.5 * whole.rmse;
  if (params.model == AlignModel::kDrift || worth) {
    result.drift = std::move(drift);
    result.rmse = local.rmse;
    result.max_error = local.max;
  }
  return result;
}

AlignModel parseAlignModel(const std::string& text) {
  if (text == "auto") return AlignModel::kAuto;
  if (text == "similarity") return AlignModel::kSimilarity;
  if (text == "drift") return AlignModel::kDrift;
  throw Error::inParameter("align_model", "expected auto, similarity or drift, got \"" + text + "\"");
}

const char* toString(AlignModel model) {
  switch (model) {
    case AlignModel::kSimilarity:
      return "similarity";
    case AlignModel::kDrift:
      return "drift";
    case AlignModel::kAuto:
      break;
  }
  return "auto";
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
