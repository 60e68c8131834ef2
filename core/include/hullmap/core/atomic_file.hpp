#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace hullmap::core {

/// Writes `path` whole or not at all: `write` fills a temporary file beside `path`, which is
/// flushed and renamed over `path` only when `write` returns normally and the stream is good.
/// On any failure the temporary file is removed and hullmap::Error names `path`.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write, bool binary = false);

}  // namespace hullmap::core
