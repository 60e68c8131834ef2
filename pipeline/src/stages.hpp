#pragma once
// Private to hullmap_pipeline: the test hook called at the start of each stage (pipeline.hpp's
// detail::stage_hook).

#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::pipeline {

inline void runStage(const char* stage) {
  if (detail::stage_hook != nullptr) detail::stage_hook(stage);
}

}  // namespace hullmap::pipeline
