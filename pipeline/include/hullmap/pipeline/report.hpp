#pragma once
// report.json: what a build did and with which parameters, as JSON.

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "hullmap/mapper/frame.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::pipeline {

/// The report.json document of a result (parameters, warnings, inputs, point account, octree,
/// clusters, obstacles, timings, peak memory); the warnings in words, parameters named by `spell`.
nlohmann::json reportJson(const BuildResult& result, const ParameterSpelling& spell = fieldSpelling);

/// The parameters object of report.json and obstacles.json.
nlohmann::json parametersJson(const BuildParams& params);

/// Reads a report.json written by write(); throws hullmap::Error naming `path` unless it is JSON
/// with a "parameters" object whose "resolution" is a positive number.
nlohmann::json readReport(const std::filesystem::path& path);

/// The frame description written into every output ("z-up map frame: input axis -y rotated to +z").
std::string frameDescription(const mapper::FrameParams& frame);

/// "x", "-x", ..., "-z": an up axis as report.json writes it (parseUpAxis reads it back).
std::string upAxisText(mapper::UpAxis up);

}  // namespace hullmap::pipeline
