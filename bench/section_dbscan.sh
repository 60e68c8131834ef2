#!/bin/sh
# Prints the "## DBSCAN" section of docs/BENCHMARKS.md (markdown) to stdout.
#
# usage: bench/section_dbscan.sh BUILD_DIR [--full]
#
# BUILD_DIR is a build configured with -DHULLMAP_BUILD_BENCH=ON and built (target hullmap_bench_dbscan).
# hullmap runs on generated scenes of 10k, 100k, 1M and 10M points (eps 0.1, minPts 10). Open3D's
# cluster_dbscan and scikit-learn's DBSCAN (kd_tree, n_jobs=2) run on the same points at 10k and 100k,
# and with --full also at 1M (minutes each). Needs /usr/bin/python3 with numpy, open3d and sklearn;
# a missing peer is reported in the agreement column.
set -eu

if [ $# -lt 1 ]; then
  echo "usage: $0 BUILD_DIR [--full]" >&2
  exit 2
fi
build=$1
full=${2:-}
here=$(cd "$(dirname "$0")" && pwd)
bench="$build/bench/hullmap_bench_dbscan"
if [ ! -x "$bench" ]; then
  echo "$0: $bench not found (configure with -DHULLMAP_BUILD_BENCH=ON, build hullmap_bench_dbscan)" >&2
  exit 2
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

peers=10000,100000
write_max=100000
if [ "$full" = "--full" ]; then
  peers=10000,100000,1000000
  write_max=1000000
fi

"$bench" --sizes 10000,100000,1000000,10000000 --write-dir "$work" --write-max "$write_max" >"$work/hullmap.jsonl"

threads=$(sed -n 's/.*"threads":\([0-9]*\).*/\1/p' "$work/hullmap.jsonl" | head -n 1)
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -n 1)

echo "## DBSCAN"
echo
echo "Exact DBSCAN (eps 0.1, minPts 10, 3D metric) on generated scenes (\`generateScene\` defaults, z-up, 8 obstacles"
echo "in a 10 m room, about 1,500 neighbours within eps per point at 1M, 3% uniform outliers, 5 gross outliers hundreds"
echo "of km away). hullmap: best of 3 runs"
echo "(1 at 10M) of \`dbscan()\` on points in memory, ${threads} threads (wall clock; CPU s is the CPU time of all"
echo "threads, which tells how much of the machine the run got when it is shared); peak MB is the growth of the resident"
echo "set during one run (result included; TBB's threads started before). Open3D \`cluster_dbscan\` and scikit-learn \`DBSCAN(algorithm='kd_tree',"
echo "n_jobs=2)\`: one timed fit each, on the same points. Agreement: same noise set and same partition of the"
echo "core points as hullmap (border points may join another cluster within reach and are not compared)."
echo "Peers at 1M points run only with \`--full\`."
echo
OMP_NUM_THREADS=2 /usr/bin/python3 "$here/dbscan_peers.py" "$work" "$work/hullmap.jsonl" --sizes "$peers" \
  --eps 0.1 --min-pts 10 --threads 2 --markdown
echo
# Third peer: the PyPI package `dbscan` (Wang, Gu and Shun, SIGMOD 2020: exact parallel DBSCAN), from the
# venv `./setup.sh bench` makes; where it could not be installed the section says so and goes on.
venv_python="${HULLMAP_DBSCAN_VENV:-$here/../build-bench/venv}/bin/python3"
if [ -x "$venv_python" ] && "$venv_python" -c "import dbscan" 2>/dev/null; then
  echo "PyPI \`dbscan\` (Wang, Gu and Shun's exact parallel DBSCAN), one timed call on the same points:"
  echo
  echo "| points | dbscan (PyPI) s | clusters |"
  echo "|---:|---:|---:|"
  for n in $(echo "$peers" | tr ',' ' '); do
    "$venv_python" - "$work/scene_$n.f64" "$n" <<'PY' || echo "| $n | failed | - |"
import sys, time
import numpy as np
from dbscan import DBSCAN
points = np.fromfile(sys.argv[1], dtype=np.float64).reshape(-1, 3)
start = time.perf_counter()
labels, core = DBSCAN(points, eps=0.1, min_samples=10)
elapsed = time.perf_counter() - start
print(f"| {int(sys.argv[2]):,} | {elapsed:.3f} | {labels.max() + 1} |")
PY
  done
else
  echo "PyPI \`dbscan\` (Wang, Gu and Shun's exact parallel DBSCAN, the third peer): not installed on this machine"
  echo "(\`./setup.sh bench\` tries \`pip install dbscan\` in a venv; the package index could not be reached), so it is not timed."
fi
echo
echo "Machine: ${cpu:-unknown CPU}, $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the end. Regenerate: \`bench/section_dbscan.sh BUILD_DIR${full:+ $full}\`."
