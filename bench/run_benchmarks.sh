#!/bin/sh
# Regenerates docs/BENCHMARKS.md: builds the benchmarks (Release) in BUILD_DIR, then runs every
# section one after the other on this machine and writes them into one file.
#
#   bench/run_benchmarks.sh [BUILD_DIR]        (default: build-bench)
#   ./setup.sh bench                           installs what it needs first, then runs it
#
# Needs Debian's python3-open3d, python3-sklearn, python3-numpy (the DBSCAN peers), time,
# pybind11-dev and python3-dev (the Python section), and
# shared/data/real/octomap_scan.dat (the insertion scan; set HULLMAP_REAL_DATA_DIR to move it).
# Takes about 15 minutes on 2 cores, most of it Open3D and scikit-learn at 1M points.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build-bench}
out=$root/docs/BENCHMARKS.md

cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DHULLMAP_BUILD_BENCH=ON -DHULLMAP_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j"$(nproc)" --target hullmap hullmap_bench_dbscan hullmap_bench_insertion hullmap_bench_collision hullmap_bench_planning hullmap_bench_octomap_cloud >/dev/null
# The Python module exists only when pybind11, Python 3's headers and numpy were found; its section is
# left out otherwise.
if cmake --build "$build" -j"$(nproc)" --target hullmap_python >/dev/null 2>&1; then
  python_section=yes
else
  python_section=no
fi
# hullmap_node exists only when ROS1 was found; its section is left out otherwise.
if cmake --build "$build" -j"$(nproc)" --target hullmap_node hullmap_bench_octomap_cloud >/dev/null 2>&1; then
  ros_section=yes
  # The ROS 2 rows of that section: the ROS 2 package against this tree (skipped, saying so, without ROS 2).
  "$root/ros2/build.sh" "$build" >&2
else
  ros_section=no
fi

mkdir -p "$root/docs"
tmp=$(mktemp "$root/docs/.BENCHMARKS.md.XXXXXX")
trap 'rm -f "$tmp"' EXIT
{
  echo "# Benchmarks"
  echo
  echo "Every number below comes from one run of \`bench/run_benchmarks.sh\` on the machine it names, hullmap"
  echo "and its peers side by side in that run (ratios are within the run). Regenerate the whole file with:"
  echo
  echo '```'
  echo "./setup.sh bench"
  echo '```'
  echo
  echo "(it installs the peers, Debian's \`python3-open3d\` and \`python3-sklearn\`, and \`time\` when they are missing,"
  echo "then runs \`bench/run_benchmarks.sh\`, which builds a Release tree in \`build-bench/\` and runs every section)."
  echo
  echo "Run on $(date -u +%Y-%m-%d), hullmap $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown),"
  echo "$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -n 1), $(nproc) cores,"
  echo "$(awk '/^MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo)."
  echo
  sh "$root/bench/section_dbscan.sh" "$build" --full
  echo
  bash "$root/bench/section_cluster_process.sh" "$build"
  echo
  sh "$root/bench/section_insertion.sh" "$build"
  echo
  bash "$root/bench/section_build_process.sh" "$build"
  echo
  sh "$root/bench/section_collision.sh" "$build"
  echo
  sh "$root/bench/section_large_map.sh" "$build"
  echo
  sh "$root/bench/section_planning.sh" "$build"
  if [ "$python_section" = yes ]; then
    echo
    sh "$root/bench/section_python.sh" "$build"
  fi
  if [ "$ros_section" = yes ]; then
    echo
    sh "$root/bench/section_ros.sh" "$build"
  fi
  echo
  /usr/bin/python3 "$root/bench/view_scale.py" "$build" ||
    echo "(The viewer's section did not run here: bench/view_scale.py said why on stderr.)"
} >"$tmp"
mv "$tmp" "$out"
trap - EXIT
echo "wrote $out"
