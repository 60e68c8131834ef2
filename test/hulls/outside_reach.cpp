// The open cells the outside reaches (markReached, for the cells a cluster encloses) against the
// oracle: a breadth-first search from every open border cell, one cell and six neighbours at a time.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/hulls/detail/outside_reach.hpp"

namespace hullmap::hulls::detail {
namespace {

/// The oracle: 2 on every open cell 6-connected to the border through open cells.
std::vector<char> reachedByBfs(std::vector<char> state, std::int64_t px, std::int64_t py, std::int64_t pz) {
  const auto at = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return std::size_t((k * py + j) * px + i); };
  std::deque<std::array<std::int64_t, 3>> queue;
  for (std::int64_t k = 0; k < pz; ++k)
    for (std::int64_t j = 0; j < py; ++j)
      for (std::int64_t i = 0; i < px; ++i) {
        const bool border = i == 0 || j == 0 || k == 0 || i == px - 1 || j == py - 1 || k == pz - 1;
        if (border && state[at(i, j, k)] == 0) {
          state[at(i, j, k)] = 2;
          queue.push_back({i, j, k});
        }
      }
  const std::array<std::array<std::int64_t, 3>, 6> steps{
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}};
  while (!queue.empty()) {
    const auto c = queue.front();
    queue.pop_front();
    for (const auto& s : steps) {
      const std::int64_t i = c[0] + s[0], j = c[1] + s[1], k = c[2] + s[2];
      if (i < 0 || j < 0 || k < 0 || i >= px || j >= py || k >= pz || state[at(i, j, k)] != 0) continue;
      state[at(i, j, k)] = 2;
      queue.push_back({i, j, k});
    }
  }
  return state;
}

TEST(OutsideReach, MatchesBreadthFirstSearchOnRandomGrids) {
  std::mt19937 rng(27);
  std::size_t enclosed_seen = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::uniform_int_distribution<std::int64_t> side(1, 12);
    const std::int64_t px = side(rng), py = side(rng), pz = side(rng);
    // Blocked shares from sparse to nearly solid, so that caves, tunnels and sealed pockets occur.
    const double share = std::uniform_real_distribution<double>(0.0, 0.8)(rng);
    std::bernoulli_distribution blocked(share);
    std::vector<char> state(std::size_t(px * py * pz));
    for (auto& s : state) s = blocked(rng) ? 1 : 0;
    const std::vector<char> expected = reachedByBfs(state, px, py, pz);
    markReached(state, px, py, pz);
    ASSERT_EQ(state, expected) << "trial " << trial << ", " << px << " x " << py << " x " << pz;
    for (const char s : state) enclosed_seen += s == 0 ? 1 : 0;
  }
  EXPECT_GT(enclosed_seen, 100u) << "the grids should hold open cells the outside does not reach";
}

TEST(OutsideReach, AHollowShellKeepsItsInsideAndATunnelOpensIt) {
  // A 7^3 grid whose cells at Chebyshev distance 2 from the centre are blocked: the 3^3 inside is
  // sealed. One hole in the shell lets the outside in.
  const std::int64_t n = 7;
  const auto at = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return std::size_t((k * n + j) * n + i); };
  std::vector<char> state(std::size_t(n * n * n), 0);
  for (std::int64_t k = 0; k < n; ++k)
    for (std::int64_t j = 0; j < n; ++j)
      for (std::int64_t i = 0; i < n; ++i)
        if (std::max({std::abs(i - 3), std::abs(j - 3), std::abs(k - 3)}) == 2) state[at(i, j, k)] = 1;
  std::vector<char> sealed = state;
  markReached(sealed, n, n, n);
  EXPECT_EQ(sealed[at(3, 3, 3)], 0);
  EXPECT_EQ(sealed[at(2, 2, 2)], 0);
  EXPECT_EQ(sealed[at(0, 0, 0)], 2);
  EXPECT_EQ(sealed[at(6, 3, 3)], 2);
  EXPECT_EQ(sealed[at(1, 1, 1)], 1);
  state[at(5, 3, 3)] = 0;  // the hole, in the shell's +x face
  markReached(state, n, n, n);
  EXPECT_EQ(state[at(3, 3, 3)], 2);
  EXPECT_EQ(state[at(2, 2, 2)], 2);
  EXPECT_EQ(state[at(1, 1, 1)], 1);
}

}  // namespace
}  // namespace hullmap::hulls::detail
