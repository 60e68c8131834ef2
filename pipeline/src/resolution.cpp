// The octree resolution a build uses: the one given, or one that fits a sparse map (resolution.hpp).
#include "resolution.hpp"

#include <cmath>

#include "hullmap/clustering/build_warnings.hpp"

namespace hullmap::pipeline {

double chooseResolution(const BuildParams& params, const io::Points& sample, std::size_t stride, BuildReport& report) {
  const double given = params.octree.resolution;
  // An eps given is in the units of the resolution given: the two go together.
  if (!params.adapt_resolution || params.eps) return given;
  ResolutionReport r;
  r.given = given;
  r.used = given;
  if (const auto spacing = clustering::pointSpacing(sample, params.auto_rule, params.metric)) {
    r.spacing = *spacing / std::sqrt(double(stride));
    if (const auto coarser = clustering::resolutionForSpacing(*r.spacing, given, params.auto_rule)) r.used = *coarser;
  }
  report.resolution = r;
  return r.used;
}

BuildParams atResolution(const BuildParams& params, double resolution) {
  BuildParams p = params;
  p.octree.resolution = resolution;
  return p;
}

}  // namespace hullmap::pipeline
