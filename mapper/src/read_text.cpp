// Plain-text points: ORB-SLAM2/3 map-point dumps, .xyz files, octomap's scan.dat.
#include <algorithm>
#include <cctype>
#include <cstring>
#include <optional>
#include <vector>

#include <tbb/parallel_for.h>

#include "read_detail.hpp"

namespace hullmap::mapper::detail {
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

/// What one chunk of whole lines after the first data line parses to.
struct ChunkResult {
  Points points;
  std::size_t read = 0;
  std::size_t non_finite = 0;
  std::size_t lines = 0;                                   ///< lines in the chunk, or up to the error
  std::optional<std::pair<std::size_t, std::string>> error;  ///< line in the chunk (1-based), message
};

void parseChunk(std::string_view bytes, std::size_t columns, ChunkResult& out) {
  ByteSource source(bytes);
  LineCursor cursor(source);
  std::string_view line;
  double values[3] = {0, 0, 0};
  out.points.reserve(bytes.size() / 24 + 1);
  while (cursor.next(line)) {
    line = stripComment(line);
    if (trim(line).empty()) continue;
    std::size_t count = 0;
    std::optional<std::string> error = parseNumbers(line, values, count);
    if (!error && count != columns) error = columnsMessage(columns, count);
    if (error) {
      out.error.emplace(cursor.lineNumber(), std::move(*error));
      return;
    }
    ++out.read;
    const Point p(values[0], values[1], values[2]);
    if (isFinite(p)) {
      out.points.push_back(p);
    } else {
      ++out.non_finite;
    }
  }
  out.lines = cursor.lineNumber();
}

// Lines after the first data line, when the whole input is visible (memory, a mapped file), are
// parsed in parallel: a window of bytes at a time is cut at line ends into chunks, the chunks are
// parsed on their own and handed on in order, so the points, counts and the first error (its line
// counted from the lines of the chunks before it) are those of a front-to-back read, and memory
// stays at one window.
constexpr std::size_t kChunkBytes = std::size_t(1) << 18;
constexpr std::size_t kWindowChunks = 32;

/// The offset one past the first '\n' at or after `pos` in the visible bytes, or `end`.
std::size_t lineEndAfter(const ByteSource& source, std::size_t pos, std::size_t end) {
  if (pos >= end) return end;
  const void* nl = std::memchr(source.at(pos), '\n', end - pos);
  return nl == nullptr ? end : pos + static_cast<std::size_t>(static_cast<const char*>(nl) - source.at(pos)) + 1;
}

void parseRestInParallel(ByteSource& source, std::size_t pos, std::size_t line_base, std::size_t columns,
                         const std::string& name, PointSink& sink, InputStats& stats) {
  const std::size_t end = source.end();
  std::vector<ChunkResult> results(kWindowChunks);
  std::vector<std::size_t> cuts;
  while (pos < end) {
    cuts.assign(1, pos);
    while (cuts.size() <= kWindowChunks && cuts.back() < end) {
      cuts.push_back(lineEndAfter(source, std::min(end, cuts.back() + kChunkBytes) - 1, end));
    }
    const std::size_t chunks = cuts.size() - 1;
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
      results[c] = ChunkResult{};
      parseChunk(source.view(cuts[c], cuts[c + 1] - cuts[c]), columns, results[c]);
    });
    for (std::size_t c = 0; c < chunks; ++c) {
      ChunkResult& r = results[c];
      stats.read += r.read;
      if (r.non_finite != 0) stats.dropped["non_finite"] += r.non_finite;
      for (const Point& p : r.points) sink.push(p);
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
      parseRestInParallel(source, cursor.offset(), cursor.lineNumber(), columns, name, sink, stats);
      return;
    }
  }
}

}  // namespace hullmap::mapper::detail
