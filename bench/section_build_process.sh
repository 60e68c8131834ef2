#!/bin/bash
# Prints the "## Whole process: hullmap build on a scan" section of docs/BENCHMARKS.md (markdown).
#
# usage: bench/section_build_process.sh BUILD_DIR [runs]
#
# What a user times: `hullmap build octomap_scan.dat --resolution 0.1 -o OUT` from start to exit (read,
# floor search, octree, clustering, convex parts, writing map.bt, voxels.csv, obstacles.json/.obj and
# report.json), at the defaults, against octomap's insertPointCloud of the same scan alone (points in
# memory, one call into an empty tree: hullmap_bench_octomap_cloud), in the same run; both without and
# with the sensor origin (`--origin 0,0,0`: free space cast along every ray, the work octomap's call
# does). hullmap: the median of RUNS (default 7) after one not counted; octomap: the median of 5.
# BUILD_DIR is configured with -DHULLMAP_BUILD_BENCH=ON and has hullmap and hullmap_bench_octomap_cloud.
set -eu

if [ $# -lt 1 ]; then
  echo "usage: $0 BUILD_DIR [runs]" >&2
  exit 2
fi
build=$1
runs=${2:-7}
here=$(cd "$(dirname "$0")" && pwd)
hullmap="$build/cli/hullmap"
octomap="$build/bench/hullmap_bench_octomap_cloud"
scan="${HULLMAP_REAL_DATA_DIR:-$here/../../shared/data/real}/octomap_scan.dat"
for f in "$hullmap" "$octomap"; do
  if [ ! -x "$f" ]; then
    echo "$0: $f not found (configure with -DHULLMAP_BUILD_BENCH=ON, build hullmap and hullmap_bench_octomap_cloud)" >&2
    exit 2
  fi
done
if [ ! -f "$scan" ]; then
  echo "$0: $scan not found (set HULLMAP_REAL_DATA_DIR)" >&2
  exit 2
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

octomap_ms=$("$octomap" "$scan" 0.1 0 0 0 5 | sed -n 's/.*"octomap_insert_ms": \([0-9.]*\).*/\1/p')
load_start=$(cut -d' ' -f1-3 /proc/loadavg)

# Median wall time of RUNS runs of `hullmap build` with the given extra options; the report.json of
# the median run is kept as $work/$2.json.
time_build() {
  extra=$1
  tag=$2
  "$hullmap" build "$scan" --resolution 0.1 $extra -o "$work/out" >/dev/null
  : >"$work/$tag.times"
  run=1
  while [ "$run" -le "$runs" ]; do
    # bash's time keyword: the command's own wall time (timing it with `date` before and after
    # added one exec of date, 6-8 ms on the hosts of these runs).
    seconds=$( { TIMEFORMAT=%3R; time "$hullmap" build "$scan" --resolution 0.1 $extra -o "$work/out" >/dev/null 2>"$work/stderr"; } 2>&1)
    echo "$seconds $run" >>"$work/$tag.times"
    cp "$work/out/report.json" "$work/$tag-$run.json"
    run=$((run + 1))
  done
  median=$(sort -g "$work/$tag.times" | sed -n "$(((runs + 1) / 2))p")
  cp "$work/$tag-$(echo "$median" | cut -d' ' -f2).json" "$work/$tag.json"
  echo "$median" | cut -d' ' -f1
}
points_s=$(time_build "" points)
rays_s=$(time_build "--origin 0,0,0" rays)
load_end=$(cut -d' ' -f1-3 /proc/loadavg)

echo "## Whole process: hullmap build on a scan"
echo
echo "What a user times: \`hullmap build octomap_scan.dat --resolution 0.1 -o OUT\` (OctoMap's FR-079 scan,"
echo "88,206 points, metric, z up) from start to exit at the defaults (read, floor search, octree, the"
echo "floor's voxels set aside, eps and minPts from the map, DBSCAN, the extension pass, obstacles, convex"
echo "parts, writing map.bt, voxels.csv, obstacles.json, obstacles.obj, report.json), against octomap's"
echo "\`insertPointCloud\` of the same points from the origin alone (in memory, one call into an empty tree,"
echo "\`hullmap_bench_octomap_cloud\`, median of 5), in the same run. *Points*: the defaults (the points are"
echo "occupied endpoints, no rays: the file is streamed); *rays*: with \`--origin 0,0,0\`, free space cast"
echo "along every ray as octomap's call does. hullmap: median of $runs runs after one not counted, each timed by"
echo "bash's \`time\` (\`bench/section_build_process.sh\`)."
echo
echo "| build | hullmap build, whole process s | octomap insertPointCloud s | octomap / hullmap |"
echo "|---|---|---|---|"
for tag in points rays; do
  if [ "$tag" = points ]; then s=$points_s; else s=$rays_s; fi
  printf '| %s | %.3f | %.3f | %.2fx |\n' "$tag" "$s" "$(echo "$octomap_ms / 1000" | bc -l)" "$(echo "$octomap_ms / 1000 / $s" | bc -l)"
done
echo
echo "Stages of the median runs (report.json \`timings_ms\`, wall ms; *rest* is the whole process less"
echo "their total: start-up, writing the outputs, exit):"
echo
/usr/bin/python3 - "$work/points.json" "$work/rays.json" "$points_s" "$rays_s" <<'PY'
import json, sys
docs = [json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))]
walls = [float(sys.argv[3]) * 1000, float(sys.argv[4]) * 1000]
stages = [k for k in docs[0]["timings_ms"] if k != "total"]
print("| build | " + " | ".join(stages) + " | rest |")
print("|---|" + "---|" * (len(stages) + 1))
for name, doc, wall in zip(("points", "rays"), docs, walls):
    t = doc["timings_ms"]
    print(f"| {name} | " + " | ".join(f"{t.get(k, 0):.0f}" for k in stages) + f" | {wall - t['total']:.0f} |")
PY
echo
echo "Load average $load_start at the start, $load_end at the end ($(nproc) cores)."
