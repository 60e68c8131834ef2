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
#include "read_outcome.hpp"
#include "test_support.hpp"

namespace {

// ---------------------------------------------------------------------------------------------
// The seed corpus holds what make_corpus.py wrote

// Every seed, whole and cut short at a dozen places, reads the same streamed as parsePoints reads
// it (same points, counts or error): in memory in batches of 2, from a file, and through a pipe read
// 1 and 7 bytes at a time, so that chunks end at every kind of place in every format.
TEST(MapperFuzzCorpus, EverySeedAndItsPrefixesStreamAsTheyParse) {
  const fs::path dir = hullmap::test::freshDir("fuzz_corpus_stream");
  std::size_t inputs = 0;
  std::size_t errors = 0;
  for (const char* target : {"text", "orbslam_echo", "pcd", "ply", "points"}) {
    for (const auto& entry : fs::directory_iterator(kCorpus / target)) {
      const std::string bytes = hullmap::test::slurp(entry.path());
      for (std::size_t cut = 0; cut <= 12; ++cut) {
        const std::string prefix = bytes.substr(0, bytes.size() - bytes.size() * cut / 13);
        const std::string name = entry.path().filename().string();
        SCOPED_TRACE(entry.path().string() + " cut to " + std::to_string(prefix.size()) + " bytes");
        ++inputs;
        const hullmap::test::ReadOutcome want = hullmap::test::parseOutcome(prefix, name);
        errors += !want.error.empty();
        EXPECT_TRUE(hullmap::test::sameOutcome(want, hullmap::test::streamOutcome(prefix, name, 2)));
        const std::string path = writeFile(dir / name, prefix);
        EXPECT_TRUE(hullmap::test::sameOutcome(want, hullmap::test::fileOutcome(path, 2, 1 << 20)));
        // A blank input's format comes from its name's extension, which a pipe does not have.
        if (want.stats.read == 0 && want.error.empty()) continue;
        for (const std::size_t read_bytes : {1, 7}) {
          const hullmap::test::FedPipe pipe(prefix);
          EXPECT_TRUE(hullmap::test::sameOutcome(want, hullmap::test::fileOutcome(pipe.path(), 2, read_bytes)))
              << "pipe read " << read_bytes << " bytes at a time";
        }
      }
    }
  }
  EXPECT_GE(inputs, 300u);
  EXPECT_GE(errors, 100u) << "the cuts should make many inputs malformed";
}

// ---------------------------------------------------------------------------------------------
// The messages docs/RELIABILITY.md quotes, exactly

}  // namespace
