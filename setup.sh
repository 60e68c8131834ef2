#!/usr/bin/env bash
# hullmap set-up: installs what is missing (Debian 12 packages), builds, then
#   ./setup.sh demo   runs `hullmap build --align` on maps/room, prints `hullmap evaluate`'s verdict and
#                     writes out/room.html (`hullmap view`)
#   ./setup.sh test   runs the whole test suite (ctest)
#   ./setup.sh bench  installs the peers (Open3D, scikit-learn) too and regenerates docs/BENCHMARKS.md
#   ./setup.sh quality  installs Open3D and SciPy too and regenerates docs/QUALITY.md (bench/run_quality.sh)
#   ./setup.sh packages MODE    prints MODE's package list, one a line (installs nothing)
#   ./setup.sh install MODE     installs what MODE's list misses, and stops there (.ci/run, to build the
#                               sanitized tree beside `./setup.sh test`)
#   ./setup.sh cmake-args MODE  prints the cmake arguments MODE configures with
# (.ci/check_packages.sh reads both to check that each mode installs all its build links and includes.)
# Environment: BUILD_DIR (default build), JOBS (default: number of cores).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

usage="usage: $0 demo|test|bench|quality, or $0 packages|cmake-args|install demo|test|bench|quality"
query=""
if [ "${1:-}" = packages ] || [ "${1:-}" = cmake-args ] || [ "${1:-}" = install ]; then
  query=$1
  shift
  [ $# -eq 1 ] || { echo "$usage" >&2; exit 2; }
fi
mode=${1:-demo}
case "$mode" in demo|test|bench|quality) ;; *) echo "$usage" >&2; exit 2 ;; esac
build_dir=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc)}

# Library packages hullmap builds against, and the tools its tests use. OMPL's CMake config names
# Boost's filesystem, serialization and system libraries, which libompl-dev does not depend on.
packages=(build-essential cmake pkg-config liboctomap-dev libfcl-dev libcgal-dev libeigen3-dev
          libtbb-dev liblzf-dev libcli11-dev nlohmann-json3-dev libnanoflann-dev libgtest-dev libbenchmark-dev
          libompl-dev libboost-filesystem-dev libboost-serialization-dev libboost-system-dev ccache ninja-build)
# three.js for `hullmap view`'s page (the demo writes one).
packages+=(libjs-three)
if [ "$mode" = test ]; then
  # python3-sklearn: DBSCAN oracle on real maps; librsvg2-bin: PNG rendering test;
  # clang + libclang-rt-14-dev: the libFuzzer targets that .ci/run runs briefly.
  packages+=(python3 python3-sklearn python3-numpy librsvg2-bin xz-utils clang libclang-rt-14-dev)
  # clang-format: .ci/check_format.sh (.clang-format); clang-tidy for .clang-tidy, run by hand.
  packages+=(clang-format clang-tidy)
  # The Python module (python/) and its pytest suite: pybind11 and the headers to build it, pytest,
  # venv and pip for the offline pip install test, Open3D for Map.to_open3d.
  packages+=(pybind11-dev python3-dev python3-pytest python3-venv python3-pip python3-open3d)
  # hullmap view's test/view/browser_test.py: headless Chromium driven by selenium (python3-pil reads
  # its screenshots).
  packages+=(chromium chromium-driver python3-selenium python3-pil)
  # ROS1 (Debian's): hullmap_node and bag input are built only when found, so the tests install them;
  # pluginlib-dev holds headers that rosbag/bag.h includes; the python3-* message modules, rospy,
  # rosbag and ros-core (rosmaster) are what test/ros/*_test.py publish, record and run with.
  packages+=(ros-core libroscpp-dev librosbag-storage-dev pluginlib-dev libstd-msgs-dev libgeometry-msgs-dev
             libsensor-msgs-dev libnav-msgs-dev libvisualization-msgs-dev libstd-srvs-dev
             python3-rospy python3-rosbag python3-yaml python3-std-msgs python3-geometry-msgs
             python3-sensor-msgs python3-nav-msgs python3-visualization-msgs python3-std-srvs)
  # ROS 2: the test core beside the checkout (../shared/ros2, see its README) runs on these packages;
  # ros2/build.sh sources it in its own process only, to build the ROS 2 package (test/ros2/ tests it).
  if [ -f ../shared/ros2/debian-packages.txt ]; then
    mapfile -t ros2_packages < <(grep -Ev '^[[:space:]]*(#|$)' ../shared/ros2/debian-packages.txt)
    packages+=("${ros2_packages[@]}")
  fi
fi
if [ "$mode" = bench ]; then
  # The peers a user would pick instead (Open3D's and scikit-learn's DBSCAN), and /usr/bin/time.
  # python3-venv: a venv for the PyPI peer `dbscan` (Wang, Gu and Shun's exact parallel DBSCAN).
  packages+=(python3 python3-numpy python3-sklearn python3-open3d python3-venv time bc)
  # The Python module, for the section that times it from Python.
  packages+=(pybind11-dev python3-dev)
  # bench/view_scale.py: hullmap view's page in headless Chromium.
  packages+=(chromium chromium-driver python3-selenium python3-pil)
fi
if [ "$mode" = quality ]; then
  # The Open3D pipeline a user would assemble, numpy/scipy for the alignment and footprints, and
  # rsvg-convert for the pictures.
  packages+=(python3 python3-numpy python3-scipy python3-open3d librsvg2-bin)
fi

# What each mode configures: the demo builds the library and the CLI only (ROS and the tests are
# not installed for it); the test mode everything its packages allow.
cmake_args=(-DHULLMAP_BUILD_TESTS=OFF -DHULLMAP_BUILD_ROS=OFF -DHULLMAP_BUILD_PYTHON=OFF)
[ "$mode" = test ] && cmake_args=(-DHULLMAP_BUILD_TESTS=ON -DHULLMAP_BUILD_ROS=ON -DHULLMAP_BUILD_PYTHON=ON)

if [ "$query" = packages ]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi
if [ "$query" = cmake-args ]; then
  echo "${cmake_args[*]}"
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "== installing: ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
[ "$query" = install ] && exit 0

if [ "$mode" = bench ]; then
  # The PyPI package `dbscan` in a venv of its own (Debian does not package it). Where the package index
  # cannot be reached the DBSCAN section still runs and says that this peer could not be installed.
  venv=${BENCH_VENV:-build-bench/venv}
  if [ ! -x "$venv/bin/python3" ] || ! "$venv/bin/python3" -c "import dbscan" 2>/dev/null; then
    echo "== installing the PyPI package dbscan into $venv"
    /usr/bin/python3 -m venv --system-site-packages "$venv" &&
      timeout 300 "$venv/bin/pip" install --quiet dbscan ||
      echo "== could not install the PyPI package dbscan (is the Python package index reachable?); its column will say so"
  fi
  export HULLMAP_DBSCAN_VENV="$venv"
  exec bench/run_benchmarks.sh  # builds its own Release tree with the benchmarks
fi

if [ "$mode" = quality ]; then
  exec bench/run_quality.sh  # builds its own Release tree
fi

echo "== building in $build_dir"
# Ninja for a new build directory (one configured before keeps its generator): it compiles a target's
# files while the libraries that the target links are still being built, so both cores stay busy.
generator=()
[ -f "$build_dir/CMakeCache.txt" ] || generator=(-G Ninja)
cmake -S . -B "$build_dir" "${generator[@]}" "${cmake_args[@]}" >/dev/null
cmake --build "$build_dir" -j"$jobs"
if [ "$mode" = test ]; then
  # The ROS 2 package against this build's hullmap; without ROS 2, one line says it was skipped.
  ros2/build.sh "$build_dir"
fi

if [ "$mode" = demo ]; then
  hullmap="$build_dir/cli/hullmap"
  # maps/room: a realistic room in ORB-SLAM's frame at monocular scale, with a metric reference
  # trajectory and the ground truth (maps/README.md); the build runs at its defaults.
  m=maps/room
  echo "== $hullmap build $m/map_points.txt --trajectory $m/KeyFrameTrajectory.txt --align $m/reference_trajectory.txt -p -o out/room"
  "$hullmap" build $m/map_points.txt --trajectory $m/KeyFrameTrajectory.txt --align $m/reference_trajectory.txt -p -o out/room
  echo "== $hullmap evaluate out/room --truth $m/ground_truth.json --radius 0.3"
  "$hullmap" evaluate out/room --truth $m/ground_truth.json --radius 0.3
  echo "== $hullmap check out/room --radius 0.3 --segments $m/segments.txt"
  "$hullmap" check out/room --radius 0.3 --segments $m/segments.txt || [ $? -eq 1 ]
  echo "== $hullmap view out/room -o out/room.html"
  "$hullmap" view out/room -o out/room.html
  echo "== open out/room.html in a browser to see the build in 3D"
  echo "== outputs in out/room: $(ls out/room | tr '\n' ' ')"
else
  ctest --test-dir "$build_dir" --output-on-failure -j"$jobs"
fi
# The Python module, when it was built (pybind11-dev, python3-dev and python3-numpy found; docs/PYTHON.md).
if compgen -G "$build_dir/python/hullmap/_hullmap*.so" >/dev/null; then
  python=$(sed -n 's/^Python3_EXECUTABLE:[A-Z]*=//p' "$build_dir/CMakeCache.txt")
  echo "== Python: export PYTHONPATH=$(cd "$build_dir" && pwd)/python; ${python:-python3} -c \"import hullmap\""
fi
