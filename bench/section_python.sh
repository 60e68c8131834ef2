#!/bin/sh
# Prints the "## Python" section of docs/BENCHMARKS.md (markdown) to stdout.
#
# usage: bench/section_python.sh BUILD_DIR
#
# BUILD_DIR is a build with the Python module (target hullmap_python: pybind11-dev, python3-dev and
# python3-numpy found) and the CLI (target hullmap). Times, from one Python process
# (bench/python_bench.py): hullmap.dbscan against scikit-learn's DBSCAN and Open3D's cluster_dbscan on
# the same 100,000 points, and Map.check in segments per second on the Path checks section's
# generated_100 scene. Needs /usr/bin/python3 with numpy, sklearn and open3d (a missing peer is
# reported in the result column). About a minute on 2 cores.
set -eu

if [ $# -lt 1 ]; then
  echo "usage: $0 BUILD_DIR" >&2
  exit 2
fi
build=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
hullmap="$build/cli/hullmap"
if [ ! -x "$hullmap" ] || ! ls "$build"/python/hullmap/_hullmap*.so >/dev/null 2>&1; then
  echo "$0: $hullmap or $build/python/hullmap not found (build the targets hullmap and hullmap_python)" >&2
  exit 2
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -n 1)

echo "## Python"
echo
echo "hullmap's Python module ([PYTHON.md](PYTHON.md)) timed from one Python process (\`bench/python_bench.py\`),"
echo "the arrays going in and out included. *hullmap.dbscan*: eps 0.1, minPts 10, 3D, on a generated scene"
echo "(\`hullmap generate --points 100000 --z-up\`: generateScene's defaults, as the DBSCAN section's scenes), median"
echo "of 5 calls after a warm-up; scikit-learn's \`DBSCAN(algorithm='kd_tree', n_jobs=2)\` and Open3D's"
echo "\`cluster_dbscan\` on the same array, one timed call each; agreement as in the DBSCAN section (noise set and"
echo "partition of the core points; scikit-learn's core points, which hullmap.dbscan does not return)."
echo "*Map.check*: the Path checks section's generated_100 scene (\`hullmap generate --obstacles 100 --room 30"
echo "--points 500000 --seed 42\`, \`hullmap.build\` with its trajectory and \`up=\"-y\"\`), 200,000 random segments"
echo "drawn as bench_collision draws them (numpy's generator, not the same segments), median of 5 calls: one"
echo "call checks the whole (N, 6) array on all cores with the GIL released and returns the structured array."
echo "Regenerate with \`bench/section_python.sh BUILD_DIR\`."
echo
OMP_NUM_THREADS=2 PYTHONPATH="$build/python" /usr/bin/python3 "$here/python_bench.py" "$hullmap" "$work" \
  --points 100000 --segments 200000 --repeat 5 --threads 2
echo
echo "Machine: ${cpu:-unknown CPU}, $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the end."
