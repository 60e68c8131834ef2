#include "hullmap/core/atomic_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include "hullmap/core/error.hpp"

namespace hullmap::core {

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write, bool binary) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path tmp = target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()));
  try {
    {
      std::ofstream out(tmp, binary ? std::ios::binary : std::ios::out);
      if (!out) throw Error(path + ": cannot open for writing: " + std::strerror(errno));
      write(out);
      out.flush();
      if (!out) throw Error(path + ": write failed");
    }
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec) throw Error(path + ": cannot rename into place: " + ec.message());
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

}  // namespace hullmap::core
