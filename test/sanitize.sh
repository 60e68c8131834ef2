#!/usr/bin/env bash
# Builds everything (libraries, CLI, tests) with AddressSanitizer + UndefinedBehaviorSanitizer
# (HULLMAP_SANITIZE=ON) in build-asan and runs the whole ctest suite there. Any sanitizer report
# fails the test that triggered it: UBSan aborts (-fno-sanitize-recover), ASan's leak checker
# is on. The hullmap binary the CLI tests run is sanitized too.
#
#   test/sanitize.sh [ctest arguments...]      e.g. test/sanitize.sh -R mapper
#
# Environment: BUILD_DIR (default <repo>/build-asan), JOBS (build and ctest parallelism, default 2),
# EXTRA_CMAKE_ARGS (more configure arguments, split on spaces; .ci/run leaves out the ROS node and the
# Python module, whose tests are not in the quick subset it runs here).
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build-asan}
jobs=${JOBS:-2}
san="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"

mkdir -p "$build"
# -O1 keeps the build and the run fast enough; NDEBUG as in Release, so the code under test is
# the code users run.
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g -DNDEBUG" -DHULLMAP_SANITIZE=ON \
  -DHULLMAP_BUILD_TESTS=ON -DHULLMAP_BUILD_CLI=ON -DCGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE=TRUE ${EXTRA_CMAKE_ARGS:-} \
  >"$build/configure.log" 2>&1 || { cat "$build/configure.log" >&2; exit 1; }
cmake --build "$build" -j"$jobs"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:check_initialization_order=1:strict_init_order=1:detect_odr_violation=2}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/test/lsan.supp:print_suppressions=0}
# install.consumer_project builds a small project against the installed (sanitized) static
# libraries: it needs the same flags (CMake takes CXXFLAGS/LDFLAGS as its defaults).
export CXXFLAGS="$san" LDFLAGS="$san"
cd "$build"
ctest --output-on-failure -j"$jobs" "$@"
