#include "cli_main.hpp"

#include <algorithm>
#include <cctype>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <optional>
#include <string>

#if defined(__GLIBC__)
#include <malloc.h>
#include <unistd.h>

#include <tbb/task_scheduler_observer.h>

#include "hullmap/core/huge_pages.hpp"
#endif

#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/detail/test_hooks.hpp"
#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::cli {
namespace {

// The first option on the command line that `cmd` does not have ("--radus" in "--radus 0.3"), or
// "" when every option is known. CLI11 checks required options and positional files before it
// reports unknown ones, so a misspelt option would otherwise surface as "--radius is required" or
// "File does not exist: 0.3", naming something the user did type right. Values of known options
// ("--up -y", "--crop -1,-1,0,1,1,2") and negative numbers are not options.
std::string firstUnknownOption(const CLI::App& cmd, int first, int argc, char** argv) {
  for (int i = first; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") break;
    if (arg.size() < 2 || arg[0] != '-' || std::isdigit(static_cast<unsigned char>(arg[1])) || arg[1] == '.') {
      continue;
    }
    const bool is_long = arg[1] == '-';
    const std::string name = is_long ? arg.substr(0, arg.find('=')) : arg.substr(0, 2);
    const CLI::Option* option = cmd.get_option_no_throw(name);
    if (option == nullptr) {
      if (name == "-h" || name == "--help") continue;
      return name;
    }
    const bool value_attached = is_long ? arg.find('=') != std::string::npos : arg.size() > 2;
    if (!value_attached) i += std::max(0, option->get_items_expected_min());
  }
  return "";
}

// The message of a library error with the parameters it names spelt as this CLI's flags
// ("min_pts: must be >= 1" -> "--min-pts: must be >= 1").
std::string cliMessage(const hullmap::Error& e) {
  if (e.parameter().empty()) return e.what();
  std::string flags;
  std::size_t start = 0;
  while (start <= e.parameter().size()) {
    std::size_t end = e.parameter().find('/', start);
    if (end == std::string::npos) end = e.parameter().size();
    const std::string name = e.parameter().substr(start, end - start);
    flags += (flags.empty() ? "" : "/") + (name == "inputs" ? name : optionName(name));
    start = end + 1;
  }
  return flags + ": " + e.detail();
}

}  // namespace

std::string optionName(std::string_view field) {
  if (field == "keyframes") return "--trajectory";
  if (field == "start") return "--from";  // planning's request: `plan --from/--to`
  if (field == "goal") return "--to";
  std::string name(field);
  std::replace(name.begin(), name.end(), '_', '-');
  return "--" + name;
}

std::string optionSpelling(std::string_view field, std::string_view value) {
  std::string out = optionName(field);
  if (!value.empty()) out.append(" ").append(value);
  return out;
}

namespace {

// A run allocates and frees large arrays again and again (point batches, each cluster's distance
// transforms, the outputs' text). glibc gives blocks above its mmap threshold (128 KiB, rising as
// such blocks are freed) back to the kernel on free, so each new one faults its pages in afresh: on
// `hullmap build octomap_scan.dat --resolution 0.1` 12,100 page faults, a fifth of the process on a
// virtual machine. Kept in the heap for reuse instead: 5,700, and 0.39 -> 0.32 s (BENCHMARKS.md).
// A command is one run: what it frees is soon asked for again, and all of it goes at exit.
//
// The heap then grows in one step of 64 MiB, which asks for transparent huge pages
// (core::adviseHugePages; what glibc's glibc.malloc.hugetlb=1 tunable does, which only the
// environment can set): its fresh memory faults in 2 MiB at a time. On the same build the main
// thread's page faults 3,000-3,200 -> 850-1,050, the whole process 4,500 -> 2,000, and 0.257 -> 0.232 s; on
// `hullmap cluster` of 257,000 points 2,200-2,900 -> 1,200 and 0.107 -> 0.086 s. Untouched pages of
// the step cost nothing; a heap that outgrows it goes on in ordinary pages.
/// The main heap's bounds after keepFreedMemoryForReuse's step (empty when it made none).
std::uintptr_t heap_begin = 0, heap_end = 0;

void keepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest: bigger blocks are still mapped and unmapped
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_TOP_PAD, 64 << 20);
  char* const before = static_cast<char*>(sbrk(0));
  void* volatile block = malloc(1 << 20);  // volatile: the compiler may not drop the pair
  free(block);
  char* const after = static_cast<char*>(sbrk(0));
  if (before != reinterpret_cast<char*>(-1) && after > before) {  // sanitizers' allocators leave brk alone
    hullmap::core::adviseHugePages(before, std::size_t(after - before));
    heap_begin = reinterpret_cast<std::uintptr_t>(before);
    heap_end = reinterpret_cast<std::uintptr_t>(after);
  }
#endif
}

/// The same for each TBB worker's heap: glibc gives a thread that allocates its own arena, whose
/// heap is one mapping aligned to its largest size (64 MiB on 64-bit Linux), made writable whole
/// under the top pad above. The worker's first block lies in it; a worker that shares the main
/// heap has nothing to advise.
class AdviseWorkerHeaps : public tbb::task_scheduler_observer {
 public:
  AdviseWorkerHeaps() { observe(true); }
  ~AdviseWorkerHeaps() override { observe(false); }
  AdviseWorkerHeaps(const AdviseWorkerHeaps&) = delete;
  AdviseWorkerHeaps& operator=(const AdviseWorkerHeaps&) = delete;

  void on_scheduler_entry(bool is_worker) override {
#if defined(__GLIBC__) && defined(__LP64__)
    thread_local bool advised = false;
    if (!is_worker || advised || heap_end == 0) return;
    advised = true;
    void* volatile block = malloc(64);
    const auto p = reinterpret_cast<std::uintptr_t>(static_cast<void*>(block));
    free(block);
    constexpr std::uintptr_t kHeapBytes = std::uintptr_t{64} << 20;
    if (p == 0 || (p >= heap_begin && p < heap_end)) return;
    hullmap::core::adviseHugePages(reinterpret_cast<void*>(p & ~(kHeapBytes - 1)), kHeapBytes);
#else
    (void)is_worker;
#endif
  }
};

// Test-only (test/e2e/heavy/build.cpp): HULLMAP_TEST_KILL_AT=<stage> makes the run SIGKILL itself
// when the pipeline reaches that stage, so that "a run killed there" is a fact, not a race with a timer.
const char* kill_at = nullptr;

void killAtStage(const char* stage) {
  if (std::strcmp(stage, kill_at) == 0) std::raise(SIGKILL);
}

}  // namespace

int runCli(int argc, char** argv, const std::vector<AddCommand>& commands) {
  keepFreedMemoryForReuse();
  // Only where the main heap was advised: under a sanitizer's allocator there is nothing to advise,
  // and an observer still registered when an error path exits would be reported as a leak.
  std::optional<AdviseWorkerHeaps> advise_worker_heaps;
  if (heap_end != 0) advise_worker_heaps.emplace();
  kill_at = std::getenv("HULLMAP_TEST_KILL_AT");
  if (kill_at != nullptr) pipeline::detail::stage_hook = killAtStage;
  CLI::App app{"hullmap: SLAM map points -> OctoMap -> DBSCAN clusters -> convex obstacles -> path checks"};
  app.set_version_flag("--version", HULLMAP_VERSION);
  app.require_subcommand(1);
  int status = 0;
  for (const AddCommand add : commands) add(app, status);
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands({})) {
      names += (names.empty() ? "" : ", ") + sub->get_name();
      known = known || sub->get_name() == argv[1];
    }
    if (!known) {
      std::cerr << "hullmap: error: unknown subcommand '" << argv[1] << "' (expected one of " << names << ")\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const CLI::App* cmd = &app;
    int first = 1;
    if (argc > 1 && argv[1][0] != '-') {
      cmd = app.get_subcommand(argv[1]);
      first = 2;
    }
    const std::string unknown = firstUnknownOption(*cmd, first, argc, argv);
    if (!unknown.empty()) {
      const std::string where = cmd == &app ? "hullmap" : "hullmap " + cmd->get_name();
      std::cerr << "hullmap: error: unknown option " << unknown << " (see " << where << " --help)\n";
      return 2;
    }
    // A bad value names its option and what is wrong with it; --help would not say more.
    const bool bad_value = dynamic_cast<const CLI::ValidationError*>(&e) != nullptr;
    std::cerr << "hullmap: error: " << e.what() << (bad_value ? "\n" : " (see hullmap --help)\n");
    return 2;
  } catch (const hullmap::Error& e) {
    std::cerr << "hullmap: error: " << cliMessage(e) << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "hullmap: error: out of memory\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "hullmap: error: " << e.what() << "\n";
    return 2;
  }
  return status;
}

}  // namespace hullmap::cli
