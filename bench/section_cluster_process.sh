#!/bin/bash
# Prints the "## Whole process: hullmap cluster" section of docs/BENCHMARKS.md (markdown) to stdout.
#
# usage: bench/section_cluster_process.sh BUILD_DIR [POINTS]
#
# What a user times: `hullmap cluster POINTS.txt -o labels.csv` from start to exit (read the text file,
# frame change, DBSCAN, the eps suggestion, write labels.csv), against Open3D's cluster_dbscan call
# alone (no file I/O) on the same points in the same run. A generated scene of POINTS points
# (default 257,000, the size issue 27 timed), eps 0.1, minPts 10; hullmap is the median of 7 runs after one not counted. Needs /usr/bin/python3
# with numpy and open3d (Debian's python3-open3d); without them the Open3D column says so.
set -eu

if [ $# -lt 1 ]; then
  echo "usage: $0 BUILD_DIR [POINTS]" >&2
  exit 2
fi
build=$1
n=${2:-257000}
hullmap="$build/cli/hullmap"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$hullmap" generate -o "$work/scene" --points "$n" --seed 5 >/dev/null
points="$work/scene/map_points.txt"
# One run to warm the page cache and the dynamic loader, not counted; then the median of 7.
"$hullmap" cluster "$points" --up -y --eps 0.1 --min-pts 10 -o "$work/labels.csv" >"$work/cluster.txt"
times=""
for run in 1 2 3 4 5 6 7; do
  # bash's time keyword: the command's own wall time (timing it with `date` before and after added
  # one exec of date, 6-8 ms on the hosts of these runs).
  seconds=$( { TIMEFORMAT=%3R; time "$hullmap" cluster "$points" --up -y --eps 0.1 --min-pts 10 -o "$work/labels.csv" >"$work/cluster.txt" 2>"$work/stderr"; } 2>&1)
  times="$times $seconds"
done
hullmap_s=$(echo $times | tr ' ' '\n' | sort -g | sed -n 4p)
clusters=$(sed -n 's/^clusters: //p' "$work/cluster.txt")

open3d_s=$(/usr/bin/python3 - "$points" <<'PY' 2>/dev/null || echo "-"
import sys, time
import numpy as np
import open3d as o3d
points = np.loadtxt(sys.argv[1])
cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
start = time.perf_counter()
cloud.cluster_dbscan(eps=0.1, min_points=10)
print(f"{time.perf_counter() - start:.2f}")
PY
)
if [ "$open3d_s" = "-" ]; then
  ratio="- (Open3D not installed)"
else
  ratio="$(echo "$open3d_s / $hullmap_s" | bc -l | xargs printf '%.0f')x"
fi

echo "## Whole process: hullmap cluster"
echo
echo "What a user times: \`hullmap cluster map_points.txt --up -y -o labels.csv\` from start to exit (read"
echo "the text file, frame change, exact DBSCAN, the eps suggestion from the k-distance curve of an evenly"
echo "spread sample of 2048 points, answered on the DBSCAN run's own grid, write one labels.csv row per"
echo "point), against Open3D's"
echo "\`cluster_dbscan\` call alone (points already in memory, no file I/O) on the same points, in the same"
echo "run; eps 0.1, minPts 10, a generated scene; hullmap the median of 7 runs after a warm-up run, each timed by bash's \`time\` (\`bench/section_cluster_process.sh\`)."
echo
echo "| points | hullmap cluster, whole process s | Open3D cluster_dbscan call s | Open3D / hullmap | clusters |"
echo "|---|---|---|---|---|"
printf '| %s | %.3f | %s | %s | %s |\n' "$n" "$hullmap_s" "$open3d_s" "$ratio" "$clusters"

# What the eps suggestion costs inside the clustering: hullmap_bench_dbscan times dbscan() alone and
# with the k-distance sample, in turns, on its own generated scene of the same size; the medians over
# the turns (of the run alone, and of with minus without), which other work on the machine moves less
# than a difference of best times.
bench="$build/bench/hullmap_bench_dbscan"
if [ -x "$bench" ]; then
  line=$("$bench" --sizes "$n" --repeat 21)
  field() { echo "$line" | sed -n "s/.*\"$1\":\([0-9.e+-]*\).*/\1/p"; }
  dbscan_ms=$(echo "$(field median_seconds) * 1000" | bc -l)
  kdist_ms=$(echo "$(field k_distance_median_seconds) * 1000" | bc -l)
  dbscan_cpu_ms=$(echo "$(field median_cpu_seconds) * 1000" | bc -l)
  kdist_cpu_ms=$(echo "$(field k_distance_median_cpu_seconds) * 1000" | bc -l)
  echo
  printf 'The eps suggestion inside it (`hullmap_bench_dbscan --sizes %s`, 21 turns with and without it, medians): on %s points\n' "$n" "$n"
  printf 'the k-distance sample adds %.1f ms to DBSCAN'"'"'s %.1f ms (%.1f%%); in CPU time of all threads %.1f ms to %.1f ms (%.1f%%).\n' \
    "$kdist_ms" "$dbscan_ms" "$(echo "100 * $kdist_ms / $dbscan_ms" | bc -l)" \
    "$kdist_cpu_ms" "$dbscan_cpu_ms" "$(echo "100 * $kdist_cpu_ms / $dbscan_cpu_ms" | bc -l)"
fi
