// libFuzzer target: the PCD (ascii, binary, binary_compressed LZF) reader, called directly (format
// detection bypassed), whole and with its bytes arriving in chunks (fuzz_parser.hpp).
#include <cstddef>
#include <cstdint>

#include "fuzz_parser.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hullmap;
  return fuzz::guarded([&] { fuzz::checkParser(io::detail::parsePcd, fuzz::bytesOf(data, size)); });
}
