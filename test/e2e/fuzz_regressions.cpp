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

#include "fuzz_regressions_fixtures.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "run_hullmap.hpp"

namespace {

// ---------------------------------------------------------------------------------------------
// The messages docs/RELIABILITY.md quotes, exactly

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
