#include "input_points.hpp"

#include "hullmap/io/readers.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::pipeline {

Error noPoints(const std::vector<std::string>& inputs) {
  std::string names;
  for (const auto& input : inputs) names += (names.empty() ? "" : ", ") + input;
  return Error(names + ": no points");
}

io::PointSet readInputPoints(const std::vector<std::string>& inputs) {
  io::PointSet set = io::readPointFiles(inputs);
  if (set.points.empty()) throw noPoints(inputs);
  return set;
}

}  // namespace hullmap::pipeline
