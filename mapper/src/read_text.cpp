// Plain-text points: ORB-SLAM2/3 map-point dumps, .xyz files, octomap's scan.dat.
#include <algorithm>
#include <cctype>

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
    forEachToken(line, [&](std::string_view token) {
      double v;
      if (!parseDouble(token, v)) {
        failAt(name, cursor.lineNumber(),
               token.empty() ? std::string("empty field") : quoted(token) + " is not a number");
      }
      if (index < 3) values[index] = v;
      ++index;
    });
    if (columns == 0) {
      if (index < 3) {
        failAt(name, cursor.lineNumber(), "expected 3 numbers (x y z), got " + std::to_string(index));
      }
      columns = index;
      // One line's length estimates the point count; never more than the input justifies.
      const std::size_t size = source.sizeHint();
      sink.expect(std::min<std::size_t>(size / (line.size() + 1) + 16, size / 6 + 1));
    } else if (index != columns) {
      failAt(name, cursor.lineNumber(),
             "expected " + std::to_string(columns) + " numbers like the first data line, got " +
                 std::to_string(index));
    }
    ++stats.read;
    keepOrDrop(Point(values[0], values[1], values[2]), sink, stats);
  }
}

}  // namespace hullmap::mapper::detail
