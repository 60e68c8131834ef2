#pragma once
// Private to hullmap_pipeline: the wall time and peak memory of each build stage (report.json's
// timings_ms and peak_rss_mb).

#include <sys/resource.h>
#include <chrono>
#include <string>

#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::pipeline {

inline double peakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

using Clock = std::chrono::steady_clock;

inline double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// Wall time of each stage, and the process's peak resident memory when it ends.
class StageTimer {
 public:
  explicit StageTimer(BuildReport& report) : report_(report) {}
  /// The stage that ends now began when the previous one ended.
  void stage(const std::string& name) { stage(name, msSince(start_)); }
  /// A stage whose time was summed over pieces interleaved with other stages.
  void stage(const std::string& name, double ms) {
    report_.timings_ms.emplace_back(name, ms);
    report_.peak_rss_mb.emplace_back(name, peakRssMb());
    start_ = Clock::now();
  }

 private:
  BuildReport& report_;
  Clock::time_point start_ = Clock::now();
};

}  // namespace hullmap::pipeline
