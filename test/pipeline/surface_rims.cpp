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
#include "hullmap/pipeline/detail/test_hooks.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::pipeline {
namespace {

using V3 = Eigen::Vector3d;
constexpr double kRes = 0.05;

V3 centre(int i, int j, int k) { return kRes * V3(i + 0.5, j + 0.5, k + 0.5); }

/// The rule written out: for each surface voxel every clustered voxel is scanned (and, for rule 2,
/// every clustered voxel again), straight from the header's description. `by_rule`, when given,
/// counts the voxels joined by rules 1 and 2.
std::vector<std::int32_t> bruteForce(const std::vector<std::array<int, 3>>& cells,
                                     const std::vector<std::int32_t>& labels, double reach,
                                     std::array<std::size_t, 2>* by_rule = nullptr) {
  const int layers = int(std::floor(std::max(2.0, reach / kRes) + 1e-9));
  const double reach2 = (reach / kRes) * (reach / kRes) + 1e-9;  // cells^2
  const auto dist2 = [&](std::size_t a, std::size_t b) {
    long d = 0;
    for (int x = 0; x < 3; ++x) d += long(cells[a][x] - cells[b][x]) * long(cells[a][x] - cells[b][x]);
    return d;
  };
  std::vector<std::int32_t> out = labels;
  for (std::size_t v = 0; v < cells.size(); ++v) {
    if (labels[v] != kFloorLabel && labels[v] != kCeilingLabel) continue;
    const int sign = labels[v] == kFloorLabel ? 1 : -1;
    // Rules 1 and 2: the 3 x 3 columns.
    long best_distance = std::numeric_limits<long>::max();
    std::int32_t best = -1;
    int rule = 0;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (labels[c] < 0) continue;
      const int di = cells[c][0] - cells[v][0], dj = cells[c][1] - cells[v][1], dk = cells[c][2] - cells[v][2];
      if (std::abs(di) > 1 || std::abs(dj) > 1 || sign * dk < 0) continue;
      if (sign * dk > 2 * layers) continue;
      if (sign * dk > layers) {
        int evidence = 0;
        for (std::size_t w = 0; w < cells.size(); ++w)
          if (labels[w] == labels[c] && sign * (cells[w][2] - cells[c][2]) >= 2 && double(dist2(w, c)) <= reach2)
            ++evidence;
        if (evidence < 2) continue;
      }
      // Every rule-1 candidate is nearer than every rule-2 one, so one minimum serves both.
      const long d = dist2(c, v);
      if (d < best_distance || (d == best_distance && labels[c] < best)) {
        best_distance = d;
        best = labels[c];
        rule = sign * dk > layers ? 2 : 1;
      }
    }
    if (best >= 0) {
      out[v] = best;
      if (by_rule) ++(*by_rule)[std::size_t(rule - 1)];
    }
  }
  return out;
}

TEST(SurfaceRims, MatchesBruteForceOnRandomLattices) {
  std::mt19937 rng(23);
  std::size_t joined = 0, stayed = 0;
  std::array<std::size_t, 2> by_rule{};
  for (int trial = 0; trial < 80; ++trial) {
    std::vector<std::array<int, 3>> cells;
    std::vector<V3> centers;
    std::vector<std::int32_t> labels;
    if (trial < 40) {
      // Dense: 20% occupied; floor low, ceiling high, clusters and noise anywhere (also beside and
      // beyond a surface). Rule 1 decides nearly everything.
      for (int i = -4; i < 5; ++i)
        for (int j = -4; j < 5; ++j)
          for (int k = -3; k < 12; ++k) {
            if (rng() % 10 >= 2) continue;
            cells.push_back({i, j, k});
            const unsigned r = rng() % 10;
            labels.push_back(r < 4 ? (k < 4 ? kFloorLabel : kCeilingLabel) : r < 7 ? -1 : std::int32_t(r % 4));
          }
    } else {
      // Sparse: bands of floor (layers -1, 0) and ceiling (24, 25) half occupied, and between them
      // 4% of the cells clustered (3 labels) or noise, so rule 2 has work.
      for (int i = -6; i < 7; ++i)
        for (int j = -6; j < 7; ++j)
          for (int k = -1; k < 26; ++k) {
            const bool band = k <= 0 || k >= 24;
            if (rng() % 100 >= (band ? 50u : 5u)) continue;
            cells.push_back({i, j, k});
            labels.push_back(band             ? (k <= 0 ? kFloorLabel : kCeilingLabel)
                             : rng() % 5 == 0 ? -1
                                              : std::int32_t(rng() % 3));
          }
    }
    for (const auto& c : cells) centers.push_back(centre(c[0], c[1], c[2]));
    const double reach = std::array<double, 5>{0.0, 0.1, 0.12, 0.2, 0.4}[std::size_t(trial) % 5];
    const std::vector<std::int32_t> expected = bruteForce(cells, labels, reach, &by_rule);
    for (std::size_t v = 0; v < labels.size(); ++v) {
      if (labels[v] != kFloorLabel && labels[v] != kCeilingLabel) continue;
      (expected[v] >= 0 ? joined : stayed) += 1;
    }
    detail::attachSurfaceRims(centers, kRes, reach, labels);
    EXPECT_EQ(labels, expected) << "trial " << trial << ", reach " << reach;
  }
  std::cout << joined << " surface voxels joined (" << by_rule[0] << ", " << by_rule[1] << " by rules 1, 2), " << stayed
            << " stayed\n";
  EXPECT_GT(stayed, 300u);
  for (std::size_t r = 0; r < 2; ++r) EXPECT_GT(by_rule[r], 50u) << "rule " << r + 1;
}

/// The floor band, layers -1 and 0, over columns [i0, i1] x [j0, j1].
void addFloor(int i0, int i1, int j0, int j1, std::vector<V3>& centers, std::vector<std::int32_t>& labels) {
  for (int i = i0; i <= i1; ++i)
    for (int j = j0; j <= j1; ++j)
      for (int k = -1; k <= 0; ++k) {
        centers.push_back(centre(i, j, k));
        labels.push_back(kFloorLabel);
      }
}

std::array<int, 3> cellOf(const V3& c) {
  return {int(std::floor(c.x() / kRes)), int(std::floor(c.y() / kRes)), int(std::floor(c.z() / kRes))};
}

TEST(SurfaceRims, SparseWallGetsItsFootAndFarFloorStaysFloor) {
  // A floor band (layers -1 and 0) under a 1 m wall standing in column i = 0; the wall is sparse:
  // only one voxel in three along it is occupied, its lowest clustered voxel 4 layers above the
  // floor band (the voxels between are empty, as on a 30 points per m^2 map). The 26-neighbourhood
  // never reaches it.
  std::vector<V3> centers;
  std::vector<std::int32_t> labels;
  addFloor(-6, 6, 0, 11, centers, labels);
  const std::size_t floor_voxels = centers.size();
  for (int j = 0; j < 12; j += 3)
    for (int k = 4; k < 20; k += 2) {
      centers.push_back(centre(0, j, k));
      labels.push_back(7);
    }
  // eps 0.1: `layers` 2, the wall's lowest voxel 4 above layer 0; rule 2 reaches 4 layers but one
  // voxel of the wall lies within 0.1 of it 2 layers higher, not two: not a face at this reach.
  std::vector<std::int32_t> narrow = labels;
  detail::attachSurfaceRims(centers, kRes, 0.1, narrow);
  EXPECT_EQ(narrow, labels);
  // eps 0.2: `layers` 4. Layer 0 under and beside the wall's occupied columns joins by rule 1
  // (|di|, |dj| <= 1); layer -1 (5 below) by rule 2, the wall going on up from its lowest voxel.
  // Every floor voxel two columns away stays floor.
  std::vector<std::int32_t> wide = labels;
  detail::attachSurfaceRims(centers, kRes, 0.2, wide);
  std::size_t joined = 0;
  for (std::size_t v = 0; v < floor_voxels; ++v) {
    const auto c = cellOf(centers[v]);
    const bool should = std::abs(c[0]) <= 1 && c[1] <= 10;
    EXPECT_EQ(wide[v], should ? 7 : kFloorLabel) << c[0] << ' ' << c[1] << ' ' << c[2];
    joined += wide[v] == 7;
  }
  // i in -1..1, j in 0..10, two layers.
  EXPECT_EQ(joined, 66u);
  for (std::size_t v = floor_voxels; v < centers.size(); ++v) EXPECT_EQ(wide[v], 7);
}

TEST(SurfaceRims, TableTopKeepsItsFloorAndALegGetsItsFoot) {
  // eps 0.4 (`layers` 8, rule 2 up to 16): a table top 2 layers thick at layers 14-15 over columns
  // i, j in 0..16, a floor band under and around it, and one leg at the corner (0, 0) seen only at
  // layer 11 (as on a sparse map: its lower part holds no point). The top is within 16 layers of the
  // floor but flat: nothing of the table lies 2 layers above a top voxel, so the floor under it
  // stays floor, also with one stray voxel of the table (an outlier) 3 layers above the top. The
  // leg's voxel has the top 3 layers above it within 0.4: the leg goes on up, so the floor in its
  // 3 x 3 columns joins the table. A wall of another cluster (column (40, 0)) changes nothing.
  for (const bool leg : {false, true}) {
    std::vector<V3> centers;
    std::vector<std::int32_t> labels;
    addFloor(-4, 20, -4, 20, centers, labels);
    const std::size_t floor_voxels = centers.size();
    const auto add = [&](int i, int j, int k, std::int32_t label) {
      centers.push_back(centre(i, j, k));
      labels.push_back(label);
    };
    for (int i = 0; i <= 16; ++i)
      for (int j = 0; j <= 16; ++j)
        for (int k = 14; k <= 15; ++k) add(i, j, k, 3);
    add(8, 8, 18, 3);  // the stray voxel
    if (leg) add(0, 0, 11, 3);
    for (int k = 1; k < 30; ++k) add(40, 0, k, 5);
    std::vector<std::int32_t> out = labels;
    detail::attachSurfaceRims(centers, kRes, 0.4, out);
    std::size_t joined = 0;
    for (std::size_t v = 0; v < floor_voxels; ++v) {
      const auto c = cellOf(centers[v]);
      const bool under_leg = leg && std::abs(c[0]) <= 1 && std::abs(c[1]) <= 1;
      EXPECT_EQ(out[v], under_leg ? 3 : kFloorLabel) << leg << ": " << c[0] << ' ' << c[1] << ' ' << c[2];
      joined += out[v] == 3;
    }
    EXPECT_EQ(joined, leg ? 18u : 0u);
  }
}

TEST(SurfaceRims, CeilingJoinsWhatHangsBelowItNearestFirst) {
  // A ceiling voxel at layer 60 with a lamp (cluster 2) 3 layers below it and a beam (cluster 1) 1
  // layer above it: only what lies below joins a ceiling voxel. A floor voxel with three clusters
  // above: the nearest wins, and of two at the same distance the lower label.
  std::vector<V3> centers{centre(0, 0, 60), centre(0, 0, 57), centre(0, 0, 61), centre(5, 5, 0),
                          centre(5, 5, 2),  centre(6, 6, 1),  centre(4, 4, 1),  centre(9, 9, 60)};
  std::vector<std::int32_t> labels{kCeilingLabel, 2, 1, kFloorLabel, 3, 5, 4, kCeilingLabel};
  std::vector<std::int32_t> out = labels;
  detail::attachSurfaceRims(centers, kRes, 0.15, out);
  EXPECT_EQ(out[0], 2);
  EXPECT_EQ(out[3], 4);              // distance^2 3 for labels 4 and 5, 4 for label 3
  EXPECT_EQ(out[7], kCeilingLabel);  // nothing near
  out = labels;
  detail::attachSurfaceRims(centers, kRes, 0.1, out);  // reach 2 layers: the lamp is out of it
  EXPECT_EQ(out[0], kCeilingLabel);

  std::vector<std::int32_t> short_labels{kFloorLabel};
  EXPECT_THROW(detail::attachSurfaceRims(centers, kRes, 0.1, short_labels), Error);
}

}  // namespace
}  // namespace hullmap::pipeline
