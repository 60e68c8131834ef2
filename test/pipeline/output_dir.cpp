// pipeline::outputDirRefusal: which directories a run may replace whole, reason by reason; and
// pipeline::checkOutputFile: an output file is checked before the work, with the reason.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "hullmap/pipeline/output_dir.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using hullmap::test::freshDir;
using hullmap::test::writeText;

// The library's answer, reason by reason (the CLI prints the message after "-o ").
TEST(OutputDir, RefusalReasons) {
  using hullmap::pipeline::OutputDirPolicy;
  using hullmap::pipeline::outputDirRefusal;
  using Reason = hullmap::pipeline::OutputDirRefusal::Reason;
  const auto dir = freshDir("reasons");
  const auto reason = [](const fs::path& p, const OutputDirPolicy& policy = {}) {
    const auto r = outputDirRefusal(p.string(), policy);
    return r ? static_cast<int>(r->reason) : -1;
  };
  EXPECT_EQ(reason(dir / "absent"), -1);
  EXPECT_EQ(reason(dir / "absent" / "deeper"), static_cast<int>(Reason::kMissingParent));
  OutputDirPolicy parents;
  parents.make_parents = true;
  EXPECT_EQ(reason(dir / "absent" / "deeper", parents), -1);
  writeText(dir / "file", "x\n");
  EXPECT_EQ(reason(dir / "file"), static_cast<int>(Reason::kNotADirectory));
  EXPECT_EQ(reason(dir / "file" / "below", parents), static_cast<int>(Reason::kNotADirectory));
  fs::create_directories(dir / "empty");
  EXPECT_EQ(reason(dir / "empty"), -1);
  OutputDirPolicy reads;
  reads.inputs = {(dir / "empty" / "in.txt").string(), "-"};
  writeText(dir / "empty" / "in.txt", "1 2 3\n");
  EXPECT_EQ(reason(dir / "empty", reads), static_cast<int>(Reason::kHoldsInput));
  EXPECT_EQ(reason(dir / "empty"), static_cast<int>(Reason::kForeign));
  hullmap::pipeline::writeOutputMarker((dir / "empty").string(), {"in.txt"});
  EXPECT_EQ(reason(dir / "empty"), -1) << "every entry listed by the marker";
  writeText(dir / "empty" / "other.txt", "y\n");
  EXPECT_EQ(reason(dir / "empty"), static_cast<int>(Reason::kForeignFiles));
  EXPECT_EQ(reason(""), static_cast<int>(Reason::kEmptyName));
  EXPECT_EQ(reason(fs::current_path()), static_cast<int>(Reason::kCurrentDirectory));
  EXPECT_EQ(hullmap::test::errorOf([&] { hullmap::pipeline::checkOutputDir((dir / "file").string()); }),
            (dir / "file").string() + ": exists and is not a directory");
}

TEST(OutputFile, CheckedBeforeTheWorkWithTheReason) {
  const auto dir = hullmap::test::freshDir("output_file");
  EXPECT_NO_THROW(hullmap::pipeline::checkOutputFile((dir / "a.csv").string()));
  EXPECT_NO_THROW(hullmap::pipeline::checkOutputFile("-"));
  EXPECT_EQ(hullmap::test::errorOf([&] { hullmap::pipeline::checkOutputFile((dir / "no" / "a.csv").string()); }),
            (dir / "no" / "a.csv").string() + ": cannot write there: " + (dir / "no").string() +
                ": No such file or directory");
  EXPECT_EQ(hullmap::test::errorOf([&] { hullmap::pipeline::checkOutputFile(dir.string()); }),
            dir.string() + ": is a directory");
}
