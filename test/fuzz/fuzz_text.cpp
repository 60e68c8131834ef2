// libFuzzer target: the x y z text (ORB-SLAM2/3 map-point dumps, .xyz) reader, called directly
// (format detection bypassed), whole and with its bytes arriving in chunks (fuzz_parser.hpp).
#include <cstddef>
#include <cstdint>

#include "fuzz_parser.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hullmap;
  return fuzz::guarded([&] { fuzz::checkParser(io::detail::parseText, fuzz::bytesOf(data, size)); });
}
