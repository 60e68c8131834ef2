#include "hullmap/clustering/build_warnings.hpp"

#include <algorithm>
#include <cmath>

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

double roundResolution(double value) {
  const double decade = std::pow(10.0, std::floor(std::log10(value)));
  double best = decade;
  // Rounding in the decade's computation (log10 of 0.05) is forgiven by a hair.
  for (const double step : {1.0, 2.0, 5.0, 10.0})
    if (step * decade <= value * (1 + 1e-9)) best = step * decade;
  return best;
}

std::optional<double> pointSpacing(const std::vector<Eigen::Vector3d>& points, const AutoParamsRule& rule,
                                   Metric metric) {
  if (points.size() <= std::size_t(rule.k)) return std::nullopt;
  std::vector<double> curve = kDistanceCurve(points, rule.k + 1, metric, rule.sample);  // sorted descending
  if (curve.empty()) return std::nullopt;
  // The knn_quantile quantile of the ascending values: the (1 - knn_quantile) one of the descending.
  const auto at = std::size_t(std::floor((1.0 - rule.knn_quantile) * double(curve.size() - 1)));
  return curve[at];
}

std::optional<double> resolutionForSpacing(double spacing, double resolution, const AutoParamsRule& rule) {
  if (!(spacing > rule.max_eps_voxels * resolution) || !std::isfinite(spacing)) return std::nullopt;
  return std::max(resolution, roundResolution(spacing / kSuggestedSpacingVoxels));
}

std::optional<Warning> sparseMapWarning(const std::vector<Eigen::Vector3d>& centres, double resolution,
                                        const AutoParams& chosen, const AutoParamsRule& rule, Metric metric) {
  if (std::isfinite(chosen.knn)) return std::nullopt;
  const std::optional<double> spacing = pointSpacing(centres, rule, metric);
  if (!spacing) return std::nullopt;
  const std::optional<double> suggested = resolutionForSpacing(*spacing, resolution, rule);
  if (!suggested) return std::nullopt;
  return Warning{Warning::Code::kSparseForResolution,
                 {{"resolution", resolution}, {"spacing", *spacing}, {"suggested", *suggested}},
                 ""};
}

}  // namespace hullmap::clustering
