#pragma once
// The keyframe rule of buildWithTrajectory: which keyframe a map point is taken as seen from. Not installed.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "hullmap/io/point_cloud.hpp"
#include "hullmap/io/readers.hpp"

namespace hullmap::mapper::detail {

// Keyframe lookup: nearest keyframe (squared distance, then lower index) among those facing the
// point, else the nearest of all. A uniform grid over the keyframe positions, searched in
// growing Chebyshev rings, gives the same answer as the brute-force rule.
class KeyframeIndex {
 public:
  explicit KeyframeIndex(const std::vector<io::Keyframe>& keyframes) : keyframes_(keyframes) {
    lo_ = hi_ = keyframes.front().position;
    for (const auto& k : keyframes) {
      lo_ = lo_.cwiseMin(k.position);
      hi_ = hi_.cwiseMax(k.position);
      forward_.push_back(k.orientation * Eigen::Vector3d::UnitZ());
    }
    const Eigen::Vector3d extent = (hi_ - lo_).cwiseMax(1e-9);
    const double volume_per_cell =
        std::max(extent.prod(), std::pow(extent.maxCoeff(), 3) * 1e-6) / static_cast<double>(keyframes.size());
    cell_ = std::max({std::cbrt(volume_per_cell), extent.maxCoeff() / 64.0, 1e-9});
    for (int i = 0; i < 3; ++i) dims_[i] = static_cast<long>(std::floor(extent[i] / cell_)) + 1;
    cells_.assign(static_cast<std::size_t>(dims_[0] * dims_[1] * dims_[2]), {});
    for (std::size_t i = 0; i < keyframes.size(); ++i) {
      const auto c = cellOf(keyframes[i].position);
      cells_[index(c[0], c[1], c[2])].push_back(static_cast<std::uint32_t>(i));
    }
  }

  std::size_t lookup(const io::Point& p) const {
    const auto c = cellOf(p);
    long r0 = 0;  // first ring that meets the grid
    for (int i = 0; i < 3; ++i) r0 = std::max({r0, -c[i], c[i] - (dims_[i] - 1)});
    const long r_max = r0 + std::max({dims_[0], dims_[1], dims_[2]});
    Best facing, any;
    for (long r = r0; r <= r_max; ++r) {
      const double bound = static_cast<double>(std::max(0L, r - 1)) * cell_;
      if (facing.found() && facing.d2 <= bound * bound) break;
      for (long x = std::max(0L, c[0] - r); x <= std::min(dims_[0] - 1, c[0] + r); ++x) {
        for (long y = std::max(0L, c[1] - r); y <= std::min(dims_[1] - 1, c[1] + r); ++y) {
          const bool edge_xy = std::abs(x - c[0]) == r || std::abs(y - c[1]) == r;
          for (long z = std::max(0L, c[2] - r); z <= std::min(dims_[2] - 1, c[2] + r); ++z) {
            if (!edge_xy && std::abs(z - c[2]) != r) continue;
            for (std::uint32_t k : cells_[index(x, y, z)]) {
              const Eigen::Vector3d d = p - keyframes_[k].position;
              const double d2 = d.squaredNorm();
              any.offer(d2, k);
              if (forward_[k].dot(d) > 0.0) facing.offer(d2, k);
            }
          }
        }
      }
    }
    return facing.found() ? facing.index : any.index;
  }

 private:
  struct Best {
    double d2 = std::numeric_limits<double>::infinity();
    std::size_t index = std::numeric_limits<std::size_t>::max();
    bool found() const { return index != std::numeric_limits<std::size_t>::max(); }
    void offer(double d, std::size_t i) {
      if (d < d2 || (d == d2 && i < index)) {
        d2 = d;
        index = i;
      }
    }
  };

  std::array<long, 3> cellOf(const io::Point& p) const {
    std::array<long, 3> c{};
    for (int i = 0; i < 3; ++i) {
      const double v = std::floor((p[i] - lo_[i]) / cell_);
      c[i] = static_cast<long>(std::clamp(v, -1e15, 1e15));
    }
    return c;
  }
  std::size_t index(long x, long y, long z) const {
    return static_cast<std::size_t>((x * dims_[1] + y) * dims_[2] + z);
  }

  const std::vector<io::Keyframe>& keyframes_;
  std::vector<Eigen::Vector3d> forward_;
  Eigen::Vector3d lo_, hi_;
  double cell_ = 1.0;
  std::array<long, 3> dims_{};
  std::vector<std::vector<std::uint32_t>> cells_;
};

}  // namespace hullmap::mapper::detail
