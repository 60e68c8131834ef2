#!/bin/sh
# Prints the "## ROS: map message to published obstacles" section of docs/BENCHMARKS.md to stdout.
#
# usage: bench/section_ros.sh BUILD_DIR [repeats]
#
# BUILD_DIR holds ros/hullmap_node (ROS1 found) and bench/hullmap_bench_octomap_cloud. Needs Debian's
# ros-core, python3-rospy and the python3-*-msgs modules (./setup.sh test installs them). The ROS 2
# rows need the ROS 2 package built against BUILD_DIR (ros2/build.sh BUILD_DIR); ROS 2 is sourced for
# them alone, as ros2/ros2_env.sh finds it.
set -eu

if [ $# -lt 1 ]; then
  echo "usage: $0 BUILD_DIR [repeats]" >&2
  exit 2
fi
build=$1
repeats=${2:-3}
here=$(cd "$(dirname "$0")" && pwd)
node="$build/ros/hullmap_node"
octomap="$build/bench/hullmap_bench_octomap_cloud"
for binary in "$node" "$octomap"; do
  if [ ! -x "$binary" ]; then
    echo "$0: $binary not found (ROS1 packages installed? configure with -DHULLMAP_BUILD_BENCH=ON)" >&2
    exit 2
  fi
done

cat <<'TEXT'
## ROS: map message to published obstacles

The live node ([ROS.md](ROS.md)), in ROS 1 and in ROS 2, receives a whole map as a FLOAT32
`sensor_msgs/PointCloud2` on `~cloud_in` (as the ORB-SLAM2/3 wrappers send it) and publishes its
obstacles on `~obstacles`; the peer
is the work octomap_server does on every such message, octomap's `insertPointCloud` of every point
from one keyframe (the room's centre) into its tree, timed on the same points in the same run
(`hullmap_bench_octomap_cloud`, median of the repeats). The map: a 10 x 8 x 3 m room, 8 boxes whose
surfaces carry 90% of the points, 10% scattered (outliers); `hullmap build`'s defaults (resolution
0.05, eps and min_pts chosen from the map, floor search, convex parts). **End-to-end**: from `publish()` in a client (rospy, rclpy) to the `~obstacles`
message with the same stamp arriving back in it (serialisation and transport both ways included);
**node latency_ms**: the node's own `~stats` (callback to obstacles published); **rebuild_ms**: the
build alone. Medians of 3 messages per size. `bench/ros_latency.py`, `bench/section_ros.sh`.

ROS 1, `hullmap_node` (rospy client, rosmaster on loopback):

TEXT
/usr/bin/python3 "$here/ros_latency.py" "$node" "$octomap" "$repeats"
cat <<'TEXT'

ROS 2, `hullmap_ros2`'s `hullmap_node` (Humble, rmw_cyclonedds_cpp on loopback; an rclpy client, the
same maps and method, `bench/ros2_latency.py`; the node's cloud input made reliable through its QoS
override, as ROS 1's TCP is):

TEXT
ros2_latency() {
  if [ -f "$build/ros2/status" ] && [ "$(cat "$build/ros2/status")" = built ]; then
    bash -c 'source "$1/ros2/ros2_env.sh" && hullmap_ros2_env && set +u && source "$2/ros2/install/setup.bash" &&
             shift 2 && exec /usr/bin/python3 "$@"' _ "$here/.." "$build" "$here/ros2_latency.py" "$octomap" "$repeats" "$@"
  else
    echo "(not measured: $(cat "$build/ros2/status" 2>/dev/null || echo "the ROS 2 package is not built in $build"))"
  fi
}
ros2_latency
cat <<'TEXT'

The same node at its defaults, no QoS override (the 1M map from the same reliable publisher; the node's
cloud input follows it and turns reliable, [ROS.md](ROS.md#qos-ros-2)):

TEXT
ros2_latency --defaults 1000000
