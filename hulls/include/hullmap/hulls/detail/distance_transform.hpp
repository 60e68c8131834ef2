#pragma once
// The squared Euclidean distance transforms of the convex split (hulls/src): a white-box header for
// the library and its tests, not installed.

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace hullmap::hulls::detail {

/// Exact squared Euclidean distance transform in place (Felzenszwalb-Huttenlocher, one pass per
/// axis) over a box of `dims` cells stored x fastest: `d2` holds 0 at the sites and a large value
/// elsewhere (kept below 1e20; lines holding only 0 and 1e20 take a faster, exactly equal path).
/// `wanted`, when given: per column (i, j) of the box (i fastest), the range [k0, k1] of the cells
/// the caller reads (k1 < k0: none); only those are exact after the call, columns with none keep
/// their values of the passes before the last.
void exactTransform(std::vector<float>& d2, const std::array<std::int64_t, 3>& dims,
                    const std::vector<std::pair<std::int64_t, std::int64_t>>* wanted = nullptr);

/// The same transform, exact only up to `cap2` (cells^2, >= 0), of `d2` holding 0 at the sites and
/// exactly 1e20f elsewhere: a cell whose squared distance to the nearest site is at most cap2 gets
/// it exactly, every other cell 1e20f. Each pass takes the least over offsets of at most floor(sqrt(cap2)) cells
/// (a site within sqrt(cap2) is no farther on any axis), x fastest: O(cells * sqrt(cap2)), and far
/// cheaper than the exact transform when cap2 is a few cells^2.
void boundedTransform(std::vector<float>& d2, const std::array<std::int64_t, 3>& dims, std::int64_t cap2);

}  // namespace hullmap::hulls::detail
