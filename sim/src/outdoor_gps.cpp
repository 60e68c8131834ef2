// The GPS log of the street (SceneLayout::kOutdoor): the keyframes' true positions with noise, in
// WGS84 around kOutdoorGeodeticOrigin, some lines without a fix; and gps.txt, which
// io::readReferenceTrajectory reads back (ReferenceFormat::kGps).
#include <cmath>
#include <cstdio>
#include <numeric>
#include <ostream>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/io/reference_trajectory.hpp"
#include "outdoor_scene.hpp"

namespace hullmap::sim::detail {
namespace {

using V3 = Eigen::Vector3d;

constexpr double kEarthA = 6378137.0;                   // WGS84 semi-major axis, metres
constexpr double kEarthF = 1.0 / 298.257223563;         // flattening
constexpr double kEarthE2 = kEarthF * (2.0 - kEarthF);  // first eccentricity squared

// Earth-centred Earth-fixed metres to WGS84 (latitude, longitude in degrees, altitude in metres),
// by fixed-point rounds on the latitude: 10 bring points near the surface to well under 1e-12 rad.
V3 ecefToGeodetic(const V3& e) {
  const double p = std::hypot(e.x(), e.y());
  double latitude = std::atan2(e.z(), p * (1.0 - kEarthE2)), altitude = 0.0;
  for (int round = 0; round < 10; ++round) {
    const double s = std::sin(latitude);
    const double n = kEarthA / std::sqrt(1.0 - kEarthE2 * s * s);
    altitude = p / std::cos(latitude) - n;
    latitude = std::atan2(e.z(), p * (1.0 - kEarthE2 * n / (n + altitude)));
  }
  return {latitude * 180.0 / kPi, std::atan2(e.y(), e.x()) * 180.0 / kPi, altitude};
}

// East-north-up metres around `origin` (WGS84 degrees, metres) to WGS84: the inverse of
// io::geodeticToEnu.
V3 enuToGeodetic(const V3& enu, const V3& origin) {
  const double lat = origin[0] * kPi / 180.0, lon = origin[1] * kPi / 180.0;
  const double sl = std::sin(lat), cl = std::cos(lat), so = std::sin(lon), co = std::cos(lon);
  const V3 east(-so, co, 0.0), north(-sl * co, -sl * so, cl), up(cl * co, cl * so, sl);
  return ecefToGeodetic(io::geodeticToEcef(origin[0], origin[1], origin[2]) + enu.x() * east + enu.y() * north +
                        enu.z() * up);
}

}  // namespace

std::vector<GpsFix> gpsLog(const SceneParams& p, const std::vector<io::Keyframe>& reference, core::RandomDraws& rng) {
  const std::size_t n = reference.size();
  const auto dropped = static_cast<std::size_t>(std::llround(p.gps_dropout * static_cast<double>(n)));
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng.index(i)]);
  std::vector<bool> no_fix(n, false);
  for (std::size_t k = 0; k < dropped; ++k) no_fix[order[k]] = true;
  const V3 origin(kOutdoorGeodeticOrigin[0], kOutdoorGeodeticOrigin[1], kOutdoorGeodeticOrigin[2]);
  std::vector<GpsFix> log(n);
  for (std::size_t k = 0; k < n; ++k) {
    const V3 noise = p.gps_sigma * rng.normal3();  // drawn for every line: a dropout moves no other fix
    log[k].stamp = reference[k].stamp;
    log[k].fix = !no_fix[k];
    if (!log[k].fix) continue;
    const V3 fix = enuToGeodetic(reference[k].position + noise, origin);
    log[k].latitude_deg = fix[0];
    log[k].longitude_deg = fix[1];
    log[k].altitude_m = fix[2];
  }
  return log;
}

void writeGpsLog(const std::vector<GpsFix>& log, const std::string& path) {
  core::writeFileAtomically(path, [&log](std::ostream& out) {
    char line[160];
    for (const GpsFix& f : log) {
      if (f.fix)
        std::snprintf(line, sizeof(line), "%.6f %.9f %.9f %.3f\n", f.stamp, f.latitude_deg, f.longitude_deg,
                      f.altitude_m);
      else
        std::snprintf(line, sizeof(line), "%.6f 0 0 0\n", f.stamp);
      out << line;
    }
  });
}

}  // namespace hullmap::sim::detail
