#pragma once

#include <cstdint>
#include <string>

namespace hullmap::plot {

/// An sRGB colour, 8 bits per channel.
struct Rgb {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
};

/// "#rrggbb", lower case.
std::string toHex(Rgb colour);

/// Colour of a cluster label, the same in every picture hullmap draws:
/// - clustering::kNoise (and any negative label) is black, #000000;
/// - labels 0..17 take Kelly's colours of maximum contrast, in Kelly's order (white, black, the
///   neutral grey and the near-black olive left out, so no cluster looks like noise);
/// - from label 18 on, the hue steps by the golden angle (137.5 degrees) in CIE LCh at lightness
///   cycling through 55, 72, 45, so consecutive labels stay far apart and none is near black.
/// Pure function, thread-safe.
Rgb clusterColour(std::int32_t label);

}  // namespace hullmap::plot
