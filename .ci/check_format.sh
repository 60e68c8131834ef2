#!/usr/bin/env bash
# Fails, naming each file, when a tracked C++ file differs from what clang-format (.clang-format)
# makes of it. Fix with:  git ls-files '*.cpp' '*.hpp' | xargs clang-format -i
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
command -v clang-format >/dev/null || { echo "check_format: clang-format is missing (setup.sh test installs it)" >&2; exit 2; }
bad=0
while IFS= read -r f; do
  if ! clang-format --style=file "$f" | cmp -s "$f" -; then
    echo "check_format: $f is not formatted (clang-format -i $f)" >&2
    bad=1
  fi
done < <(git ls-files '*.cpp' '*.hpp' '*.h' '*.cc')
[ $bad -eq 0 ] && echo "check_format: every C++ file is formatted"
exit $bad
