#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "hullmap/core/number_text.hpp"

namespace {

std::string oracle(double value) {
  char buffer[64];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

std::string shortest(double value) {
  char buffer[hullmap::core::kShortestTextMax];
  return std::string(buffer, hullmap::core::writeShortest(buffer, value));
}

std::string shortestFrom(double value, int& decimals) {
  char buffer[hullmap::core::kShortestTextMax];
  return std::string(buffer, hullmap::core::writeShortest(buffer, value, decimals));
}

// Every value the fast path may take, and those it leaves to to_chars, give to_chars' bytes.
TEST(NumberText, SameBytesAsToCharsOnDecimalsReadFromText) {
  std::mt19937_64 rng(11);
  for (int digits = 0; digits <= 17; ++digits) {
    std::uniform_int_distribution<std::int64_t> mantissa(-99999999, 99999999);
    for (int i = 0; i < 20000; ++i) {
      const std::string text = std::to_string(mantissa(rng)) + "e-" + std::to_string(digits);
      const double value = std::strtod(text.c_str(), nullptr);
      ASSERT_EQ(shortest(value), oracle(value)) << text;
    }
  }
}

TEST(NumberText, SameBytesAsToCharsOnRandomBitsAndEdges) {
  std::mt19937_64 rng(12);
  for (int i = 0; i < 400000; ++i) {
    // Exponents around the fast path's range [1e-3, 1e15), and all mantissa bits.
    const std::uint64_t bits = (rng() & 0x800FFFFFFFFFFFFFull) | (std::uint64_t(1000 + rng() % 80) << 52);
    double value;
    std::memcpy(&value, &bits, sizeof value);
    ASSERT_EQ(shortest(value), oracle(value)) << oracle(value);
  }
  for (int e = -6; e <= 17; ++e) {
    const double power = std::pow(10.0, e);
    double below = power, above = power;
    for (int k = 0; k < 40; ++k) {
      for (const double v : {below, above, -below, -above, power * 1.5, power * 9.999999}) {
        ASSERT_EQ(shortest(v), oracle(v)) << oracle(v);
      }
      below = std::nextafter(below, 0.0);
      above = std::nextafter(above, 1e300);
    }
  }
  for (const double v : {0.0, -0.0, 1e-3, 1e15, 123456789012345.0, 1e14, 100.0, 0.001, 0.00123, 1000000.0,
                         std::numeric_limits<double>::infinity(), std::numeric_limits<double>::denorm_min(),
                         std::numeric_limits<double>::max(), 0.1 + 0.2}) {
    ASSERT_EQ(shortest(v), oracle(v)) << oracle(v);
  }
}

// The guess of decimals only changes where the search starts: every guess, right, too few, too many,
// out of range, or left by the number before, gives to_chars' bytes.
TEST(NumberText, SameBytesAsToCharsWhateverTheGuessedDecimals) {
  std::mt19937_64 rng(13);
  int carried = 0;
  for (int digits = 0; digits <= 17; ++digits) {
    std::uniform_int_distribution<std::int64_t> mantissa(-99999999, 99999999);
    for (int i = 0; i < 4000; ++i) {
      const std::string text = std::to_string(mantissa(rng)) + "e-" + std::to_string(digits);
      const double value = std::strtod(text.c_str(), nullptr);
      const std::string want = oracle(value);
      for (const int guess : {-5, 0, 1, digits - 1, digits, digits + 1, 17, 18, 40}) {
        int decimals = guess;
        ASSERT_EQ(shortestFrom(value, decimals), want) << text << " guess " << guess;
        // What it sets is what it wrote: a guess from it starts at the answer.
        int again = decimals;
        ASSERT_EQ(shortestFrom(value, again), want) << text;
        ASSERT_EQ(again, decimals) << text;
      }
      ASSERT_EQ(shortestFrom(value, carried), want) << text;
    }
  }
  for (int i = 0; i < 200000; ++i) {
    const std::uint64_t bits = (rng() & 0x800FFFFFFFFFFFFFull) | (std::uint64_t(1000 + rng() % 80) << 52);
    double value;
    std::memcpy(&value, &bits, sizeof value);
    int decimals = int(rng() % 20);
    ASSERT_EQ(shortestFrom(value, decimals), oracle(value)) << oracle(value);
    ASSERT_EQ(shortestFrom(value, carried), oracle(value)) << oracle(value);
  }
}

}  // namespace
