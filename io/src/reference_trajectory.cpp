#include "hullmap/io/reference_trajectory.hpp"
#include "hullmap/core/constants.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "byte_source.hpp"
#include "hullmap/core/error.hpp"
#include "read_detail.hpp"

namespace hullmap::io {
namespace {

constexpr double kWgs84A = 6378137.0;                   // semi-major axis, metres
constexpr double kWgs84F = 1.0 / 298.257223563;         // flattening
constexpr double kWgs84E2 = kWgs84F * (2.0 - kWgs84F);  // first eccentricity squared

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
  return {-so * d.x() + co * d.y(),                         // east
          -sl * co * d.x() - sl * so * d.y() + cl * d.z(),  // north
          cl * co * d.x() + cl * so * d.y() + sl * d.z()};  // up
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
      detail::failAt(name, line, "expected 4 or 8 numbers (t x y z [qx qy qz qw]), got " + std::to_string(count));
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

}  // namespace hullmap::io
