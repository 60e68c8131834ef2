// libFuzzer target: the PLY (ascii, binary little and big endian) reader, called directly (format detection bypassed).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "read_detail.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hullmap;
  return fuzz::guarded([&] {
    mapper::Points points;
    mapper::InputStats stats;
    mapper::detail::parsePly(fuzz::bytesOf(data, size), fuzz::kInputName, points, stats);
    fuzz::checkStats(points, stats);
  });
}
