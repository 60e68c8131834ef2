// What the fuzzers (test/fuzz) found and what they start from:
// - regressions: inputs that crashed, hung or gave a wrong result, kept after the fix;
// - the seed corpus (test/fuzz/corpus, written by test/fuzz/make_corpus.py) against the points
//   make_corpus.py wrote, and every seed replayed through the checks the fuzz targets make, so a
//   gcc build without libFuzzer still runs them;
// - the exact one-line messages docs/RELIABILITY.md quotes for each kind of bad input.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/io/readers.hpp"
#include "run_hullmap.hpp"

namespace {

namespace fs = std::filesystem;
using hullmap::Error;
using namespace hullmap::mapper;
using namespace hullmap::io;

const fs::path kCorpus = fs::path(HULLMAP_SOURCE_DIR) / "test" / "fuzz" / "corpus";

/// The points make_corpus.py writes (POINTS there).
const std::vector<Point> kSeedPoints = {{0.0, 0.0, 1.0},    {0.1, -0.05, 1.01}, {0.2, -0.1, 1.02},
                                        {-1.5, 2.25, 3e-3}, {12.0, -7.5, 0.5},  {0.0, 0.0, 0.0}};

std::string seed(const std::string& target, const std::string& name) {
  const fs::path p = kCorpus / target / name;
  EXPECT_TRUE(fs::exists(p)) << p;
  return hullmap::test::slurp(p);
}

using hullmap::test::errorOf;

std::string writeFile(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path.string();
}

// ---------------------------------------------------------------------------------------------
// The messages docs/RELIABILITY.md quotes, exactly

std::string pcdHeader(const std::string& data, const std::string& width = "2") {
  return "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " + width +
         "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + width + "\nDATA " + data + "\n";
}

std::string compressedPcd(std::uint32_t compressed, std::uint32_t uncompressed, const std::string& lzf) {
  std::string out = pcdHeader("binary_compressed");
  out.append(reinterpret_cast<const char*>(&compressed), 4);
  out.append(reinterpret_cast<const char*>(&uncompressed), 4);
  return out + lzf;
}

const std::string kPlyHead =
    "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
    "property float y\nproperty float z\nend_header\n";

// The CLI prints the reader's message as one line `hullmap: error: <message>` and exits 2.
TEST(MapperFuzzRegressions, CliPrintsReaderErrorsOnOneLineAndExits2) {
  const fs::path dir = hullmap::test::freshDir("fuzz_regressions_cli");
  const std::string good = writeFile(dir / "good.txt", "1 2 3\n4 5 6\n");
  const std::string bad = writeFile(dir / "bad.txt", "1 2 3\n4 five 6\n");
  const std::string empty = writeFile(dir / "empty.txt", "");
  const std::string traj = writeFile(dir / "traj.txt", "0 1 2 3 0 0 0 0\n");
  const std::string pcd = writeFile(dir / "z.pcd", compressedPcd(4, 24, std::string(4, '\xff')));
  const std::string cut = writeFile(dir / "cut.bt", seed("bt", "chain.bt").substr(0, 150));
  const std::string out = " -o " + (dir / "out").string();
  const struct {
    std::string args;
    std::string err;
  } cases[] = {
      {"build " + bad + out, bad + ":2: 'five' is not a number"},
      {"build " + empty + out, empty + ": no points"},
      {"build " + good + " --trajectory " + traj + out, traj + ":1: zero quaternion"},
      {"build " + pcd + out, pcd + ": binary_compressed PCD: LZF data from byte offset 152 decompresses to 0 "
                                   "bytes, expected 24 (corrupt or truncated)"},
      {"build " + cut + out, cut + ": truncated OctoMap data (file ends inside node 8)"},
      {"build " + good + " --frobnicate" + out, "unknown option --frobnicate (see hullmap build --help)"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    const hullmap::test::CommandResult r = hullmap::test::runHullmap(c.args);
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.err, "hullmap: error: " + c.err + "\n");
    EXPECT_FALSE(fs::exists(dir / "out"));  // nothing half-written
  }
}

}  // namespace
