#!/usr/bin/env bash
# Proves the README's two Quick start commands on a pristine Debian 12 machine: for each of
# `./setup.sh demo` and `./setup.sh test`, mmdebstrap builds a minimal bookworm root (variant apt:
# apt and essential packages only, nothing this project needs) from the package index this machine's
# apt uses, copies the committed checkout in (`git archive HEAD`, what a user clones), runs the
# command in it as root and times it from nothing: package downloads, the build without any compiler
# cache, and the demo or the whole test suite. Data the tests find beside the checkout
# (../shared/data/real, ../shared/ros2) is not copied: a user does not have it, and those tests skip.
# Not run by CI: each run downloads and builds everything (demo about 10 minutes, test more).
#
#   .ci/pristine_root.sh [demo|test|both] [--keep DIR]
#
# Needs root and mmdebstrap (apt-get install mmdebstrap). Prints each command's output and its
# wall time; exits non-zero when a command fails. --keep DIR keeps the roots (DIR/demo, DIR/test)
# for a look inside instead of removing them.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

which=${1:-both}
case "$which" in demo|test|both) ;; *) echo "usage: $0 [demo|test|both] [--keep DIR]" >&2; exit 2 ;; esac
keep=""
if [ "${2:-}" = --keep ]; then
  [ -n "${3:-}" ] || { echo "$0: --keep needs a directory" >&2; exit 2; }
  keep=$3
fi
[ "$(id -u)" -eq 0 ] || { echo "$0: needs root (mmdebstrap's root mode and chroot)" >&2; exit 2; }
command -v mmdebstrap >/dev/null || { echo "$0: needs mmdebstrap (apt-get install mmdebstrap)" >&2; exit 2; }

# The package index this machine's apt uses, as it is configured (deb822 or one-line sources).
sources=()
for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.sources /etc/apt/sources.list.d/*.list; do
  [ -s "$f" ] && grep -q bookworm "$f" && sources+=("$f")
done
[ ${#sources[@]} -gt 0 ] || { echo "$0: no bookworm entry in this machine's apt sources" >&2; exit 2; }

work=$(mktemp -d /tmp/hullmap-pristine.XXXXXX)
cleanup() { [ -n "$keep" ] || rm -rf "$work"; }
trap cleanup EXIT
git archive --format=tar --prefix=hullmap/ HEAD >"$work/checkout.tar"

run_in_pristine_root() {
  local mode=$1 root
  root=${keep:+$keep/$mode}
  root=${root:-$work/root-$mode}
  rm -rf "$root"
  mkdir -p "$(dirname "$root")"
  echo "== pristine root for ./setup.sh $mode: $root"
  local start=$SECONDS
  # The command runs in a customize hook: mmdebstrap has mounted /proc, /sys and /dev for it. Its
  # time is measured inside, from the first apt-get to the last test. A root that mmdebstrap makes
  # has no /etc/hosts (an installed machine has one): without it `localhost` does not resolve and
  # chromedriver, which selenium reaches there, cannot be reached.
  mmdebstrap --variant=apt --mode=root --skip=cleanup/tmp \
    --customize-hook="tar -C \"\$1/root\" -xf $work/checkout.tar" \
    --customize-hook="cp /etc/resolv.conf \"\$1/etc/resolv.conf\"" \
    --customize-hook="cp /etc/hosts \"\$1/etc/hosts\"" \
    --customize-hook="chroot \"\$1\" /bin/bash -c 'cd /root/hullmap && s=\$(date +%s) && ./setup.sh $mode && echo \"== ./setup.sh $mode took \$((\$(date +%s) - s)) s in the pristine root\"'" \
    bookworm "$root" "${sources[@]}"
  echo "== pristine root for ./setup.sh $mode: done in $((SECONDS - start)) s (root made, command run)"
}

[ "$which" = test ] || run_in_pristine_root demo
[ "$which" = demo ] || run_in_pristine_root test
