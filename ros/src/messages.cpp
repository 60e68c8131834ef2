#include "hullmap/ros1/messages.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <set>

#include <sensor_msgs/PointField.h>

#include "hullmap/core/error.hpp"

namespace hullmap::ros1 {
namespace {

constexpr int kAllPointsId = 0;
constexpr int kReferencePointsId = 6;
constexpr int kTreeDepth = 16;  // octomap's

geometry_msgs::Point toPoint(double x, double y, double z) {
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

geometry_msgs::Point toPoint(const Eigen::Vector3d& v) { return toPoint(v.x(), v.y(), v.z()); }

std_msgs::ColorRGBA color(float r, float g, float b, float a) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

visualization_msgs::Marker marker(const std_msgs::Header& header, const std::string& ns, int id, int type) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  return m;
}

visualization_msgs::Marker deletion(const std_msgs::Header& header, const std::string& ns, int id) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = id;
  m.action = visualization_msgs::Marker::DELETE;
  m.pose.orientation.w = 1.0;
  return m;
}

struct CloudField {
  std::size_t offset = 0;
  std::uint8_t datatype = 0;
};

CloudField findField(const sensor_msgs::PointCloud2& cloud, const char* name) {
  for (const auto& f : cloud.fields) {
    if (f.name != name) continue;
    if (f.datatype != sensor_msgs::PointField::FLOAT32 && f.datatype != sensor_msgs::PointField::FLOAT64) {
      throw Error(std::string("PointCloud2: field ") + name + " is of datatype " + std::to_string(f.datatype) +
                  ", expected FLOAT32 (7) or FLOAT64 (8)");
    }
    const std::size_t size = f.datatype == sensor_msgs::PointField::FLOAT32 ? 4 : 8;
    if (f.offset + size > cloud.point_step) {
      throw Error(std::string("PointCloud2: field ") + name + " at offset " + std::to_string(f.offset) +
                  " lies beyond point_step " + std::to_string(cloud.point_step));
    }
    return {f.offset, f.datatype};
  }
  throw Error(std::string("PointCloud2: no field ") + name);
}

double readField(const std::uint8_t* point, const CloudField& field) {
  if (field.datatype == sensor_msgs::PointField::FLOAT32) {
    float v;
    std::memcpy(&v, point + field.offset, sizeof v);
    return v;
  }
  double v;
  std::memcpy(&v, point + field.offset, sizeof v);
  return v;
}

}  // namespace

bool OrbSlamMapMarkers::add(const visualization_msgs::Marker& m) {
  if (m.ns != "MapPoints") return false;
  if (m.action == visualization_msgs::Marker::DELETEALL) {
    const bool changed = !empty();
    clear();
    return changed;
  }
  std::optional<mapper::Points>* slot = m.id == kAllPointsId         ? &all_
                                        : m.id == kReferencePointsId ? &reference_
                                                                     : nullptr;
  if (!slot) return false;
  if (m.action == visualization_msgs::Marker::DELETE) {
    const bool changed = slot->has_value();
    slot->reset();
    return changed;
  }
  if (m.type != visualization_msgs::Marker::POINTS) return false;
  mapper::Points points;
  points.reserve(m.points.size());
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const auto& p = m.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw Error("MapPoints id " + std::to_string(m.id) + ": point " + std::to_string(i) + " is not finite");
    }
    points.emplace_back(p.x, p.y, p.z);
  }
  *slot = std::move(points);
  return true;
}

mapper::Points OrbSlamMapMarkers::points() const {
  mapper::Points points;
  points.reserve((all_ ? all_->size() : 0) + (reference_ ? reference_->size() : 0));
  if (all_) points.insert(points.end(), all_->begin(), all_->end());
  if (reference_) points.insert(points.end(), reference_->begin(), reference_->end());
  return points;
}

void OrbSlamMapMarkers::clear() {
  all_.reset();
  reference_.reset();
}

mapper::Points cloudPoints(const sensor_msgs::PointCloud2& cloud, std::size_t* non_finite) {
  if (cloud.is_bigendian) throw Error("PointCloud2: big-endian data is not read");
  const CloudField x = findField(cloud, "x");
  const CloudField y = findField(cloud, "y");
  const CloudField z = findField(cloud, "z");
  const std::uint64_t count = std::uint64_t{cloud.width} * cloud.height;
  if (cloud.height > 0 && std::uint64_t{cloud.row_step} < std::uint64_t{cloud.width} * cloud.point_step) {
    throw Error("PointCloud2: row_step " + std::to_string(cloud.row_step) + " < width * point_step");
  }
  if (std::uint64_t{cloud.row_step} * cloud.height > cloud.data.size()) {
    throw Error("PointCloud2: data holds " + std::to_string(cloud.data.size()) + " bytes, its header says " +
                std::to_string(std::uint64_t{cloud.row_step} * cloud.height));
  }
  mapper::Points points;
  points.reserve(count);
  std::size_t skipped = 0;
  for (std::uint32_t row = 0; row < cloud.height; ++row) {
    const std::uint8_t* base = cloud.data.data() + std::size_t{row} * cloud.row_step;
    for (std::uint32_t col = 0; col < cloud.width; ++col) {
      const std::uint8_t* p = base + std::size_t{col} * cloud.point_step;
      const Eigen::Vector3d v(readField(p, x), readField(p, y), readField(p, z));
      if (!v.allFinite()) {
        ++skipped;
        continue;
      }
      points.push_back(v);
    }
  }
  if (non_finite) *non_finite = skipped;
  return points;
}

namespace {

/// The footprints an obstacle stands on: its convex parts' when it has parts, else its own.
std::vector<const clustering::Footprint*> footprintsOf(const clustering::Obstacle& o) {
  std::vector<const clustering::Footprint*> prints;
  if (o.parts.empty()) {
    prints.push_back(&o.footprint);
  } else {
    for (const auto& part : o.parts) prints.push_back(&part.footprint);
  }
  return prints;
}

}  // namespace

visualization_msgs::MarkerArray obstacleMarkers(const std::vector<clustering::Obstacle>& obstacles,
                                                const std::vector<int>& previous_ids,
                                                const std_msgs::Header& header) {
  visualization_msgs::MarkerArray array;
  std::set<int> ids;
  for (const auto& o : obstacles) {
    ids.insert(o.id);
    // An obstacle in convex parts is drawn as its parts (what the path checks use): the hull of the
    // whole cluster can cover free space the parts leave open.
    auto hull = marker(header, "hulls", o.id, visualization_msgs::Marker::TRIANGLE_LIST);
    hull.color = color(0.9f, 0.5f, 0.1f, 0.6f);
    const auto add_hull = [&hull](const clustering::ConvexHull& h) {
      for (const auto& t : h.triangles) {
        for (int k : t) hull.points.push_back(toPoint(h.vertices[k]));
      }
    };
    if (o.parts.empty()) {
      add_hull(o.hull);
    } else {
      for (const auto& part : o.parts) add_hull(part.hull);
    }
    array.markers.push_back(std::move(hull));

    // One polygon: a closed LINE_STRIP; the polygons of several parts: a LINE_LIST of their edges.
    const auto prints = footprintsOf(o);
    auto footprint = marker(header, "footprints", o.id,
                            prints.size() == 1 ? visualization_msgs::Marker::LINE_STRIP
                                               : visualization_msgs::Marker::LINE_LIST);
    footprint.scale.x = 0.02;
    footprint.color = color(0.1f, 0.1f, 0.1f, 1.0f);
    for (const auto* f : prints) {
      const auto& poly = f->polygon;
      if (poly.empty()) continue;
      if (prints.size() == 1) {
        for (const auto& p : poly) footprint.points.push_back(toPoint(p.x(), p.y(), f->z_min));
        footprint.points.push_back(footprint.points.front());
      } else {
        for (std::size_t i = 0; i < poly.size(); ++i) {
          const auto& a = poly[i];
          const auto& b = poly[(i + 1) % poly.size()];
          footprint.points.push_back(toPoint(a.x(), a.y(), f->z_min));
          footprint.points.push_back(toPoint(b.x(), b.y(), f->z_min));
        }
      }
    }
    array.markers.push_back(std::move(footprint));

    auto label = marker(header, "labels", o.id, visualization_msgs::Marker::TEXT_VIEW_FACING);
    label.pose.position = toPoint(o.centroid.x(), o.centroid.y(), o.aabb_max.z() + 0.1);
    label.scale.z = 0.2;
    label.color = color(1.0f, 1.0f, 1.0f, 1.0f);
    label.text = std::to_string(o.id);
    array.markers.push_back(std::move(label));
  }
  for (int id : previous_ids) {
    if (ids.count(id)) continue;
    for (const char* ns : {"hulls", "footprints", "labels"}) array.markers.push_back(deletion(header, ns, id));
  }
  return array;
}

visualization_msgs::MarkerArray occupiedCellMarkers(const std::vector<mapper::OccupiedVoxel>& voxels,
                                                    double resolution, const std_msgs::Header& header) {
  visualization_msgs::MarkerArray array;
  for (int depth = 0; depth <= kTreeDepth; ++depth) {
    auto m = marker(header, header.frame_id, depth, visualization_msgs::Marker::CUBE_LIST);
    const double size = resolution * double(1 << (kTreeDepth - depth));
    m.scale.x = m.scale.y = m.scale.z = size;
    m.color = color(0.0f, 0.0f, 1.0f, 1.0f);
    if (depth == kTreeDepth) {
      m.points.reserve(voxels.size());
      for (const auto& v : voxels) m.points.push_back(toPoint(v.center));
    }
    if (m.points.empty()) m.action = visualization_msgs::Marker::DELETE;
    array.markers.push_back(std::move(m));
  }
  return array;
}

namespace {

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

nav_msgs::OccupancyGrid projectedMap(const std::vector<clustering::Obstacle>& obstacles, double resolution,
                                     double min_z, double max_z, double margin, const std_msgs::Header& header) {
  if (!(resolution > 0.0) || !std::isfinite(resolution)) {
    throw Error::inParameter("resolution", "must be finite and > 0, got " + std::to_string(resolution));
  }
  std::vector<const clustering::Footprint*> in_band;
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
  nav_msgs::OccupancyGrid grid;
  grid.header = header;
  grid.info.map_load_time = header.stamp;
  grid.info.resolution = static_cast<float>(resolution);
  grid.info.origin.orientation.w = 1.0;
  if (in_band.empty()) {
    grid.info.width = grid.info.height = 1;
    grid.data.assign(1, 0);
    return grid;
  }
  lo -= Eigen::Vector2d::Constant(margin);
  hi += Eigen::Vector2d::Constant(margin);
  // The origin on the grid of cell corners k * resolution, so cells line up between rebuilds.
  lo = (lo / resolution).array().floor().matrix() * resolution;
  const auto width = static_cast<std::uint32_t>(std::max(1.0, std::ceil((hi.x() - lo.x()) / resolution)));
  const auto height = static_cast<std::uint32_t>(std::max(1.0, std::ceil((hi.y() - lo.y()) / resolution)));
  grid.info.width = width;
  grid.info.height = height;
  grid.info.origin.position = toPoint(lo.x(), lo.y(), 0.0);
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

visualization_msgs::MarkerArray pathCheckMarkers(const std::vector<Eigen::Vector3d>& waypoints,
                                                 const collision::PathCheck& check, double line_width,
                                                 const std_msgs::Header& header) {
  visualization_msgs::MarkerArray array;
  auto m = marker(header, "path_check", 0, visualization_msgs::Marker::LINE_LIST);
  m.scale.x = line_width;
  m.color = color(0.0f, 0.8f, 0.0f, 1.0f);
  for (std::size_t i = 0; i + 1 < waypoints.size() && i < check.segments.size(); ++i) {
    const auto c = check.segments[i].collides ? color(1.0f, 0.0f, 0.0f, 1.0f) : color(0.0f, 0.8f, 0.0f, 1.0f);
    m.points.push_back(toPoint(waypoints[i]));
    m.points.push_back(toPoint(waypoints[i + 1]));
    m.colors.push_back(c);
    m.colors.push_back(c);
  }
  if (m.points.empty()) m.action = visualization_msgs::Marker::DELETE;
  array.markers.push_back(std::move(m));
  return array;
}

}  // namespace hullmap::ros1
