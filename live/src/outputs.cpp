#include "hullmap/live/outputs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

#include "hullmap/core/error.hpp"

namespace hullmap::live {
namespace {

constexpr int kTreeDepth = 16;  // octomap's

MarkerSpec added(const std::string& ns, int id, int type) {
  MarkerSpec m;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.scale = Eigen::Vector3d::Ones();
  return m;
}

MarkerSpec deletion(const std::string& ns, int id) {
  MarkerSpec m;
  m.ns = ns;
  m.id = id;
  m.action = marker::kDelete;
  return m;
}

/// The footprints an obstacle stands on: its convex parts' when it has parts, else its own.
std::vector<const hulls::Footprint*> footprintsOf(const hulls::Obstacle& o) {
  std::vector<const hulls::Footprint*> prints;
  if (o.parts.empty()) {
    prints.push_back(&o.footprint);
  } else {
    for (const auto& part : o.parts) prints.push_back(&part.footprint);
  }
  return prints;
}

/// True when the convex polygon (counter-clockwise) and the axis-aligned square meet (separating axes:
/// the square's two axes and the polygon's edge normals).
bool polygonTouchesSquare(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& lo,
                          const Eigen::Vector2d& hi) {
  Eigen::Vector2d pmin = polygon.front(), pmax = polygon.front();
  for (const auto& p : polygon) {
    pmin = pmin.cwiseMin(p);
    pmax = pmax.cwiseMax(p);
  }
  if (pmin.x() > hi.x() || pmax.x() < lo.x() || pmin.y() > hi.y() || pmax.y() < lo.y()) return false;
  const Eigen::Vector2d corners[4] = {lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}};
  for (std::size_t i = 0; i < polygon.size() && polygon.size() >= 3; ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    const Eigen::Vector2d outward(b.y() - a.y(), a.x() - b.x());
    bool all_outside = true;
    for (const auto& c : corners) all_outside = all_outside && outward.dot(c - a) > 0.0;
    if (all_outside) return false;
  }
  return true;
}

}  // namespace

std::vector<MarkerSpec> obstacleMarkers(const std::vector<hulls::Obstacle>& obstacles,
                                        const std::vector<int>& previous_ids) {
  std::vector<MarkerSpec> markers;
  std::set<int> ids;
  for (const auto& o : obstacles) {
    ids.insert(o.id);
    // An obstacle in convex parts is drawn as its parts (what the path checks use): the hull of the
    // whole cluster can cover free space the parts leave open.
    auto hull = added("hulls", o.id, marker::kTriangleList);
    hull.color = {0.9f, 0.5f, 0.1f, 0.6f};
    const auto add_hull = [&hull](const hulls::ConvexHull& h) {
      for (const auto& t : h.triangles) {
        for (int k : t) hull.points.push_back(h.vertices[k]);
      }
    };
    if (o.parts.empty()) {
      add_hull(o.hull);
    } else {
      for (const auto& part : o.parts) add_hull(part.hull);
    }
    markers.push_back(std::move(hull));

    // One polygon: a closed LINE_STRIP; the polygons of several parts: a LINE_LIST of their edges.
    const auto prints = footprintsOf(o);
    auto footprint = added("footprints", o.id, prints.size() == 1 ? marker::kLineStrip : marker::kLineList);
    footprint.scale.x() = 0.02;
    footprint.color = {0.1f, 0.1f, 0.1f, 1.0f};
    for (const auto* f : prints) {
      const auto& poly = f->polygon;
      if (poly.empty()) continue;
      if (prints.size() == 1) {
        for (const auto& p : poly) footprint.points.emplace_back(p.x(), p.y(), f->z_min);
        footprint.points.push_back(footprint.points.front());
      } else {
        for (std::size_t i = 0; i < poly.size(); ++i) {
          const auto& a = poly[i];
          const auto& b = poly[(i + 1) % poly.size()];
          footprint.points.emplace_back(a.x(), a.y(), f->z_min);
          footprint.points.emplace_back(b.x(), b.y(), f->z_min);
        }
      }
    }
    markers.push_back(std::move(footprint));

    auto label = added("labels", o.id, marker::kTextViewFacing);
    label.position = {o.centroid.x(), o.centroid.y(), o.aabb_max.z() + 0.1};
    label.scale.z() = 0.2;
    label.color = {1.0f, 1.0f, 1.0f, 1.0f};
    label.text = std::to_string(o.id);
    markers.push_back(std::move(label));
  }
  for (int id : previous_ids) {
    if (ids.count(id)) continue;
    for (const char* ns : {"hulls", "footprints", "labels"}) markers.push_back(deletion(ns, id));
  }
  return markers;
}

std::vector<MarkerSpec> occupiedCellMarkers(const std::vector<mapper::OccupiedVoxel>& voxels, double resolution,
                                            const std::string& ns) {
  std::vector<MarkerSpec> markers;
  for (int depth = 0; depth <= kTreeDepth; ++depth) {
    auto m = added(ns, depth, marker::kCubeList);
    m.scale = Eigen::Vector3d::Constant(resolution * double(1 << (kTreeDepth - depth)));
    m.color = {0.0f, 0.0f, 1.0f, 1.0f};
    if (depth == kTreeDepth) {
      m.points.reserve(voxels.size());
      for (const auto& v : voxels) m.points.push_back(v.center);
    }
    if (m.points.empty()) m.action = marker::kDelete;
    markers.push_back(std::move(m));
  }
  return markers;
}

std::vector<MarkerSpec> pathCheckMarkers(const std::vector<Eigen::Vector3d>& waypoints,
                                         const collision::PathCheck& check, double line_width) {
  auto m = added("path_check", 0, marker::kLineList);
  m.scale.x() = line_width;
  m.color = {0.0f, 0.8f, 0.0f, 1.0f};
  for (std::size_t i = 0; i + 1 < waypoints.size() && i < check.segments.size(); ++i) {
    const Rgba c = check.segments[i].collides ? Rgba{1.0f, 0.0f, 0.0f, 1.0f} : Rgba{0.0f, 0.8f, 0.0f, 1.0f};
    m.points.push_back(waypoints[i]);
    m.points.push_back(waypoints[i + 1]);
    m.colors.push_back(c);
    m.colors.push_back(c);
  }
  if (m.points.empty()) m.action = marker::kDelete;
  return {std::move(m)};
}

ProjectedGrid projectedGrid(const std::vector<hulls::Obstacle>& obstacles, double resolution, double min_z,
                            double max_z, double margin) {
  if (!(resolution > 0.0) || !std::isfinite(resolution)) {
    throw Error::inParameter("resolution", "must be finite and > 0, got " + std::to_string(resolution));
  }
  std::vector<const hulls::Footprint*> in_band;
  Eigen::Vector2d lo(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const auto& o : obstacles) {
    for (const auto* f : footprintsOf(o)) {
      if (f->polygon.empty() || f->z_max < min_z || f->z_min > max_z) continue;
      in_band.push_back(f);
      for (const auto& p : f->polygon) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
  }
  ProjectedGrid grid;
  grid.resolution = resolution;
  if (in_band.empty()) {
    grid.width = grid.height = 1;
    grid.data.assign(1, 0);
    return grid;
  }
  lo -= Eigen::Vector2d::Constant(margin);
  hi += Eigen::Vector2d::Constant(margin);
  // The origin on the grid of cell corners k * resolution, so cells line up between rebuilds.
  lo = (lo / resolution).array().floor().matrix() * resolution;
  const double columns = std::max(1.0, std::ceil((hi.x() - lo.x()) / resolution));
  const double rows = std::max(1.0, std::ceil((hi.y() - lo.y()) / resolution));
  if (!(columns * rows <= double(kMaxGridCells))) {
    char size[64];
    std::snprintf(size, sizeof size, "%.0f x %.0f", columns, rows);
    throw Error::inParameter("resolution", std::string("the projected map would be ") + size + " cells, more than " +
                                               std::to_string(kMaxGridCells) + "; a coarser resolution draws it");
  }
  const auto width = static_cast<std::uint32_t>(columns);
  const auto height = static_cast<std::uint32_t>(rows);
  grid.width = width;
  grid.height = height;
  grid.origin = lo;
  grid.data.assign(std::size_t{width} * height, 0);
  for (const auto* f : in_band) {
    Eigen::Vector2d pmin = f->polygon.front(), pmax = pmin;
    for (const auto& p : f->polygon) {
      pmin = pmin.cwiseMin(p);
      pmax = pmax.cwiseMax(p);
    }
    const auto cell = [&](double v, double origin, std::uint32_t n) {
      return static_cast<std::uint32_t>(std::clamp(std::floor((v - origin) / resolution), 0.0, double(n - 1)));
    };
    for (std::uint32_t r = cell(pmin.y(), lo.y(), height); r <= cell(pmax.y(), lo.y(), height); ++r) {
      for (std::uint32_t c = cell(pmin.x(), lo.x(), width); c <= cell(pmax.x(), lo.x(), width); ++c) {
        const Eigen::Vector2d cmin(lo.x() + c * resolution, lo.y() + r * resolution);
        if (polygonTouchesSquare(f->polygon, cmin, cmin + Eigen::Vector2d::Constant(resolution))) {
          grid.data[std::size_t{r} * width + c] = 100;
        }
      }
    }
  }
  return grid;
}

}  // namespace hullmap::live
