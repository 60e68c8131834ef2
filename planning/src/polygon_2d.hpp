#pragma once
// Plane geometry on polygons and segments that the roadmap uses around CGAL's segment Delaunay
// graph: distances, inside tests, convex polygons that meet, rings that cross, clipping, and a
// grid of boxes. Internal to planning (not installed); double precision, no validation of inputs.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

namespace hullmap::planning {

/// Distance from p to segment ab (a point when a == b).
double segmentDistance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p);

/// Boxes binned into a uniform grid over the bounds (about one box per cell), to find those near a
/// query box without scanning them all.
class BoxGrid {
 public:
  BoxGrid(const std::vector<Eigen::AlignedBox<double, 2>>& boxes, const Eigen::AlignedBox<double, 2>& bounds)
      : lo_(bounds.min()) {
    const Eigen::Vector2d size = bounds.sizes().cwiseMax(1e-12);
    const double side =
        std::sqrt(std::max(size.x() * size.y() / double(std::max<std::size_t>(boxes.size(), 1)), 1e-24));
    inv_ = 1.0 / side;
    nx_ = std::clamp(static_cast<int>(std::ceil(size.x() * inv_)), 1, 4096);
    ny_ = std::clamp(static_cast<int>(std::ceil(size.y() * inv_)), 1, 4096);
    cells_.resize(std::size_t(nx_) * std::size_t(ny_));
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      const auto [x0, y0, x1, y1] = range(boxes[i], 0.0);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) cells_[std::size_t(y) * std::size_t(nx_) + std::size_t(x)].push_back(i);
    }
    stamp_.assign(boxes.size(), 0);
  }

  /// Calls f(i) once for every box i binned in a cell within `margin` of `box` (a superset of the
  /// boxes within margin of it). Not thread-safe (a visit stamp).
  template <class F>
  void forEachNear(const Eigen::AlignedBox<double, 2>& box, double margin, F&& f) const {
    ++visit_;
    const auto [x0, y0, x1, y1] = range(box, margin);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        for (std::size_t i : cells_[std::size_t(y) * std::size_t(nx_) + std::size_t(x)]) {
          if (stamp_[i] == visit_) continue;
          stamp_[i] = visit_;
          f(i);
        }
  }

 private:
  std::array<int, 4> range(const Eigen::AlignedBox<double, 2>& box, double margin) const {
    const auto cell = [&](double v, double lo, int n) {
      const double c = std::floor((v - lo) * inv_);
      return static_cast<int>(std::clamp(c, 0.0, double(n - 1)));
    };
    return {cell(box.min().x() - margin, lo_.x(), nx_), cell(box.min().y() - margin, lo_.y(), ny_),
            cell(box.max().x() + margin, lo_.x(), nx_), cell(box.max().y() + margin, lo_.y(), ny_)};
  }

  Eigen::Vector2d lo_;
  double inv_ = 1.0;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<std::size_t>> cells_;
  mutable std::vector<std::uint64_t> stamp_;
  mutable std::uint64_t visit_ = 0;
};

/// Distance between segments ab and cd (0 when they cross).
double segmentsDistance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                        const Eigen::Vector2d& d);

/// `p` strictly inside the region bounded by `rings` (outer boundary and holes; even-odd rule).
bool insideRings(const std::vector<std::vector<Eigen::Vector2d>>& rings, const Eigen::Vector2d& p);

/// Twice the signed area of triangle (a, b, p): > 0 when p is left of ab.
double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p);

/// Convex counter-clockwise polygons P and Q touch, overlap or come within eps of each other.
bool polygonsMeet(const std::vector<Eigen::Vector2d>& P, const std::vector<Eigen::Vector2d>& Q, double eps);

/// Some two segments of `rings` (closed polygons) cross or touch other than at a shared end: the
/// union's vertices rounded to double may do that, which the SDG traits without intersections forbid.
bool selfIntersecting(const std::vector<std::vector<Eigen::Vector2d>>& rings);

/// Clips a convex polygon to the box (Sutherland-Hodgman); empty when nothing is left.
std::vector<Eigen::Vector2d> clipToBox(std::vector<Eigen::Vector2d> poly, const Eigen::Vector2d& lo,
                                       const Eigen::Vector2d& hi);

}  // namespace hullmap::planning
