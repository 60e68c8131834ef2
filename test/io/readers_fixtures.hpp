#pragma once
// Helpers shared by io/readers.cpp, io/heavy/readers.cpp.

#include <gtest/gtest.h>
#include <liblzf/lzf.h>
#include <malloc.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "read_outcome.hpp"
#include "test_support.hpp"

namespace {
namespace fs = std::filesystem;
using hullmap::Error;
using namespace hullmap::io;
using hullmap::test::errorOf;
using hullmap::test::FedPipe;
using hullmap::test::ReadOutcome;
using hullmap::test::sameOutcome;

const double kNaN = std::numeric_limits<double>::quiet_NaN();

inline std::string fixture(const std::string& name) { return std::string(HULLMAP_SOURCE_DIR) + "/test/data/" + name; }

inline std::string writeFile(const fs::path& dir, const std::string& name, const std::string& bytes) {
  const fs::path p = dir / name;
  std::ofstream out(p, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return p.string();
}

struct PcdField {
  std::string name;
  char type;
  int size;
  int count = 1;
};

struct PcdCloud {
  std::vector<PcdField> fields;
  std::size_t width = 0;
  std::size_t height = 1;
  std::vector<std::vector<double>> rows;  // one row per point, all field values in order
};

inline std::string encodeValue(double v, char type, int size) {
  std::string b(static_cast<std::size_t>(size), '\0');
  if (type == 'F' && size == 4) {
    const float f = static_cast<float>(v);
    std::memcpy(b.data(), &f, 4);
  } else if (type == 'F' && size == 8) {
    std::memcpy(b.data(), &v, 8);
  } else if (type == 'U' && size == 1) {
    const auto u = static_cast<std::uint8_t>(v);
    std::memcpy(b.data(), &u, 1);
  } else if (type == 'U' && size == 4) {
    const auto u = static_cast<std::uint32_t>(v);
    std::memcpy(b.data(), &u, 4);
  } else if (type == 'I' && size == 2) {
    const auto i = static_cast<std::int16_t>(v);
    std::memcpy(b.data(), &i, 2);
  } else {
    ADD_FAILURE() << "writer: unsupported type " << type << size;
  }
  return b;
}

inline std::string pcdHeader(const PcdCloud& c, const std::string& data) {
  std::ostringstream h;
  h << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS";
  for (const auto& f : c.fields) h << ' ' << f.name;
  h << "\nSIZE";
  for (const auto& f : c.fields) h << ' ' << f.size;
  h << "\nTYPE";
  for (const auto& f : c.fields) h << ' ' << f.type;
  h << "\nCOUNT";
  for (const auto& f : c.fields) h << ' ' << f.count;
  h << "\nWIDTH " << c.width << "\nHEIGHT " << c.height << "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << c.width * c.height
    << "\nDATA " << data << "\n";
  return h.str();
}

inline std::string writePcd(const PcdCloud& c, const std::string& data) {
  std::string out = pcdHeader(c, data);
  if (data == "ascii") {
    char buf[64];
    for (const auto& row : c.rows) {
      for (std::size_t i = 0; i < row.size(); ++i) {
        if (std::isnan(row[i])) {
          std::snprintf(buf, sizeof buf, "%snan", i ? " " : "");
        } else {
          std::snprintf(buf, sizeof buf, "%s%.17g", i ? " " : "", row[i]);
        }
        out += buf;
      }
      out += '\n';
    }
    return out;
  }
  if (data == "binary") {
    for (const auto& row : c.rows) {
      std::size_t col = 0;
      for (const auto& f : c.fields) {
        for (int k = 0; k < f.count; ++k) out += encodeValue(row[col++], f.type, f.size);
      }
    }
    return out;
  }
  // binary_compressed: struct of arrays, then LZF.
  std::string raw;
  std::size_t col = 0;
  for (const auto& f : c.fields) {
    for (const auto& row : c.rows) {
      for (int k = 0; k < f.count; ++k) raw += encodeValue(row[col + k], f.type, f.size);
    }
    col += f.count;
  }
  std::string packed(raw.size() * 2 + 64, '\0');
  const unsigned int n = lzf_compress(raw.data(), static_cast<unsigned int>(raw.size()), packed.data(),
                                      static_cast<unsigned int>(packed.size()));
  EXPECT_GT(n, 0u) << "lzf_compress failed";
  const std::uint32_t sizes[2] = {n, static_cast<std::uint32_t>(raw.size())};
  out.append(reinterpret_cast<const char*>(sizes), 8);
  out.append(packed.data(), n);
  return out;
}

struct PlyVertex {
  double x, y, z;
  std::uint8_t red;
  float nx;
};

template <typename T>
void put(std::string& out, T v, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

/// `n` lines of `x y z nx ny nz` after a header and comments; CRLF on some lines, a NaN on every
/// 97th, a comment every 1000th.
inline std::string textCloud(std::size_t n) {
  std::string out = "# generated\npos_x, pos_y, pos_z, nx, ny, nz\n";
  char line[160];
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 1000 == 500) out += "# a comment line\n";
    const double x = 0.001 * double(i) - 3.0, y = std::sin(0.01 * double(i)), z = 1.0 / (1.0 + double(i));
    std::snprintf(line, sizeof line, "%.9g %.9g %s 0 0 1%s", x, y, i % 97 == 3 ? "nan" : std::to_string(z).c_str(),
                  i % 5 == 0 ? "\r\n" : "\n");
    out += line;
  }
  return out;
}

inline PcdCloud pcdCloud(std::size_t n) {
  PcdCloud c;
  c.fields = {{"x", 'F', 4}, {"y", 'F', 4}, {"z", 'F', 4}, {"rgb", 'U', 4}};
  c.width = n;
  for (std::size_t i = 0; i < n; ++i) {
    const double v = 0.01 * double(i);
    c.rows.push_back({i % 50 == 7 ? kNaN : v, -v, 2.0 + std::cos(v), double(i % 256)});
  }
  return c;
}

}  // namespace
