#include "hullmap/core/number_text.hpp"

#include <string>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace hullmap::core {
namespace {

constexpr double kPow10[] = {1e0, 1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,
                             1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17};

int digitCount(std::uint64_t m) {
  static constexpr std::uint64_t kPowers[] = {10ull,
                                              100ull,
                                              1000ull,
                                              10000ull,
                                              100000ull,
                                              1000000ull,
                                              10000000ull,
                                              100000000ull,
                                              1000000000ull,
                                              10000000000ull,
                                              100000000000ull,
                                              1000000000000ull,
                                              10000000000000ull,
                                              100000000000000ull,
                                              1000000000000000ull,
                                              10000000000000000ull,
                                              100000000000000000ull,
                                              1000000000000000000ull,
                                              10000000000000000000ull};
  int n = 1;
  while (n < 20 && m >= kPowers[n - 1]) ++n;
  return n;
}

/// The n digits of m (m < 10^n), written two at a time from a table of the pairs 00..99.
char* writeDigits(char* first, std::uint64_t m, int n) {
  static constexpr char kPairs[] =
      "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
      "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
      "8081828384858687888990919293949596979899";
  int i = n;
  while (i >= 2) {
    const std::size_t pair = std::size_t(m % 100) * 2;
    m /= 100;
    first[--i] = kPairs[pair + 1];
    first[--i] = kPairs[pair];
  }
  if (i == 1) first[0] = char('0' + m);
  return first + n;
}

}  // namespace

char* writeShortest(char* first, double value) {
  int decimals = 0;
  return writeShortest(first, value, decimals);
}

char* writeShortest(char* first, double value, int& decimals) {
  char* const last = first + kShortestTextMax;
  const double a = std::fabs(value);
  if (!(a >= 1e-3 && a < 1e15)) return std::to_chars(first, last, value).ptr;
  // The fewest decimals p for which the integer m nearest to a * 10^p reads back as a: m / 10^p, both
  // exact doubles, divides to the double nearest m * 10^-p, which is what reading the text gives. The
  // fewest decimals are the fewest significant digits, as to_chars finds them. Below 2^50 the rounded
  // product is within 0.2 of the exact one (0.35 after adding 0.5), so no p that works is missed.
  // For the same reason a p that works makes p + 1 work (10 m rounds from a * 10^(p+1) and divides to
  // the same quotient) while a * 10^(p+1) stays below 2^50: the fewest p is the p that works when
  // p - 1 does not, and the search may start at any p below the limit, here the caller's guess.
  constexpr double kLimit = 1125899906842624.0;  // 2^50
  enum class Trip { kHolds, kFails, kOverLimit };
  const auto roundTrip = [a](int p, std::int64_t& whole) {
    const double scaled = a * kPow10[p];
    if (scaled >= kLimit) return Trip::kOverLimit;
    // Signed conversions: one instruction each way, the unsigned ones are not.
    whole = static_cast<std::int64_t>(scaled + 0.5);  // nearest, ties never round-trip
    return static_cast<double>(whole) / kPow10[p] == a ? Trip::kHolds : Trip::kFails;
  };
  int p = std::clamp(decimals, 0, 17);
  std::int64_t whole = 0;
  Trip trip = roundTrip(p, whole);
  if (trip == Trip::kOverLimit) {
    p = 0;
    trip = roundTrip(p, whole);
  }
  if (trip == Trip::kHolds) {
    std::int64_t fewer = 0;
    while (p > 0 && roundTrip(p - 1, fewer) == Trip::kHolds) {
      --p;
      whole = fewer;
    }
  } else {
    while (trip == Trip::kFails && p < 17) trip = roundTrip(++p, whole);
    if (trip != Trip::kHolds) return std::to_chars(first, last, value).ptr;
  }
  const auto m = static_cast<std::uint64_t>(whole);
  const int n = digitCount(m);
  // Scientific notation's length: significant digits, the point when more than one, "e+dd".
  int significant = n;
  for (std::uint64_t t = m; t % 10 == 0; t /= 10) --significant;
  const int exponent = n - 1 - p;
  const int exponent_digits = std::abs(exponent) >= 100 ? 3 : 2;
  const int scientific = significant + (significant > 1 ? 1 : 0) + 2 + exponent_digits;
  const int fixed = p == 0 ? n : (n > p ? n + 1 : p + 2);
  if (scientific < fixed) return std::to_chars(first, last, value).ptr;  // to_chars writes scientific
  decimals = p;
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

bool parseDouble(std::string_view token, double& value) {
  if (token.empty()) return false;
  const char* first = token.data();
  const char* last = first + token.size();
  if (*first == '+') {
    ++first;
    if (first == last || *first == '-' || *first == '+') return false;
  }
  const auto [ptr, ec] = std::from_chars(first, last, value);
  if (ec == std::errc::result_out_of_range) {
    // from_chars leaves `value` untouched on overflow/underflow: fall back to strtod's answer
    // (±inf or a denormal/zero), which is what the writer meant.
    value = std::strtod(std::string(token).c_str(), nullptr);
    return ptr == last;
  }
  return ec == std::errc() && ptr == last;
}

}  // namespace hullmap::core
