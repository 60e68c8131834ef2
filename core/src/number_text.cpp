#include "hullmap/core/number_text.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>

namespace hullmap::core {
namespace {

constexpr double kPow10[] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,
                             1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17};

int digitCount(std::uint64_t m) {
  int n = 1;
  while (m >= 10) {
    m /= 10;
    ++n;
  }
  return n;
}

char* writeDigits(char* first, std::uint64_t m, int n) {
  for (int i = n - 1; i >= 0; --i) {
    first[i] = char('0' + m % 10);
    m /= 10;
  }
  return first + n;
}

}  // namespace

char* writeShortest(char* first, double value) {
  char* const last = first + kShortestTextMax;
  const double a = std::fabs(value);
  if (!(a >= 1e-3 && a < 1e15)) return std::to_chars(first, last, value).ptr;
  // The fewest decimals p for which the integer m nearest to a * 10^p reads back as a: m / 10^p, both
  // exact doubles, divides to the double nearest m * 10^-p, which is what reading the text gives. The
  // fewest decimals are the fewest significant digits, as to_chars finds them. Below 2^50 the rounded
  // product is within 0.2 of the exact one (0.35 after adding 0.5), so no p that works is missed.
  constexpr double kLimit = 1125899906842624.0;  // 2^50
  for (int p = 0; p < 18; ++p) {
    const double scaled = a * kPow10[p];
    if (scaled >= kLimit) break;
    // Signed conversions: one instruction each way, the unsigned ones are not.
    const auto whole = static_cast<std::int64_t>(scaled + 0.5);  // nearest, ties never round-trip
    if (static_cast<double>(whole) / kPow10[p] != a) continue;
    const auto m = static_cast<std::uint64_t>(whole);
    const int n = digitCount(m);
    // Scientific notation's length: significant digits, the point when more than one, "e+dd".
    int significant = n;
    for (std::uint64_t t = m; t % 10 == 0; t /= 10) --significant;
    const int exponent = n - 1 - p;
    const int exponent_digits = std::abs(exponent) >= 100 ? 3 : 2;
    const int scientific = significant + (significant > 1 ? 1 : 0) + 2 + exponent_digits;
    const int fixed = p == 0 ? n : (n > p ? n + 1 : p + 2);
    if (scientific < fixed) break;  // to_chars writes scientific
    char* out = first;
    if (std::signbit(value)) *out++ = '-';
    if (p == 0) return writeDigits(out, m, n);
    if (n > p) {
      out = writeDigits(out, m / static_cast<std::uint64_t>(kPow10[p]), n - p);
      *out++ = '.';
      return writeDigits(out, m % static_cast<std::uint64_t>(kPow10[p]), p);
    }
    *out++ = '0';
    *out++ = '.';
    for (int i = n; i < p; ++i) *out++ = '0';
    return writeDigits(out, m, n);
  }
  return std::to_chars(first, last, value).ptr;
}

}  // namespace hullmap::core
