#include "hullmap/clustering/build_warnings.hpp"

namespace hullmap::clustering {
namespace {

bool mostlyNoise(const ClusteringOutcome& o) {
  return o.occupied_voxels > 0 && double(o.noise_voxels) > kNoiseShareLimit * double(o.occupied_voxels);
}

Warning noiseShare(Warning::Code code, const ClusteringOutcome& o) {
  return {code, {{"noise_voxels", double(o.noise_voxels)}, {"occupied_voxels", double(o.occupied_voxels)}}, ""};
}

}  // namespace

std::vector<Warning> buildWarnings(const ClusteringOutcome& o) {
  std::vector<Warning> warnings;
  if (o.resolution > 0.0 && o.eps < o.resolution) {
    warnings.push_back(
        {o.metric == Metric::kXyz ? Warning::Code::kEpsBelowResolution : Warning::Code::kEpsBelowResolutionInColumns,
         {{"eps", o.eps}, {"resolution", o.resolution}},
         ""});
  }
  if (o.obstacles == 0 && o.occupied_voxels > 0) {
    warnings.push_back(
        {Warning::Code::kNoObstacle,
         {{"occupied_voxels", double(o.occupied_voxels)}, {"eps", o.eps}, {"min_pts", double(o.min_pts)}},
         ""});
  } else if (mostlyNoise(o)) {
    warnings.push_back(noiseShare(Warning::Code::kMostlyNoise, o));
  }
  return warnings;
}

std::vector<Warning> hullCheckWarnings(const ClusteringOutcome& o) {
  std::vector<Warning> warnings;
  if (o.obstacles == 0) {
    warnings.push_back({Warning::Code::kCheckNoObstacle, {{"occupied_voxels", double(o.occupied_voxels)}}, ""});
  } else if (mostlyNoise(o)) {
    warnings.push_back(noiseShare(Warning::Code::kCheckMostlyNoise, o));
  }
  return warnings;
}

}  // namespace hullmap::clustering
