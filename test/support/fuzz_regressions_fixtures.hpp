#pragma once
// Helpers shared by mapper/fuzz_regressions.cpp, mapper/heavy/fuzz_regressions.cpp, e2e/fuzz_regressions.cpp.

#include <gtest/gtest.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "read_outcome.hpp"
#include "test_support.hpp"

namespace {
namespace fs = std::filesystem;
using hullmap::Error;
using namespace hullmap::mapper;
using namespace hullmap::io;
using hullmap::test::errorOf;

const fs::path kCorpus = fs::path(HULLMAP_SOURCE_DIR) / "test" / "fuzz" / "corpus";

/// The points make_corpus.py writes (POINTS there).
const std::vector<Point> kSeedPoints = {{0.0, 0.0, 1.0},    {0.1, -0.05, 1.01}, {0.2, -0.1, 1.02},
                                        {-1.5, 2.25, 3e-3}, {12.0, -7.5, 0.5},  {0.0, 0.0, 0.0}};

inline std::string seed(const std::string& target, const std::string& name) {
  const fs::path p = kCorpus / target / name;
  EXPECT_TRUE(fs::exists(p)) << p;
  return hullmap::test::slurp(p);
}

inline std::string writeFile(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path.string();
}

inline std::string pcdHeader(const std::string& data, const std::string& width = "2") {
  return "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " + width +
         "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + width + "\nDATA " + data + "\n";
}

inline std::string compressedPcd(std::uint32_t compressed, std::uint32_t uncompressed, const std::string& lzf) {
  std::string out = pcdHeader("binary_compressed");
  out.append(reinterpret_cast<const char*>(&compressed), 4);
  out.append(reinterpret_cast<const char*>(&uncompressed), 4);
  return out + lzf;
}

const std::string kPlyHead =
    "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
    "property float y\nproperty float z\nend_header\n";

}  // namespace
