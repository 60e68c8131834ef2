#pragma once

#include <limits>

namespace hullmap {

/// π to double precision (std::numbers::pi is C++20).
inline constexpr double kPi = 3.14159265358979323846;

/// +∞, for minima that start above every value and for "no bound".
inline constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace hullmap
