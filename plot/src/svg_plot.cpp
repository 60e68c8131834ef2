// renderMapSvg: one map drawn as SVG (voxel cells, obstacle outlines, floor, roadmap, paths, scale
// bar, captions).
#include "hullmap/plot/svg_plot.hpp"
#include "hullmap/core/convex_hull_2d.hpp"
#include "hullmap/core/markup.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "hullmap/core/error.hpp"
#include "layout.hpp"

namespace hullmap::plot {
namespace {

using namespace detail;

// The visible label of each projected cell, keyed (row, column) so rows come out in order.
struct CellWinner {
  std::int32_t label = -1;
  double depth = 0.0;  // larger is nearer the viewer
};
using CellMap = std::map<std::pair<std::int64_t, std::int64_t>, CellWinner>;

// The label a cell of the floor's voxels is drawn with (MapPlot::floor_label): after noise.
constexpr std::int32_t kFloorCell = -2;
constexpr const char* kFloorCellColour = "#ddd3bb";

// A cell shows a clustered voxel before noise, noise before the floor; then the nearest.
int cellRank(std::int32_t label) { return label >= 0 ? 0 : label == kFloorCell ? 2 : 1; }

void offer(CellMap& cells, const Eigen::Vector2d& p, double cell, std::int32_t label, double depth) {
  const auto key = std::make_pair(static_cast<std::int64_t>(std::floor(p.y() / cell)),
                                  static_cast<std::int64_t>(std::floor(p.x() / cell)));
  const std::int32_t l = label < 0 && label != kFloorCell ? -1 : label;
  auto [it, inserted] = cells.try_emplace(key, CellWinner{l, depth});
  if (inserted) return;
  CellWinner& w = it->second;
  const int rank = cellRank(l), was = cellRank(w.label);
  if (rank < was || (rank == was && depth > w.depth)) w = CellWinner{l, depth};
}

// Merges runs of equal cells per row; one <path> per label in cell coordinates, mapped to pixels
// by the group's transform, so each rectangle costs a dozen bytes.
void writeCells(std::ostream& svg, const CellMap& cells, double cell, const Viewport& vp) {
  std::map<std::int32_t, std::string> paths;
  auto it = cells.begin();
  while (it != cells.end()) {
    const auto [row, col] = it->first;
    const std::int32_t label = it->second.label;
    std::int64_t length = 1;
    auto next = std::next(it);
    while (next != cells.end() && next->first.first == row && next->first.second == col + length &&
           next->second.label == label) {
      ++length;
      ++next;
    }
    std::string& d = paths[label];
    d += 'M' + std::to_string(col) + ' ' + std::to_string(row) + 'h' + std::to_string(length) + "v1h-" +
         std::to_string(length) + 'z';
    it = next;
  }
  char matrix[256];
  std::snprintf(matrix, sizeof matrix, "matrix(%.9g 0 0 %.9g %.9g %.9g)", cell * vp.scale, -cell * vp.scale,
                vp.left - vp.world.x0 * vp.scale, vp.top + vp.world.y1 * vp.scale);
  svg << "<g class=\"voxels\" transform=\"" << matrix << "\" shape-rendering=\"crispEdges\">\n";
  // Cells smaller than 3 pixels get a one-pixel outline in their own colour, so sparse points
  // stay visible in big maps.
  const bool tiny = cell * vp.scale < 3.0;
  for (const auto& [label, d] : paths) {
    const std::string colour = label == kFloorCell ? kFloorCellColour : toHex(clusterColour(label));
    svg << "<path class=\"cells\" data-label=\"" << label << "\" fill=\"" << colour << "\" d=\"" << d << '"';
    if (tiny) svg << " stroke=\"" << colour << "\" stroke-width=\"1\" vector-effect=\"non-scaling-stroke\"";
    svg << "/>\n";
  }
  svg << "</g>\n";
}

// Frame, ticks and tick labels around the viewport; axis names when given.
void writeAxes(std::ostream& svg, const Viewport& vp, const std::string& x_name, const std::string& y_name,
               double font) {
  const Box2& w = vp.world;
  svg << "<g class=\"axes\" font-family=\"sans-serif\" font-size=\"" << num(font) << "\" fill=\"#333\">\n";
  svg << "<rect x=\"" << num(vp.left) << "\" y=\"" << num(vp.top) << "\" width=\"" << num(vp.width()) << "\" height=\""
      << num(vp.height()) << "\" fill=\"none\" stroke=\"#666\" stroke-width=\"1\"/>\n";
  const double step = niceStep(std::max(w.x1 - w.x0, w.y1 - w.y0), vp.width() > 400 ? 8.0 : 4.0);
  const int dec = decimalsFor(step);
  const double bottom = vp.top + vp.height();
  for (double t = std::ceil(w.x0 / step) * step; t <= w.x1 + 1e-9 * step; t += step) {
    const double x = vp.px(t);
    svg << "<line x1=\"" << num(x) << "\" y1=\"" << num(bottom) << "\" x2=\"" << num(x) << "\" y2=\"" << num(bottom + 4)
        << "\" stroke=\"#666\"/><text x=\"" << num(x) << "\" y=\"" << num(bottom + 5 + font)
        << "\" text-anchor=\"middle\">" << num(t, dec) << "</text>\n";
  }
  // A flat view gets a finer step on its short axis, so it shows at least two ticks.
  const double y_step = std::floor(w.y1 / step) - std::ceil(w.y0 / step) >= 1.0 ? step : niceStep(w.y1 - w.y0, 3.0);
  const int y_dec = decimalsFor(y_step);
  for (double t = std::ceil(w.y0 / y_step) * y_step; t <= w.y1 + 1e-9 * y_step; t += y_step) {
    const double y = vp.py(t);
    svg << "<line x1=\"" << num(vp.left - 4) << "\" y1=\"" << num(y) << "\" x2=\"" << num(vp.left) << "\" y2=\""
        << num(y) << "\" stroke=\"#666\"/><text x=\"" << num(vp.left - 6) << "\" y=\"" << num(y + font * 0.35)
        << "\" text-anchor=\"end\">" << num(t, y_dec) << "</text>\n";
  }
  if (!x_name.empty()) {
    svg << "<text x=\"" << num(vp.left + vp.width() / 2) << "\" y=\"" << num(bottom + 2 * font + 12)
        << "\" text-anchor=\"middle\">" << core::escapeMarkup(x_name) << "</text>\n";
  }
  if (!y_name.empty()) {
    const double x = vp.left - 3.2 * font - 14;
    const double y = vp.top + vp.height() / 2;
    svg << "<text x=\"" << num(x) << "\" y=\"" << num(y) << "\" text-anchor=\"middle\" transform=\"rotate(-90 "
        << num(x) << ' ' << num(y) << ")\">" << core::escapeMarkup(y_name) << "</text>\n";
  }
  svg << "</g>\n";
}

// A bar of a round length (about a fifth of the width) with its length in map units; returns the
// height it takes.
double writeScaleBar(std::ostream& svg, const Viewport& vp, double y, double font) {
  const double length = niceStep(vp.world.x1 - vp.world.x0, 5.0);
  const double x1 = vp.left + vp.width();
  const double x0 = x1 - length * vp.scale;
  svg << "<g class=\"scale-bar\" font-family=\"sans-serif\" font-size=\"" << num(font) << "\">\n"
      << "<path d=\"M" << num(x0) << ' ' << num(y) << "v6H" << num(x1) << "v-6\" fill=\"none\" stroke=\"#000\" "
      << "stroke-width=\"1.5\"/>\n<text x=\"" << num(x0 - 6) << "\" y=\"" << num(y + 6) << "\" text-anchor=\"end\">"
      << num(length, decimalsFor(length)) << (length == 1.0 ? " map unit" : " map units") << "</text>\n</g>\n";
  return 6 + font;
}

/// The outline of a hull in the view: its footprint (top) or its projected hull (side), else the box.
std::vector<Eigen::Vector2d> outline(const hulls::ConvexHull& hull, const hulls::Footprint& footprint,
                                     const Eigen::Vector3d& aabb_min, const Eigen::Vector3d& aabb_max, PlotView view) {
  if (view == PlotView::kTop) {
    if (footprint.polygon.size() >= 3) return footprint.polygon;
    return {{aabb_min.x(), aabb_min.y()},
            {aabb_max.x(), aabb_min.y()},
            {aabb_max.x(), aabb_max.y()},
            {aabb_min.x(), aabb_max.y()}};
  }
  std::vector<Eigen::Vector2d> projected;
  projected.reserve(hull.vertices.size());
  for (const auto& v : hull.vertices) projected.push_back(project(v, view));
  auto outer = hullmap::core::convexHull2d(std::move(projected));
  if (outer.size() >= 3) return outer;
  return {{aabb_min.x(), aabb_min.z()},
          {aabb_max.x(), aabb_min.z()},
          {aabb_max.x(), aabb_max.z()},
          {aabb_min.x(), aabb_max.z()}};
}

/// One outline per convex part of the obstacle (its whole outline when it has no parts): the whole
/// hull of a ring of walls would cover the room inside it.
std::vector<std::vector<Eigen::Vector2d>> outlines(const hulls::Obstacle& o, PlotView view) {
  if (o.parts.empty()) return {outline(o.hull, o.footprint, o.aabb_min, o.aabb_max, view)};
  std::vector<std::vector<Eigen::Vector2d>> out;
  for (const auto& part : o.parts)
    out.push_back(outline(part.hull, part.footprint, part.aabb_min, part.aabb_max, view));
  return out;
}

void writeObstacles(std::ostream& svg, const std::vector<hulls::Obstacle>& obstacles, PlotView view,
                    const Viewport& vp) {
  svg << "<g class=\"obstacles\" font-family=\"sans-serif\" font-size=\"12\" font-weight=\"bold\">\n";
  for (const auto& o : obstacles) {
    // The id is written once per obstacle, inside its largest outline; every part's outline is
    // drawn (the first carries the element id "obstacle-<id>", all carry data-obstacle).
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    double size = 7.0, largest = -1.0;
    bool first = true;
    for (const auto& polygon : outlines(o, view)) {
      std::string points;
      Eigen::Vector2d centre = Eigen::Vector2d::Zero();
      for (const auto& p : polygon) {
        points += num(vp.px(p.x())) + ',' + num(vp.py(p.y())) + ' ';
        centre += p;
      }
      centre /= static_cast<double>(std::max<std::size_t>(polygon.size(), 1));
      if (!points.empty()) points.pop_back();
      Box2 extent;
      for (const auto& p : polygon) extent.add(p);
      const double area = (extent.x1 - extent.x0) * (extent.y1 - extent.y0);
      if (area > largest) {
        largest = area;
        mean = centre;
        // Numbers shrink with their outline (12 px down to 7 px), so crowded small obstacles stay legible.
        size = std::clamp(0.6 * std::min(extent.x1 - extent.x0, extent.y1 - extent.y0) * vp.scale, 7.0, 12.0);
      }
      // A white halo under the dark outline keeps it visible on any cluster colour.
      svg << "<polygon class=\"footprint-halo\" points=\"" << points
          << "\" fill=\"none\" stroke=\"#fff\" stroke-width=\"3.5\" stroke-linejoin=\"round\"/>\n"
          << "<polygon class=\"footprint\"";
      if (first) svg << " id=\"obstacle-" << o.id << '"';
      svg << " data-obstacle=\"" << o.id << "\" points=\"" << points
          << "\" fill=\"none\" stroke=\"#111\" stroke-width=\"1.5\" stroke-linejoin=\"round\"/>\n";
      first = false;
    }
    svg << "<text class=\"obstacle-id\" x=\"" << num(vp.px(mean.x())) << "\" y=\"" << num(vp.py(mean.y()) + size / 3)
        << "\" font-size=\"" << num(size) << "\" text-anchor=\"middle\" fill=\"#111\" stroke=\"#fff\" stroke-width=\""
        << num(size / 4) << "\" paint-order=\"stroke\">" << o.id << "</text>\n";
  }
  svg << "</g>\n";
}

std::string point3(const Eigen::Vector3d& p) {
  return "(" + num(p.x(), 3) + ", " + num(p.y(), 3) + ", " + num(p.z(), 3) + ")";
}

// Draws the roadmap's edges and nodes (top view).
void writeRoadmap(std::ostream& svg, const PlotRoadmap& roadmap, const Viewport& vp) {
  svg << "<g class=\"roadmap\" fill=\"none\" stroke=\"#16a34a\" stroke-opacity=\"0.75\" stroke-width=\"1\">\n";
  for (std::size_t i = 0; i < roadmap.edges.size(); ++i) {
    std::string points;
    for (const auto& p : roadmap.edges[i]) points += num(vp.px(p.x())) + ',' + num(vp.py(p.y())) + ' ';
    if (!points.empty()) points.pop_back();
    svg << "<polyline class=\"roadmap-edge\"";
    if (i < roadmap.clearance.size()) svg << " data-clearance=\"" << shortNum(roadmap.clearance[i]) << '"';
    svg << " points=\"" << points << "\"/>\n";
  }
  for (const auto& p : roadmap.nodes) {
    svg << "<circle class=\"roadmap-node\" cx=\"" << num(vp.px(p.x())) << "\" cy=\"" << num(vp.py(p.y()))
        << "\" r=\"1.5\" fill=\"#16a34a\" stroke=\"none\"/>\n";
  }
  svg << "</g>\n";
}

// The outline of the floor's voxels: the convex hull of their cells' corners in the view plane.
std::vector<Eigen::Vector2d> floorOutline(const MapPlot& plot) {
  std::vector<Eigen::Vector2d> corners;
  const double h = plot.voxel_size / 2;
  for (std::size_t i = 0; i < plot.centers.size(); ++i) {
    if (plot.labels[i] != *plot.floor_label) continue;
    const Eigen::Vector2d c = project(plot.centers[i], plot.view);
    for (const double dx : {-h, h})
      for (const double dy : {-h, h}) corners.emplace_back(c.x() + dx, c.y() + dy);
  }
  return hullmap::core::convexHull2d(std::move(corners));
}

void writeFloorOutline(std::ostream& svg, const std::vector<Eigen::Vector2d>& outline, const Viewport& vp) {
  std::string points;
  for (const auto& p : outline) points += num(vp.px(p.x())) + ',' + num(vp.py(p.y())) + ' ';
  if (!points.empty()) points.pop_back();
  svg << "<polygon class=\"floor-outline\" points=\"" << points
      << "\" fill=\"none\" stroke=\"#8b6f3a\" stroke-width=\"1.5\" stroke-dasharray=\"7 4\"/>\n";
}

// The keyframes as the camera's path: a dashed line through them and a dot at each.
void writeTrajectory(std::ostream& svg, const std::vector<Eigen::Vector3d>& keyframes, PlotView view,
                     const Viewport& vp) {
  std::string points;
  for (const auto& k : keyframes) {
    const Eigen::Vector2d q = project(k, view);
    points += num(vp.px(q.x())) + ',' + num(vp.py(q.y())) + ' ';
  }
  if (!points.empty()) points.pop_back();
  svg << "<g class=\"trajectory\" stroke=\"#6d28d9\" fill=\"#6d28d9\">\n<polyline points=\"" << points
      << "\" fill=\"none\" stroke-width=\"1.2\" stroke-dasharray=\"5 3\"/>\n";
  for (const auto& k : keyframes) {
    const Eigen::Vector2d q = project(k, view);
    svg << "<circle class=\"keyframe\" cx=\"" << num(vp.px(q.x())) << "\" cy=\"" << num(vp.py(q.y()))
        << "\" r=\"1.8\" stroke=\"none\"/>\n";
  }
  svg << "</g>\n";
}

// Draws the path in its colour; returns its caption line.
std::string writePath(std::ostream& svg, const PlotPath& path, std::size_t index, PlotView view, const Viewport& vp) {
  const std::string colour = toHex(pathColour(index));
  const auto& wp = path.waypoints;
  if (wp.size() >= 2 && path.check.segments.size() != wp.size() - 1) {
    throw Error("plot: path check has " + std::to_string(path.check.segments.size()) + " segments for " +
                std::to_string(wp.size()) + " waypoints");
  }
  std::string points;
  for (const auto& p : wp) {
    const Eigen::Vector2d q = project(p, view);
    points += num(vp.px(q.x())) + ',' + num(vp.py(q.y())) + ' ';
  }
  if (!points.empty()) points.pop_back();
  svg << "<g class=\"path\" data-index=\"" << index << "\">\n"
      << "<polyline class=\"path-band\" points=\"" << points << "\" fill=\"none\" stroke=\"" << colour << "\" "
      << "stroke-opacity=\"0.22\" stroke-width=\"" << num(std::max(2.0 * path.radius * vp.scale, 1.0))
      << "\" stroke-linecap=\"round\" stroke-linejoin=\"round\"/>\n"
      << "<polyline class=\"path-line\" points=\"" << points << "\" fill=\"none\" stroke=\"" << colour
      << "\" stroke-width=\"1.5\"/>\n";
  std::size_t colliding = 0;
  double clearance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < path.check.segments.size(); ++i) {
    const auto& s = path.check.segments[i];
    clearance = std::min(clearance, s.clearance);
    if (!s.collides) continue;
    ++colliding;
    const Eigen::Vector2d a = project(wp[i], view);
    const Eigen::Vector2d b = project(wp[i + 1], view);
    svg << "<line class=\"colliding-segment\" data-segment=\"" << i << "\" x1=\"" << num(vp.px(a.x())) << "\" y1=\""
        << num(vp.py(a.y())) << "\" x2=\"" << num(vp.px(b.x())) << "\" y2=\"" << num(vp.py(b.y()))
        << "\" stroke=\"#e00000\" stroke-width=\"3\" stroke-linecap=\"round\"/>\n";
  }
  for (const auto& p : wp) {
    const Eigen::Vector2d q = project(p, view);
    svg << "<circle class=\"waypoint\" cx=\"" << num(vp.px(q.x())) << "\" cy=\"" << num(vp.py(q.y()))
        << "\" r=\"2.5\" fill=\"" << colour << "\"/>\n";
  }
  std::string caption = "path" + (path.name.empty() ? std::string() : " " + path.name) + " (" + colour +
                        "): " + std::to_string(path.check.segments.size()) + " segments, radius " +
                        shortNum(path.radius) + ", ";
  if (path.check.first_contact) {
    const Eigen::Vector2d c = project(*path.check.first_contact, view);
    const double x = vp.px(c.x());
    const double y = vp.py(c.y());
    svg << "<g class=\"first-contact\" stroke=\"#e00000\" stroke-width=\"2.5\" fill=\"none\">"
        << "<circle cx=\"" << num(x) << "\" cy=\"" << num(y) << "\" r=\"7\"/>"
        << "<path d=\"M" << num(x - 11) << ' ' << num(y) << "h22M" << num(x) << ' ' << num(y - 11) << "v22\"/>"
        << "</g>\n<text x=\"" << num(x + 10) << "\" y=\"" << num(y - 10) << "\" font-family=\"sans-serif\" "
        << "font-size=\"12\" fill=\"#e00000\" stroke=\"#fff\" stroke-width=\"3\" paint-order=\"stroke\">"
        << "first contact</text>\n";
    caption += std::to_string(colliding) + " colliding (red), first contact at " + point3(*path.check.first_contact);
    if (path.check.first_colliding_segment) {
      caption += " on segment " + std::to_string(*path.check.first_colliding_segment);
    }
  } else if (colliding > 0) {
    caption += std::to_string(colliding) + " colliding (red)";
  } else {
    caption += "clear";
    if (std::isfinite(clearance)) caption += ", min clearance " + shortNum(clearance);
  }
  svg << "</g>\n";
  return caption;
}

// Rough width of the longest line in sans-serif at `font` pixels, to keep captions inside the picture.
double captionWidth(const std::vector<std::string>& lines, double font) {
  std::size_t longest = 0;
  for (const auto& line : lines) longest = std::max(longest, line.size());
  return 0.58 * font * static_cast<double>(longest);
}

std::string svgHeader(double width, double height) {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(width) +
         "\" height=\"" + num(height) + "\" viewBox=\"0 0 " + num(width) + ' ' + num(height) +
         "\">\n<rect class=\"background\" width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
}

}  // namespace

Rgb pathColour(std::size_t index) {
  static constexpr Rgb kColours[] = {{0x1d, 0x4e, 0xd8}, {0xea, 0x58, 0x0c}, {0x15, 0x80, 0x3d}, {0x7e, 0x22, 0xce},
                                     {0xdc, 0x26, 0x26}, {0x0f, 0x76, 0x6e}, {0xdb, 0x27, 0x77}, {0x65, 0x73, 0x0e}};
  return kColours[index % (sizeof kColours / sizeof kColours[0])];
}

namespace {

// What the picture shows: the box around everything clustered or drawn on top plus the bulk of the
// noise (noise voxels outside it are far outliers, hidden), and the viewport that maps it to the page.
struct PlotFrame {
  Box2 shown;
  Viewport vp;
};

PlotFrame plotFrame(const MapPlot& plot) {
  const PlotView view = plot.view;
  const double cell = plot.voxel_size;
  std::vector<Eigen::Vector2d> noise;
  Box2 box;
  for (std::size_t i = 0; i < plot.centers.size(); ++i) {
    const Eigen::Vector2d p = project(plot.centers[i], view);
    if (plot.labels[i] >= 0) {
      box.add(p, cell / 2);
    } else {
      noise.push_back(p);
    }
  }
  const Box2 bulk = quantileBox(noise);
  if (!bulk.empty()) {
    box.add({bulk.x0, bulk.y0});
    box.add({bulk.x1, bulk.y1});
  }
  for (const auto& o : plot.obstacles) {
    for (const auto& polygon : outlines(o, view))
      for (const auto& p : polygon) box.add(p);
  }
  for (const auto& path : plot.paths) {
    for (const auto& p : path.waypoints) box.add(project(p, view), path.radius);
  }
  if (plot.roadmap && view == PlotView::kTop) {
    for (const auto& e : plot.roadmap->edges)
      for (const auto& p : e) box.add(p);
  }
  for (const auto& k : plot.keyframes) box.add(project(k, view));
  const Box2 shown = withNearby(box, noise, 4 * cell);  // noise voxels outside are hidden outliers
  box = shown;
  box.x0 -= cell / 2;
  box.y0 -= cell / 2;
  box.x1 += cell / 2;
  box.y1 += cell / 2;
  Viewport vp;
  vp.world = padded(box, 0.04, 4 * cell);
  const double max_w = 760.0;
  const double max_h = 620.0;
  vp.scale = std::min(max_w / (vp.world.x1 - vp.world.x0), max_h / (vp.world.y1 - vp.world.y0));
  vp.left = 78.0;
  vp.top = 36.0;
  return {shown, vp};
}

struct VoxelCounts {
  std::size_t clusters = 0, noise = 0, floor = 0;
};

VoxelCounts countVoxels(const MapPlot& plot) {
  std::set<std::int32_t> clusters;
  std::size_t noise_voxels = 0, floor_voxels = 0;
  for (std::int32_t l : plot.labels) {
    if (l >= 0) {
      clusters.insert(l);
    } else if (plot.floor_label && l == *plot.floor_label) {
      ++floor_voxels;
    } else {
      ++noise_voxels;
    }
  }
  return {clusters.size(), noise_voxels, floor_voxels};
}

}  // namespace

SvgPicture renderMapSvg(const MapPlot& plot) {
  if (!(plot.voxel_size > 0.0) || !std::isfinite(plot.voxel_size)) {
    throw Error("plot: voxel size must be > 0, got " + shortNum(plot.voxel_size));
  }
  if (plot.labels.size() != plot.centers.size()) {
    throw Error("plot: " + std::to_string(plot.labels.size()) + " labels for " + std::to_string(plot.centers.size()) +
                " voxels");
  }
  const PlotView view = plot.view;
  const double cell = plot.voxel_size;

  const PlotFrame frame = plotFrame(plot);
  const Box2& shown = frame.shown;
  const Viewport& vp = frame.vp;

  SvgPicture picture;
  CellMap cells;
  for (std::size_t i = 0; i < plot.centers.size(); ++i) {
    const Eigen::Vector3d& c = plot.centers[i];
    const Eigen::Vector2d p = project(c, view);
    if (!shown.empty() && !shown.contains(p) && plot.labels[i] < 0) {
      ++picture.hidden_voxels;
      continue;
    }
    const bool floor = plot.floor_label && plot.labels[i] == *plot.floor_label;
    offer(cells, p, cell,
          floor                ? kFloorCell
          : plot.labels[i] < 0 ? -1
                               : plot.labels[i],
          view == PlotView::kTop ? c.z() : -c.y());
  }
  picture.cells = cells.size();

  const VoxelCounts counts = countVoxels(plot);

  std::ostringstream body;
  const double font = 12.0;
  writeCells(body, cells, cell, vp);
  if (plot.floor_label) {
    const auto outline = floorOutline(plot);
    if (outline.size() >= 3) writeFloorOutline(body, outline, vp);
  }
  writeObstacles(body, plot.obstacles, view, vp);
  std::vector<std::string> caption = plot.caption;
  caption.push_back(std::to_string(plot.centers.size()) + " voxels, " + std::to_string(counts.clusters) +
                    " clusters (colours), " + std::to_string(counts.noise) + " noise voxels (black), " +
                    std::to_string(plot.obstacles.size()) + " obstacles (outlined, numbered)");
  caption.push_back(view == PlotView::kTop
                        ? "top view: each x-y cell shows its topmost clustered voxel, else its topmost voxel"
                        : "side view from -y: each x-z cell shows its nearest clustered voxel, else its nearest voxel");
  if (picture.hidden_voxels > 0) {
    caption.push_back(std::to_string(picture.hidden_voxels) + " far noise voxels outside the view, not drawn");
  }
  if (counts.floor > 0) {
    caption.push_back("floor (light brown cells, dashed outline): " + std::to_string(counts.floor) +
                      " voxels, not clustered");
  }
  if (!plot.keyframes.empty()) {
    writeTrajectory(body, plot.keyframes, view, vp);
    caption.push_back("keyframe trajectory (dashed purple): " + std::to_string(plot.keyframes.size()) + " keyframes");
  }
  if (plot.roadmap && view == PlotView::kTop) {
    writeRoadmap(body, *plot.roadmap, vp);
    caption.push_back("roadmap (green): " + std::to_string(plot.roadmap->edges.size()) + " edges, " +
                      std::to_string(plot.roadmap->nodes.size()) + " nodes");
  }
  for (std::size_t i = 0; i < plot.paths.size(); ++i) caption.push_back(writePath(body, plot.paths[i], i, view, vp));
  writeAxes(body, vp, "x (map units)", view == PlotView::kTop ? "y (map units)" : "z (map units)", font);
  double y = vp.top + vp.height() + 2 * font + 28;
  y += writeScaleBar(body, vp, y - 10, font) + 4;
  body << "<g class=\"caption\" font-family=\"sans-serif\" font-size=\"" << num(font) << "\" fill=\"#111\">\n";
  for (const auto& line : caption) {
    y += font + 5;
    body << "<text x=\"" << num(vp.left) << "\" y=\"" << num(y) << "\">" << core::escapeMarkup(line) << "</text>\n";
  }
  body << "</g>\n";

  const double width = std::max({vp.left + vp.width() + 24.0, 620.0, vp.left + 20 + captionWidth(caption, font)});
  const double height = y + 14.0;
  std::string svg = svgHeader(width, height);
  svg += "<text class=\"title\" x=\"" + num(vp.left) + "\" y=\"22\" font-family=\"sans-serif\" font-size=\"15\" " +
         "font-weight=\"bold\">hullmap: " + (view == PlotView::kTop ? "top view (x-y)" : "side view (x-z)") +
         "</text>\n";
  svg += body.str();
  svg += "</svg>\n";
  picture.svg = std::move(svg);
  return picture;
}

std::string renderSweepSvg(const std::vector<Eigen::Vector3d>& points, const std::vector<SweepPanel>& panels,
                           double cell_size, const std::string& title) {
  for (const auto& panel : panels) {
    if (panel.labels.size() != points.size()) {
      throw Error("sweep plot: panel eps=" + shortNum(panel.eps) + " min_pts=" + std::to_string(panel.min_pts) +
                  " has " + std::to_string(panel.labels.size()) + " labels for " + std::to_string(points.size()) +
                  " points");
    }
  }
  std::vector<Eigen::Vector2d> xy(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) xy[i] = project(points[i], PlotView::kTop);
  const Box2 shown = withNearby(quantileBox(xy), xy, 0.0);
  if (!(cell_size > 0.0)) {
    const Box2 extent = padded(shown, 0.0, 0.0);
    cell_size = std::max(extent.x1 - extent.x0, extent.y1 - extent.y0) / 150.0;
    if (!(cell_size > 0.0)) cell_size = 1.0;  // all points in one place
  }
  const Box2 world = padded(shown, 0.04, 4 * cell_size);

  // Layout: a full eps x min_pts grid when the panels are one, else row by row.
  std::set<double> eps_values;
  std::set<int> min_pts_values;
  std::set<std::pair<double, int>> combos;
  for (const auto& p : panels) {
    eps_values.insert(p.eps);
    min_pts_values.insert(p.min_pts);
    combos.insert({p.eps, p.min_pts});
  }
  const bool grid = combos.size() == panels.size() && eps_values.size() * min_pts_values.size() == panels.size();
  const std::size_t columns =
      grid ? eps_values.size()
           : std::max<std::size_t>(1,
                                   static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(panels.size())))));
  const std::size_t rows = panels.empty() ? 0 : (panels.size() + columns - 1) / columns;

  const double panel_max = 280.0;
  const double scale = std::min(panel_max / (world.x1 - world.x0), panel_max / (world.y1 - world.y0));
  const double pw = (world.x1 - world.x0) * scale;
  const double ph = (world.y1 - world.y0) * scale;
  const double gap_x = 62.0;
  const double gap_y = 74.0;
  const double left0 = 56.0;
  const double top0 = 70.0;
  const double font = 10.0;

  std::ostringstream body;
  std::size_t hidden = 0;
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const SweepPanel& panel = panels[k];
    std::size_t row = k / columns;
    std::size_t col = k % columns;
    if (grid) {
      row = static_cast<std::size_t>(std::distance(min_pts_values.begin(), min_pts_values.find(panel.min_pts)));
      col = static_cast<std::size_t>(std::distance(eps_values.begin(), eps_values.find(panel.eps)));
    }
    Viewport vp;
    vp.world = world;
    vp.scale = scale;
    vp.left = left0 + static_cast<double>(col) * (pw + gap_x);
    vp.top = top0 + static_cast<double>(row) * (ph + gap_y);

    CellMap cells;
    std::set<std::int32_t> clusters;
    std::size_t noise = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const std::int32_t l = panel.labels[i];
      if (l >= 0) {
        clusters.insert(l);
      } else {
        ++noise;
      }
      if (!shown.contains(xy[i])) {
        if (k == 0) ++hidden;
        continue;
      }
      // Depth by input order: the first point of a cell wins among equals.
      offer(cells, xy[i], cell_size, l, -static_cast<double>(i));
    }
    const double noise_pct =
        points.empty() ? 0.0 : 100.0 * static_cast<double>(noise) / static_cast<double>(points.size());
    body << "<g class=\"panel\" data-eps=\"" << shortNum(panel.eps) << "\" data-min-pts=\"" << panel.min_pts
         << "\" data-clusters=\"" << clusters.size() << "\">\n"
         << "<text class=\"panel-title\" x=\"" << num(vp.left) << "\" y=\"" << num(vp.top - 20)
         << "\" font-family=\"sans-serif\" font-size=\"12\" font-weight=\"bold\">\u03b5 = " << shortNum(panel.eps)
         << ", minPts = " << panel.min_pts << "</text>\n"
         << "<text x=\"" << num(vp.left) << "\" y=\"" << num(vp.top - 6)
         << "\" font-family=\"sans-serif\" font-size=\"11\" fill=\"#333\">" << clusters.size() << " clusters, "
         << num(noise_pct, 1) << "% noise</text>\n";
    writeCells(body, cells, cell_size, vp);
    writeAxes(body, vp, "", "", font);
    body << "</g>\n";
  }

  const double width = left0 + static_cast<double>(columns) * (pw + gap_x);
  double y = top0 + static_cast<double>(rows) * (ph + gap_y) - gap_y + 2 * font + 26;
  Viewport first;
  first.world = world;
  first.scale = scale;
  first.left = left0;
  first.top = 0;
  writeScaleBar(body, first, y - 14, 11.0);
  std::vector<std::string> caption = {
      std::to_string(points.size()) + " points, top view (x-y); clusters in colours, noise in black; each cell of " +
      num(cell_size, std::max(2, decimalsFor(cell_size) + 1)) + " map units shows a clustered point when it has one"};
  if (hidden > 0) caption.push_back(std::to_string(hidden) + " far points outside the view, not drawn");
  body << "<g class=\"caption\" font-family=\"sans-serif\" font-size=\"11\" fill=\"#111\">\n";
  for (const auto& line : caption) {
    y += 16;
    body << "<text x=\"" << num(left0) << "\" y=\"" << num(y) << "\">" << core::escapeMarkup(line) << "</text>\n";
  }
  body << "</g>\n";

  std::string svg = svgHeader(std::max({width, 520.0, left0 + 20 + captionWidth(caption, 11.0)}), y + 14);
  svg += "<text class=\"title\" x=\"" + num(left0) + "\" y=\"20\" font-family=\"sans-serif\" font-size=\"15\" " +
         "font-weight=\"bold\">" + core::escapeMarkup(title) + "</text>\n";
  svg += body.str();
  svg += "</svg>\n";
  return svg;
}

}  // namespace hullmap::plot
