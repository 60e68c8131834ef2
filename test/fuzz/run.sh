#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan, coverage instrumentation) in the sanitized tree
# build-asan that test/scripts/sanitize.sh uses too (test/scripts/sanitized_build.sh), and runs each for SECONDS,
# starting from the seed corpus test/fuzz/corpus/<target>/.
#
#   test/fuzz/run.sh SECONDS [target...]     e.g. test/fuzz/run.sh 20;  test/fuzz/run.sh 240 pcd ply
#
# Targets: text orbslam_echo pcd ply points tum bt (<target>.dict here is passed as -dict).
# New inputs go to build-asan/fuzz/corpus/<target>/ (the repository's corpus is only read); a crash,
# hang (> 5 s), leak or out-of-memory (> 2 GB) is saved as build-asan/fuzz/artifacts/<target>-crash-*
# etc. and fails the script. The last line of each target's log (build-asan/fuzz/logs/<target>.log)
# gives executions and coverage (cov:, ft:).
# Environment: BUILD_DIR (default <repo>/build-asan), JOBS (build parallelism, and how many fuzzers
# run at once; default 2), EXTRA_CMAKE_ARGS (as test/scripts/sanitized_build.sh).
set -euo pipefail

seconds=${1:?usage: test/fuzz/run.sh SECONDS [target...]}
shift
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${BUILD_DIR:-$root/build-asan}
jobs=${JOBS:-2}
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(text orbslam_echo pcd ply points tum bt)

declare -A max_len=([text]=4096 [orbslam_echo]=8192 [pcd]=4096 [ply]=4096 [points]=8192 [tum]=2048 [bt]=2048)

BUILD_DIR=$build "$root/test/scripts/sanitized_build.sh" "${targets[@]/#/fuzz_}"

out=$build/fuzz  # corpus/, logs/, artifacts/
mkdir -p "$out/logs" "$out/artifacts"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
for t in "${targets[@]}"; do
  [ -n "${max_len[$t]:-}" ] || { echo "unknown target $t" >&2; exit 2; }
done
run_target() {  # $1: target; its exit status goes to logs/<target>.status
  local t=$1 status=0 dict=()
  mkdir -p "$out/corpus/$t"
  [ -f "$here/$t.dict" ] && dict=(-dict="$here/$t.dict")
  "$build/test/fuzz/fuzz_$t" "${dict[@]}" -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 \
    -max_len="${max_len[$t]}" -print_final_stats=1 -artifact_prefix="$out/artifacts/$t-" \
    "$out/corpus/$t" "$here/corpus/$t" >"$out/logs/$t.log" 2>&1 || status=$?
  echo "$status" >"$out/logs/$t.status"
}
# JOBS targets at a time (each fuzzer is one process on one core), then the results in order.
running=0
for t in "${targets[@]}"; do
  run_target "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait
failed=()
for t in "${targets[@]}"; do
  log=$out/logs/$t.log
  summary=$(grep -a -E '^#[0-9]+' "$log" | tail -n 1 || true)
  printf '%-13s %s\n' "$t" "${summary:-no progress line}"
  if [ "$(cat "$out/logs/$t.status")" -ne 0 ]; then
    failed+=("$t")
    grep -a -E 'ERROR|SUMMARY|invariant|Test unit written' "$log" | head -n 8 | sed 's/^/    /'
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: failures in: ${failed[*]} (logs in $out/logs, inputs in $out/artifacts)" >&2
  exit 1
fi
echo "fuzz: ${#targets[@]} targets ran ${seconds}s each without a finding"
