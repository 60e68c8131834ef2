// The coplanar merge after DBSCAN: its thickness against analytic slabs, the whole rule against a
// brute-force oracle on random labelled point sets, and the cases it is for (a wall's foot cut off
// the wall joins it; a box, a table top or a corner's other wall by a wall does not).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "hullmap/clustering/coplanar_merge.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "test_support.hpp"

namespace hullmap::clustering {
namespace {

using Points = std::vector<Eigen::Vector3d>;
using hullmap::test::kVoxel;

/// A DbscanResult holding `labels` (kNoise or 0..k-1), sizes counted, no core flags.
DbscanResult labelled(const std::vector<std::int32_t>& labels) {
  DbscanResult r;
  r.labels = labels;
  r.core.assign(labels.size(), 0);
  std::int32_t k = 0;
  for (const auto l : labels) k = std::max(k, l + 1);
  r.cluster_sizes.assign(std::size_t(k), 0);
  for (const auto l : labels) {
    if (l >= 0) {
      ++r.cluster_sizes[std::size_t(l)];
    } else {
      ++r.noise;
    }
  }
  return r;
}

/// The documented rule by brute force: every pair of points compared, clusters joined by following
/// each decision to its end, labels renumbered by first point. Thickness is pointSetThickness (its
/// own test checks it against analytic slabs).
std::vector<std::int32_t> oracle(const Points& points, const std::vector<std::int32_t>& labels,
                                 const CoplanarMergeParams& params, std::size_t& merged) {
  std::int32_t k = 0;
  for (const auto l : labels) k = std::max(k, l + 1);
  const std::size_t kk = static_cast<std::size_t>(k);
  std::vector<std::vector<std::size_t>> members(kk);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (labels[i] >= 0) members[std::size_t(labels[i])].push_back(i);
  const auto distance2ToB = [&](std::size_t j, std::size_t b) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto i : members[b]) best = std::min(best, (points[i] - points[j]).squaredNorm());
    return best;
  };
  std::vector<std::size_t> target(kk);
  std::iota(target.begin(), target.end(), std::size_t(0));
  const double reach2 = params.reach * params.reach;
  for (std::size_t b = 0; b < kk; ++b) {
    if (members[b].size() < 3 || pointSetThickness(points, members[b]) > params.thickness) continue;
    std::size_t best = b, best_count = 0;
    for (std::size_t a = 0; a < kk; ++a) {
      if (a == b) continue;
      const bool larger = members[a].size() > members[b].size() || (members[a].size() == members[b].size() && a < b);
      if (!larger) continue;
      std::vector<std::pair<double, std::size_t>> around;
      bool adjacent = false;
      for (const auto j : members[a]) {
        const double d2 = distance2ToB(j, b);
        adjacent = adjacent || d2 <= reach2;
        if (d2 <= 4.0 * reach2) around.emplace_back(d2, j);
      }
      if (!adjacent || around.size() < 3 || around.size() <= best_count) continue;
      std::sort(around.begin(), around.end());
      const std::size_t m = std::min(around.size(), std::max<std::size_t>(3, members[b].size()));
      std::vector<std::size_t> both = members[b], surface;
      for (std::size_t t = 0; t < m; ++t) surface.push_back(around[t].second);
      both.insert(both.end(), surface.begin(), surface.end());
      if (pointSetThickness(points, both) > params.thickness) continue;
      // The surface's extent along the union's middle axis (Eigen's eigenvectors, as documented).
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto i : both) mean += points[i];
      mean /= double(both.size());
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (const auto i : both) covariance += (points[i] - mean) * (points[i] - mean).transpose();
      const Eigen::Vector3d middle = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvectors().col(1);
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto i : surface) {
        lo = std::min(lo, middle.dot(points[i]));
        hi = std::max(hi, middle.dot(points[i]));
      }
      if (hi - lo < 2.0 * params.thickness) continue;
      best = a;
      best_count = around.size();
    }
    target[b] = best;
  }
  merged = 0;
  std::vector<std::size_t> root(kk);
  for (std::size_t c = 0; c < kk; ++c) {
    std::size_t r = c;
    while (target[r] != r) r = target[r];
    root[c] = r;
    merged += r != c;
  }
  std::vector<std::int32_t> number(kk, -1), out = labels;
  std::int32_t next = 0;
  for (auto& l : out) {
    if (l < 0) continue;
    const std::size_t r = root[std::size_t(l)];
    if (number[r] < 0) number[r] = next++;
    l = number[r];
  }
  return out;
}

/// Voxel centres of a sparse slab: cells (i, j, k) of [i0, i1) x [j0, j1) x [k0, k1), one in
/// `one_in` kept (seeded).
void addSparse(Points& p, std::vector<std::int32_t>& labels, std::int32_t label, int i0, int i1, int j0, int j1, int k0,
               int k1, int one_in, std::mt19937& rng) {
  std::uniform_int_distribution<int> pick(0, one_in - 1);
  for (int i = i0; i < i1; ++i)
    for (int j = j0; j < j1; ++j)
      for (int k = k0; k < k1; ++k)
        if (pick(rng) == 0) {
          p.emplace_back((i + 0.5) * kVoxel, (j + 0.5) * kVoxel, (k + 0.5) * kVoxel);
          labels.push_back(label);
        }
}

TEST(CoplanarMerge, ThicknessOfRotatedSlabsIsTheirWidth) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const double width = 0.02 + 0.01 * trial;
    Points p;
    // Both faces of a 2 x 1.5 slab `width` thick, then rotated and moved: the thickness is the width.
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 15; ++j)
        for (const double z : {0.0, width}) p.emplace_back(0.1 * i, 0.1 * j, z);
    const Eigen::Matrix3d r = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    const Eigen::Vector3d t(u(rng) * 5, u(rng) * 5, u(rng) * 5);
    for (auto& x : p) x = r * x + t;
    std::vector<std::size_t> all(p.size());
    std::iota(all.begin(), all.end(), std::size_t(0));
    EXPECT_NEAR(pointSetThickness(p, all), width, 1e-9);
  }
  const Points three{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_NEAR(pointSetThickness(three, {0, 1, 2}), 0.0, 1e-12);
  EXPECT_EQ(pointSetThickness(three, {0, 1}), 0.0);
}

TEST(CoplanarMerge, MatchesTheOracleOnRandomLabelledSets) {
  // Random flat and solid blobs near each other, some coplanar, some not, labels at random.
  std::size_t merges = 0, kept = 0;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> count(1, 9), pos(0, 30), size(2, 12), kind(0, 3);
    Points p;
    std::vector<std::int32_t> labels;
    const int clusters = count(rng);
    for (std::int32_t c = 0; c < clusters; ++c) {
      const int i0 = pos(rng), j0 = pos(rng), k0 = pos(rng) / 3;
      switch (kind(rng)) {
        case 0:  // a sparse wall piece in x = const
          addSparse(p, labels, c, 10, 12, j0, j0 + size(rng), k0, k0 + size(rng), 3, rng);
          break;
        case 1:  // a sparse piece of another plane
          addSparse(p, labels, c, i0, i0 + size(rng), 20, 22, k0, k0 + size(rng), 3, rng);
          break;
        case 2:  // a solid blob
          addSparse(p, labels, c, i0, i0 + 4, j0, j0 + 4, k0, k0 + 4, 2, rng);
          break;
        default:  // a few points anywhere
          addSparse(p, labels, c, i0, i0 + 3, j0, j0 + 3, k0, k0 + 3, 6, rng);
      }
    }
    std::uniform_int_distribution<int> noise(0, 9);
    for (auto& l : labels)
      if (noise(rng) == 0) l = kNoise;
    // Drop labels no point holds, so that the input is a valid clustering.
    std::vector<std::int32_t> used(std::size_t(clusters), -1);
    std::int32_t next = 0;
    for (auto& l : labels)
      if (l >= 0) {
        if (used[std::size_t(l)] < 0) used[std::size_t(l)] = next++;
        l = used[std::size_t(l)];
      }
    for (const double reach : {0.1, 0.3}) {
      const CoplanarMergeParams params{reach, 0.11};
      std::size_t merged = 0;
      const auto expected = oracle(p, labels, params, merged);
      DbscanResult r = labelled(labels);
      const CoplanarMerge m = mergeCoplanarClusters(p, r, params);
      EXPECT_EQ(r.labels, expected);
      EXPECT_EQ(m.merged, merged);
      merges += merged;
      kept += r.cluster_sizes.size();
      EXPECT_EQ(r.cluster_sizes.size() + merged, labelled(labels).cluster_sizes.size());
      EXPECT_EQ(r.cluster_sizes, labelled(r.labels).cluster_sizes);
      EXPECT_EQ(r.noise, labelled(labels).noise);
    }
  }
  // Both outcomes occur (the sets are not all merged, nor all left alone).
  std::cout << merges << " clusters joined, " << kept << " left\n";
  EXPECT_GT(merges, 10u);
  EXPECT_GT(kept, merges);
}

TEST(CoplanarMerge, AWallsFootCutOffTheWallJoinsIt) {
  // A sparse wall (x = 0.05-0.1, 3 m long, 2 m high) in cluster 0, with a hole above a 0.6 m stretch
  // of its foot, which is cluster 1 (as DBSCAN leaves it when no core point of the wall is within
  // eps of the foot's): the foot joins the wall.
  std::mt19937 rng(3);
  Points p;
  std::vector<std::int32_t> labels;
  addSparse(p, labels, 1, 1, 3, 30, 42, 1, 12, 3, rng);   // the foot: y 1.5-2.1, z up to 0.6
  addSparse(p, labels, 0, 1, 3, 0, 28, 0, 40, 5, rng);    // the wall left of it
  addSparse(p, labels, 0, 1, 3, 44, 60, 0, 40, 5, rng);   // and right of it
  addSparse(p, labels, 0, 1, 3, 28, 44, 17, 40, 5, rng);  // and above the hole
  DbscanResult r = labelled(labels);
  const CoplanarMerge m = mergeCoplanarClusters(p, r, CoplanarMergeParams{0.4, 0.15});
  EXPECT_EQ(m.merged, 1u);
  EXPECT_EQ(m.points, std::size_t(std::count(labels.begin(), labels.end(), 1)));
  ASSERT_EQ(r.cluster_sizes.size(), 1u);
  EXPECT_EQ(r.cluster_sizes[0], p.size());
  EXPECT_TRUE(std::all_of(r.labels.begin(), r.labels.end(), [](std::int32_t l) { return l == 0; }));
}

TEST(CoplanarMerge, ABoxATableTopAndTheOtherWallByAWallStay) {
  std::mt19937 rng(4);
  Points p;
  std::vector<std::int32_t> labels;
  addSparse(p, labels, 0, 0, 2, 0, 80, 0, 40, 4, rng);     // a wall in x = 0-0.1, 4 m long
  addSparse(p, labels, 1, 3, 15, 5, 15, 0, 14, 2, rng);    // a box against it: solid, not flat
  addSparse(p, labels, 2, 3, 20, 30, 45, 14, 15, 2, rng);  // a table top by it: flat, level
  addSparse(p, labels, 3, 2, 40, 78, 80, 0, 40, 4, rng);   // the other wall of the corner
  addSparse(p, labels, 4, 2, 3, 60, 70, 10, 20, 2, rng);   // a poster a voxel off the wall: joins
  DbscanResult r = labelled(labels);
  const CoplanarMerge m = mergeCoplanarClusters(p, r, CoplanarMergeParams{0.4, 0.15});
  EXPECT_EQ(m.merged, 1u);
  ASSERT_EQ(r.cluster_sizes.size(), 4u);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::int32_t expected = labels[i] == 4 ? 0 : labels[i];
    ASSERT_EQ(r.labels[i], expected) << "point " << i;
  }
}

TEST(CoplanarMerge, APatchOfFloorByADenseWallsFootStays) {
  // A densely sampled wall and a small patch of floor (0.2 x 0.75 m, level) at its foot, as a depth
  // camera's map holds them when the floor is not set aside: the wall's voxels nearest the patch are
  // its foot's row, which lies in the patch's plane, so the two are flat together; but that row is a
  // line, not a surface around the patch, so the patch stays. Before that check it joined the wall.
  std::mt19937 rng(8);
  Points p;
  std::vector<std::int32_t> labels;
  addSparse(p, labels, 0, 0, 2, 0, 80, 0, 40, 1, rng);  // the wall in x = 0-0.1, every voxel
  addSparse(p, labels, 1, 2, 6, 45, 60, 0, 1, 1, rng);  // the floor patch, z = 0-0.05
  DbscanResult r = labelled(labels);
  EXPECT_EQ(mergeCoplanarClusters(p, r, CoplanarMergeParams{0.4, 0.15}).merged, 0u);
  EXPECT_EQ(r.labels, labels);
  // A patch in the wall's own plane (x = 0-0.1, beyond its end) joins it.
  addSparse(p, labels, 2, 0, 2, 81, 90, 0, 20, 1, rng);
  r = labelled(labels);
  EXPECT_EQ(mergeCoplanarClusters(p, r, CoplanarMergeParams{0.4, 0.15}).merged, 1u);
}

TEST(CoplanarMerge, NoiseStaysAndOneClusterIsLeftAlone) {
  std::mt19937 rng(6);
  Points p;
  std::vector<std::int32_t> labels;
  addSparse(p, labels, 0, 0, 2, 0, 20, 0, 20, 3, rng);
  addSparse(p, labels, kNoise, 0, 2, 20, 24, 0, 20, 3, rng);
  DbscanResult r = labelled(labels);
  const DbscanResult before = r;
  EXPECT_EQ(mergeCoplanarClusters(p, r, {}).merged, 0u);
  EXPECT_EQ(r.labels, before.labels);
  EXPECT_EQ(r.noise, before.noise);
  DbscanResult empty;
  EXPECT_EQ(mergeCoplanarClusters({}, empty, {}).merged, 0u);
}

TEST(CoplanarMerge, RejectsBadInput) {
  const Points p{{0, 0, 0}, {1, 0, 0}};
  DbscanResult r = labelled({0, 0});
  const auto names = [&](const CoplanarMergeParams& params, const std::string& parameter) {
    try {
      mergeCoplanarClusters(p, r, params);
      ADD_FAILURE() << "no error for " << parameter;
    } catch (const Error& e) {
      EXPECT_EQ(e.parameter(), parameter) << e.what();
    }
  };
  names({0.0, 0.15}, "reach");
  names({std::nan(""), 0.15}, "reach");
  names({std::numeric_limits<double>::infinity(), 0.15}, "reach");
  names({0.4, -1.0}, "thickness");
  names({0.4, std::nan("")}, "thickness");
  DbscanResult mismatch = labelled({0});
  EXPECT_THROW(mergeCoplanarClusters(p, mismatch, {}), Error);
}

}  // namespace
}  // namespace hullmap::clustering
