// libFuzzer target: the TUM trajectory reader (t tx ty tz qx qy qz qw).
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "hullmap/io/readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hullmap;
  return fuzz::guarded([&] {
    const auto keyframes = io::parseTumTrajectory(fuzz::bytesOf(data, size), fuzz::kInputName);
    for (const io::Keyframe& k : keyframes) {
      if (!std::isfinite(k.stamp) || !k.position.allFinite() || !k.orientation.coeffs().allFinite()) {
        fuzz::violated("non-finite keyframe");
      }
      if (std::abs(k.orientation.norm() - 1.0) > 1e-9) fuzz::violated("quaternion not normalised");
    }
  });
}
