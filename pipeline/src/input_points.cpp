#include "input_points.hpp"

#include "hullmap/mapper/readers.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::pipeline {

Error noPoints(const std::vector<std::string>& inputs) {
  std::string names;
  for (const auto& input : inputs) names += (names.empty() ? "" : ", ") + input;
  return Error(names + ": no points");
}

mapper::PointSet readInputPoints(const std::vector<std::string>& inputs) {
  mapper::PointSet set = mapper::readPointFiles(inputs);
  if (set.points.empty()) throw noPoints(inputs);
  return set;
}

}  // namespace hullmap::pipeline
