// The build's rims step (detail::attachSurfaceRims): floor and ceiling voxels at the foot of a
// cluster join it, against a brute-force scan and on hand-built sparse walls.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::pipeline {
namespace {

using V3 = Eigen::Vector3d;
constexpr double kRes = 0.05;

V3 centre(int i, int j, int k) { return kRes * V3(i + 0.5, j + 0.5, k + 0.5); }

/// The rule written out: every clustered voxel scanned, the nearest (squared lattice distance, then
/// the lower label) in the 3 x 3 columns on the far side of the surface within the reach.
std::vector<std::int32_t> bruteForce(const std::vector<std::array<int, 3>>& cells, const std::vector<std::int32_t>& labels,
                                     double reach) {
  const int layers = int(std::floor(std::max(2.0, reach / kRes) + 1e-9));
  std::vector<std::int32_t> out = labels;
  for (std::size_t v = 0; v < cells.size(); ++v) {
    if (labels[v] != kFloorLabel && labels[v] != kCeilingLabel) continue;
    const int sign = labels[v] == kFloorLabel ? 1 : -1;
    long best_distance = std::numeric_limits<long>::max();
    std::int32_t best = -1;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (labels[c] < 0) continue;
      const int di = cells[c][0] - cells[v][0], dj = cells[c][1] - cells[v][1], dk = cells[c][2] - cells[v][2];
      if (std::abs(di) > 1 || std::abs(dj) > 1 || sign * dk < 0 || sign * dk > layers) continue;
      const long d = long(di * di + dj * dj + dk * dk);
      if (d < best_distance || (d == best_distance && labels[c] < best)) {
        best_distance = d;
        best = labels[c];
      }
    }
    if (best >= 0) out[v] = best;
  }
  return out;
}

TEST(SurfaceRims, MatchesBruteForceOnRandomLattices) {
  std::mt19937 rng(23);
  std::size_t joined = 0, stayed = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<std::array<int, 3>> cells;
    std::vector<V3> centers;
    std::vector<std::int32_t> labels;
    for (int i = -4; i < 5; ++i)
      for (int j = -4; j < 5; ++j)
        for (int k = -3; k < 12; ++k) {
          if (rng() % 10 >= 2) continue;  // 20% occupied
          cells.push_back({i, j, k});
          centers.push_back(centre(i, j, k));
          const unsigned r = rng() % 10;
          // Floor low, ceiling high, clusters and noise anywhere (also beside and beyond a surface).
          labels.push_back(r < 4 ? (k < 4 ? kFloorLabel : kCeilingLabel) : r < 7 ? -1 : std::int32_t(r % 4));
        }
    const double reach = std::array<double, 5>{0.0, 0.1, 0.12, 0.2, 0.4}[std::size_t(trial) % 5];
    const std::vector<std::int32_t> expected = bruteForce(cells, labels, reach);
    for (std::size_t v = 0; v < labels.size(); ++v) {
      if (labels[v] != kFloorLabel && labels[v] != kCeilingLabel) continue;
      (expected[v] >= 0 ? joined : stayed) += 1;
    }
    detail::attachSurfaceRims(centers, kRes, reach, labels);
    EXPECT_EQ(labels, expected) << "trial " << trial << ", reach " << reach;
  }
  std::cout << joined << " surface voxels joined, " << stayed << " stayed\n";
  EXPECT_GT(joined, 300u);
  EXPECT_GT(stayed, 300u);
}

TEST(SurfaceRims, SparseWallGetsItsFootAndFarFloorStaysFloor) {
  // A floor band (layers -1 and 0) under a 1 m wall standing in column i = 0; the wall is sparse:
  // only one voxel in three along it is occupied, its lowest clustered voxel 4 layers above the
  // floor band (the voxels between are empty, as on a 30 points per m^2 map). The 26-neighbourhood
  // never reaches it; the column rule does within max(2 voxels, eps).
  std::vector<V3> centers;
  std::vector<std::int32_t> labels;
  for (int i = -6; i <= 6; ++i)
    for (int j = 0; j < 12; ++j)
      for (int k = -1; k <= 0; ++k) {
        centers.push_back(centre(i, j, k));
        labels.push_back(kFloorLabel);
      }
  const std::size_t floor_voxels = centers.size();
  for (int j = 0; j < 12; j += 3)
    for (int k = 4; k < 20; k += 2) {
      centers.push_back(centre(0, j, k));
      labels.push_back(7);
    }
  const auto cellOf = [&](std::size_t v) {
    return std::array<int, 3>{int(std::floor(centers[v].x() / kRes)), int(std::floor(centers[v].y() / kRes)),
                              int(std::floor(centers[v].z() / kRes))};
  };
  // eps 0.1: the reach is 2 layers, the wall's lowest voxel is 4 above: nothing joins.
  std::vector<std::int32_t> narrow = labels;
  detail::attachSurfaceRims(centers, kRes, 0.1, narrow);
  EXPECT_EQ(narrow, labels);
  // eps 0.2: 4 layers. Layer 0 under and beside the wall's occupied columns joins (|di|, |dj| <= 1);
  // layer -1 (5 below) and every floor voxel two columns away stay floor.
  std::vector<std::int32_t> wide = labels;
  detail::attachSurfaceRims(centers, kRes, 0.2, wide);
  std::size_t joined = 0;
  for (std::size_t v = 0; v < floor_voxels; ++v) {
    const auto c = cellOf(v);
    bool near_column = false;
    for (int wall_j = 0; wall_j < 12; wall_j += 3) near_column |= std::abs(c[0]) <= 1 && std::abs(c[1] - wall_j) <= 1;
    const bool should = c[2] == 0 && near_column;
    EXPECT_EQ(wide[v], should ? 7 : kFloorLabel) << c[0] << ' ' << c[1] << ' ' << c[2];
    joined += wide[v] == 7;
  }
  // Columns j = 0, 3, 6, 9 and their neighbours: j in 0..10, i in -1..1.
  EXPECT_EQ(joined, 33u);
  for (std::size_t v = floor_voxels; v < centers.size(); ++v) EXPECT_EQ(wide[v], 7);
}

TEST(SurfaceRims, CeilingJoinsWhatHangsBelowItNearestFirst) {
  // A ceiling voxel at layer 60 with a lamp (cluster 2) 3 layers below it and a beam (cluster 1) 1
  // layer above it: only what lies below joins a ceiling voxel. A floor voxel with three clusters
  // above: the nearest wins, and of two at the same distance the lower label.
  std::vector<V3> centers{centre(0, 0, 60), centre(0, 0, 57), centre(0, 0, 61),
                          centre(5, 5, 0), centre(5, 5, 2), centre(6, 6, 1), centre(4, 4, 1),
                          centre(9, 9, 60)};
  std::vector<std::int32_t> labels{kCeilingLabel, 2, 1, kFloorLabel, 3, 5, 4, kCeilingLabel};
  std::vector<std::int32_t> out = labels;
  detail::attachSurfaceRims(centers, kRes, 0.15, out);
  EXPECT_EQ(out[0], 2);
  EXPECT_EQ(out[3], 4);             // distance^2 3 for labels 4 and 5, 4 for label 3
  EXPECT_EQ(out[7], kCeilingLabel);  // nothing near
  out = labels;
  detail::attachSurfaceRims(centers, kRes, 0.1, out);  // reach 2 layers: the lamp is out of it
  EXPECT_EQ(out[0], kCeilingLabel);

  std::vector<std::int32_t> short_labels{kFloorLabel};
  EXPECT_THROW(detail::attachSurfaceRims(centers, kRes, 0.1, short_labels), Error);
}

}  // namespace
}  // namespace hullmap::pipeline
