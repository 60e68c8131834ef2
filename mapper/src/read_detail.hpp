#pragma once

// Shared pieces of the point readers (read_*.cpp). Not installed.

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <string>
#include <string_view>

#include "hullmap/mapper/error.hpp"
#include "hullmap/mapper/point_cloud.hpp"

namespace hullmap::mapper::detail {

/// Parses a whole token as a double ("1.5", "-2e-3", "+4", "nan", "inf"). False unless every
/// character is consumed.
inline bool parseDouble(std::string_view token, double& value) {
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

inline bool isFinite(const Point& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

/// Walks `bytes` line by line; tracks the 1-based line number. Handles \n and \r\n.
class LineCursor {
 public:
  explicit LineCursor(std::string_view bytes) : bytes_(bytes) {}

  /// Next line without its terminator; false at the end.
  bool next(std::string_view& line) {
    if (pos_ >= bytes_.size()) return false;
    const std::size_t end = bytes_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? bytes_.size() : end;
    line = bytes_.substr(pos_, stop - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end == std::string_view::npos ? bytes_.size() : end + 1;
    ++line_;
    return true;
  }

  std::size_t lineNumber() const { return line_; }
  /// Byte offset of the start of the next line.
  std::size_t offset() const { return pos_; }

 private:
  std::string_view bytes_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
};

inline bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

/// True when `s` holds only whitespace (newlines included); stops at the first other byte.
inline bool isBlank(std::string_view s) {
  for (char c : s) {
    if (!isSpace(c) && c != '\n') return false;
  }
  return true;
}

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
  return s;
}

/// Calls `f(token)` for each token separated by whitespace and/or one comma; returns the count.
/// An empty token between two commas ("1,,2") is passed as empty so the caller can reject it.
template <typename F>
std::size_t forEachToken(std::string_view line, F&& f) {
  std::size_t count = 0;
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n && isSpace(line[i])) ++i;
  if (i == n) return 0;
  while (true) {
    std::size_t start = i;
    while (i < n && !isSpace(line[i]) && line[i] != ',') ++i;
    f(line.substr(start, i - start));
    ++count;
    while (i < n && isSpace(line[i])) ++i;
    if (i < n && line[i] == ',') {
      ++i;
      while (i < n && isSpace(line[i])) ++i;
      if (i == n) {  // trailing comma: an empty last field
        f(std::string_view());
        return count + 1;
      }
    }
    if (i >= n) return count;
  }
}

/// Quotes a token for a message, cut to a readable length.
inline std::string quoted(std::string_view token) {
  std::string s(token.substr(0, 40));
  if (token.size() > 40) s += "...";
  return "'" + s + "'";
}

[[noreturn]] inline void failAt(const std::string& name, std::size_t line, const std::string& what) {
  throw Error(name + ":" + std::to_string(line) + ": " + what);
}

[[noreturn]] inline void fail(const std::string& name, const std::string& what) {
  throw Error(name + ": " + what);
}

/// Appends `p` or counts it as non-finite.
inline void keepOrDrop(const Point& p, Points& points, InputStats& stats) {
  if (isFinite(p)) {
    points.push_back(p);
  } else {
    ++stats.dropped["non_finite"];
  }
}

// One parser per format. Each fills `stats.read` and `stats.dropped`, appends to `points`.
void parseText(std::string_view bytes, const std::string& name, Points& points, InputStats& stats);
void parseOrbSlamEcho(std::string_view bytes, const std::string& name, Points& points, InputStats& stats);
void parsePcd(std::string_view bytes, const std::string& name, Points& points, InputStats& stats);
void parsePly(std::string_view bytes, const std::string& name, Points& points, InputStats& stats);

}  // namespace hullmap::mapper::detail
