// PLY 1.0 (Stanford polygon format): ascii, binary_little_endian, binary_big_endian.
// Points are the x y z properties of the `vertex` element; every other property and element
// (faces with list properties, edges, ...) is walked over and ignored.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "read_detail.hpp"

namespace hullmap::io::detail {
namespace {

enum class Scalar { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

bool scalarFromName(std::string_view s, Scalar& out) {
  static const struct {
    const char* name;
    Scalar type;
  } kNames[] = {{"char", Scalar::kInt8},      {"int8", Scalar::kInt8},       {"uchar", Scalar::kUint8},
                {"uint8", Scalar::kUint8},    {"short", Scalar::kInt16},     {"int16", Scalar::kInt16},
                {"ushort", Scalar::kUint16},  {"uint16", Scalar::kUint16},   {"int", Scalar::kInt32},
                {"int32", Scalar::kInt32},    {"uint", Scalar::kUint32},     {"uint32", Scalar::kUint32},
                {"float", Scalar::kFloat32},  {"float32", Scalar::kFloat32}, {"double", Scalar::kFloat64},
                {"float64", Scalar::kFloat64}};
  for (const auto& n : kNames) {
    if (s == n.name) {
      out = n.type;
      return true;
    }
  }
  return false;
}

std::size_t sizeOf(Scalar t) {
  switch (t) {
    case Scalar::kInt8:
    case Scalar::kUint8:
      return 1;
    case Scalar::kInt16:
    case Scalar::kUint16:
      return 2;
    case Scalar::kInt32:
    case Scalar::kUint32:
    case Scalar::kFloat32:
      return 4;
    case Scalar::kFloat64:
      return 8;
  }
  return 0;
}

struct Property {
  std::string name;
  Scalar type = Scalar::kFloat32;  // the item type for a list
  bool is_list = false;
  Scalar count_type = Scalar::kUint8;  // lists only
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;
  std::size_t line = 0;
};

enum class Encoding { kAscii, kLittle, kBig };

struct PlyHeader {
  Encoding encoding = Encoding::kAscii;
  std::vector<Element> elements;
  std::size_t data_offset = 0;
  std::size_t end_line = 0;
};

std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  forEachToken(line, [&](std::string_view t) { out.push_back(t); });
  return out;
}

PlyHeader parsePlyHeader(ByteSource& source, const std::string& name) {
  PlyHeader h;
  LineCursor cursor(source);
  std::string_view line;
  if (!cursor.next(line) || trim(line) != "ply") fail(name, "not a PLY file (first line is not 'ply')");
  bool have_format = false;
  while (true) {
    if (!cursor.next(line)) fail(name, "PLY header has no end_header line");
    const std::size_t n = cursor.lineNumber();
    const std::string_view t = trim(line);
    if (t.empty()) continue;
    const auto w = words(t);
    const std::string_view key = w.front();
    if (key == "comment" || key == "obj_info") continue;
    if (key == "end_header") {
      h.data_offset = cursor.offset();
      h.end_line = n;
      break;
    }
    if (key == "format") {
      if (w.size() != 3) failAt(name, n, "expected 'format <encoding> 1.0'");
      if (w[1] == "ascii")
        h.encoding = Encoding::kAscii;
      else if (w[1] == "binary_little_endian")
        h.encoding = Encoding::kLittle;
      else if (w[1] == "binary_big_endian")
        h.encoding = Encoding::kBig;
      else
        failAt(name, n, "unknown PLY format " + quoted(w[1]));
      have_format = true;
    } else if (key == "element") {
      if (w.size() != 3) failAt(name, n, "expected 'element <name> <count>'");
      std::uint64_t count = 0;
      const auto [ptr, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), count);
      if (ec != std::errc() || ptr != w[2].data() + w[2].size() || count > (std::uint64_t(1) << 40)) {
        failAt(name, n, "element count " + quoted(w[2]) + " is not a valid count");
      }
      h.elements.push_back(Element{std::string(w[1]), static_cast<std::size_t>(count), {}, n});
    } else if (key == "property") {
      if (h.elements.empty()) failAt(name, n, "property before any element");
      Property p;
      if (w.size() == 5 && w[1] == "list") {
        p.is_list = true;
        if (!scalarFromName(w[2], p.count_type) || !scalarFromName(w[3], p.type)) {
          failAt(name, n, "unknown PLY list property types " + quoted(w[2]) + " " + quoted(w[3]));
        }
        if (p.count_type == Scalar::kFloat32 || p.count_type == Scalar::kFloat64) {
          failAt(name, n, "PLY list count type must be an integer type");
        }
        p.name = std::string(w[4]);
      } else if (w.size() == 3) {
        if (!scalarFromName(w[1], p.type)) failAt(name, n, "unknown PLY property type " + quoted(w[1]));
        p.name = std::string(w[2]);
      } else {
        failAt(name, n, "expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
      }
      h.elements.back().properties.push_back(p);
    } else {
      failAt(name, n, "unknown PLY header line " + quoted(t));
    }
  }
  if (!have_format) failAt(name, h.end_line, "PLY header has no format line");
  return h;
}

// Binary data: a bounds-checked reader.
class BinaryReader {
 public:
  BinaryReader(ByteSource& source, std::size_t offset, bool big_endian, const std::string& name)
      : source_(source), pos_(offset), swap_(big_endian), name_(name) {}

  double read(Scalar t, const char* element, std::size_t index) {
    const std::size_t size = sizeOf(t);
    need(size, element, index);
    unsigned char b[8];
    std::memcpy(b, source_.at(pos_), size);
    pos_ += size;
    if (swap_) std::reverse(b, b + size);
    switch (t) {
      case Scalar::kInt8:
        return static_cast<std::int8_t>(b[0]);
      case Scalar::kUint8:
        return b[0];
      case Scalar::kInt16:
        return get<std::int16_t>(b);
      case Scalar::kUint16:
        return get<std::uint16_t>(b);
      case Scalar::kInt32:
        return get<std::int32_t>(b);
      case Scalar::kUint32:
        return get<std::uint32_t>(b);
      case Scalar::kFloat32:
        return get<float>(b);
      case Scalar::kFloat64:
        return get<double>(b);
    }
    return 0;
  }

  void skip(std::size_t count, std::size_t size, const char* element, std::size_t index) {
    std::size_t total = 0;
    if (__builtin_mul_overflow(count, size, &total)) {
      source_.loadAll();
      total = source_.end() - pos_ + 1;
    }
    // Skipped bytes are released before they are loaded: a pipe does not buffer them.
    source_.release(pos_ + total);
    need(total, element, index);
    pos_ += total;
  }

  /// The bytes before the current position are done with.
  void release() { source_.release(pos_); }
  std::size_t remaining() const { return remainingHint(source_, pos_); }

 private:
  template <typename T>
  static double get(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
  }

  void need(std::size_t size, const char* element, std::size_t index) {
    if (!source_.ensure(pos_, size)) {
      fail(name_, std::string("truncated binary PLY data: ") + element + " " + std::to_string(index) +
                      " needs bytes up to offset " + std::to_string(pos_ + size) + ", the file ends at " +
                      std::to_string(source_.end()));
    }
  }

  ByteSource& source_;
  std::size_t pos_;
  bool swap_;
  const std::string& name_;
};

// ASCII data: a token stream that knows its line number.
class TokenReader {
 public:
  TokenReader(ByteSource& source, std::size_t offset, std::size_t line, const std::string& name)
      : source_(source), pos_(offset), line_(line), name_(name) {}

  double number(const char* element, std::size_t index) {
    const std::string_view t = token(element, index);
    double v;
    if (!parseDouble(t, v)) failAt(name_, line_, quoted(t) + " is not a number");
    return v;
  }

  std::size_t count(const char* element, std::size_t index) {
    const std::string_view t = token(element, index);
    std::uint64_t v = 0;
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || ptr != t.data() + t.size() || v > (std::uint64_t(1) << 32)) {
      failAt(name_, line_, "list count " + quoted(t) + " is not a valid count");
    }
    return static_cast<std::size_t>(v);
  }

  void release() { source_.release(pos_); }
  std::size_t line() const { return line_; }
  std::size_t remaining() const { return remainingHint(source_, pos_); }

 private:
  bool available() { return pos_ < source_.end() || source_.more(); }

  // The token stays valid until the next call.
  std::string_view token(const char* element, std::size_t index) {
    source_.release(pos_);
    while (true) {
      if (!available()) {
        fail(name_, std::string("truncated PLY data: ") + element + " " + std::to_string(index) +
                        " is incomplete at the end of the file (line " + std::to_string(line_) + ")");
      }
      const char c = *source_.at(pos_);
      if (!isSpace(c) && c != '\n') break;
      if (c == '\n') ++line_;
      ++pos_;
    }
    const std::size_t start = pos_;
    while (available()) {
      const char c = *source_.at(pos_);
      if (isSpace(c) || c == '\n') break;
      ++pos_;
    }
    return source_.view(start, pos_ - start);
  }

  ByteSource& source_;
  std::size_t pos_;
  std::size_t line_;
  const std::string& name_;
};

template <typename Reader>
void readElements(const PlyHeader& h, Reader& reader, const std::string& name, PointSink& sink, InputStats& stats) {
  constexpr bool kAscii = std::is_same_v<Reader, TokenReader>;
  for (const Element& e : h.elements) {
    const bool is_vertex = e.name == "vertex";
    int axis_of[3] = {-1, -1, -1};
    std::vector<int> axis(e.properties.size(), -1);
    std::size_t min_bytes = 0;
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      const Property& p = e.properties[i];
      min_bytes += kAscii ? 2 : sizeOf(p.is_list ? p.count_type : p.type);
      const int a = p.name == "x" ? 0 : p.name == "y" ? 1 : p.name == "z" ? 2 : -1;
      if (is_vertex && a >= 0 && !p.is_list) {
        axis[i] = a;
        axis_of[a] = static_cast<int>(i);
      }
    }
    if (is_vertex) {
      if (axis_of[0] < 0 || axis_of[1] < 0 || axis_of[2] < 0) {
        failAt(name, e.line, "PLY vertex element has no scalar x y z properties");
      }
      // Never reserve more vertices than the remaining bytes can hold.
      sink.expect(std::min(e.count, reader.remaining() / std::max<std::size_t>(min_bytes, 1) + 1));
    }
    // An element without properties holds no bytes: walking its (up to 2^40) items would only
    // spin.
    if (e.properties.empty()) continue;
    const char* label = e.name.c_str();
    double xyz[3] = {0, 0, 0};
    for (std::size_t k = 0; k < e.count; ++k) {
      reader.release();
      for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const Property& p = e.properties[i];
        if (p.is_list) {
          std::size_t n = 0;
          if constexpr (kAscii) {
            n = reader.count(label, k);
            for (std::size_t j = 0; j < n; ++j) reader.number(label, k);
          } else {
            const double c = reader.read(p.count_type, label, k);
            if (c < 0) fail(name, std::string("negative list count in PLY ") + label + " " + std::to_string(k));
            n = static_cast<std::size_t>(c);
            reader.skip(n, sizeOf(p.type), label, k);
          }
        } else if constexpr (kAscii) {
          const double v = reader.number(label, k);
          if (axis[i] >= 0) xyz[axis[i]] = v;
        } else {
          const double v = reader.read(p.type, label, k);
          if (axis[i] >= 0) xyz[axis[i]] = v;
        }
      }
      if (is_vertex) {
        ++stats.read;
        keepOrDrop(Point(xyz[0], xyz[1], xyz[2]), sink, stats);
      }
    }
  }
}

}  // namespace

void parsePly(ByteSource& source, const std::string& name, PointSink& sink, InputStats& stats) {
  const PlyHeader h = parsePlyHeader(source, name);
  if (h.encoding == Encoding::kAscii) {
    TokenReader reader(source, h.data_offset, h.end_line + 1, name);
    readElements(h, reader, name, sink, stats);
  } else {
    BinaryReader reader(source, h.data_offset, h.encoding == Encoding::kBig, name);
    readElements(h, reader, name, sink, stats);
  }
}

}  // namespace hullmap::io::detail
