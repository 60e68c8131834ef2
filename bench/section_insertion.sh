#!/bin/sh
# Prints the "## Octree insertion" section of docs/BENCHMARKS.md (markdown) to stdout.
#
# usage: bench/section_insertion.sh BUILD_DIR [repeats]
#
# BUILD_DIR is a build configured with -DHULLMAP_BUILD_BENCH=ON and built (target
# hullmap_bench_insertion). Times octomap's insertPointCloud and hullmap's insertScan on the same
# scan in one run (OctoMap's FR-079 scan octomap_scan.dat from shared/data/real, a generated
# 65,536-point in-room scan and a generated 65,536-beam lidar scan of a large yard), at 0.05, 0.1
# and 0.2 m, and checks the two trees are identical.
set -eu

if [ $# -lt 1 ]; then
  echo "usage: $0 BUILD_DIR [repeats]" >&2
  exit 2
fi
build=$1
repeats=${2:-5}
here=$(cd "$(dirname "$0")" && pwd)
bench="$build/bench/hullmap_bench_insertion"
scan="${HULLMAP_REAL_DATA_DIR:-$here/../../shared/data/real}/octomap_scan.dat"
if [ ! -x "$bench" ]; then
  echo "$0: $bench not found (configure with -DHULLMAP_BUILD_BENCH=ON, build hullmap_bench_insertion)" >&2
  exit 2
fi
if [ ! -f "$scan" ]; then
  echo "$0: $scan not found (set HULLMAP_REAL_DATA_DIR)" >&2
  exit 2
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bench" "$scan" "$repeats" >"$work/results.jsonl" 2>/dev/null

echo "## Octree insertion"
echo
echo "One scan inserted into an empty OcTree: octomap's \`insertPointCloud(points, origin)\` against"
echo "hullmap's \`insertScan\` (same tree, checked leaf for leaf in the run), median of $repeats runs on"
echo "$(nproc) cores. *Ray keys only*: octomap's \`computeRayKeys\` for every point and nothing else"
echo "(one thread), the arithmetic both must do; *hullmap / ray keys* is hullmap's whole insertion against"
echo "it. *Cast* and *apply* are hullmap's two phases: rays walked in parallel (four at a time per thread,"
echo "in SSE2 lanes) into per-thread bit bricks, sorted in octree order; one ordered pass updating the tree,"
echo "brick by brick."
echo
echo "Scans: \`octomap_scan.dat\`, OctoMap's FR-079 corridor scan (sensor at the origin);"
echo "\`generated_65536\`, the map points of hullmap's generated room scene (10 m room, 8 obstacles) seen"
echo "from its first keyframe: short rays that overlap near the camera; \`lidar_65536\`, a generated"
echo "64-beam x 1024-step spinning lidar 1.8 m above a 120 m x 90 m walled yard with buildings, cars and"
echo "poles: long rays spread over a large volume, few rays through each voxel."
echo "Regenerate with \`bench/section_insertion.sh BUILD_DIR\`."
echo
echo "| scan | points | resolution (m) | octomap ms | hullmap ms | speed-up | ray-keys-only ms | hullmap / ray keys | cast ms | apply ms | voxels updated | identical |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
/usr/bin/python3 - "$work/results.jsonl" <<'PY'
import json, sys
for line in open(sys.argv[1]):
    r = json.loads(line)
    print(f"| {r['scan']} | {r['points']} | {r['resolution']:.2f} | {r['octomap_ms']:.1f} | {r['hullmap_ms']:.1f} | "
          f"{r['octomap_ms'] / r['hullmap_ms']:.1f}x | {r['ray_keys_ms']:.1f} | {r['hullmap_ms'] / r['ray_keys_ms']:.2f} | "
          f"{r['cast_ms']:.1f} | {r['apply_ms']:.1f} | "
          f"{r['voxels_updated']} | {'yes' if r['identical'] else 'NO'} |")
PY
