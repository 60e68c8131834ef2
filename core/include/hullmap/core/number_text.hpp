#pragma once

#include <string_view>

namespace hullmap::core {

/// Buffer size, in chars, that writeShortest needs for any double.
inline constexpr int kShortestTextMax = 32;

/// Writes the text `std::to_chars(first, last, value)` writes (the shortest text that reads back to
/// `value`; fixed notation unless scientific is shorter) at `first`, which must have room for
/// kShortestTextMax chars, and returns one past its end. Byte for byte the same as std::to_chars;
/// faster for values with few decimals in [1e-3, 1e15), which is what point files hold (how much:
/// docs/DESIGN_NOTES.md, "number_text.hpp").
char* writeShortest(char* first, double value);

/// writeShortest(first, value), with a guess of the value's decimals to start from: numbers of one
/// file mostly share theirs, and a right guess costs two round-trip tests instead of one per decimal.
/// `decimals` (any int; 0 to start) is set to the decimals written when the fast path wrote them.
/// The text is the same whatever the guess.
char* writeShortest(char* first, double value, int& decimals);

/// Parses a whole token as a double ("1.5", "-2e-3", "+4", "nan", "inf"). False unless every
/// character is consumed.
bool parseDouble(std::string_view token, double& value);

}  // namespace hullmap::core
