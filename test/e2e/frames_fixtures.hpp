#pragma once
// Helpers shared by e2e/frames.cpp, e2e/heavy/frames.cpp.

#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "hullmap/mapper/align.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "run_hullmap.hpp"

namespace {
namespace fs = std::filesystem;
using hullmap::test::freshDir;
using hullmap::test::readJson;
using hullmap::test::runHullmap;
using hullmap::test::slurp;
using hullmap::test::writeText;
using V3 = Eigen::Vector3d;

inline std::string sample(const std::string& name) { return std::string(HULLMAP_SOURCE_DIR) + "/maps/" + name; }

inline hullmap::mapper::Similarity inputToOutput(const fs::path& out) {
  return hullmap::pipeline::similarityFromJson(readJson(out / "report.json")["input_to_output"], "report.json",
                                               "input_to_output");
}

inline std::vector<nlohmann::json> jsonLines(const std::string& text) {
  std::vector<nlohmann::json> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

}  // namespace
