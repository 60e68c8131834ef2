#pragma once

#include <cstdint>

#include "hullmap/core/big_allocator.hpp"

namespace hullmap::clustering::detail {

/// A point's grid DBSCAN sort key (grid_dbscan.hpp's sortKey) and its index in the input.
struct KeyedPoint {
  std::uint64_t key;
  std::uint32_t index;
  bool operator<(const KeyedPoint& o) const { return key < o.key || (key == o.key && index < o.index); }
};

/// Sorts (key, index) pairs, given in index order, by key then index: one parallel stable scatter
/// on the top key bits (a hash), then each bucket sorted on its own in parallel. The result is a
/// total order, independent of the thread count.
void sortByKey(core::BigVector<KeyedPoint>& items);

}  // namespace hullmap::clustering::detail
