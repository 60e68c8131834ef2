// libFuzzer target: parsePoints, the public entry point (content-based format detection, then the
// reader it picks).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "hullmap/mapper/readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hullmap;
  return fuzz::guarded([&] {
    const mapper::PointSet set = mapper::parsePoints(fuzz::bytesOf(data, size), fuzz::kInputName);
    if (set.inputs.size() != 1) fuzz::violated("parsePoints gave other than one InputStats");
    if (set.inputs.front().path != fuzz::kInputName) fuzz::violated("InputStats::path is not the name");
    fuzz::checkStats(set.points, set.inputs.front());
  });
}
