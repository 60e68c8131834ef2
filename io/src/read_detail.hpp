#pragma once

// Shared pieces of the point readers (read_*.cpp). Not installed.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <string>
#include <string_view>

#include "byte_source.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/core/huge_pages.hpp"
#include "hullmap/core/number_text.hpp"
#include "hullmap/io/point_cloud.hpp"
#include "hullmap/io/readers.hpp"

namespace hullmap::io::detail {

using core::parseDouble;

inline bool isFinite(const Point& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

/// Walks a source line by line from `offset`; tracks the 1-based line number (counted from
/// `offset`). Handles \n and \r\n. Each line stays valid until the next call: the bytes before it
/// are released.
class LineCursor {
 public:
  explicit LineCursor(ByteSource& source, std::size_t offset = 0) : source_(source), pos_(offset) {}

  /// Next line without its terminator; false at the end.
  bool next(std::string_view& line) {
    source_.release(pos_);
    if (!source_.ensure(pos_, 1)) return false;
    const std::size_t end = source_.find('\n', pos_);
    const std::size_t stop = end == ByteSource::kNpos ? source_.end() : end;
    line = source_.view(pos_, stop - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end == ByteSource::kNpos ? stop : end + 1;
    ++line_;
    return true;
  }

  std::size_t lineNumber() const { return line_; }
  /// Byte offset of the start of the next line.
  std::size_t offset() const { return pos_; }

 private:
  ByteSource& source_;
  std::size_t pos_;
  std::size_t line_ = 0;
};

/// The bytes of the source after `pos` when its size is known before reading it all (an estimate
/// for reserving), else 0.
inline std::size_t remainingHint(const ByteSource& source, std::size_t pos) {
  return source.sizeHint() > pos ? source.sizeHint() - pos : 0;
}

inline bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

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

[[noreturn]] inline void fail(const std::string& name, const std::string& what) { throw Error(name + ": " + what); }

/// The numeric rows of a trajectory-like text (TUM, GPS): `#` comments and blank lines skipped,
/// numbers separated as forEachToken separates them. Calls row(values, count, line_number) per
/// row with its first 8 numbers in `values` and how many it had in `count` (a row with more than 8
/// is reported by its count); a token that is not a number is an Error naming `name` and the line.
template <typename F>
void forEachNumberRow(std::string_view bytes, const std::string& name, F&& row) {
  ByteSource source(bytes);
  LineCursor cursor(source);
  std::string_view line;
  while (cursor.next(line)) {
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    if (trim(line).empty()) continue;
    double v[8] = {};
    std::size_t count = 0;
    forEachToken(line, [&](std::string_view token) {
      double value = 0;
      if (!parseDouble(token, value)) {
        failAt(name, cursor.lineNumber(),
               token.empty() ? std::string("empty field") : quoted(token) + " is not a number");
      }
      if (count < 8) v[count] = value;
      ++count;
    });
    row(static_cast<const double*>(v), count, cursor.lineNumber());
  }
}

/// Gathers the points a parser keeps into batches of `batch_points` for a PointBatchConsumer.
/// With batch_points = SIZE_MAX the one batch is the whole input (readPointFile's case).
class PointSink {
 public:
  PointSink(std::size_t batch_points, const PointBatchConsumer& consume)
      : batch_points_(batch_points), consume_(consume) {}

  /// About `n` more points are coming (an estimate bounded by the input's size): reserves room
  /// for them, at most one batch.
  void expect(std::size_t n) { core::reserveHuge(batch_, batch_.size() + std::min(n, batch_points_ - batch_.size())); }

  void push(const Point& p) {
    batch_.push_back(p);
    if (batch_.size() >= batch_points_) flush();
  }

  /// Hands the points gathered so far to the consumer.
  void flush() {
    if (batch_.empty()) return;
    consume_(batch_);
    batch_.clear();
  }

 private:
  std::size_t batch_points_;
  const PointBatchConsumer& consume_;
  Points batch_;
};

/// Keeps `p` or counts it as non-finite.
inline void keepOrDrop(const Point& p, PointSink& sink, InputStats& stats) {
  if (isFinite(p)) {
    sink.push(p);
  } else {
    ++stats.dropped["non_finite"];
  }
}

/// Guesses the format from the first bytes of `source` (see detectPointFormat); `blank` is set
/// when the whole input is whitespace.
PointFormat detectPointFormat(ByteSource& source, const std::string& name, bool& blank);

// One parser per format, reading `source` from its start. Each fills `stats.read` and
// `stats.dropped` and pushes the points it keeps into `sink`; the caller flushes it.
void parseText(ByteSource& source, const std::string& name, PointSink& sink, InputStats& stats);
// The map is the last message of each id: the whole dump is loaded before a point is known.
void parseOrbSlamEcho(ByteSource& source, const std::string& name, PointSink& sink, InputStats& stats);
void parsePcd(ByteSource& source, const std::string& name, PointSink& sink, InputStats& stats);
void parsePly(ByteSource& source, const std::string& name, PointSink& sink, InputStats& stats);

}  // namespace hullmap::io::detail
