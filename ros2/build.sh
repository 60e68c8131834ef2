#!/usr/bin/env bash
# Builds hullmap's ROS 2 packages (ros2/hullmap_interfaces, ros2/hullmap_ros2) with colcon against the
# hullmap of BUILD_DIR, installed as a user installs it (cmake --install) into BUILD_DIR/ros2/hullmap:
# the workspace is BUILD_DIR/ros2/{src,build,install,log}, src/hullmap a link to this checkout. `./setup.sh test` runs it; test/ros2/ uses it.
#
# usage: ros2/build.sh BUILD_DIR [SKIP_STATUS]
#
# ROS 2 is found by ros2/ros2_env.sh in this script's process only (a sourced ROS 2, or
# ../shared/ros2/activate). Without it: one line saying so, BUILD_DIR/ros2/status holds why (the
# ROS 2 tests skip with it), exit SKIP_STATUS (default 0; CTest's ros2.build passes 77, skipped).
# A failed build exits 1.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if [ $# -lt 1 ] || [ $# -gt 2 ] || [ ! -d "$1" ]; then
  echo "usage: $0 BUILD_DIR [SKIP_STATUS] (BUILD_DIR: a configured and built hullmap build directory)" >&2
  exit 2
fi
skip_status=${2:-0}
build=$(cd "$1" && pwd)
out="$build/ros2"
mkdir -p "$out"
rm -f "$out/status"
start=$SECONDS

# shellcheck source=ros2_env.sh
source "$root/ros2/ros2_env.sh"
if ! hullmap_ros2_env; then
  echo "== ROS 2 not found: the ROS 2 package was skipped ($HULLMAP_ROS2_MISSING)"
  echo "ROS 2 not found: $HULLMAP_ROS2_MISSING" > "$out/status"
  exit "$skip_status"
fi

echo "== ROS 2 packages: hullmap installed into $out/hullmap, colcon workspace $out"
cmake --install "$build" --prefix "$out/hullmap" >/dev/null
export CMAKE_PREFIX_PATH="$out/hullmap${CMAKE_PREFIX_PATH:+:$CMAKE_PREFIX_PATH}"
# The workspace as a user lays it out: this checkout in its src/ (colcon finds the two packages through
# colcon.pkg), a plain `colcon build` (hullmap_ros2 builds Release by default).
mkdir -p "$out/src"
ln -sfn "$root" "$out/src/hullmap"
# A package's build directory that CMake configured from another source path (an earlier layout, or
# another checkout) would stop colcon: it starts again from nothing.
for pkg in hullmap_interfaces hullmap_ros2; do
  cache="$out/build/$pkg/CMakeCache.txt"
  if [ -f "$cache" ] && ! grep -qx "CMAKE_HOME_DIRECTORY:INTERNAL=$out/src/hullmap/ros2/$pkg" "$cache"; then
    rm -rf "${out:?}/build/$pkg"
  fi
done
if ! (cd "$out" && colcon build --base-paths src > "$out/colcon.log" 2>&1); then
  tail -n 40 "$out/colcon.log" >&2
  echo "ROS 2 package build failed: see $out/colcon.log" > "$out/status"
  echo "== ROS 2 package build failed (log: $out/colcon.log)" >&2
  exit 1
fi
grep -h "^-- hullmap_ros2: hullmap" "$out/log/latest_build/hullmap_ros2/stdout.log" 2>/dev/null | head -n 1 || true
echo "built" > "$out/status"
echo "== ROS 2 packages built in $((SECONDS - start)) s"
