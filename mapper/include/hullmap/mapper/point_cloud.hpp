#pragma once
// The point types live in the io library; this header stays for code written against the old path.
#include "hullmap/io/point_cloud.hpp"

namespace hullmap::mapper {
using io::InputStats;
using io::Point;
using io::Points;
using io::PointSet;
}  // namespace hullmap::mapper
