#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>

#include <tbb/parallel_for.h>

namespace hullmap::clustering::detail {

/// Lock-free union-find over cells; a root is always linked under the smaller root.
class UnionFind {
 public:
  using Index = std::uint32_t;

  explicit UnionFind(std::size_t n) : parent_(new std::atomic<Index>[n]) {
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) { parent_[i].store(Index(i), std::memory_order_relaxed); });
  }

  Index find(Index x) const {
    while (true) {
      Index p = parent_[x].load(std::memory_order_relaxed);
      if (p == x) return x;
      const Index gp = parent_[p].load(std::memory_order_relaxed);
      if (gp != p) parent_[x].compare_exchange_weak(p, gp, std::memory_order_relaxed);
      x = gp;
    }
  }

  void unite(Index a, Index b) {
    while (true) {
      a = find(a);
      b = find(b);
      if (a == b) return;
      if (a < b) std::swap(a, b);
      Index expected = a;
      if (parent_[a].compare_exchange_strong(expected, b, std::memory_order_relaxed)) return;
    }
  }

 private:
  std::unique_ptr<std::atomic<Index>[]> parent_;
};

}  // namespace hullmap::clustering::detail
