#pragma once

// Shared checks of the libFuzzer targets. A target returns normally when the reader either
// returned a consistent result or threw hullmap::Error with a one-line message naming the input;
// anything else (a crash, a sanitizer report, another exception, a broken invariant) aborts and
// libFuzzer saves the input.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "hullmap/core/error.hpp"
#include "hullmap/io/point_cloud.hpp"

namespace hullmap::fuzz {

/// The name every target passes as the input's file name; error messages must start with it.
inline const std::string kInputName = "fuzz.input";

[[noreturn]] inline void violated(const char* what, const std::string& detail = {}) {
  std::fprintf(stderr, "fuzz invariant violated: %s %s\n", what, detail.c_str());
  std::abort();
}

/// An Error's message is one line that names the input.
inline void checkMessage(const hullmap::Error& e, const std::string& name = kInputName) {
  const std::string message = e.what();
  if (message.rfind(name, 0) != 0) violated("message does not start with the input name:", message);
  if (message.find('\n') != std::string::npos) violated("message spans several lines:", message);
}

/// What a reader returns is consistent: every point finite, every point read either kept or
/// counted as dropped.
inline void checkStats(const io::Points& points, const io::InputStats& stats) {
  for (const io::Point& p : points) {
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) {
      violated("a non-finite point was kept");
    }
  }
  if (stats.read != points.size() + stats.droppedTotal()) {
    violated("read != kept + dropped:", std::to_string(stats.read) + " != " + std::to_string(points.size()) + " + " +
                                            std::to_string(stats.droppedTotal()));
  }
}

/// Runs `parse` on the input; hullmap::Error is an accepted outcome, its message is checked.
template <typename Parse>
int guarded(Parse&& parse) {
  try {
    parse();
  } catch (const hullmap::Error& e) {
    checkMessage(e);
  }
  return 0;
}

inline std::string_view bytesOf(const unsigned char* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace hullmap::fuzz
