#!/usr/bin/env bash
# Configures and builds the sanitized tree that test/scripts/sanitize.sh and test/fuzz/run.sh share
# (build-asan):
#   - clang, AddressSanitizer + UndefinedBehaviorSanitizer on every target (HULLMAP_SANITIZE=ON);
#   - -O1 with line tables only (-gline-tables-only): a report names function, file and line, as with
#     -g, without the full debug information;
#   - NDEBUG as in Release, so the code under test is the code users run;
#   - the test programs' own code at -O1 too, and without the instrumentation: the code under test
#     (libraries and the hullmap command) carries it, the tests' fixtures and oracles need not, and
#     the programs still link the sanitizer runtime. Instrumented, they took about 310 CPU-s to
#     compile against about 190, and the quick tests 430 CPU-s to run against about 300;
#   - the libFuzzer targets (HULLMAP_BUILD_FUZZ=ON): the libraries they read through (core, io, mapper)
#     also carry libFuzzer's coverage instrumentation, which the other programs ignore.
# clang rather than gcc: libFuzzer needs it, so one tree serves both scripts, and it compiles the
# sanitized code faster (one CLI file: 26 s with gcc -O1 -g, 9 s with clang -O1 -gline-tables-only;
# clustering's obstacles.cpp: 58 s against 33 s). CI builds this tree once, from nothing.
#
#   test/scripts/sanitized_build.sh [target...]      no target: everything
#
# Environment: BUILD_DIR (default <repo>/build-asan), JOBS (build parallelism, default 2),
# EXTRA_CMAKE_ARGS (more configure arguments, split on spaces).
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-asan}
jobs=${JOBS:-2}
targets=()
for t in "$@"; do targets+=(--target "$t"); done

mkdir -p "$build"
generator=()  # Ninja for a new tree, as setup.sh
[ -f "$build/CMakeCache.txt" ] || generator=(-G Ninja)
# shellcheck disable=SC2086  # EXTRA_CMAKE_ARGS is a list of arguments
CC=clang CXX=clang++ cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" -DHULLMAP_SANITIZE=ON \
  -DHULLMAP_BUILD_TESTS=ON -DHULLMAP_BUILD_CLI=ON -DHULLMAP_BUILD_FUZZ=ON \
  -DCGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE=TRUE ${EXTRA_CMAKE_ARGS:-} \
  >"$build/configure.log" 2>&1 || { cat "$build/configure.log" >&2; exit 1; }
grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++' "$build/CMakeCache.txt" ||
  { echo "$0: $build was configured with another compiler than clang++; remove it first" >&2; exit 1; }
cmake --build "$build" -j"$jobs" "${targets[@]}"
