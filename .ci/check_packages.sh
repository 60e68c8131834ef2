#!/usr/bin/env bash
# Does setup.sh install everything a mode's build links and includes? Configures the build as
# `./setup.sh MODE` does (its own cmake arguments) in a scratch directory, lists every file and
# directory under /usr that the link lines (link.txt) and include lines (flags.make) name, finds the
# package that owns each (dpkg -S; a symlink not owned itself is followed), and fails, naming the
# file and the package, unless that package is in setup.sh's list for the mode or among their
# dependencies (apt-cache depends --recurse). A machine that already has every package (any
# developer's) builds either way; a fresh one fails where this check fails.
#
#   .ci/check_packages.sh demo|test [--without PACKAGE]...
#
# --without drops a package from the mode's list first (the check's own test: without
# libboost-filesystem-dev the demo list must fail). Exit 0: all covered; 1: something is not; 2: usage.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

mode=${1:-}
case "$mode" in demo|test) shift ;; *) echo "usage: $0 demo|test [--without PACKAGE]..." >&2; exit 2 ;; esac
without=()
while [ $# -gt 0 ]; do
  case "$1" in
    --without) [ $# -ge 2 ] || { echo "$0: --without needs a package" >&2; exit 2; }; without+=("$2"); shift 2 ;;
    *) echo "$0: unknown option $1" >&2; exit 2 ;;
  esac
done

mapfile -t packages < <(./setup.sh packages "$mode")
for w in "${without[@]+"${without[@]}"}"; do
  kept=()
  for p in "${packages[@]}"; do [ "$p" = "$w" ] || kept+=("$p"); done
  packages=("${kept[@]}")
done
read -r -a cmake_args <<<"$(./setup.sh cmake-args "$mode")"

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
if ! cmake -S . -B "$scratch" "${cmake_args[@]}" -DHULLMAP_CCACHE=OFF >"$scratch.log" 2>&1; then
  cat "$scratch.log" >&2
  echo "check_packages: cmake could not configure the $mode build" >&2
  exit 1
fi
rm -f "$scratch.log"

# Every path under /usr on the link lines (libraries, the compiler, -l names resolved the way the
# linker would) and the include directories.
named=$(
  find "$scratch" -name link.txt -exec cat {} + | tr ' ' '\n' | while read -r token; do
    case "$token" in
      /usr/*) echo "$token" ;;
      -l*)
        name=${token#-l}
        for dir in /usr/lib/x86_64-linux-gnu /usr/lib; do
          for f in "$dir/lib$name.so" "$dir/lib$name.a"; do
            if [ -e "$f" ]; then echo "$f"; break 2; fi
          done
        done ;;
    esac
  done
  find "$scratch" -name flags.make -exec grep -h '^CXX_INCLUDES' {} + | tr ' ' '\n' |
    sed -n 's|^-I\(/usr/.*\)|\1|p; s|^\(/usr/.*\)|\1|p'
)
named=$(echo "$named" | grep -v '^$' | sort -u)

# The closure as a set: a lookup with `echo "$closure" | grep -q` raced (grep -q leaves at its first
# match, the echo still writing then dies of SIGPIPE, and pipefail turned a found package into a miss).
declare -A in_closure=()
while read -r p; do
  [ -n "$p" ] && in_closure[$p]=1
done < <(apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts --no-breaks --no-replaces \
           --no-enhances "${packages[@]}" 2>/dev/null | grep -v '^ ' | sed 's/:.*//' | sort -u)

# The packages that own each path (dpkg -S, once for all paths: one call reads dpkg's file lists
# once), following a symlink nobody owns.
declare -A owner_of=()
record_owners() {  # dpkg -S's lines "pkg1, pkg2: /path" for the paths given
  local line
  while IFS= read -r line; do
    case "$line" in diversion*) continue ;; *": /"*) ;; *) continue ;; esac
    local path="/${line#*: /}"
    [ -n "${owner_of[$path]:-}" ] || owner_of[$path]=${line%%: /*}
  done < <(dpkg -S "$@" 2>/dev/null)
}
mapfile -t paths < <(echo "$named" | grep -v '^$')
[ ${#paths[@]} -eq 0 ] || record_owners "${paths[@]}"
unowned_links=()
for path in "${paths[@]}"; do
  [ -z "${owner_of[$path]:-}" ] && [ -L "$path" ] && unowned_links+=("$(readlink -f "$path")")
done
[ ${#unowned_links[@]} -eq 0 ] || record_owners "${unowned_links[@]}"
owners() {
  local path=$1 out
  out=${owner_of[$path]:-}
  if [ -z "$out" ] && [ -L "$path" ]; then out=${owner_of[$(readlink -f "$path")]:-}; fi
  echo "$out" | tr ',' '\n' | sed 's/^ *//; s/:.*//' | grep -v '^$' || true
}

failures=0
checked=0
while read -r path; do
  [ -n "$path" ] || continue
  checked=$((checked + 1))
  mapfile -t own < <(owners "$path")
  if [ ${#own[@]} -eq 0 ]; then
    echo "check_packages: $mode build names $path, which no Debian package installed here owns"
    failures=$((failures + 1))
    continue
  fi
  covered=no
  for o in "${own[@]}"; do
    if [ -n "${in_closure[$o]:-}" ]; then covered=yes; break; fi
  done
  if [ $covered = no ]; then
    echo "check_packages: $mode build names $path (package ${own[*]}), which setup.sh's $mode list does not install"
    failures=$((failures + 1))
  fi
done <<<"$named"

if [ $failures -gt 0 ]; then
  echo "check_packages: $failures of $checked paths not covered by setup.sh's $mode packages: a fresh machine fails there"
  exit 1
fi
echo "check_packages: $mode: all $checked paths the build links and includes come from setup.sh's $mode packages or their dependencies"
