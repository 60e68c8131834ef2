#include "hullmap/mapper/align.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "byte_source.hpp"
#include "hullmap/core/error.hpp"
#include "read_detail.hpp"

namespace hullmap::mapper {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kWgs84A = 6378137.0;                 // semi-major axis, metres
constexpr double kWgs84F = 1.0 / 298.257223563;       // flattening
constexpr double kWgs84E2 = kWgs84F * (2.0 - kWgs84F);  // first eccentricity squared

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

ReferenceFormat parseReferenceFormat(const std::string& text) {
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (lower == "tum") return ReferenceFormat::kTum;
  if (lower == "gps") return ReferenceFormat::kGps;
  throw Error::inParameter("align_format", "expected 'tum' or 'gps', got '" + text + "'");
}

std::string toString(ReferenceFormat format) { return format == ReferenceFormat::kTum ? "tum" : "gps"; }

Eigen::Vector3d geodeticToEcef(double latitude_deg, double longitude_deg, double altitude_m) {
  const double lat = latitude_deg * kPi / 180.0;
  const double lon = longitude_deg * kPi / 180.0;
  const double s = std::sin(lat);
  const double n = kWgs84A / std::sqrt(1.0 - kWgs84E2 * s * s);  // prime vertical radius of curvature
  return {(n + altitude_m) * std::cos(lat) * std::cos(lon), (n + altitude_m) * std::cos(lat) * std::sin(lon),
          (n * (1.0 - kWgs84E2) + altitude_m) * s};
}

Eigen::Vector3d geodeticToEnu(const Eigen::Vector3d& geodetic, const Eigen::Vector3d& origin) {
  const Eigen::Vector3d d =
      geodeticToEcef(geodetic[0], geodetic[1], geodetic[2]) - geodeticToEcef(origin[0], origin[1], origin[2]);
  const double lat = origin[0] * kPi / 180.0;
  const double lon = origin[1] * kPi / 180.0;
  const double sl = std::sin(lat), cl = std::cos(lat), so = std::sin(lon), co = std::cos(lon);
  return {-so * d.x() + co * d.y(),                              // east
          -sl * co * d.x() - sl * so * d.y() + cl * d.z(),       // north
          cl * co * d.x() + cl * so * d.y() + sl * d.z()};       // up
}

namespace {

/// Why a GPS line `t lat lon alt` holds no fix, or nullptr when it holds one.
const char* missingFix(const double* v) {
  for (int i = 0; i < 4; ++i)
    if (!std::isfinite(v[i])) return "non_finite";
  if (std::abs(v[1]) > 90.0 || v[2] < -180.0 || v[2] > 360.0) return "out_of_range";
  if (v[1] == 0.0 && v[2] == 0.0) return "no_fix";
  return nullptr;
}

}  // namespace

std::vector<ReferencePose> parseReferenceTrajectory(std::string_view bytes, const std::string& name,
                                                    ReferenceFormat format, ReferenceStats* stats) {
  std::vector<ReferencePose> poses;
  Eigen::Vector3d origin;
  detail::forEachNumberRow(bytes, name, [&](const double* v, std::size_t count, std::size_t line) {
    if (format == ReferenceFormat::kTum && count != 4 && count != 8) {
      detail::failAt(name, line,
                     "expected 4 or 8 numbers (t x y z [qx qy qz qw]), got " + std::to_string(count));
    }
    if (format == ReferenceFormat::kGps && count != 4) {
      detail::failAt(name, line, "expected 4 numbers (t lat lon alt), got " + std::to_string(count));
    }
    if (format == ReferenceFormat::kGps) {
      // Receivers log lines before their first fix (0 0 0, NaN): those are no positions.
      if (const char* reason = missingFix(v)) {
        if (stats) ++stats->dropped[reason];
        return;
      }
    }
    for (std::size_t i = 0; i < count; ++i) {
      if (!std::isfinite(v[i])) detail::failAt(name, line, "non-finite value");
    }
    ReferencePose pose;
    pose.stamp = v[0] > kNanosecondStampThreshold ? v[0] * 1e-9 : v[0];
    if (format == ReferenceFormat::kTum) {
      pose.position = Eigen::Vector3d(v[1], v[2], v[3]);
    } else {
      const Eigen::Vector3d fix(v[1], v[2], v[3]);
      if (poses.empty()) origin = fix;
      pose.position = geodeticToEnu(fix, origin);
    }
    poses.push_back(pose);
  });
  return poses;
}

std::vector<ReferencePose> readReferenceTrajectory(const std::string& path, ReferenceFormat format,
                                                   ReferenceStats* stats) {
  detail::ByteSource source(path, PointStreamParams{}.read_bytes);
  source.loadAll();
  return parseReferenceTrajectory(source.view(0, source.end()), path, format, stats);
}

Alignment alignTrajectory(const std::vector<Keyframe>& keyframes, const std::vector<ReferencePose>& reference,
                          const AlignParams& params) {
  if (!(params.stamp_tolerance >= 0.0) || !std::isfinite(params.stamp_tolerance)) {
    throw Error("align: the timestamp tolerance must be finite and >= 0");
  }
  std::vector<ReferencePose> sorted = reference;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const ReferencePose& a, const ReferencePose& b) { return a.stamp < b.stamp; });

  Alignment result;
  std::vector<Eigen::Vector3d> from, to;
  for (const Keyframe& k : keyframes) {
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), k.stamp,
                                     [](const ReferencePose& r, double t) { return r.stamp < t; });
    const ReferencePose* best = nullptr;
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

void applySimilarity(const Similarity& s, Points& points) {
  for (Point& p : points) p = s(p);
}

void applySimilarity(const Similarity& s, std::vector<Keyframe>& keyframes) {
  const Eigen::Quaterniond q(s.rotation);
  for (Keyframe& k : keyframes) {
    k.position = s(k.position);
    k.orientation = (q * k.orientation).normalized();
  }
}

}  // namespace hullmap::mapper
