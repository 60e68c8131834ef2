#!/usr/bin/env bash
# Fails, naming each file, when a tracked C++ file differs from what clang-format (.clang-format)
# makes of it. Fix with:  git ls-files '*.cpp' '*.hpp' | xargs clang-format -i
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
command -v clang-format >/dev/null || { echo "check_format: clang-format is missing (setup.sh test installs it)" >&2; exit 2; }
# One clang-format process per 40 files (--dry-run -Werror reports each misformatted place as
# FILE:LINE:COL: error: ...), two at a time; a file with any such place is named once.
out=$(git ls-files -z '*.cpp' '*.hpp' '*.h' '*.cc' |
      xargs -0 -P 2 -n 40 clang-format --style=file --dry-run -Werror 2>&1) && status=0 || status=$?
files=$(printf '%s\n' "$out" | sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: error: .*clang-format-violations.*/\1/p' | sort -u)
if [ -n "$files" ]; then
  while read -r f; do echo "check_format: $f is not formatted (clang-format -i $f)" >&2; done <<<"$files"
  exit 1
fi
if [ "$status" -ne 0 ]; then
  printf '%s\n' "$out" | head -n 5 >&2
  echo "check_format: clang-format failed" >&2
  exit 2
fi
echo "check_format: every C++ file is formatted"
