#pragma once
// Oracles for the octree tests: octomap's own insertion and a leaf-for-leaf tree comparison.

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include "hullmap/io/point_cloud.hpp"

namespace hullmap::test {

struct Leaf {
  unsigned k0, k1, k2, depth;
  float log_odds;
};

inline std::vector<Leaf> leavesOf(const octomap::OcTree& tree) {
  std::vector<Leaf> leaves;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    const auto k = it.getKey();
    leaves.push_back({k[0], k[1], k[2], it.getDepth(), it->getLogOdds()});
  }
  std::sort(leaves.begin(), leaves.end(), [](const Leaf& a, const Leaf& b) {
    return std::tie(a.k0, a.k1, a.k2, a.depth) < std::tie(b.k0, b.k1, b.k2, b.depth);
  });
  return leaves;
}

/// Same leaves (keys, depth) with the same log-odds, both ways; same node count.
inline ::testing::AssertionResult sameTree(const octomap::OcTree& expected, const octomap::OcTree& actual) {
  const auto a = leavesOf(expected);
  const auto b = leavesOf(actual);
  if (a.size() != b.size()) {
    return ::testing::AssertionFailure() << "leaf counts differ: expected " << a.size() << ", got " << b.size();
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].k0 != b[i].k0 || a[i].k1 != b[i].k1 || a[i].k2 != b[i].k2 || a[i].depth != b[i].depth) {
      return ::testing::AssertionFailure()
             << "leaf " << i << " differs: expected key (" << a[i].k0 << "," << a[i].k1 << "," << a[i].k2 << ") depth "
             << a[i].depth << ", got (" << b[i].k0 << "," << b[i].k1 << "," << b[i].k2 << ") depth " << b[i].depth;
    }
    if (std::abs(a[i].log_odds - b[i].log_odds) > 1e-5f) {
      return ::testing::AssertionFailure()
             << "leaf " << i << " log-odds differ: expected " << a[i].log_odds << ", got " << b[i].log_odds;
    }
  }
  // Both ways: every leaf of `actual` is found in `expected` as a leaf at the same depth.
  for (const Leaf& l : b) {
    const octomap::OcTreeKey key(static_cast<octomap::key_type>(l.k0), static_cast<octomap::key_type>(l.k1),
                                 static_cast<octomap::key_type>(l.k2));
    const octomap::OcTreeNode* n = expected.search(key, l.depth);
    if (n == nullptr || expected.nodeHasChildren(n)) {
      return ::testing::AssertionFailure() << "leaf of actual tree not a leaf of the expected one";
    }
  }
  if (expected.size() != actual.size()) {
    return ::testing::AssertionFailure() << "node counts differ: expected " << expected.size() << ", got "
                                         << actual.size();
  }
  return ::testing::AssertionSuccess();
}

inline octomap::Pointcloud toCloud(const io::Points& points) {
  octomap::Pointcloud cloud;
  for (const auto& p : points) {
    cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  }
  return cloud;
}

inline octomap::point3d toPoint3d(const io::Point& p) {
  return octomap::point3d(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
}

/// `x y z` text, one point a line (octomap_scan.dat).
inline io::Points readXyz(const std::string& path) {
  io::Points points;
  std::ifstream in(path);
  double x, y, z;
  while (in >> x >> y >> z) points.emplace_back(x, y, z);
  return points;
}

}  // namespace hullmap::test
