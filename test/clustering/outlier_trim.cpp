#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/clustering/outlier_trim.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::clustering {
namespace {

using Points = std::vector<Eigen::Vector3d>;

/// trimOutliers' rule by brute force: loners against every point, then each loner's patch, its
/// slab along the covariance's least eigenvector and its 2D hull by gift wrapping.
std::vector<std::int32_t> oracleTrim(const Points& points, const DbscanResult& r, const Points& support,
                                     const OutlierTrimParams& params) {
  const std::size_t n = points.size();
  const auto at = [&](std::size_t k) -> const Eigen::Vector3d& { return k < n ? points[k] : support[k - n]; };
  const double r2 = params.radius * params.radius, reach2 = params.reach * params.reach;
  std::vector<bool> loner(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    if (r.labels[i] < 0 || r.core[i]) continue;
    loner[i] = true;
    for (std::size_t k = 0; k < n + support.size(); ++k)
      if (k != i && (at(k) - points[i]).squaredNorm() <= r2) loner[i] = false;
  }
  std::vector<std::int32_t> labels = r.labels;
  for (std::size_t i = 0; i < n; ++i) {
    if (!loner[i]) continue;
    Points q;
    for (std::size_t k = 0; k < n + support.size(); ++k)
      if (k != i && (k >= n || (r.labels[k] >= 0 && !loner[k])) && (at(k) - points[i]).squaredNorm() <= reach2)
        q.push_back(at(k));
    if (q.size() < 3) continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& x : q) mean += x;
    mean /= double(q.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto& x : q) cov += (x - mean) * (x - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> pca(cov);
    const Eigen::Vector3d nn = pca.eigenvectors().col(0), u = pca.eigenvectors().col(1), v = pca.eigenvectors().col(2);
    double lo = 1e300, hi = -1e300;
    for (const auto& x : q) {
      lo = std::min(lo, nn.dot(x - mean));
      hi = std::max(hi, nn.dot(x - mean));
    }
    const double off = nn.dot(points[i] - mean);
    if (hi - lo > params.radius || (off <= hi + params.radius && off >= lo - params.radius)) continue;
    // Inside the 2D hull: no projected point q sees p strictly beyond an edge of the hull, which by
    // brute force is: p is inside when every directed pair (a, b) of hull edges keeps p on its left;
    // equivalently, p is outside when some pair (a, b) of projected points has p strictly on its right
    // while all the other points are on its left or on it.
    std::vector<Eigen::Vector2d> f;
    for (const auto& x : q) f.emplace_back(u.dot(x - mean), v.dot(x - mean));
    const Eigen::Vector2d pp(u.dot(points[i] - mean), v.dot(points[i] - mean));
    const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
      return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    };
    bool outside = false, degenerate = true;
    for (std::size_t a = 0; a < f.size() && !outside; ++a)
      for (std::size_t b = 0; b < f.size() && !outside; ++b) {
        if (a == b || f[a] == f[b]) continue;
        bool edge = true;
        for (std::size_t c = 0; c < f.size() && edge; ++c) {
          const double x = cross(f[a], f[b], f[c]);
          if (x < 0) edge = false;
          if (x != 0) degenerate = false;
        }
        if (edge && cross(f[a], f[b], pp) < 0) outside = true;
      }
    if (!outside && !degenerate) labels[i] = kNoise;
  }
  return labels;
}

/// A sparse wall (x = 0, y and z in [0, 3]), a table-leg-like line of points, a few outliers
/// in front of the wall, clustered with DBSCAN at a wide eps.
struct Scene {
  Points points, support;
  DbscanResult clusters;
};

Scene sparseScene(unsigned seed, std::size_t outliers) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  Scene s;
  for (int k = 0; k < 300; ++k) s.points.emplace_back(0.0, u(rng), u(rng));
  for (double z = 0.1; z < 0.8; z += 0.17) s.points.emplace_back(1.5, 1.5, z);  // a leg, every 17 cm
  std::uniform_real_distribution<double> off(0.05, 0.4), along(0.3, 2.7);
  for (std::size_t k = 0; k < outliers; ++k) s.points.emplace_back(off(rng), along(rng), along(rng));
  for (double x = 0.05; x < 3.0; x += 0.1)  // the floor
    for (double y = 0.05; y < 3.0; y += 0.1) s.support.emplace_back(x, y, -0.02);
  s.clusters = dbscan(s.points, {}, DbscanParams{0.4, 5});
  return s;
}

TEST(OutlierTrim, MatchesOracleOnSparseScenes) {
  std::size_t dropped_all = 0, candidates_kept = 0;
  for (unsigned seed = 1; seed <= 6; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Scene s = sparseScene(seed, 25);
    const OutlierTrimParams params{0.15, 0.6};
    const auto expected = oracleTrim(s.points, s.clusters, s.support, params);
    DbscanResult r = s.clusters;
    const OutlierTrim trim = trimOutliers(s.points, r, s.support, params);
    EXPECT_EQ(r.labels, expected);
    std::size_t dropped = 0;
    for (std::size_t i = 0; i < expected.size(); ++i) dropped += s.clusters.labels[i] >= 0 && expected[i] < 0;
    EXPECT_EQ(trim.dropped, dropped);
    dropped_all += dropped;
    for (std::size_t i = 0; i < expected.size(); ++i) candidates_kept += expected[i] >= 0 && !s.clusters.core[i];
    // Sizes and noise follow the labels.
    std::vector<std::size_t> sizes(r.cluster_sizes.size(), 0);
    std::size_t noise = 0;
    for (const auto l : r.labels) (l < 0 ? noise : sizes[std::size_t(l)])++;
    EXPECT_EQ(r.cluster_sizes, sizes);
    EXPECT_EQ(r.noise, noise);
    EXPECT_EQ(r.core, s.clusters.core);
  }
  // Both ways taken: some border points dropped, some kept.
  EXPECT_GT(dropped_all, 0u);
  EXPECT_GT(candidates_kept, 0u);
}

TEST(OutlierTrim, DropsAPointInFrontOfAWallKeepsALegAndAPointPastItsEdge) {
  // A wall sampled every 0.2 m (x = 0), a point 0.3 m in front of it, a "leg" of points 0.2 m apart
  // standing on the floor, and a point at the far corner of a table top sampled every 0.2 m.
  Points points;
  for (double y = 0.0; y <= 2.0 + 1e-9; y += 0.2)
    for (double z = 0.0; z <= 2.0 + 1e-9; z += 0.2) points.emplace_back(0.0, y, z);
  const std::size_t outlier = points.size();
  points.emplace_back(0.3, 1.1, 1.1);
  const std::size_t leg = points.size();
  points.emplace_back(3.0, 1.0, 0.2);
  points.emplace_back(3.0, 1.0, 0.42);
  points.emplace_back(3.0, 1.0, 0.64);
  points.emplace_back(3.0, 1.0, 0.86);  // the table top above it
  const Points floor = {Eigen::Vector3d(3.0, 1.0, -0.02)};
  DbscanResult r;
  r.labels.assign(points.size(), 0);
  r.core.assign(points.size(), 1);
  r.core[outlier] = 0;
  for (std::size_t k = leg; k < leg + 3; ++k) r.core[k] = 0;  // the leg's points: border, alone
  r.cluster_sizes = {points.size()};
  const OutlierTrim trim = trimOutliers(points, r, floor, OutlierTrimParams{0.15, 0.6});
  EXPECT_EQ(trim.dropped, 1u);
  EXPECT_EQ(r.labels[outlier], kNoise);
  for (std::size_t k = leg; k < leg + 3; ++k) EXPECT_EQ(r.labels[k], 0) << k;
  EXPECT_EQ(r.noise, 1u);
  EXPECT_EQ(r.cluster_sizes[0], points.size() - 1);
  // The same point 0.3 m in front of the wall but beyond its edge (over no patch) stays, as does a
  // point in the wall's plane past its edge.
  for (const Eigen::Vector3d& where : {Eigen::Vector3d(0.3, 2.4, 1.0), Eigen::Vector3d(0.0, 2.3, 1.0)}) {
    Points moved = points;
    moved[outlier] = where;
    DbscanResult m = r;
    m.labels.assign(moved.size(), 0);
    m.noise = 0;
    m.cluster_sizes = {moved.size()};
    EXPECT_EQ(trimOutliers(moved, m, floor, OutlierTrimParams{0.15, 0.6}).dropped, 0u) << where.transpose();
  }
  // A core point is never dropped, nor one with another point (noise too) within the radius.
  DbscanResult core = r;
  core.labels.assign(points.size(), 0);
  core.noise = 0;
  core.cluster_sizes = {points.size()};
  core.core[outlier] = 1;
  EXPECT_EQ(trimOutliers(points, core, floor, OutlierTrimParams{0.15, 0.6}).dropped, 0u);
  Points pair = points;
  pair.emplace_back(0.35, 1.15, 1.1);
  DbscanResult p = r;
  p.labels.assign(pair.size(), 0);
  p.labels.back() = kNoise;
  p.core.push_back(0);
  p.noise = 1;
  p.cluster_sizes = {pair.size() - 1};
  EXPECT_EQ(trimOutliers(pair, p, floor, OutlierTrimParams{0.15, 0.6}).dropped, 0u);
}

TEST(OutlierTrim, RejectsBadInput) {
  DbscanResult r;
  r.labels = {0};
  r.core = {0};
  r.cluster_sizes = {1};
  const Points one = {Eigen::Vector3d::Zero()};
  EXPECT_THROW(trimOutliers(one, r, {}, OutlierTrimParams{0.0, 0.6}), Error);
  EXPECT_THROW(trimOutliers(one, r, {}, OutlierTrimParams{0.2, 0.1}), Error);
  EXPECT_THROW(trimOutliers(Points{}, r, {}, OutlierTrimParams{}), Error);
  EXPECT_THROW(trimOutliers(Points{Eigen::Vector3d(NAN, 0, 0)}, r, {}, OutlierTrimParams{}), Error);
  // Nothing to do: nothing changes.
  DbscanResult empty;
  EXPECT_EQ(trimOutliers(Points{}, empty, {}, OutlierTrimParams{}).dropped, 0u);
}

}  // namespace
}  // namespace hullmap::clustering
