#!/usr/bin/env bash
# Runs one ROS 2 test (CTest's label ros2) with ROS 2 and the package built by ros2/build.sh sourced in
# its own environment only: usage: test/ros2/run_test.sh BUILD_DIR COMMAND [ARGS...]
# Exits 77 (CTest: skipped), saying why, when ROS 2 was not found or the package was not built.
set -euo pipefail
build=$1
shift
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
status_file="$build/ros2/status"
if [ ! -f "$status_file" ]; then
  echo "skipped: the ROS 2 package was not built (./setup.sh test builds it, or ros2/build.sh $build)"
  exit 77
fi
status=$(cat "$status_file")
if [ "$status" != built ]; then
  echo "skipped: $status"
  exit 77
fi
# shellcheck source=../../ros2/ros2_env.sh
source "$root/ros2/ros2_env.sh"
if ! hullmap_ros2_env; then
  echo "skipped: ROS 2 not found: $HULLMAP_ROS2_MISSING"
  exit 77
fi
set +u  # colcon's setup scripts read unset variables
# shellcheck disable=SC1091
source "$build/ros2/install/setup.bash"
set -u
exec "$@"
