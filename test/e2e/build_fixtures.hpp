#pragma once
// Helpers shared by e2e/build.cpp, e2e/heavy/build.cpp.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hullmap/mapper/frame.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "run_hullmap.hpp"

namespace fs = std::filesystem;
using hullmap::test::freshDir;
using hullmap::test::lineCount;
using hullmap::test::readJson;
using hullmap::test::runHullmap;
using hullmap::test::slurp;
using hullmap::test::writeText;

namespace {

/// A small generated scene (ORB-SLAM frame) written to `dir`.
inline fs::path sampleScene(const fs::path& dir, std::size_t points = 6000) {
  hullmap::sim::SceneParams params;
  params.points = points;
  params.seed = 7;
  hullmap::sim::writeScene(hullmap::sim::generateScene(params), params, dir.string());
  return dir;
}

}  // namespace
