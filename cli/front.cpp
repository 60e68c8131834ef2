// hullmap: the program users run. `hullmap cluster` and `hullmap build` (without --topic: no bag)
// run here, in a program that loads only what they need (TBB, OctoMap, GMP: about 6 ms from start to
// exit) rather than what every command needs (OMPL, FCL, ROS's bag reader and theirs: about 30 ms).
// Every other command line, and help, goes unchanged to hullmap-all (main.cpp), which has every
// subcommand: next to this program in the build tree, in HULLMAP_ALL_FROM_BIN relative to it when
// installed.
#include <cerrno>
#include <cstring>
#include <iostream>
#include <string>

#include <limits.h>
#include <unistd.h>

#include "cli_main.hpp"
#include "commands.hpp"

namespace {

// `hullmap cluster ...` or `hullmap build ...` with no argument that CLI11 would read as another
// subcommand or as a call for help or the version, and for build no --topic (a bag, read by
// hullmap-all): then this program parses it exactly as hullmap-all would.
bool runsHere(int argc, char** argv) {
  if (argc < 2 || (std::strcmp(argv[1], "cluster") != 0 && std::strcmp(argv[1], "build") != 0)) return false;
  const bool build = std::strcmp(argv[1], "build") == 0;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help" || arg == "--help-all" || arg == "--version") return false;
    if (build && (arg == "--topic" || arg.rfind("--topic=", 0) == 0 || arg == "--trajectory-topic" ||
                  arg.rfind("--trajectory-topic=", 0) == 0))
      return false;
    for (const char* name : hullmap::cli::kCommandNames) {
      if (arg == name) return false;
    }
  }
  return true;
}

// This program's directory, from /proc/self/exe.
std::string ownDirectory() {
  char path[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) return ".";
  const std::string self(path, static_cast<std::size_t>(n));
  const std::size_t slash = self.rfind('/');
  return slash == std::string::npos ? "." : self.substr(0, slash == 0 ? 1 : slash);
}

}  // namespace

int main(int argc, char** argv) {
  if (runsHere(argc, argv))
    return hullmap::cli::runCli(argc, argv, {hullmap::cli::addBuildCommand, hullmap::cli::addClusterCommand});
  const std::string dir = ownDirectory();
  const std::string candidates[] = {dir + "/hullmap-all", dir + "/" + HULLMAP_ALL_FROM_BIN};
  int error = ENOENT;
  for (const std::string& candidate : candidates) {
    ::execv(candidate.c_str(), argv);  // returns only on failure
    if (errno != ENOENT) error = errno;
  }
  std::cerr << "hullmap: error: cannot run " << candidates[1] << ": " << std::strerror(error) << "\n";
  return 2;
}
