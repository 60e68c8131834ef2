// The convex split's distance transforms against the O(cells x sites) oracle: every cell's squared
// distance to its nearest site, by brute force.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/hulls/detail/distance_transform.hpp"

namespace hullmap::hulls::detail {
namespace {

constexpr float kFar = 1e20f;

/// Sites (0) and the rest (kFar) of a box: each cell a site with chance `share`, and a few whole
/// rows and planes empty, so that lines with no site and lines of sites only occur.
std::vector<float> randomSites(const std::array<std::int64_t, 3>& dims, double share, std::mt19937& rng) {
  std::vector<float> d2(std::size_t(dims[0] * dims[1] * dims[2]), kFar);
  std::bernoulli_distribution site(share);
  for (auto& x : d2)
    if (site(rng)) x = 0.0f;
  return d2;
}

/// The oracle: exact squared distances to the nearest site (kFar without sites).
std::vector<double> bruteForce(const std::vector<float>& sites, const std::array<std::int64_t, 3>& dims) {
  std::vector<std::array<std::int64_t, 3>> at;
  for (std::int64_t k = 0; k < dims[2]; ++k)
    for (std::int64_t j = 0; j < dims[1]; ++j)
      for (std::int64_t i = 0; i < dims[0]; ++i)
        if (sites[std::size_t((k * dims[1] + j) * dims[0] + i)] == 0.0f) at.push_back({i, j, k});
  std::vector<double> out(sites.size(), double(kFar));
  for (std::int64_t k = 0; k < dims[2]; ++k)
    for (std::int64_t j = 0; j < dims[1]; ++j)
      for (std::int64_t i = 0; i < dims[0]; ++i) {
        std::int64_t best = std::numeric_limits<std::int64_t>::max();
        for (const auto& s : at)
          best = std::min(best, (s[0] - i) * (s[0] - i) + (s[1] - j) * (s[1] - j) + (s[2] - k) * (s[2] - k));
        if (!at.empty()) out[std::size_t((k * dims[1] + j) * dims[0] + i)] = double(best);
      }
  return out;
}

TEST(DistanceTransform, ExactAndBoundedAgreeWithBruteForce) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::int64_t> side(1, 14);
  int boxes = 0;
  for (int trial = 0; trial < 120; ++trial) {
    const std::array<std::int64_t, 3> dims{side(rng), side(rng), side(rng)};
    for (const double share : {0.0, 0.002, 0.02, 0.2, 1.0}) {
      const std::vector<float> sites = randomSites(dims, share, rng);
      const std::vector<double> truth = bruteForce(sites, dims);
      std::vector<float> exact = sites;
      exactTransform(exact, dims);
      for (std::size_t x = 0; x < truth.size(); ++x)
        ASSERT_EQ(double(exact[x]), truth[x] >= double(kFar) ? double(kFar) : truth[x])
            << "exact, box " << dims[0] << "x" << dims[1] << "x" << dims[2] << " cell " << x;
      // Only some columns' ranges wanted (the convex split reads its hull's cells only): those exact.
      std::vector<std::pair<std::int64_t, std::int64_t>> wanted(std::size_t(dims[0] * dims[1]));
      std::uniform_int_distribution<std::int64_t> k_of(0, dims[2] - 1);
      for (auto& range : wanted) {
        const std::int64_t k0 = k_of(rng), k1 = k_of(rng);
        range = k0 <= k1 ? std::make_pair(k0, k1) : std::make_pair(std::int64_t(1), std::int64_t(0));
      }
      std::vector<float> some = sites;
      exactTransform(some, dims, &wanted);
      for (std::int64_t j = 0; j < dims[1]; ++j)
        for (std::int64_t i = 0; i < dims[0]; ++i) {
          const auto [k0, k1] = wanted[std::size_t(j * dims[0] + i)];
          for (std::int64_t k = k0; k <= k1; ++k) {
            const std::size_t x = std::size_t((k * dims[1] + j) * dims[0] + i);
            ASSERT_EQ(double(some[x]), truth[x] >= double(kFar) ? double(kFar) : truth[x])
                << "exact on wanted columns, box " << dims[0] << "x" << dims[1] << "x" << dims[2] << " cell " << x;
          }
        }
      for (const std::int64_t cap2 : {0, 1, 2, 4, 9, 10, 26}) {
        std::vector<float> bounded = sites;
        boundedTransform(bounded, dims, cap2);
        for (std::size_t x = 0; x < truth.size(); ++x)
          ASSERT_EQ(double(bounded[x]), truth[x] <= double(cap2) ? truth[x] : double(kFar))
              << "bounded at " << cap2 << ", box " << dims[0] << "x" << dims[1] << "x" << dims[2] << " cell " << x;
      }
      ++boxes;
    }
  }
  EXPECT_EQ(boxes, 600);
}

// Long lines: the exact transform's crossings of parabolas far apart, on a thin box along each axis
// with sites at its ends and a few inside: 3,000 cells (the comparisons in 64 bits) and 20,000 (longer
// than 2^14: in 128 bits).
TEST(DistanceTransform, ExactOnLongLinesAlongEachAxis) {
  for (const std::int64_t length : {3000, 20000})
    for (int axis = 0; axis < 3; ++axis) {
      std::array<std::int64_t, 3> dims{2, 2, 2};
      dims[std::size_t(axis)] = length;
      std::vector<float> sites(std::size_t(dims[0] * dims[1] * dims[2]), kFar);
      const std::array<std::int64_t, 3> stride{1, dims[0], dims[0] * dims[1]};
      // Sites at both ends, next to the first, and every 1,700 cells (at most 2^12 apart: the squared
      // distances stay exact in floats).
      for (std::int64_t q = 0; q < length; q += 1700) sites[std::size_t(q * stride[std::size_t(axis)])] = 0.0f;
      for (const std::int64_t q : {std::int64_t(1), length - 1})
        sites[std::size_t(q * stride[std::size_t(axis)])] = 0.0f;
      const std::vector<double> truth = bruteForce(sites, dims);
      std::vector<float> exact = sites;
      exactTransform(exact, dims);
      for (std::size_t x = 0; x < truth.size(); ++x)
        ASSERT_EQ(double(exact[x]), truth[x]) << "length " << length << ", axis " << axis;
    }
}

}  // namespace
}  // namespace hullmap::hulls::detail
