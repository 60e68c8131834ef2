#!/usr/bin/env bash
# Fails, naming each file, when a tracked C++ file differs from what clang-format (.clang-format)
# makes of it. Fix with:  git ls-files '*.cpp' '*.hpp' | xargs clang-format -i
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
command -v clang-format >/dev/null || { echo "check_format: clang-format is missing (setup.sh test installs it)" >&2; exit 2; }
# Files in batches, two clang-formats at once.
bad=0
git ls-files -z '*.cpp' '*.hpp' '*.h' '*.cc' | xargs -0 -P 2 -n 25 bash -c '
  status=0
  for f; do
    if ! clang-format --style=file "$f" | cmp -s "$f" -; then
      echo "check_format: $f is not formatted (clang-format -i $f)" >&2
      status=1
    fi
  done
  exit $status' check_format || bad=1
[ $bad -eq 0 ] && echo "check_format: every C++ file is formatted"
exit $bad
