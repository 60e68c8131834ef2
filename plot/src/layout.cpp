#include "layout.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace hullmap::plot::detail {

std::string num(double v, int decimals) {
  if (std::abs(v) < 0.5 * std::pow(10.0, -decimals)) v = 0.0;  // no "-0"
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s(buf);
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

// Shortest text that round-trips well enough for a caption ("0.1", "12", "0.05").
std::string shortNum(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// A step of 1, 2 or 5 times a power of ten close to range / target.
double niceStep(double range, double target) {
  const double raw = range / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double norm = raw / mag;
  const double f = norm < 1.5 ? 1.0 : norm < 3.0 ? 2.0 : norm < 7.0 ? 5.0 : 10.0;
  return f * mag;
}

int decimalsFor(double step) { return std::max(0, static_cast<int>(std::ceil(-std::log10(step) - 1e-9))); }

// Pads a box by `fraction` of its extent and makes it at least `min_extent` wide and high.
Box2 padded(Box2 box, double fraction, double min_extent) {
  if (box.empty()) box = Box2{0.0, 0.0, 1.0, 1.0};
  for (auto [lo, hi] : {std::pair<double*, double*>{&box.x0, &box.x1}, {&box.y0, &box.y1}}) {
    const double grow = std::max(min_extent - (*hi - *lo), 0.0) / 2.0;
    *lo -= grow;
    *hi += grow;
    const double pad = (*hi - *lo) * fraction;
    *lo -= pad;
    *hi += pad;
  }
  return box;
}

// The box between the 5% and 95% quantiles of `points` per axis: the bulk, blind to a few far outliers.
Box2 quantileBox(const std::vector<Eigen::Vector2d>& points) {
  Box2 box;
  if (points.empty()) return box;
  std::vector<double> xs(points.size());
  std::vector<double> ys(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    xs[i] = points[i].x();
    ys[i] = points[i].y();
  }
  const auto quantile = [](std::vector<double>& v, double q) {
    const auto k = static_cast<std::size_t>(std::floor(q * static_cast<double>(v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
  };
  box.x0 = quantile(xs, 0.05);
  box.x1 = quantile(xs, 0.95);
  box.y0 = quantile(ys, 0.05);
  box.y1 = quantile(ys, 0.95);
  return box;
}

// `core` grown to take in every candidate that lies within core's larger extent (at least
// `min_extent`) beyond it; candidates farther away are gross outliers and stay outside.
Box2 withNearby(Box2 core, const std::vector<Eigen::Vector2d>& candidates, double min_extent) {
  if (core.empty()) return core;
  const double reach = std::max({core.x1 - core.x0, core.y1 - core.y0, min_extent});
  Box2 limit{core.x0 - reach, core.y0 - reach, core.x1 + reach, core.y1 + reach};
  for (const auto& p : candidates) {
    if (limit.contains(p)) core.add(p);
  }
  return core;
}

Eigen::Vector2d project(const Eigen::Vector3d& p, PlotView view) {
  return view == PlotView::kTop ? Eigen::Vector2d(p.x(), p.y()) : Eigen::Vector2d(p.x(), p.z());
}

}  // namespace hullmap::plot::detail
