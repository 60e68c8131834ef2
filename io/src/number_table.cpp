#include "hullmap/io/number_table.hpp"

#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "read_detail.hpp"

namespace hullmap::io {

std::vector<std::vector<double>> readNumberTable(const std::string& path, std::size_t columns,
                                                 const std::string& names) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open: " + std::strerror(errno));
  std::vector<std::vector<double>> rows;
  std::string text;
  bool first_content = true;
  for (std::size_t number = 1; std::getline(in, text); ++number) {
    std::string_view line(text);
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    if (detail::trim(line).empty()) continue;
    if (first_content) {
      first_content = false;
      bool all_words = true;
      detail::forEachToken(line, [&](std::string_view t) {
        double v;
        all_words = all_words && !t.empty() &&
                    (std::isalpha(static_cast<unsigned char>(t.front())) || t.front() == '_') &&
                    !detail::parseDouble(t, v);
      });
      if (all_words) continue;  // a header of column names
    }
    std::vector<double> row;
    detail::forEachToken(line, [&](std::string_view token) {
      double v;
      if (!detail::parseDouble(token, v)) {
        detail::failAt(path, number,
                       token.empty() ? std::string("empty field") : detail::quoted(token) + " is not a number");
      }
      row.push_back(v);
    });
    if (row.size() != columns) {
      detail::failAt(
          path, number,
          "expected " + std::to_string(columns) + " numbers (" + names + "), got " + std::to_string(row.size()));
    }
    for (double v : row)
      if (!std::isfinite(v)) detail::failAt(path, number, "non-finite coordinate");
    rows.push_back(std::move(row));
  }
  if (rows.empty()) throw Error(path + ": no coordinates");
  return rows;
}

}  // namespace hullmap::io
