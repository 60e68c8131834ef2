// Plain-text points: ORB-SLAM2/3 map-point dumps, .xyz files, octomap's scan.dat.
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

#include <tbb/parallel_for.h>

#include "read_detail.hpp"

namespace hullmap::io::detail {
namespace {

bool isWord(std::string_view token) {
  if (token.empty()) return false;
  const auto c = static_cast<unsigned char>(token.front());
  return std::isalpha(c) || c == '_';
}

std::string_view stripComment(std::string_view line) {
  const std::size_t hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

/// The numbers of one data line: the first three in `values`, how many in `count`; the message of
/// its first token that is not a number, if any.
std::optional<std::string> parseNumbers(std::string_view line, double (&values)[3], std::size_t& count) {
  std::optional<std::string> error;
  count = 0;
  forEachToken(line, [&](std::string_view token) {
    double v = 0;
    if (!parseDouble(token, v) && !error) {
      error = token.empty() ? std::string("empty field") : quoted(token) + " is not a number";
    }
    if (count < 3) values[count] = v;
    ++count;
  });
  return error;
}

std::string columnsMessage(std::size_t columns, std::size_t count) {
  return "expected " + std::to_string(columns) + " numbers like the first data line, got " + std::to_string(count);
}

/// A chunk's points, in order: first in its slice of the window's buffer (room for as many as its bytes
/// most likely hold), then, once that is full, in `more`.
struct ChunkPoints {
  Point* slice = nullptr;
  std::size_t capacity = 0;
  std::size_t size = 0;
  Points more;

  void push(const Point& p) {
    if (size < capacity) {
      slice[size++] = p;
    } else {
      more.push_back(p);
    }
  }
};

/// What one chunk of whole lines after the first data line parses to.
struct ChunkResult {
  ChunkPoints points;
  std::size_t read = 0;
  std::size_t non_finite = 0;
  std::size_t lines = 0;                                     ///< lines in the chunk, or up to the error
  std::optional<std::pair<std::size_t, std::string>> error;  ///< line in the chunk (1-based), message
};

constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,
                             1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19};

bool isDigit(char c) { return static_cast<unsigned char>(c - '0') < 10; }

/// A plain decimal at `p` ("-12.5", "3", "0.000"; at most 19 digits): its value in `value`, `p` moved
/// past it. False, `p` unmoved, for anything else (a '+', an exponent, "1.", ".5", more digits,
/// nan, inf): parseDouble reads those.
bool parsePlainDecimal(const char*& p, const char* end, double& value) {
  const char* q = p;
  const bool negative = q != end && *q == '-';
  if (negative) ++q;
  const char* const digits = q;
  std::uint64_t m = 0;
  while (q != end && isDigit(*q)) m = m * 10 + std::uint64_t(*q++ - '0');
  const std::size_t whole = std::size_t(q - digits);
  std::size_t decimals = 0;
  if (q != end && *q == '.') {
    const char* const fraction = ++q;
    while (q != end && isDigit(*q)) m = m * 10 + std::uint64_t(*q++ - '0');
    decimals = std::size_t(q - fraction);
    if (decimals == 0) return false;
  }
  // m and 10^decimals are exact doubles, so their quotient is the double nearest the decimal, as
  // from_chars reads it (Clinger's fast path).
  if (whole == 0 || whole + decimals > 19 || m > (std::uint64_t(1) << 53)) return false;
  const double magnitude = double(m) / kPow10[decimals];
  value = negative ? -magnitude : magnitude;
  p = q;
  return true;
}

/// parseChunk's common line, read without parseNumbers: `columns` plain decimals separated as
/// forEachToken separates tokens (whitespace and/or one comma), the first three in `values`. Returns
/// one past the line's '\n' (or `end`); nullptr for any other line (blank, a comment, another token,
/// another count), which the general path then reads.
const char* parsePlainLine(const char* p, const char* end, std::size_t columns, double (&values)[3]) {
  const auto skipSpace = [end](const char* q) {
    while (q != end && isSpace(*q)) ++q;
    return q;
  };
  std::size_t count = 0;
  p = skipSpace(p);
  while (p != end && *p != '\n') {
    double value;
    if (!parsePlainDecimal(p, end, value)) return nullptr;
    if (p != end && !isSpace(*p) && *p != ',' && *p != '\n') return nullptr;
    if (count < 3) values[count] = value;
    ++count;
    p = skipSpace(p);
    if (p != end && *p == ',') {
      p = skipSpace(p + 1);
      if (p == end || *p == '\n') return nullptr;  // a trailing comma: an empty last field
    }
  }
  if (count != columns) return nullptr;
  return p == end ? end : p + 1;
}

void parseChunk(std::string_view bytes, std::size_t columns, ChunkResult& out) {
  const char* p = bytes.data();
  const char* const end = p + bytes.size();
  std::size_t line_number = 0;
  double values[3] = {0, 0, 0};
  while (p != end) {
    ++line_number;
    if (const char* const next = parsePlainLine(p, end, columns, values)) {
      ++out.read;
      out.points.push(Point(values[0], values[1], values[2]));  // plain decimals are finite
      p = next;
      continue;
    }
    const char* const newline = static_cast<const char*>(std::memchr(p, '\n', std::size_t(end - p)));
    std::string_view line(p, std::size_t((newline == nullptr ? end : newline) - p));
    p = newline == nullptr ? end : newline + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    line = stripComment(line);
    if (trim(line).empty()) continue;
    std::size_t count = 0;
    std::optional<std::string> error = parseNumbers(line, values, count);
    if (!error && count != columns) error = columnsMessage(columns, count);
    if (error) {
      out.error.emplace(line_number, std::move(*error));
      return;
    }
    ++out.read;
    const Point point(values[0], values[1], values[2]);
    if (isFinite(point)) {
      out.points.push(point);
    } else {
      ++out.non_finite;
    }
  }
  out.lines = line_number;
}

// Lines after the first data line, when the whole input is visible (memory, a mapped file), are
// parsed in parallel: a window of bytes at a time is cut at line ends into chunks, the chunks are
// parsed on their own and handed on in order, so the points, counts and the first error (its line
// counted from the lines of the chunks before it) are those of a front-to-back read, and memory
// stays at one window. The window's points go into one buffer that asks for huge pages
// (core::adviseHugePages), a slice a chunk, sized by the first data line's length: 8 MB of points in
// 4 KiB pages otherwise cost 2,000 first-touch page faults.
constexpr std::size_t kChunkBytes = std::size_t(1) << 18;
constexpr std::size_t kWindowChunks = 32;

/// The offset one past the first '\n' at or after `pos` in the visible bytes, or `end`.
std::size_t lineEndAfter(const ByteSource& source, std::size_t pos, std::size_t end) {
  if (pos >= end) return end;
  const void* nl = std::memchr(source.at(pos), '\n', end - pos);
  return nl == nullptr ? end : pos + static_cast<std::size_t>(static_cast<const char*>(nl) - source.at(pos)) + 1;
}

void parseRestInParallel(ByteSource& source, std::size_t pos, std::size_t line_base, std::size_t columns,
                         std::size_t line_bytes, const std::string& name, PointSink& sink, InputStats& stats) {
  const std::size_t end = source.end();
  std::vector<ChunkResult> results(kWindowChunks);
  // Lines are rarely much shorter than the first: room for a quarter more points than its length says.
  const std::size_t per_point = std::max<std::size_t>(6, line_bytes * 3 / 4);
  const std::size_t stride = kChunkBytes / per_point + 64;
  const std::size_t window_points = std::min(kWindowChunks * stride, (end - pos) / per_point + kWindowChunks * 64);
  const std::unique_ptr<Point[]> buffer(new Point[window_points]);  // Eigen leaves it uninitialised: untouched
  core::adviseHugePages(buffer.get(), window_points * sizeof(Point));
  std::vector<std::size_t> cuts;
  while (pos < end) {
    cuts.assign(1, pos);
    while (cuts.size() <= kWindowChunks && cuts.back() < end) {
      cuts.push_back(lineEndAfter(source, std::min(end, cuts.back() + kChunkBytes) - 1, end));
    }
    const std::size_t chunks = cuts.size() - 1;
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
      results[c] = ChunkResult{};
      const std::size_t first = c * stride;
      if (first < window_points) {
        results[c].points.slice = buffer.get() + first;
        results[c].points.capacity = std::min(stride, window_points - first);
      }
      parseChunk(source.view(cuts[c], cuts[c + 1] - cuts[c]), columns, results[c]);
    });
    for (std::size_t c = 0; c < chunks; ++c) {
      ChunkResult& r = results[c];
      stats.read += r.read;
      if (r.non_finite != 0) stats.dropped["non_finite"] += r.non_finite;
      for (std::size_t i = 0; i < r.points.size; ++i) sink.push(r.points.slice[i]);
      for (const Point& p : r.points.more) sink.push(p);
      if (r.error) failAt(name, line_base + r.error->first, r.error->second);
      line_base += r.lines;
    }
    pos = cuts.back();
    source.release(pos);
  }
}

}  // namespace

void parseText(ByteSource& source, const std::string& name, PointSink& sink, InputStats& stats) {
  LineCursor cursor(source);
  std::string_view line;
  std::size_t columns = 0;  // fixed by the first data line
  bool first_content = true;
  double values[3] = {0, 0, 0};
  while (cursor.next(line)) {
    line = stripComment(line);
    if (trim(line).empty()) continue;
    if (first_content) {
      first_content = false;
      // A header line of column names (`pos_x, pos_y, pos_z`, `x y z`) may open the file.
      bool all_words = true;
      std::size_t n = forEachToken(line, [&](std::string_view t) {
        double v;
        all_words = all_words && isWord(t) && !parseDouble(t, v);
      });
      if (all_words && n >= 3) continue;
    }
    std::size_t index = 0;
    if (std::optional<std::string> error = parseNumbers(line, values, index)) {
      failAt(name, cursor.lineNumber(), *error);
    }
    if (columns == 0) {
      if (index < 3) {
        failAt(name, cursor.lineNumber(), "expected 3 numbers (x y z), got " + std::to_string(index));
      }
      columns = index;
      // One line's length estimates the point count; never more than the input justifies.
      const std::size_t size = source.sizeHint();
      sink.expect(std::min<std::size_t>(size / (line.size() + 1) + 16, size / 6 + 1));
    } else if (index != columns) {
      failAt(name, cursor.lineNumber(), columnsMessage(columns, index));
    }
    ++stats.read;
    keepOrDrop(Point(values[0], values[1], values[2]), sink, stats);
    if (source.complete()) {
      parseRestInParallel(source, cursor.offset(), cursor.lineNumber(), columns, line.size() + 1, name, sink, stats);
      return;
    }
  }
}

}  // namespace hullmap::io::detail
