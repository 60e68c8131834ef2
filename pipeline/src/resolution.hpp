#pragma once
// Private to hullmap_pipeline: the octree resolution a build uses (resolution.cpp).

#include <cstddef>

#include "hullmap/io/point_cloud.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::pipeline {

/// The octree's resolution (BuildParams::adapt_resolution): the one given, or a coarser one when
/// the map's points lie too far apart for it (clustering::resolutionForSpacing); recorded in
/// report.resolution when adapting is on. The spacing is measured on the build's `sample`, which
/// keeps every `stride`-th point: on a surface the spacing grows with the square root of the
/// stride, so it is divided by that. Both paths (whole, streamed) keep the same sample.
double chooseResolution(const BuildParams& params, const io::Points& sample, std::size_t stride, BuildReport& report);

/// `params` with the octree resolution `resolution`.
BuildParams atResolution(const BuildParams& params, double resolution);

}  // namespace hullmap::pipeline
