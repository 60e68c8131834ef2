// PCD v0.7 (Point Cloud Library): DATA ascii, binary and binary_compressed.
//
// binary stores points one after another (array of structs); binary_compressed stores
// `u32 compressed size, u32 uncompressed size`, then LZF data that decompresses to the fields
// one after another (struct of arrays: all x, then all y, ...). Values are in host byte order
// (little-endian on every machine PCL runs on).
#include <cstdint>
#include <cstring>
#include <optional>
#include <vector>

#include <lzf.h>

#include "read_detail.hpp"

namespace hullmap::io::detail {
namespace {

struct Field {
  std::string name;
  std::size_t size = 0;
  char type = 0;
  std::size_t count = 1;
  std::size_t offset = 0;  // byte offset inside one point (binary)
  std::size_t column = 0;  // first token index inside one line (ascii)
};

struct PcdHeader {
  std::vector<Field> fields;
  std::size_t width = 0;
  std::size_t height = 1;
  std::optional<std::size_t> points;
  std::string data;
  std::size_t data_offset = 0;  // first byte after the DATA line
  std::size_t data_line = 0;    // line number of the DATA line
  std::size_t point_size = 0;
  std::size_t columns = 0;
  int xyz[3] = {-1, -1, -1};  // index into fields
};

// A count above 2^40 (a trillion points) is a corrupt header; the bound keeps products in range.
constexpr std::uint64_t kMaxCount = std::uint64_t(1) << 40;

std::size_t parseCount(std::string_view token, const std::string& name, std::size_t line, std::string_view what) {
  std::uint64_t v = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || ptr != token.data() + token.size() || v > kMaxCount) {
    failAt(name, line, std::string(what) + ": " + quoted(token) + " is not a valid count");
  }
  return static_cast<std::size_t>(v);
}

std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !isSpace(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

PcdHeader parsePcdHeader(ByteSource& source, const std::string& name) {
  PcdHeader h;
  LineCursor cursor(source);
  std::string_view line;
  bool have_width = false;
  bool have_size = false;
  bool have_type = false;
  std::size_t fields_line = 0;
  while (cursor.next(line)) {
    const std::size_t n = cursor.lineNumber();
    const std::string_view t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    const auto tok = tokens(t);
    const std::string_view key = tok.front();
    const std::size_t args = tok.size() - 1;
    const auto needFields = [&] {
      if (h.fields.empty()) failAt(name, n, std::string(key) + " before FIELDS");
      if (args != h.fields.size()) {
        failAt(name, n,
               std::string(key) + " has " + std::to_string(args) + " entries for " + std::to_string(h.fields.size()) +
                   " FIELDS");
      }
    };
    if (key == "VERSION") {
      continue;
    } else if (key == "FIELDS" || key == "COLUMNS") {
      if (args == 0) failAt(name, n, "FIELDS is empty");
      fields_line = n;
      h.fields.clear();
      for (std::size_t i = 1; i < tok.size(); ++i) h.fields.push_back(Field{std::string(tok[i])});
    } else if (key == "SIZE") {
      needFields();
      for (std::size_t i = 0; i < args; ++i) {
        h.fields[i].size = parseCount(tok[i + 1], name, n, "SIZE");
        const std::size_t s = h.fields[i].size;
        if (s != 1 && s != 2 && s != 4 && s != 8)
          failAt(name, n, "SIZE must be 1, 2, 4 or 8, got " + quoted(tok[i + 1]));
      }
      have_size = true;
    } else if (key == "TYPE") {
      needFields();
      for (std::size_t i = 0; i < args; ++i) {
        if (tok[i + 1] != "F" && tok[i + 1] != "I" && tok[i + 1] != "U") {
          failAt(name, n, "TYPE must be F, I or U, got " + quoted(tok[i + 1]));
        }
        h.fields[i].type = tok[i + 1].front();
      }
      have_type = true;
    } else if (key == "COUNT") {
      needFields();
      for (std::size_t i = 0; i < args; ++i) {
        h.fields[i].count = parseCount(tok[i + 1], name, n, "COUNT");
        if (h.fields[i].count == 0 || h.fields[i].count > 65536)
          failAt(name, n, "COUNT out of range: " + quoted(tok[i + 1]));
      }
    } else if (key == "WIDTH") {
      if (args != 1) failAt(name, n, "WIDTH needs one value");
      h.width = parseCount(tok[1], name, n, "WIDTH");
      have_width = true;
    } else if (key == "HEIGHT") {
      if (args != 1) failAt(name, n, "HEIGHT needs one value");
      h.height = parseCount(tok[1], name, n, "HEIGHT");
    } else if (key == "VIEWPOINT") {
      continue;
    } else if (key == "POINTS") {
      if (args != 1) failAt(name, n, "POINTS needs one value");
      h.points = parseCount(tok[1], name, n, "POINTS");
    } else if (key == "DATA") {
      if (args != 1) failAt(name, n, "DATA needs one value");
      h.data = std::string(tok[1]);
      h.data_offset = cursor.offset();
      h.data_line = n;
      if (h.data != "ascii" && h.data != "binary" && h.data != "binary_compressed") {
        failAt(name, n, "unknown PCD DATA type " + quoted(tok[1]) + " (expected ascii, binary or binary_compressed)");
      }
      break;
    } else {
      failAt(name, n, "unknown PCD header line " + quoted(t));
    }
  }
  if (h.data.empty()) fail(name, "PCD header has no DATA line");
  const std::size_t n = h.data_line;
  if (h.fields.empty()) failAt(name, n, "PCD header has no FIELDS line");
  if (!have_size || !have_type) failAt(name, n, "PCD header needs SIZE and TYPE lines");
  if (!have_width) failAt(name, n, "PCD header has no WIDTH line");
  if (h.height != 0 && h.width > kMaxCount / h.height) failAt(name, n, "WIDTH * HEIGHT is too large");
  if (!h.points) h.points = h.width * h.height;
  if (*h.points != h.width * h.height) {
    failAt(
        name, n,
        "POINTS " + std::to_string(*h.points) + " differs from WIDTH * HEIGHT = " + std::to_string(h.width * h.height));
  }
  for (std::size_t i = 0; i < h.fields.size(); ++i) {
    Field& f = h.fields[i];
    if (f.type == 'F' && f.size != 4 && f.size != 8) {
      failAt(name, n, "field " + f.name + ": TYPE F needs SIZE 4 or 8");
    }
    f.offset = h.point_size;
    f.column = h.columns;
    h.point_size += f.size * f.count;
    h.columns += f.count;
    const int axis = f.name == "x" ? 0 : f.name == "y" ? 1 : f.name == "z" ? 2 : -1;
    if (axis >= 0) {
      if (f.type != 'F' || f.count != 1)
        failAt(name, fields_line, "field " + f.name + " must be F4 or F8 with COUNT 1");
      h.xyz[axis] = static_cast<int>(i);
    }
  }
  if (h.xyz[0] < 0 || h.xyz[1] < 0 || h.xyz[2] < 0) failAt(name, fields_line, "FIELDS has no x y z");
  std::size_t bytes_needed = 0;
  if (__builtin_mul_overflow(*h.points, h.point_size, &bytes_needed)) {
    failAt(name, n, "POINTS * point size overflows");
  }
  return h;
}

double readFloat(const unsigned char* p, std::size_t size) {
  if (size == 4) {
    float v;
    std::memcpy(&v, p, 4);
    return v;
  }
  double v;
  std::memcpy(&v, p, 8);
  return v;
}

void readAscii(ByteSource& source, const PcdHeader& h, const std::string& name, PointSink& sink, InputStats& stats) {
  LineCursor cursor(source, h.data_offset);
  const auto lineNo = [&] { return h.data_line + cursor.lineNumber(); };
  std::string_view line;
  const std::size_t cols[3] = {h.fields[h.xyz[0]].column, h.fields[h.xyz[1]].column, h.fields[h.xyz[2]].column};
  // Each point takes at least two bytes per column: never reserve beyond what the data can hold.
  sink.expect(std::min(*h.points, remainingHint(source, h.data_offset) / (2 * h.columns) + 1));
  std::size_t done = 0;
  double xyz[3] = {0, 0, 0};
  while (cursor.next(line)) {
    if (trim(line).empty()) continue;
    if (done == *h.points) failAt(name, lineNo(), "more data lines than POINTS " + std::to_string(*h.points));
    std::size_t index = 0;
    forEachToken(line, [&](std::string_view token) {
      for (int a = 0; a < 3; ++a) {
        if (index == cols[a] && !parseDouble(token, xyz[a])) {
          failAt(name, lineNo(), quoted(token) + " is not a number");
        }
      }
      ++index;
    });
    if (index != h.columns) {
      failAt(name, lineNo(), "expected " + std::to_string(h.columns) + " values, got " + std::to_string(index));
    }
    ++done;
    ++stats.read;
    keepOrDrop(Point(xyz[0], xyz[1], xyz[2]), sink, stats);
  }
  if (done != *h.points) {
    fail(name, "truncated PCD data: POINTS " + std::to_string(*h.points) + " but the data ends after point " +
                   std::to_string(done));
  }
}

void readBinary(ByteSource& source, const PcdHeader& h, const std::string& name, PointSink& sink, InputStats& stats) {
  const std::size_t need = *h.points * h.point_size;
  // Points are checked as they come: a pipe's size is known only at its end. The whole data is
  // checked first when the size is known, so a truncated file fails before any point is delivered.
  const auto truncated = [&] {
    source.loadAll();
    const std::size_t available = source.end() - h.data_offset;
    const std::size_t complete = h.point_size ? available / h.point_size : 0;
    fail(name, "truncated binary PCD data: " + std::to_string(*h.points) + " points of " +
                   std::to_string(h.point_size) + " bytes need " + std::to_string(need) + " bytes from byte offset " +
                   std::to_string(h.data_offset) + ", only " + std::to_string(available) + " there (point " +
                   std::to_string(complete) + " is incomplete)");
  };
  if (source.complete()) {
    if (!source.ensure(h.data_offset, need)) truncated();
    sink.expect(*h.points);
  }
  const Field* f[3] = {&h.fields[h.xyz[0]], &h.fields[h.xyz[1]], &h.fields[h.xyz[2]]};
  std::size_t pos = h.data_offset;
  for (std::size_t i = 0; i < *h.points; ++i, pos += h.point_size) {
    source.release(pos);
    if (!source.ensure(pos, h.point_size)) truncated();
    const auto* p = reinterpret_cast<const unsigned char*>(source.at(pos));
    keepOrDrop(Point(readFloat(p + f[0]->offset, f[0]->size), readFloat(p + f[1]->offset, f[1]->size),
                     readFloat(p + f[2]->offset, f[2]->size)),
               sink, stats);
  }
  stats.read += *h.points;
}

void readCompressed(ByteSource& source, const PcdHeader& h, const std::string& name, PointSink& sink,
                    InputStats& stats) {
  if (!source.ensure(h.data_offset, 8)) {
    fail(name, "truncated binary_compressed PCD: no size words at byte offset " + std::to_string(h.data_offset));
  }
  std::uint32_t compressed = 0;
  std::uint32_t uncompressed = 0;
  std::memcpy(&compressed, source.at(h.data_offset), 4);
  std::memcpy(&uncompressed, source.at(h.data_offset + 4), 4);
  const std::size_t need = *h.points * h.point_size;
  if (uncompressed != need) {
    fail(name, "binary_compressed PCD: uncompressed size " + std::to_string(uncompressed) + " at byte offset " +
                   std::to_string(h.data_offset + 4) + " differs from POINTS * point size = " + std::to_string(need));
  }
  const std::size_t lzf_offset = h.data_offset + 8;
  if (!source.ensure(lzf_offset, compressed)) {
    fail(name, "truncated binary_compressed PCD: " + std::to_string(compressed) +
                   " compressed bytes from byte offset " + std::to_string(lzf_offset) + ", only " +
                   std::to_string(source.end() - lzf_offset) + " there");
  }
  // An LZF back reference expands 3 bytes into at most 264: a larger claim is corrupt, and is
  // refused before allocating for it.
  if (uncompressed > std::size_t(compressed) * 90 + 64) {
    fail(name, "binary_compressed PCD: uncompressed size " + std::to_string(uncompressed) + " is impossible for " +
                   std::to_string(compressed) + " LZF bytes");
  }
  if (need == 0) return;
  // One LZF block holding all x, then all y, ...: no point is whole before all of it is decompressed.
  std::vector<unsigned char> raw(need);
  const unsigned int got =
      lzf_decompress(source.at(lzf_offset), compressed, raw.data(), static_cast<unsigned int>(need));
  source.release(lzf_offset + compressed);
  if (got != need) {
    fail(name, "binary_compressed PCD: LZF data from byte offset " + std::to_string(lzf_offset) + " decompresses to " +
                   std::to_string(got) + " bytes, expected " + std::to_string(need) + " (corrupt or truncated)");
  }
  const std::size_t n = *h.points;
  const unsigned char* column[3];
  std::size_t size[3];
  for (int a = 0; a < 3; ++a) {
    const Field& f = h.fields[h.xyz[a]];
    column[a] = raw.data() + f.offset * n;  // fields are stored one after another
    size[a] = f.size;
  }
  sink.expect(n);
  for (std::size_t i = 0; i < n; ++i) {
    keepOrDrop(Point(readFloat(column[0] + i * size[0], size[0]), readFloat(column[1] + i * size[1], size[1]),
                     readFloat(column[2] + i * size[2], size[2])),
               sink, stats);
  }
  stats.read += n;
}

}  // namespace

void parsePcd(ByteSource& source, const std::string& name, PointSink& sink, InputStats& stats) {
  const PcdHeader h = parsePcdHeader(source, name);
  if (h.data == "ascii") {
    readAscii(source, h, name, sink, stats);
  } else if (h.data == "binary") {
    readBinary(source, h, name, sink, stats);
  } else {
    readCompressed(source, h, name, sink, stats);
  }
}

}  // namespace hullmap::io::detail
