#pragma once
// Private to hullmap_clustering: the exact squared Euclidean distance transform of the convex split.

#include <array>
#include <cstdint>
#include <vector>

namespace hullmap::hulls::detail {

/// Exact squared Euclidean distance transform in place (Felzenszwalb-Huttenlocher, one pass per
/// axis) over a box of `dims` cells stored x fastest: `d2` holds 0 at the sites and a large value
/// elsewhere (kept below 1e20; lines holding only 0 and 1e20 take a faster, exactly equal path).
void exactTransform(std::vector<float>& d2, const std::array<std::int64_t, 3>& dims);

}  // namespace hullmap::hulls::detail
