// libFuzzer target: parsePoints, the public entry point (content-based format detection, then the
// reader it picks), and streamPoints, which must deliver the same points in batches.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "hullmap/io/readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hullmap;
  return fuzz::guarded([&] {
    const io::PointSet set = io::parsePoints(fuzz::bytesOf(data, size), fuzz::kInputName);
    if (set.inputs.size() != 1) fuzz::violated("parsePoints gave other than one InputStats");
    if (set.inputs.front().path != fuzz::kInputName) fuzz::violated("InputStats::path is not the name");
    fuzz::checkStats(set.points, set.inputs.front());
    io::Points streamed;
    io::PointStreamParams params;
    params.batch_points = 3;
    const io::InputStats stats =
        io::streamPoints(fuzz::bytesOf(data, size), fuzz::kInputName, params,
                         [&](io::Points& batch) { streamed.insert(streamed.end(), batch.begin(), batch.end()); });
    if (streamed != set.points) fuzz::violated("streamPoints gave other points than parsePoints");
    if (stats.read != set.inputs.front().read || stats.dropped != set.inputs.front().dropped)
      fuzz::violated("streamPoints gave other counts than parsePoints");
  });
}
