// The ground of a map that no floor plane explains: the terrain fitted to its points, raised into
// their middle and kept under the keyframes (ground.hpp).
#include "ground.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "hullmap/core/error.hpp"

namespace hullmap::pipeline {
namespace {

/// The node indices (clamped to the grid) of the cells around `v` along one axis: nodes lie at
/// origin + step * (k + 0.5).
std::pair<std::size_t, std::size_t> nodesAround(double v, double origin, double step, std::size_t n) {
  const auto k = static_cast<long>(std::floor((v - origin) / step - 0.5));
  return {std::size_t(std::clamp<long>(k, 0, long(n) - 1)), std::size_t(std::clamp<long>(k + 1, 0, long(n) - 1))};
}

}  // namespace

std::optional<Ground> fitGround(const std::vector<Eigen::Vector3d>& points,
                                const std::vector<Eigen::Vector3d>& keyframes, const mapper::TerrainParams& params) {
  if (points.empty()) return std::nullopt;
  mapper::Terrain terrain;
  try {
    terrain = mapper::fitTerrain(points, keyframes, params);
  } catch (const Error& e) {
    // A bad setting is the caller's to hear; a map the filter finds no ground in has none.
    if (!e.parameter().empty()) throw;
    return std::nullopt;
  }
  if (terrain.ground_cells < 4) return std::nullopt;
  HeightField& f = terrain.surface;
  // The points on the ground (within initial_threshold over the fit), each node's by its four cells.
  std::vector<std::vector<double>> over(f.heights.size());
  std::size_t on_ground = 0;
  for (const auto& p : points) {
    const double rise = p.z() - f.height(p.x(), p.y());
    if (rise > params.initial_threshold) continue;
    ++on_ground;
    const auto [i0, i1] = nodesAround(p.x(), f.origin.x(), f.step, f.nx);
    const auto [j0, j1] = nodesAround(p.y(), f.origin.y(), f.step, f.ny);
    for (std::size_t j = j0; j <= j1; ++j)
      for (std::size_t k = i0; k <= i1; ++k) over[j * f.nx + k].push_back(rise);
  }
  if (double(on_ground) < kGroundMinShare * double(points.size())) return std::nullopt;
  Ground g;
  GroundReport& report = g.report;
  for (std::size_t k = 0; k < over.size(); ++k) {
    auto& rises = over[k];
    if (rises.size() < std::size_t(params.min_support)) continue;  // too few points to speak for the ground
    std::nth_element(rises.begin(), rises.begin() + std::ptrdiff_t(rises.size() / 2), rises.end());
    const double rise = std::max(0.0, rises[rises.size() / 2]);
    f.heights[k] += rise;
    report.raised_most = std::max(report.raised_most, rise);
  }
  report.lowered = mapper::keepUnderKeyframes(f, keyframes, params.keyframe_clearance);
  const std::vector<std::size_t> support = mapper::slopeSupport(f, terrain.ground, params.slope);
  for (std::size_t c = 0; c < support.size(); ++c) {
    if (support[c] == std::numeric_limits<std::size_t>::max()) continue;
    ++report.filled_cells;
    report.fill_above_support_max = std::max(report.fill_above_support_max, f.heights[c] - f.heights[support[c]]);
  }
  report.step = f.step;
  report.nx = f.nx;
  report.ny = f.ny;
  report.origin = f.origin;
  report.cells_with_points = terrain.cells_with_points;
  report.measured_cells = terrain.ground_cells;
  report.coverage = double(terrain.ground_cells) / double(f.nx * f.ny);
  report.lowest = f.lowest();
  report.highest = f.highest();
  g.measured = std::move(terrain.ground);
  g.surface = collision::Surface::heightField("ground", std::move(f));
  return g;
}

bool planeExplainsGround(const mapper::Plane& floor, const Ground& ground, const mapper::TerrainParams& params) {
  const HeightField& f = *ground.surface.field;
  if (!(std::abs(floor.normal.z()) > 1e-9)) return false;
  const double band = 2.0 * params.initial_threshold;
  // Each measured node's height over the plane; the ones within the band are the plane's.
  std::vector<std::pair<Eigen::Vector2d, double>> on, above, below;
  for (std::size_t j = 0; j < f.ny; ++j)
    for (std::size_t i = 0; i < f.nx; ++i) {
      if (!ground.measured[j * f.nx + i]) continue;
      const Eigen::Vector2d xy = f.node(i, j);
      const double plane_z = (floor.offset - floor.normal.x() * xy.x() - floor.normal.y() * xy.y()) / floor.normal.z();
      const double rise = f.at(i, j) - plane_z;
      (rise > band ? above : rise < -band ? below : on).emplace_back(xy, rise);
    }
  if (on.empty()) return above.empty() && below.empty();
  // A node above the band is ground that rises from the plane (a street's slope) when it stands no
  // higher than the slope allows over its distance from the plane's nodes; higher, it is something
  // standing on the floor whose foot the map did not see, and says nothing of the floor.
  std::size_t off = below.size(), rising = 0;
  for (const auto& [xy, rise] : above) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& p : on) nearest = std::min(nearest, (p.first - xy).norm());
    rising += rise <= band + params.slope * nearest ? 1 : 0;
  }
  off += rising;
  const std::size_t measured = on.size() + below.size() + rising;
  return double(off) < kPlaneMissShare * double(measured);
}

double groundBand(const mapper::TerrainParams& params, double resolution) {
  return 0.5 * resolution + 0.5 * params.initial_threshold;
}

/// The ground (BuildParams::terrain) when no floor plane explains the map: fitted to the build's
/// sample of its points (map frame) under the keyframes, the same in both paths. A floor plane found
/// (not levelled: a levelled map is a camera's frame, not metric) gives way to the ground when it
/// does not explain it (planeExplainsGround).
void recordGround(const BuildParams& params, const io::Points& sample, const std::vector<io::Keyframe>& keyframes,
                  BuildResult& result) {
  PlaneReport& floor = result.report.floor;
  if (!params.ground || params.floor.mode != mapper::PlaneSetting::Mode::kAuto || floor.levelled) return;
  std::vector<Eigen::Vector3d> positions;
  for (const auto& k : keyframes) positions.push_back(k.position);
  std::optional<Ground> ground = fitGround(sample, positions, params.terrain);
  if (!ground) return;
  if (floor.plane) {
    if (planeExplainsGround(*floor.plane, *ground, params.terrain)) return;
    floor.plane.reset();
    floor.ground_instead = true;
  }
  result.report.ground = ground->report;
  result.surfaces.push_back(std::move(ground->surface));
}

}  // namespace hullmap::pipeline
