// The open cells the outside reaches (outside_reach.hpp): by runs of open cells along x, joined
// where runs of the rows j - 1 and k - 1 share an x with them (union-find); a run on the grid's
// border reaches the outside, and with it every run of its set.
#include "hullmap/hulls/detail/outside_reach.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <numeric>

namespace hullmap::hulls::detail {

void markReached(std::vector<char>& state, std::int64_t px, std::int64_t py, std::int64_t pz) {
  struct Run {
    std::int64_t i0, i1;  ///< cells [i0, i1) of the row
  };
  std::vector<Run> runs;
  std::vector<std::size_t> row_start(std::size_t(py * pz) + 1);
  for (std::int64_t row = 0; row < py * pz; ++row) {
    row_start[std::size_t(row)] = runs.size();
    const char* line = state.data() + row * px;
    for (std::int64_t i = 0; i < px;) {
      const char* open = static_cast<const char*>(std::memchr(line + i, 0, std::size_t(px - i)));
      if (!open) break;
      const std::int64_t i0 = open - line;
      std::int64_t i1 = i0 + 1;
      while (i1 < px && line[i1] == 0) ++i1;
      runs.push_back({i0, i1});
      i = i1;
    }
  }
  row_start[std::size_t(py * pz)] = runs.size();
  std::vector<std::uint32_t> parent(runs.size());
  std::iota(parent.begin(), parent.end(), 0u);
  const auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  // The later root under the earlier: a set's root is its first run.
  const auto unite = [&](std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  };
  const auto join_rows = [&](std::size_t row, std::size_t before) {
    std::size_t a = row_start[row], b = row_start[before];
    const std::size_t a_end = row_start[row + 1], b_end = row_start[before + 1];
    while (a < a_end && b < b_end) {
      if (runs[a].i0 < runs[b].i1 && runs[b].i0 < runs[a].i1) unite(std::uint32_t(a), std::uint32_t(b));
      if (runs[a].i1 < runs[b].i1)
        ++a;
      else
        ++b;
    }
  };
  for (std::int64_t k = 0; k < pz; ++k)
    for (std::int64_t j = 0; j < py; ++j) {
      const std::size_t row = std::size_t(k * py + j);
      if (j > 0) join_rows(row, row - 1);
      if (k > 0) join_rows(row, row - std::size_t(py));
    }
  std::vector<char> outside(runs.size(), 0);
  for (std::int64_t k = 0; k < pz; ++k)
    for (std::int64_t j = 0; j < py; ++j) {
      const std::size_t row = std::size_t(k * py + j);
      const bool border_row = j == 0 || k == 0 || j == py - 1 || k == pz - 1;
      for (std::size_t r = row_start[row]; r < row_start[row + 1]; ++r)
        if (border_row || runs[r].i0 == 0 || runs[r].i1 == px) outside[find(std::uint32_t(r))] = 1;
    }
  for (std::int64_t row = 0; row < py * pz; ++row)
    for (std::size_t r = row_start[std::size_t(row)]; r < row_start[std::size_t(row) + 1]; ++r)
      if (outside[find(std::uint32_t(r))])
        std::fill(state.begin() + row * px + runs[r].i0, state.begin() + row * px + runs[r].i1, char(2));
}

}  // namespace hullmap::hulls::detail
