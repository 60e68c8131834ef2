#include "hullmap/plot/colour.hpp"
#include "hullmap/core/constants.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace hullmap::plot {
namespace {

// Kelly (1965), colours of maximum contrast in his order, without white, black, grey (#848482)
// and the near-black olive (#2b3d26): a cluster must never look like noise.
constexpr std::array<std::uint32_t, 18> kKellyColours = {0xf3c300, 0x875692, 0xf38400, 0xa1caf1, 0xbe0032, 0xc2b280,
                                                         0x008856, 0xe68fac, 0x0067a5, 0xf99379, 0x604e97, 0xf6a600,
                                                         0xb3446c, 0xdcd300, 0x882d17, 0x8db600, 0x654522, 0xe25822};

constexpr double kGoldenAngleDeg = 137.50776405003785;

double srgbGamma(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

// CIE LCh(ab), D65 white, to sRGB; false when out of gamut.
bool lchToRgb(double l, double c, double h_deg, Rgb& out) {
  const double a = c * std::cos(h_deg * kPi / 180.0);
  const double b = c * std::sin(h_deg * kPi / 180.0);
  const double fy = (l + 16.0) / 116.0;
  const double fx = fy + a / 500.0;
  const double fz = fy - b / 200.0;
  const auto finv = [](double t) { return t > 6.0 / 29.0 ? t * t * t : 3.0 * 36.0 / 841.0 * (t - 4.0 / 29.0); };
  const double x = 0.95047 * finv(fx);
  const double y = 1.00000 * finv(fy);
  const double z = 1.08883 * finv(fz);
  const std::array<double, 3> linear = {3.2404542 * x - 1.5371385 * y - 0.4985314 * z,
                                        -0.9692660 * x + 1.8760108 * y + 0.0415560 * z,
                                        0.0556434 * x - 0.2040259 * y + 1.0572252 * z};
  std::array<std::uint8_t, 3> channel{};
  for (int i = 0; i < 3; ++i) {
    if (linear[i] < -1e-9 || linear[i] > 1.0 + 1e-9) return false;
    const double v = srgbGamma(std::clamp(linear[i], 0.0, 1.0));
    channel[i] = static_cast<std::uint8_t>(std::lround(v * 255.0));
  }
  out = Rgb{channel[0], channel[1], channel[2]};
  return true;
}

}  // namespace

std::string toHex(Rgb colour) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", colour.r, colour.g, colour.b);
  return buf;
}

Rgb clusterColour(std::int32_t label) {
  if (label < 0) return Rgb{0, 0, 0};
  if (static_cast<std::size_t>(label) < kKellyColours.size()) {
    const std::uint32_t c = kKellyColours[static_cast<std::size_t>(label)];
    return Rgb{static_cast<std::uint8_t>(c >> 16), static_cast<std::uint8_t>(c >> 8), static_cast<std::uint8_t>(c)};
  }
  const auto i = static_cast<std::int64_t>(label) - static_cast<std::int64_t>(kKellyColours.size());
  constexpr std::array<double, 3> kLightness = {55.0, 72.0, 45.0};
  const double l = kLightness[static_cast<std::size_t>(i % 3)];
  const double h = std::fmod(30.0 + static_cast<double>(i) * kGoldenAngleDeg, 360.0);
  Rgb out;
  // Highest chroma the sRGB gamut allows at this lightness and hue, capped at 60.
  for (double c = 60.0; c > 0.0; c -= 2.0) {
    if (lchToRgb(l, c, h, out)) return out;
  }
  lchToRgb(l, 0.0, h, out);
  return out;
}

}  // namespace hullmap::plot
