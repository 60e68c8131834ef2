#pragma once
// Helpers shared by pipeline/frames.cpp, pipeline/heavy/frames.cpp.

#include <gtest/gtest.h>
#include <octomap/OcTree.h>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/pipeline/map_obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/pipeline/report.hpp"
#include "octree_oracle.hpp"
#include "test_support.hpp"

namespace hullmap::pipeline {

namespace {
using V3 = Eigen::Vector3d;

inline std::string sample(const std::string& name) { return std::string(HULLMAP_SOURCE_DIR) + "/maps/" + name; }

inline AlignSettings alignTo(const std::string& reference, io::ReferenceFormat format = io::ReferenceFormat::kTum) {
  AlignSettings align;
  align.reference = reference;
  align.format = format;
  return align;
}

}  // namespace
}  // namespace hullmap::pipeline
