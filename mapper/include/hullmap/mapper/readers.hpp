#pragma once
// The readers live in the io library; this header stays for code written against the old path.
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/point_cloud.hpp"

namespace hullmap::mapper {
using io::detectPointFormat;
using io::Keyframe;
using io::parsePoints;
using io::parseTumTrajectory;
using io::PointBatchConsumer;
using io::PointFormat;
using io::PointStreamParams;
using io::readPointFile;
using io::readPointFiles;
using io::readTumTrajectory;
using io::streamPointFile;
using io::streamPointFiles;
using io::streamPoints;
}  // namespace hullmap::mapper
