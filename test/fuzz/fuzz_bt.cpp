// libFuzzer target: reading a .bt octree (mapper::readMap). readMap takes a path, so the input
// is written to a temporary file of this process first.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "fuzz_support.hpp"
#include "hullmap/mapper/occupancy_map.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hullmap;
  static const std::string path = "/tmp/hullmap_fuzz_bt_" + std::to_string(getpid()) + ".bt";
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) fuzz::violated("cannot write", path);
  if (size > 0 && std::fwrite(data, 1, size, file) != size) fuzz::violated("cannot write", path);
  std::fclose(file);
  try {
    const mapper::OccupancyMap map = mapper::readMap(path);
    const double resolution = map.resolution();
    if (!std::isfinite(resolution) || !(resolution > 0)) fuzz::violated("map with a bad resolution");
  } catch (const hullmap::Error& e) {
    fuzz::checkMessage(e, path);
  }
  std::remove(path.c_str());
  return 0;
}
