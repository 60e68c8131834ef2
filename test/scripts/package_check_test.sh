#!/usr/bin/env bash
# The package check of .ci/run (.ci/check_packages.sh) passes on setup.sh's lists and fails, naming
# the library and its package, when the demo list leaves out libboost-filesystem-dev (OMPL's CMake
# config links libboost_filesystem.so, and libompl-dev does not depend on it). Exit 77 (skipped)
# where dpkg or apt-cache is missing.
set -uo pipefail
source_dir=$1
command -v dpkg >/dev/null && command -v apt-cache >/dev/null || { echo "skipped: no dpkg/apt-cache here"; exit 77; }
check="$source_dir/.ci/check_packages.sh"
"$check" demo || { echo "FAIL: the demo list does not cover the demo build"; exit 1; }
out=$("$check" demo --without libboost-filesystem-dev)
status=$?
echo "$out"
[ $status -eq 1 ] || { echo "FAIL: expected exit 1 without libboost-filesystem-dev, got $status"; exit 1; }
grep -q 'libboost_filesystem.so (package libboost-filesystem1.74-dev)' <<<"$out" ||
  { echo "FAIL: the failure does not name libboost_filesystem.so and its package"; exit 1; }
"$check" demo --bogus >/dev/null 2>&1
[ $? -eq 2 ] || { echo "FAIL: an unknown option is not a usage error"; exit 1; }
echo "package check: passes on the lists, fails without libboost-filesystem-dev"
