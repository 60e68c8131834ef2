#include "hullmap/pipeline/check_json.hpp"

#include <nlohmann/json.hpp>

namespace hullmap::pipeline {

std::string segmentCheckJsonLine(std::size_t index, const collision::SegmentCheck& c) {
  nlohmann::json j{{"index", index}, {"collides", c.collides}};
  j["obstacle"] = c.obstacle >= 0 ? nlohmann::json(c.obstacle) : nlohmann::json(nullptr);
  if (c.part >= 0) j["part"] = c.part;
  j["surface"] = c.surface.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.surface);
  j["t"] = c.collides ? nlohmann::json(c.t) : nlohmann::json(nullptr);
  j["clearance"] = c.clearance;
  return j.dump();
}

}  // namespace hullmap::pipeline
