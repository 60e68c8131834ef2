// The drift model's warp (mapper/align.hpp applyAlignment): each point moved by the similarities
// at the ends of its nearest anchor segment, blended by where it lies along the segment. The
// nearest segment is searched among those touching the point's nearest anchors (nanoflann's k-d
// tree), so a map of n points and k anchors costs O(n log k), not O(n k).

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "hullmap/core/kd_tree.hpp"
#include "hullmap/mapper/align.hpp"

namespace hullmap::mapper {
namespace {

using AnchorTree = core::PointKdTree<3>;

/// Nearest anchors searched per point: the nearest segment touches one of them unless segments are
/// far longer than the anchors' spacing around the point.
constexpr std::size_t kNearestAnchors = 8;

class DriftWarp {
 public:
  DriftWarp(const DriftCorrection& d, const Eigen::Matrix3d& rotation)
      : d_(d),
        rotation_(rotation),
        cloud_{d.anchors},
        tree_(3, cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}

  Eigen::Vector3d operator()(const Eigen::Vector3d& p) const {
    const std::size_t n = d_.anchors.size();
    std::array<std::uint32_t, kNearestAnchors> near{};
    std::array<double, kNearestAnchors> squared{};
    const double query[3] = {p.x(), p.y(), p.z()};
    const std::size_t found = tree_.knnSearch(query, std::min(kNearestAnchors, n), near.data(), squared.data());
    double best = std::numeric_limits<double>::infinity();
    std::size_t segment = 0;
    double fraction = 0.0;
    for (std::size_t j = 0; j < found; ++j) {
      const std::size_t a = near[j];
      for (const std::size_t s : {a > 0 ? a - 1 : a, a}) {
        if (s + 1 >= n) continue;
        const Eigen::Vector3d d = d_.anchors[s + 1] - d_.anchors[s];
        const double length = d.squaredNorm();
        const double f = length > 0.0 ? std::clamp((p - d_.anchors[s]).dot(d) / length, 0.0, 1.0) : 0.0;
        const double distance = (d_.anchors[s] + f * d - p).squaredNorm();
        if (distance < best || (distance == best && s < segment)) {
          best = distance;
          segment = s;
          fraction = f;
        }
      }
    }
    const Eigen::Vector3d rotated = rotation_ * p;
    if (n == 1) return d_.scales[0] * rotated + d_.translations[0];
    const std::size_t i = segment;
    return (1.0 - fraction) * (d_.scales[i] * rotated + d_.translations[i]) +
           fraction * (d_.scales[i + 1] * rotated + d_.translations[i + 1]);
  }

 private:
  const DriftCorrection& d_;
  Eigen::Matrix3d rotation_;
  core::PointsAdaptor cloud_;
  AnchorTree tree_;
};

}  // namespace

void applyAlignment(const Alignment& a, io::Points& points) {
  if (!a.drift) {
    applySimilarity(a.transform, points);
    return;
  }
  const DriftWarp warp(*a.drift, a.transform.rotation);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) points[i] = warp(points[i]);
                    });
}

void applyAlignment(const Alignment& a, std::vector<io::Keyframe>& keyframes) {
  if (!a.drift) {
    applySimilarity(a.transform, keyframes);
    return;
  }
  const DriftWarp warp(*a.drift, a.transform.rotation);
  const Eigen::Quaterniond q(a.transform.rotation);
  for (io::Keyframe& k : keyframes) {
    k.position = warp(k.position);
    k.orientation = (q * k.orientation).normalized();
  }
}

}  // namespace hullmap::mapper
