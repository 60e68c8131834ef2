#pragma once
// The picture's geometry and number formatting shared by the renderers: boxes in the view plane,
// the viewport from map units to SVG pixels, which part of a cloud to show, axis steps. Not installed.

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/plot/svg_plot.hpp"

namespace hullmap::plot::detail {

/// `v` with `decimals` decimals, trailing zeros and "-0" dropped.
std::string num(double v, int decimals = 1);
/// Shortest text that round-trips well enough for a caption ("0.1", "12", "0.05").
std::string shortNum(double v);
/// A step of 1, 2 or 5 times a power of ten close to range / target.
double niceStep(double range, double target);
/// Decimals that show a multiple of `step` exactly.
int decimalsFor(double step);

/// A box in the view plane, map units; empty until a point is added.
struct Box2 {
  double x0 = std::numeric_limits<double>::infinity();
  double y0 = std::numeric_limits<double>::infinity();
  double x1 = -std::numeric_limits<double>::infinity();
  double y1 = -std::numeric_limits<double>::infinity();
  bool empty() const { return !(x0 <= x1 && y0 <= y1); }
  void add(const Eigen::Vector2d& p, double pad = 0.0) {
    x0 = std::min(x0, p.x() - pad);
    y0 = std::min(y0, p.y() - pad);
    x1 = std::max(x1, p.x() + pad);
    y1 = std::max(y1, p.y() + pad);
  }
  bool contains(const Eigen::Vector2d& p) const { return p.x() >= x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= y1; }
};

// Map coordinates (view plane) to SVG pixels: x right, the plane's second axis up.
struct Viewport {
  Box2 world;
  double scale = 1.0;  // pixels per map unit
  double left = 0.0;
  double top = 0.0;
  double width() const { return (world.x1 - world.x0) * scale; }
  double height() const { return (world.y1 - world.y0) * scale; }
  double px(double x) const { return left + (x - world.x0) * scale; }
  double py(double y) const { return top + (world.y1 - y) * scale; }
};

/// Pads a box by `fraction` of its extent and makes it at least `min_extent` wide and high.
Box2 padded(Box2 box, double fraction, double min_extent);
/// The box between the 5% and 95% quantiles of `points` per axis: the bulk, blind to a few far outliers.
Box2 quantileBox(const std::vector<Eigen::Vector2d>& points);
/// `core` grown to take in every candidate that lies within core's larger extent (at least
/// `min_extent`) beyond it; candidates farther away are gross outliers and stay outside.
Box2 withNearby(Box2 core, const std::vector<Eigen::Vector2d>& candidates, double min_extent);
/// A map-frame point on the view's plane.
Eigen::Vector2d project(const Eigen::Vector3d& p, PlotView view);

}  // namespace hullmap::plot::detail
