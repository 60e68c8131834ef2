#include "hullmap/ros1/node_params.hpp"

#include "hullmap/core/error.hpp"

namespace hullmap::ros1 {

live::ParameterValues readParameterValues(const ::ros::NodeHandle& nh) {
  live::ParameterValues values;
  for (const auto& spec : live::nodeParameters()) {
    const std::string& name = spec.name;
    switch (spec.kind) {
      case live::ParameterKind::kNumber:
      case live::ParameterKind::kOptionalNumber: {
        double number = 0.0;
        if (nh.getParam(name, number)) values[name] = number;
        break;
      }
      case live::ParameterKind::kText: {
        std::string text;
        if (nh.getParam(name, text)) values[name] = text;
        break;
      }
      case live::ParameterKind::kWordOrNumber:
      case live::ParameterKind::kWord: {
        if (!nh.hasParam(name)) break;
        std::string text;
        double number = 0.0;
        int whole = 0;
        if (nh.getParam(name, text)) {
          values[name] = text;
        } else if (nh.getParam(name, number)) {
          values[name] = number;
        } else if (nh.getParam(name, whole)) {
          values[name] = std::int64_t{whole};
        } else {
          throw Error::inParameter("~" + name, "expected a number or a word such as auto");
        }
        break;
      }
    }
  }
  return values;
}

live::NodeSettings readSettings(const ::ros::NodeHandle& nh) {
  return live::readSettings(readParameterValues(nh), live::Checking::kParse, "~");
}

pipeline::BuildParams readBuildParams(const ::ros::NodeHandle& nh) { return readSettings(nh).build; }

NodeParams readNodeParams(const ::ros::NodeHandle& nh) { return readSettings(nh).node; }

}  // namespace hullmap::ros1
