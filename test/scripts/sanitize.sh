#!/usr/bin/env bash
# Builds everything (libraries, CLI, tests) with AddressSanitizer + UndefinedBehaviorSanitizer in
# build-asan (test/scripts/sanitized_build.sh: clang, HULLMAP_SANITIZE=ON, -O1) and runs the ctest suite
# there. Any sanitizer report fails the test that triggered it: UBSan aborts
# (-fno-sanitize-recover), ASan's leak checker is on. The hullmap binary the CLI tests run is
# sanitized too.
#
#   test/scripts/sanitize.sh [ctest arguments...]      e.g. test/scripts/sanitize.sh -R mapper
#
# Environment: BUILD_DIR (default <repo>/build-asan), JOBS (build and ctest parallelism, default 2),
# BUILD_TARGETS (the targets to build first, split on spaces; default everything: .ci/run, which runs
# only the quick tests here, builds hullmap_quick_tests),
# EXTRA_CMAKE_ARGS (more configure arguments, split on spaces; .ci/run leaves out the ROS node and the
# Python module, whose tests are not in the quick subset it runs here).
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-asan}
jobs=${JOBS:-2}
san="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"

# shellcheck disable=SC2086  # BUILD_TARGETS is a list of targets
BUILD_DIR=$build JOBS=$jobs "$root/test/scripts/sanitized_build.sh" ${BUILD_TARGETS:-}

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:check_initialization_order=1:strict_init_order=1:detect_odr_violation=2}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/test/scripts/lsan.supp:print_suppressions=0}
# install.consumer_project builds a small project against the installed (sanitized) static
# libraries: it needs the same compiler and flags (CMake takes CC, CXX, CXXFLAGS and LDFLAGS as its
# defaults).
export CC=clang CXX=clang++ CXXFLAGS="$san" LDFLAGS="$san"
cd "$build"
ctest --output-on-failure -j"$jobs" "$@"
