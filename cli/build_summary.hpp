#pragma once
// What `hullmap build` prints of a build's report, a line per stage (build_summary.cpp).

#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::cli {

/// The alignment or frame, the floor and the ceiling: one line each, to standard output.
void printStages(const pipeline::BuildResult& result);

/// The clusters, eps and minPts, the extension and the obstacles' parts: one line each.
void printClustering(const pipeline::BuildResult& result);

}  // namespace hullmap::cli
