// `hullmap build -o DIR` replaces DIR whole. It may replace only what hullmap wrote: an absent or
// empty directory, or a previous output (its .hullmap-output marker, nothing else in it). Everything
// else is refused with exit 2 and one line naming the directory, and every file stays byte-identical.
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "run_hullmap.hpp"

namespace fs = std::filesystem;
using hullmap::test::CommandResult;
using hullmap::test::freshDir;
using hullmap::test::lineCount;
using hullmap::test::runHullmap;
using hullmap::test::runHullmapIn;
using hullmap::test::slurp;
using hullmap::test::writeText;

namespace {

/// Every file and directory below `root` (relative name -> contents, "<dir>" for directories).
std::map<std::string, std::string> snapshot(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string name = fs::relative(entry.path(), root).string();
    files[name] = entry.is_directory() ? "<dir>" : slurp(entry.path());
  }
  return files;
}

void expectRefused(const CommandResult& r, const std::string& needle) {
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("hullmap: error: -o ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << "expected '" << needle << "' in: " << r.err;
}

const std::string kPoints = "0 0 0\n0.01 0 0\n0.02 0 0\n";

}  // namespace

// The case: the input's own directory as -o. Before, it exited 0 and the input and
// important.txt were gone.
TEST(CliOutputDir, InputDirectoryIsRefusedAndKeptByteIdentical) {
  const auto dir = freshDir("mydata_case");
  const auto mydata = dir / "mydata";
  fs::create_directories(mydata);
  writeText(mydata / "map_points.txt", kPoints);
  writeText(mydata / "important.txt", "do not lose me\n");
  const auto before = snapshot(dir);
  const std::string in = (mydata / "map_points.txt").string();
  expectRefused(runHullmap("build " + in + " --up -y --min-pts 1 -o " + mydata.string()),
                "-o " + mydata.string() + ": holds the input " + in);
  // Through a symbolic link to it, and with a trailing slash: the same directory.
  fs::create_directory_symlink(mydata, dir / "link");
  expectRefused(runHullmap("build " + in + " --min-pts 1 -o " + (dir / "link").string()), "holds the input");
  expectRefused(runHullmap("build " + in + " --min-pts 1 -o " + mydata.string() + "/"), "holds the input");
  // A trajectory inside counts as an input too.
  writeText(dir / "p.txt", kPoints);
  writeText(mydata / "traj.txt", "0 0 0 0 0 0 0 1\n");
  const auto with_traj = snapshot(dir);
  expectRefused(runHullmap("build " + (dir / "p.txt").string() + " --trajectory " + (mydata / "traj.txt").string() +
                           " --min-pts 1 -o " + mydata.string()),
                "holds the input " + (mydata / "traj.txt").string());
  EXPECT_EQ(snapshot(dir), with_traj);
  fs::remove(dir / "p.txt");
  fs::remove(mydata / "traj.txt");
  fs::remove(dir / "link");
  EXPECT_EQ(snapshot(dir), before);
}

TEST(CliOutputDir, ForeignDirectoryIsRefusedAndKeptByteIdentical) {
  const auto dir = freshDir("foreign");
  writeText(dir / "p.txt", kPoints);
  const auto target = dir / "results";
  fs::create_directories(target / "sub");
  writeText(target / "important.txt", "keep\n");
  writeText(target / "sub" / "deep.txt", "keep too\n");
  const auto before = snapshot(dir);
  expectRefused(runHullmap("build " + (dir / "p.txt").string() + " --min-pts 1 -o " + target.string()),
                "-o " + target.string() +
                    ": not empty and not a hullmap output (holds important.txt, sub; no "
                    ".hullmap-output marker); refusing to replace it: give a new or empty directory");
  EXPECT_EQ(snapshot(dir), before);
  // A forged marker of another format is no marker.
  writeText(target / ".hullmap-output", "something else\nimportant.txt\nsub\n");
  const auto forged = snapshot(dir);
  expectRefused(runHullmap("build " + (dir / "p.txt").string() + " --min-pts 1 -o " + target.string()),
                "not empty and not a hullmap output");
  EXPECT_EQ(snapshot(dir), forged);
}

TEST(CliOutputDir, PreviousOutputIsReplacedUnlessItHoldsForeignFiles) {
  const auto dir = freshDir("previous");
  writeText(dir / "p.txt", kPoints);
  const auto out = dir / "out";
  const std::string build = "build " + (dir / "p.txt").string() + " --min-pts 1 -o " + out.string();
  // An empty directory is taken.
  fs::create_directories(out);
  ASSERT_EQ(runHullmap(build).status, 0);
  EXPECT_EQ(slurp(out / ".hullmap-output"),
            "hullmap-output/1\nmap.bt\nvoxels.csv\nobstacles.json\nobstacles.obj\nreport.json\n");
  // A previous output is replaced, with --ot and without (map.ot comes and goes).
  ASSERT_EQ(runHullmap(build + " --ot").status, 0);
  EXPECT_TRUE(fs::exists(out / "map.ot"));
  const auto r = runHullmap(build);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(out / "map.ot"));
  // A file the user put there (a picture of the map, notes) makes it the user's again.
  writeText(out / "top.svg", "<svg/>\n");
  const auto before = snapshot(dir);
  expectRefused(runHullmap(build), "-o " + out.string() +
                                       ": a hullmap output that also holds files hullmap did not write (top.svg); "
                                       "refusing to replace it: move them out first");
  EXPECT_EQ(snapshot(dir), before);
  // So does a directory, even under a name hullmap writes.
  fs::remove(out / "top.svg");
  fs::remove(out / "map.bt");
  fs::create_directories(out / "map.bt");
  writeText(out / "map.bt" / "x", "keep\n");
  const auto with_dir = snapshot(dir);
  expectRefused(runHullmap(build), "holds files hullmap did not write (map.bt)");
  EXPECT_EQ(snapshot(dir), with_dir);
}

TEST(CliOutputDir, CurrentDirectoryAndItsAncestorsAreRefused) {
  const auto dir = freshDir("cwd");
  writeText(dir / "p.txt", kPoints);
  fs::create_directories(dir / "sub");
  const auto before = snapshot(dir);
  expectRefused(runHullmapIn(dir, "build p.txt --min-pts 1 -o ."),
                "-o .: is the current directory; a run replaces its output directory whole, so give a new "
                "directory for it (e.g. out)");
  expectRefused(runHullmapIn(dir / "sub", "build ../p.txt --min-pts 1 -o .."), "-o ..: contains the current directory");
  expectRefused(runHullmapIn(dir / "sub", "build ../p.txt --min-pts 1 -o /"), "-o /: contains the current directory");
  EXPECT_EQ(snapshot(dir), before);
  // The current directory stays refused when it is empty: the run would swap it away under the shell.
  const auto empty = freshDir("cwd_empty");
  expectRefused(runHullmapIn(empty, "build " + (dir / "p.txt").string() + " --min-pts 1 -o ./"),
                "is the current directory");
  const auto ok = runHullmapIn(dir, "build p.txt --min-pts 1 -o out");
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_TRUE(fs::exists(dir / "out" / "map.bt"));
}

// Like mkdir: a missing parent is refused unless -p (--parents) asks for it.
TEST(CliOutputDir, MissingParentNeedsDashP) {
  const auto dir = freshDir("parents");
  writeText(dir / "p.txt", kPoints);
  const auto out = dir / "new" / "a" / "out";
  const std::string build = "build " + (dir / "p.txt").string() + " --min-pts 1 -o " + out.string();
  expectRefused(runHullmap(build), "-o " + out.string() + ": its parent directory " + (dir / "new" / "a").string() +
                                       " does not exist (give -p to create missing parents)");
  EXPECT_FALSE(fs::exists(dir / "new"));
  const auto r = runHullmap(build + " -p");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "map.bt"));
  ASSERT_EQ(runHullmap(build + " --parents").status, 0) << "a previous output, parents present";
}
