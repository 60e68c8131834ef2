#pragma once
// The projected grids' oracle (live/outputs.cpp, ros/messages.cpp): which cells a footprint touches.

#include <algorithm>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace hullmap::test {

// Exact oracle: a convex polygon and a closed square meet iff a vertex of one lies in the other or
// two of their edges cross.
inline bool segmentsMeet(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                         const Eigen::Vector2d& d) {
  const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
  const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a), d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  return ((d1 > 0) != (d2 > 0) || d1 == 0 || d2 == 0) && ((d3 > 0) != (d4 > 0) || d3 == 0 || d4 == 0) &&
         std::max(a.x(), b.x()) >= std::min(c.x(), d.x()) && std::max(c.x(), d.x()) >= std::min(a.x(), b.x()) &&
         std::max(a.y(), b.y()) >= std::min(c.y(), d.y()) && std::max(c.y(), d.y()) >= std::min(a.y(), b.y());
}

inline bool insideConvex(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d e = poly[(i + 1) % poly.size()] - poly[i];
    const Eigen::Vector2d q = p - poly[i];
    if (e.x() * q.y() - e.y() * q.x() < 0) return false;
  }
  return true;
}

inline bool meetsOracle(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& lo,
                        const Eigen::Vector2d& hi) {
  const std::vector<Eigen::Vector2d> square{lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}};
  for (const auto& v : poly)
    if (v.x() >= lo.x() && v.x() <= hi.x() && v.y() >= lo.y() && v.y() <= hi.y()) return true;
  for (const auto& c : square)
    if (insideConvex(poly, c)) return true;
  for (std::size_t i = 0; i < poly.size(); ++i)
    for (std::size_t j = 0; j < 4; ++j)
      if (segmentsMeet(poly[i], poly[(i + 1) % poly.size()], square[j], square[(j + 1) % 4])) return true;
  return false;
}

}  // namespace hullmap::test
