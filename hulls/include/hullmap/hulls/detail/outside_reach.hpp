#pragma once
// Which open cells of a grid the outside reaches, for the cells a cluster encloses (hulls/src): a
// white-box header for the library and its tests, not installed.

#include <cstdint>
#include <vector>

namespace hullmap::hulls::detail {

/// Marks 2 the open cells (0) of a px * py * pz grid, stored x fastest, that are 6-connected to the
/// grid's border through open cells (an open cell on the border is reached); blocked cells (1) and
/// the open cells the outside does not reach stay as they are. One pass over the cells, the rest
/// near-linear in the runs of open cells along x.
void markReached(std::vector<char>& state, std::int64_t px, std::int64_t py, std::int64_t pz);

}  // namespace hullmap::hulls::detail
