#include "key_sort.hpp"

#include <algorithm>
#include <cstddef>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace hullmap::clustering::detail {

void sortByKey(core::BigVector<KeyedPoint>& items) {
  const std::size_t n = items.size();
  using Item = KeyedPoint;
  if (n < 4096) {
    std::sort(items.begin(), items.end());
    return;
  }
  constexpr int kBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  constexpr int kLowBits = 12;  // the Morton code of a cell inside its block (sortKey)
  constexpr std::size_t kLowKeys = std::size_t{1} << kLowBits;
  const std::size_t chunk = 1 << 15;
  const std::size_t chunks = (n + chunk - 1) / chunk;
  std::vector<std::uint32_t> offsets(chunks * kBuckets, 0);  // chunk-major counts, then offsets
  const auto bucketOf = [](const Item& item) { return std::size_t(item.key >> (64 - kBits)); };
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    std::uint32_t* count = &offsets[c * kBuckets];
    for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) ++count[bucketOf(items[i])];
  });
  std::vector<std::size_t> bucket_start(kBuckets + 1, 0);
  std::size_t running = 0;
  for (std::size_t b = 0; b < kBuckets; ++b) {
    bucket_start[b] = running;
    for (std::size_t c = 0; c < chunks; ++c) {
      const std::uint32_t count = offsets[c * kBuckets + b];
      offsets[c * kBuckets + b] = std::uint32_t(running);
      running += count;
    }
  }
  bucket_start[kBuckets] = running;
  core::BigVector<Item> sorted(n);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    std::uint32_t* next = &offsets[c * kBuckets];
    for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i)
      sorted[next[bucketOf(items[i])]++] = items[i];
  });
  // Each bucket, still in index order (the scatter is stable), goes back into `items` sorted: a
  // counting sort on the low 12 key bits (the cell inside its block; stable), then, only when the
  // bucket holds several blocks, a stable sort on the block bits.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kBuckets, 16), [&](const tbb::blocked_range<std::size_t>& r) {
    std::vector<std::uint32_t> count;
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      const std::size_t begin = bucket_start[b], end = bucket_start[b + 1];
      if (end - begin < 512) {
        std::copy(sorted.begin() + begin, sorted.begin() + end, items.begin() + begin);
        std::sort(items.begin() + begin, items.begin() + end);
        continue;
      }
      count.assign(kLowKeys + 1, 0);
      bool one_block = true;
      const std::uint64_t block = sorted[begin].key >> kLowBits;
      for (std::size_t i = begin; i < end; ++i) {
        ++count[(sorted[i].key & (kLowKeys - 1)) + 1];
        one_block = one_block && (sorted[i].key >> kLowBits) == block;
      }
      for (std::size_t k = 1; k <= kLowKeys; ++k) count[k] += count[k - 1];
      for (std::size_t i = begin; i < end; ++i) items[begin + count[sorted[i].key & (kLowKeys - 1)]++] = sorted[i];
      if (!one_block) {
        std::stable_sort(items.begin() + begin, items.begin() + end,
                         [](const Item& u, const Item& v) { return (u.key >> 12) < (v.key >> 12); });
      }
    }
  });
}

}  // namespace hullmap::clustering::detail
