#pragma once
// Private to hullmap_pipeline: the test hook called at the start of each stage (test_hooks.hpp's
// detail::stage_hook).

#include "hullmap/pipeline/detail/test_hooks.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::pipeline {

inline void runStage(const char* stage) {
  if (detail::stage_hook != nullptr) detail::stage_hook(stage);
}

}  // namespace hullmap::pipeline
